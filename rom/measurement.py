"""Measured responses: loading and checking CSV files.

A measured impulse response is a CSV with a header row and the columns

    time_s               sample time [s], strictly increasing
    tip_displacement_m   tip displacement [m]
    force_N              (optional) applied force [N]
    reaction_force_N     (optional) reaction force at the clamp or object [N]

Other columns are ignored. Lines starting with ``#`` are comments (for provenance).
"""
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ccedi.errors import InputError

REQUIRED_COLUMNS = ("time_s", "tip_displacement_m")
OPTIONAL_COLUMNS = ("force_N", "reaction_force_N")
MIN_SAMPLES = 8


@dataclass(frozen=True)
class MeasuredResponse:
    """time_s [s], tip_displacement_m [m], force_N [N] or None, where it came from, and
    reaction_force_N [N] or None."""

    time_s: np.ndarray
    tip_displacement_m: np.ndarray
    force_N: np.ndarray | None
    source: str
    reaction_force_N: np.ndarray | None = None


def load_response(path):
    """Read and validate a measured response CSV (see module docstring)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"measured response file not found: {path}")
    try:
        frame = pd.read_csv(path, comment="#")
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as err:
        raise InputError(f"{path}: not a readable CSV ({err})") from None
    return response_from_frame(frame, source=str(path))


def response_from_frame(frame, source="<frame>"):
    """Validate a DataFrame with the measured-response columns."""
    missing = [c for c in REQUIRED_COLUMNS if c not in frame.columns]
    if missing:
        raise InputError(f"{source}: missing column(s) {', '.join(missing)}; "
                         f"need {', '.join(REQUIRED_COLUMNS)} (and optionally force_N), found {list(frame.columns)}")
    cols = list(REQUIRED_COLUMNS) + [c for c in OPTIONAL_COLUMNS if c in frame.columns]
    data = {}
    for c in cols:
        values = pd.to_numeric(frame[c], errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(~np.isfinite(values))
        if len(bad):
            raise InputError(f"{source}: column {c} has a missing or non-numeric value at data row {bad[0] + 1}")
        data[c] = values
    t = data["time_s"]
    if len(t) < MIN_SAMPLES:
        raise InputError(f"{source}: {len(t)} samples; at least {MIN_SAMPLES} are needed")
    step = np.diff(t)
    if np.any(step <= 0.0):
        i = int(np.argmax(step <= 0.0))
        raise InputError(f"{source}: time_s must be strictly increasing (row {i + 2}: {t[i + 1]} s after {t[i]} s)")
    return MeasuredResponse(time_s=t, tip_displacement_m=data["tip_displacement_m"],
                            force_N=data.get("force_N"), source=source,
                            reaction_force_N=data.get("reaction_force_N"))
