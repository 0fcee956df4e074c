"""Speed of a user-like finger with slivers, with and without mass scaling.

The finger: data/fingers/tapered_two_holes.geo (a Gmsh script: an elliptical section
tapering from root to tip, two transverse holes; 10-node tetrahedra), the paper's rubber,
alpha = 180 1/s, a 1 N tip pulse along y for 10 ms. Reported: the element that sets the
stable step (where, how small, against the median element), the mass scaling's figures
(``mass_scaled(model, dt_target_s="auto")``: target step, elements scaled, mass added,
the first three natural frequencies before and after), and the impulse run of
``--t-end-s`` seconds (default 0.02; the paper's runs are 0.2 s: ``--t-end-s 0.2``) on
both models, side by side, best of ``--repeat``: wall time, steps, the speed-up, and
the tip deflection's largest difference over its peak. Writes
benchmarks/mass_scaling_speed.json.

Run: ``.venv/bin/python benchmarks/mass_scaling_speed.py [--t-end-s 0.2] [--repeat 2]``.
"""
import argparse
import os
import time
from pathlib import Path

import numpy as np

from ccedi.fea.material import RUBBER
from ccedi.fea.mesh.readers import read_finger_mesh
from ccedi.fea.model import cantilever_model, tip_pulse
from ccedi.fea.solvers.explicit import limiting_element, run
from ccedi.fea.solvers.mass_scaling import mass_scaled
from ccedi.outputs import report_figures

ROOT = Path(__file__).resolve().parents[1]
FINGER = ROOT / "data" / "fingers" / "tapered_two_holes.geo"
OUT = Path(__file__).with_suffix(".json")


def best_run(model, t_end_s, repeat):
    """The fastest of ``repeat`` runs (the results are the same each time)."""
    best = None
    for _ in range(repeat):
        res = run(model, t_end_s, n_outputs=200, threads=1)
        if best is None or res.summary["wall_time_s"] < best.summary["wall_time_s"]:
            best = res
    return best


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end-s", type=float, default=0.02, help="impulse run length [s] (default 0.02)")
    parser.add_argument("--repeat", type=int, default=1, help="runs of each model, the best kept (default 1)")
    args = parser.parse_args()
    t0 = time.perf_counter()
    mesh = read_finger_mesh(FINGER)
    mesh_s = time.perf_counter() - t0
    model = cantilever_model(mesh, RUBBER, alpha=180.0, pulses=[tip_pulse(mesh, [0.0, 1.0, 0.0], 0.01)])
    e = limiting_element(model)
    t0 = time.perf_counter()
    scaled, report = mass_scaled(model)
    scaling_s = time.perf_counter() - t0
    run(model, 1e-4, n_outputs=1, threads=1)                    # compile outside the timing
    plain = best_run(model, args.t_end_s, args.repeat)
    fast = best_run(scaled, args.t_end_s, args.repeat)
    y0, y1 = plain.history["tip_uy_m"].to_numpy(), fast.history["tip_uy_m"].to_numpy()
    figures = {
        "finger": FINGER.relative_to(ROOT).as_posix(),
        "elements": mesh.n_elements, "nodes": mesh.n_nodes, "element_type": mesh.element_type,
        "meshing_s": round(mesh_s, 2),
        "step_limiting_element": e["element"],
        "step_limiting_element_centroid_mm": [round(float(1e3 * c), 3) for c in e["centroid_m"]],
        "step_limiting_element_length_mm": round(1e3 * e["length_m"], 4),
        "median_element_length_mm": round(1e3 * e["median_length_m"], 4),
        **{k: (round(v, 9) if isinstance(v, float) else v) for k, v in report.summary().items()},
        "mass_scaling_wall_s": round(scaling_s, 2),
        "t_end_s": args.t_end_s,
        "best_of": args.repeat,
        "steps_plain": plain.summary["steps"], "steps_scaled": fast.summary["steps"],
        "wall_time_s_plain": round(plain.summary["wall_time_s"], 3),
        "wall_time_s_scaled": round(fast.summary["wall_time_s"], 3),
        "speedup": round(plain.summary["wall_time_s"] / fast.summary["wall_time_s"], 3),
        "tip_difference_over_peak": float(f"{np.abs(y0 - y1).max() / np.abs(y0).max():.3g}"),
        "load_average_after": round(os.getloadavg()[0], 2),
        "cores": os.cpu_count(),
    }
    report_figures(figures, OUT)


if __name__ == "__main__":
    main()
