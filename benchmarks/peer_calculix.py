"""ccedi against a peer explicit solver, CalculiX, on the paper's impulse case, in one run.

SM-A of the 4.5-in finger (725 hexahedra, the mesh ccedi runs), E = 6.1 MPa, nu = 0.49,
rho = 1000 kg/m^3, root clamped, 1 N along y over the tip face for 10 ms, mass-
proportional damping alpha = 180 1/s. ccedi runs it (one thread, compiled kernels, its
own stable step), then CalculiX 2.20 (``*DYNAMIC, EXPLICIT`` with C3D8R on the same mesh,
``*DAMPING, ALPHA=180``, NLGEOM, the linear elastic material ccedi's neo-Hookean reduces
to at small strain, its own stable increment; :func:`ccedi.fea.io.calculix.calculix_impulse_deck`).
CalculiX 2.20's C3D8R hourglass vectors are defective (``shape8hr.f``, replaced upstream in
2025): this compares speed; accuracy is compared with its C3D20R/C3D8I implicit runs in
``validation/peer_reference.py``. The tip histories are still compared (the weighted tip
deflection along y, interpolated on CalculiX's output times).

Prints and writes benchmarks/peer_calculix.json: wall time, steps and ns per
element-cycle of each, the ratios per element-cycle and per simulated second, and the
tip-displacement difference (peak and RMS over the run, relative to ccedi's peak).

Run: ``.venv/bin/python benchmarks/peer_calculix.py [--t-end-s 0.2]`` (CalculiX: about
10^5 increments for 0.2 s, minutes). Needs ``ccx`` on the PATH (Debian/Ubuntu:
``apt-get install calculix-ccx``); the script installs nothing.
"""
import argparse
import os
import platform
import sys
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from ccedi.errors import SolverError  # noqa: E402
from ccedi.fea.cases.studies import impulse_model  # noqa: E402
from ccedi.fea.io.calculix import (  # noqa: E402
    CCX_INSTALL_HINT,
    calculix_impulse_deck,
    ccx_executable,
    ccx_version,
    parse_tip_history,
    run_ccx,
)
from ccedi.fea.material import RUBBER  # noqa: E402
from ccedi.fea.solvers.explicit import run  # noqa: E402
from ccedi.outputs import report_figures  # noqa: E402

OUT = Path(__file__).with_suffix(".json")
ALPHA = 180.0
FORCE_N, DURATION_S = 1.0, 0.01
CCX_OUTPUT_EVERY = 200
"""CalculiX increments between tip outputs (about 0.4 ms)."""


def ccedi_run(t_end_s):
    """ccedi's run: (time [s], tip deflection [m], summary) of the SM-A impulse."""
    model = impulse_model(4.5, alpha=ALPHA, force_N=FORCE_N, duration_s=DURATION_S)
    run(model, 2e-3, n_outputs=2)                                   # compile outside the timing
    res = run(model, t_end_s, n_outputs=2000)
    return res.history.time_s.to_numpy(), res.history.tip_uy_m.to_numpy(), res.summary, model


def calculix_run(model, t_end_s):
    """CalculiX's run: (time [s], tip deflection [m], wall [s], increments)."""
    deck = calculix_impulse_deck(model.mesh, RUBBER, ALPHA, force_N=FORCE_N, duration_s=DURATION_S, t_end_s=t_end_s,
                                 output_every=CCX_OUTPUT_EVERY)
    outputs, wall = run_ccx(deck.text)
    t, u = parse_tip_history(outputs["dat"], deck.tip_ids, deck.tip_weights)
    increments = int(round(t_end_s / ((t[-1] - t[0]) / (CCX_OUTPUT_EVERY * (len(t) - 1)))))
    return t, u, wall, increments


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end-s", type=float, default=0.2, help="simulated time [s] (default 0.2)")
    t_end_s = parser.parse_args().t_end_s
    try:
        ccx_executable()
    except SolverError:
        sys.exit(f"peer_calculix: ccx not found; {CCX_INSTALL_HINT}")
    t, u, summary, model = ccedi_run(t_end_s)
    n_el = model.mesh.n_elements
    print(f"ccedi: {summary['steps']} steps, {summary['wall_time_s']:.2f} s", flush=True)
    t_ccx, u_ccx, wall_ccx, inc_ccx = calculix_run(model, t_end_s)
    ns_ccedi = summary["ns_per_element_cycle"]
    ns_ccx = 1e9 * wall_ccx / (inc_ccx * n_el)
    u_on_ccx = np.interp(t_ccx, t, u)
    peak = np.abs(u).max()
    figures = {
        "case": f"SM-A 4.5 in, {n_el} hexahedra, alpha {ALPHA:g} 1/s, {FORCE_N:g} N for {1e3 * DURATION_S:g} ms, "
                f"{t_end_s:g} s simulated, one thread each",
        "ccx_version": ccx_version(),
        "ccedi_wall_s": round(summary["wall_time_s"], 3), "ccedi_steps": summary["steps"],
        "ccedi_dt_us": round(1e6 * summary["dt_initial_s"], 4), "ccedi_ns_per_element_cycle": round(ns_ccedi, 1),
        "calculix_wall_s": round(wall_ccx, 2), "calculix_increments": inc_ccx,
        "calculix_dt_us": round(1e6 * t_end_s / inc_ccx, 4),
        "calculix_ns_per_element_cycle": round(ns_ccx, 1),
        "speedup_per_element_cycle": round(ns_ccx / ns_ccedi, 2),
        "speedup_per_simulated_second": round(wall_ccx / summary["wall_time_s"], 2),
        "ccedi_tip_peak_mm": round(1e3 * peak, 4), "calculix_tip_peak_mm": round(1e3 * np.abs(u_ccx).max(), 4),
        "tip_peak_difference_percent": round(100 * (np.abs(u_ccx).max() / peak - 1), 3),
        "tip_rms_difference_percent_of_peak": round(100 * np.sqrt(np.mean((u_ccx - u_on_ccx) ** 2)) / peak, 3),
        "load_average_1min_at_end": round(os.getloadavg()[0], 2),
        "python": sys.version.split()[0], "machine": platform.machine(),
    }
    report_figures(figures, OUT)


if __name__ == "__main__":
    main()
