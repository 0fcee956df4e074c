"""The surrogate's model against the full FEA: the error on each output, and the margin a
design carries where the error is larger than :data:`TOLERANCE`.

The check (``validation/design_rom_check.py``) runs the design's contact ROM and the full
explicit FEA on the same cases (finger length x alpha x damping kind) and keeps both
runs' outputs (:func:`ccedi.design.outputs.design_outputs`). The error of an output is

    e = (ROM - FEA) / |FEA|                    forces, stresses, impulse, times
    e = (ROM - FEA) / max(|FEA|, FLOOR_M)      lengths (recovery, ringing, contact side
                                               and patch), FLOOR_M = 5 mm

(a finger that has recovered to 1 um in one model and 0.2 mm in the other has recovered in
both: lengths are compared at the scale of the requirements on them). An output whose
|e| exceeds :data:`TOLERANCE` in any case inside the design space becomes a
:class:`ccedi.design.optimise.ModelError`: its under- and over-prediction at each checked
case (relative, or in metres for lengths), interpolated between the cases over
(ln alpha, L), tighten every requirement on it where the design lands.
"""
import json
from pathlib import Path

import numpy as np

from ccedi.errors import InputError
from ccedi.units import INCH

from .optimise import ModelError
from .outputs import UNITS

TOLERANCE = 0.10
"""Largest |error| an output may show against the FEA without a margin."""

FLOOR_M = 0.005
"""Scale below which a length output's error is taken in absolute terms [m]."""


def output_error(name, rom, fea):
    """The error e of output ``name`` (module docstring); None where either is undefined.

    Parameters
    ----------
    name : str
        Output name (:data:`ccedi.design.outputs.UNITS` tells a length).
    rom, fea : float or None
        The two models' values.

    Returns
    -------
    float or None
    """
    if rom is None or fea is None or not np.isfinite(rom) or not np.isfinite(fea):
        return None
    if UNITS.get(name) == "m":
        return (rom - fea) / max(abs(fea), FLOOR_M)
    return None if fea == 0.0 else (rom - fea) / abs(fea)


def _inside(case, damping, alpha_bounds_per_s, length_bounds_in):
    lo_a, hi_a = alpha_bounds_per_s
    lo_l, hi_l = length_bounds_in
    return (case["damping"] == damping and lo_a * (1 - 1e-9) <= case["alpha_per_s"] <= hi_a * (1 + 1e-9)
            and lo_l - 1e-9 <= case["length_in"] <= hi_l + 1e-9)


def model_errors(cases, *, damping, alpha_bounds_per_s, length_bounds_in, tolerance=TOLERANCE):
    """``{output: ModelError}`` for the outputs whose error exceeds ``tolerance`` in a
    case inside the design space.

    Parameters
    ----------
    cases : list of dict
        ``{"damping", "alpha_per_s", "length_in", "rom": {...}, "fea": {...}}``.
    damping : str
        The design's damping kind.
    alpha_bounds_per_s, length_bounds_in : tuple
        The design space [1/s], [in].
    tolerance : float, optional
        Largest |error| without a margin.

    Returns
    -------
    dict
    """
    inside = [c for c in cases if _inside(c, damping, alpha_bounds_per_s, length_bounds_in)]
    out = {}
    for name in UNITS:
        rows = [c for c in inside if output_error(name, c["rom"].get(name), c["fea"].get(name)) is not None]
        if not rows or max(abs(output_error(name, c["rom"][name], c["fea"][name])) for c in rows) <= tolerance:
            continue
        relative = UNITS[name] != "m"

        def gap(c, sign, relative=relative, name=name):
            d = sign * (c["fea"][name] - c["rom"][name])
            return max(d / abs(c["fea"][name]) if relative else d, 0.0)

        alphas = np.unique([c["alpha_per_s"] for c in rows])
        lengths = np.unique([c["length_in"] for c in rows])
        tables = []
        for sign in (1.0, -1.0):
            table = np.zeros((len(alphas), len(lengths)))
            for j, length in enumerate(lengths):
                own = sorted((c["alpha_per_s"], gap(c, sign)) for c in rows if c["length_in"] == length)
                table[:, j] = np.interp(np.log(alphas), np.log([a for a, _ in own]), [g for _, g in own])
            tables.append(table)
        out[name] = ModelError(alphas, lengths * INCH, under=tables[0], over=tables[1], relative=relative)
    return out


def read_cases(path):
    """The cases of a ROM check file (JSON with a ``cases`` list).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    list of dict

    Raises
    ------
    InputError
        Missing, unreadable or without cases.
    """
    try:
        data = json.loads(Path(path).read_text())
        cases = data["cases"]
    except (OSError, ValueError, KeyError, TypeError) as err:
        raise InputError(f"model error file {path}: not a ROM check JSON with 'cases' ({type(err).__name__})") from None
    return cases
