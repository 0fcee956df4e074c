"""Measured responses: loading and checking CSV files.

A measured impulse response is a CSV with a header row and the columns

    time_s               sample time [s], strictly increasing
    tip_displacement_m   tip displacement [m]
    force_N              (optional) applied force [N]
    reaction_force_N     (optional) reaction force at the clamp or object [N]

Other columns are ignored. Lines starting with ``#`` are comments (for provenance). Every
row has at most as many fields as the header; each column is named once.
"""
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ccedi.errors import InputError, brief_repr, one_line

REQUIRED_COLUMNS = ("time_s", "tip_displacement_m")
CONTACT_COLUMNS = ("time_s", "reaction_force_N")
"""Required columns of a contact record (the force on the object as the transducer reads it)."""
OPTIONAL_COLUMNS = ("force_N", "reaction_force_N", "contact_force_x_N", "contact_force_y_N")
MIN_SAMPLES = 8


@dataclass(frozen=True)
class MeasuredResponse:
    """A measured impulse response (validated, see the module docstring).

    Parameters
    ----------
    time_s : numpy.ndarray
        Sample times, strictly increasing, (n,) [s].
    tip_displacement_m : numpy.ndarray
        Tip displacement, (n,) [m].
    force_N : numpy.ndarray or None
        Applied force, (n,) [N], or None when the file has no such column.
    source : str
        Where the data came from (file path or ``"<frame>"``).
    reaction_force_N : numpy.ndarray or None, optional
        Reaction force at the clamp or object, (n,) [N], or None. Default None.
    contact_force_x_N, contact_force_y_N : numpy.ndarray or None, optional
        Lab-frame components of the force on the object, (n,) [N], or None.
    """

    time_s: np.ndarray
    tip_displacement_m: np.ndarray | None
    force_N: np.ndarray | None
    source: str
    reaction_force_N: np.ndarray | None = None
    contact_force_x_N: np.ndarray | None = None
    contact_force_y_N: np.ndarray | None = None


def load_response(path, required=REQUIRED_COLUMNS):
    """Read and validate a measured response CSV.

    Columns ``required`` (default ``time_s`` and ``tip_displacement_m``; a contact record:
    :data:`CONTACT_COLUMNS`) are required, the others of :data:`OPTIONAL_COLUMNS` optional;
    lines starting with ``#`` are comments.

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV file.
    required : tuple of str, optional
        The required columns.

    Returns
    -------
    MeasuredResponse
        The validated response, ``source`` set to the path.

    Raises
    ------
    InputError
        If the file does not exist or is not a readable CSV (not UTF-8, an unclosed
        quote, a row with more fields than the header), has no header row, or the data
        fail the checks of :func:`response_from_frame`.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"measured response file not found: {path}")
    try:        # all text: the header is a row like the others, and no cell is guessed a number
        table = pd.read_csv(path, comment="#", header=None, dtype=str, keep_default_na=False)
    except pd.errors.EmptyDataError:
        raise InputError(f"{path}: no header row; expected a CSV with the columns {', '.join(required)}") \
            from None
    except (pd.errors.ParserError, UnicodeDecodeError) as err:
        raise InputError(f"{path}: not a readable CSV ({one_line(err)}){_separator_hint(path)}") from None
    frame = pd.DataFrame(table.iloc[1:].to_numpy(), columns=table.iloc[0].to_numpy())
    if len(frame.columns) == 1 and _separator_hint(path):
        raise InputError(f"{path}: one column {brief_repr(str(frame.columns[0]))}{_separator_hint(path)}")
    return response_from_frame(frame, source=str(path), required=required)


def _separator_hint(path):
    """``"; the header is separated by ';' ..."`` when the file's first non-comment line
    holds a semicolon or a tab and no comma (a spreadsheet's export with a decimal comma),
    else ``""``."""
    try:
        with open(path, encoding="utf-8-sig", errors="replace") as fh:
            header = next((line for line in fh if line.strip() and not line.startswith("#")), "")
    except OSError:
        return ""
    sep = next((s for s in (";", "\t") if s in header and "," not in header), None)
    if sep is None:
        return ""
    shown = "a tab" if sep == "\t" else "';'"
    return (f"; the header is separated by {shown}: ccedi reads comma-separated values with a decimal point "
            "(export the sheet as CSV with ',' between columns and '.' in numbers)")


def response_from_frame(frame, source="<frame>", required=REQUIRED_COLUMNS):
    """Validate a DataFrame with the measured-response columns.

    Parameters
    ----------
    frame : pandas.DataFrame
        With the ``required`` columns (default ``time_s`` [s] and ``tip_displacement_m``
        [m]), optionally those of :data:`OPTIONAL_COLUMNS` [N]; other columns are ignored.
    source : str, optional
        Name used in error messages and stored in the result. Default ``"<frame>"``.
    required : tuple of str, optional
        The required columns.

    Returns
    -------
    MeasuredResponse
        The validated response.

    Raises
    ------
    InputError
        If a required column is missing, a used column is there twice or has a missing,
        non-numeric or non-finite value, there are fewer than 8 samples, or ``time_s`` is
        not strictly increasing.
    """
    missing = [c for c in required if c not in frame.columns]
    if missing:
        raise InputError(f"{source}: missing column(s) {', '.join(missing)}; need {', '.join(required)} "
                         f"(and optionally {', '.join(c for c in OPTIONAL_COLUMNS if c not in required)}), found "
                         f"{brief_repr(list(frame.columns))}")
    cols = list(required) + [c for c in OPTIONAL_COLUMNS if c in frame.columns and c not in required]
    twice = [c for c in cols if list(frame.columns).count(c) > 1]
    if twice:
        raise InputError(f"{source}: column {twice[0]} is there {list(frame.columns).count(twice[0])} times; "
                         f"expected once")
    data = {}
    for c in cols:
        values = pd.to_numeric(frame[c], errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(~np.isfinite(values))
        if len(bad):
            got = frame[c].to_numpy(dtype=object)[bad[0]]
            raise InputError(f"{source}: column {c} has a missing, non-numeric or non-finite value at data row "
                             f"{bad[0] + 1} (got {brief_repr(got)}); expected a finite number")
        data[c] = values
    t = data["time_s"]
    if len(t) < MIN_SAMPLES:
        raise InputError(f"{source}: {len(t)} samples; at least {MIN_SAMPLES} are needed")
    back = np.flatnonzero(t[1:] <= t[:-1])          # compared, not subtracted: no overflow
    if len(back):
        i = int(back[0])
        raise InputError(f"{source}: time_s must be strictly increasing (row {i + 2}: {t[i + 1]} s after {t[i]} s)")
    return MeasuredResponse(time_s=t, tip_displacement_m=data.get("tip_displacement_m"),
                            force_N=data.get("force_N"), source=source,
                            reaction_force_N=data.get("reaction_force_N"),
                            contact_force_x_N=data.get("contact_force_x_N"),
                            contact_force_y_N=data.get("contact_force_y_N"))


def check_sampling(time_s, omega1_rad_s, source):
    """Reject a record whose time column cannot be seconds for the declared structure.

    The largest sample interval must be below a quarter of the first period 2 pi / omega_1:
    a record in milliseconds, or one too coarse to resolve the first mode, fails.

    Parameters
    ----------
    time_s : array_like
        Sample times of the record [s].
    omega1_rad_s : float
        First natural frequency of the declared structure [rad/s] (take the highest the
        declaration allows, e.g. at E x (1 + tolerance)).
    source : str
        Name of the record in the message (its path).

    Raises
    ------
    InputError
        Naming the largest interval and the period it exceeds a quarter of.
    """
    with np.errstate(over="ignore"):                # steps beyond the float range are inf: too coarse
        dt = float(np.max(np.diff(np.asarray(time_s, dtype=float))))
    period = 2.0 * np.pi / float(omega1_rad_s)
    if dt > period / 4.0:
        raise InputError(f"{source}: time_s steps up to {dt:.4g} s, more than a quarter of the declared "
                         f"structure's first period ({period:.4g} s): not seconds, or too coarse to resolve it")


def force_pulse(time_s, force_N):
    """The pulse of a measured force column: where |F| is at least half its peak.

    Parameters
    ----------
    time_s : numpy.ndarray
        Sample times [s], increasing.
    force_N : numpy.ndarray
        The force column [N].

    Returns
    -------
    tuple of float
        ``(amplitude [N], start [s], duration [s])``: the signed force at the peak, the
        first sample at half the peak or more, and the span of those samples plus one
        (median) sample interval.

    Raises
    ------
    InputError
        A force column that is all zero.
    """
    peak = float(np.max(np.abs(force_N)))
    if peak == 0.0:
        raise InputError("force_N column is all zero: cannot infer the impulse")
    on = np.flatnonzero(np.abs(force_N) >= 0.5 * peak)
    dt = float(np.median(np.diff(time_s)))
    return (float(force_N[on[np.argmax(np.abs(force_N[on]))]]), float(time_s[on[0]]),
            float(time_s[on[-1]] - time_s[on[0]] + dt))
