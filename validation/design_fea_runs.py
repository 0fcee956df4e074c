"""Full-FEA drum runs for the design's ROM check, cached as histories.

The design's outputs are computed from a run's history (:func:`ccedi.design.objectives.design_outputs`),
so the expensive part, the full explicit FE runs, is done once and kept: every case of
:data:`CASES` (finger length x alpha x damping kind) is run with
:class:`ccedi.fea.contact.drum.FullContactModel` (no per-output object stress: the design computes
its own) for :data:`T_END_S` at :data:`OUTPUT_STEP_S`, and its history written to
``validation/cache/design_fea/L{L}_a{alpha}_{kind}.csv.gz`` with a JSON sidecar (summary,
wall time). ``validation/design_rom_check.py`` reads them.

Run: ``NUMBA_NUM_THREADS=1 .venv/bin/python validation/design_fea_runs.py [global|relative ...]``
(one process per damping kind uses one core each; ~25 min per kind on the 2-core AMD VM).
"""
import json
import sys
import time
from pathlib import Path

from ccedi.design.rubber import alpha_cr_of_length
from ccedi.fea.contact.drum import DrumSetup, FullContactModel
from ccedi.units import inch_to_m

CACHE = Path(__file__).parent / "cache" / "design_fea"
LENGTHS_IN = (8.0, 5.0, 3.0)
T_END_S = 2.2
"""Simulated time [s]: the latest first contact in the check (~0.6 s) plus the default cycle (1.5 s)."""
OUTPUT_STEP_S = 0.0005
"""Output interval [s] (resolves the FE finger's ~400 Hz friction chatter before the transducer filters it)."""


def alphas(length_in):
    """The checked alphas [1/s] at ``length_in``: 3, 7.5, about alpha_cr, 180, 600."""
    return (3.0, 7.5, round(alpha_cr_of_length(length_in), 1), 180.0, 600.0)


def case_path(length_in, alpha, kind):
    """History file of one case."""
    return CACHE / f"L{length_in:g}_a{alpha:g}_{kind}.csv.gz"


def cases(kinds=("global", "relative")):
    """Every (length_in, alpha, kind) of the check."""
    return [(L, a, k) for k in kinds for L in LENGTHS_IN for a in alphas(L)]


def run_case(length_in, alpha, kind):
    """Run one case (or read it when cached); returns the history path."""
    path = case_path(length_in, alpha, kind)
    if path.exists() and path.with_suffix(".json").exists():
        return path
    setup = DrumSetup(finger_length_m=inch_to_m(length_in))
    t0 = time.perf_counter()
    res = FullContactModel(setup, object_stress=False).run(alpha, damping=kind, t_end_s=T_END_S,
                                                           n_outputs=int(round(T_END_S / OUTPUT_STEP_S)))
    wall = time.perf_counter() - t0
    CACHE.mkdir(parents=True, exist_ok=True)
    res.history.to_csv(path, index=False)
    summary = {k: v for k, v in res.summary.items() if k != "warnings"} | {"warnings": list(res.summary["warnings"])}
    path.with_suffix(".json").write_text(json.dumps({"summary": summary, "wall_time_s": wall}, indent=1, default=str))
    print(f"L {length_in:g} in, alpha {alpha:g} 1/s, {kind}: {wall:.0f} s", flush=True)
    return path


if __name__ == "__main__":
    for case in cases(tuple(sys.argv[1:]) or ("global", "relative")):
        run_case(*case)
