"""Speed of the explicit solver.

SM-A 4.5-in finger, 1 N tip impulse for 10 ms, alpha = 180 1/s, 0.2 s simulated, one core.
Prints and writes to benchmarks/fea_speed.json: wall time [s], steps, and nanoseconds per
element-cycle for the whole run and for the internal-force kernel alone. Target: < 100 ns.

Run: ``make bench`` or ``.venv/bin/python benchmarks/fea_speed.py``.
"""
import os
import platform
import sys
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from _output import report  # noqa: E402  (benchmarks/ is on sys.path when run as a script)

from ccedi.fea.explicit import run  # noqa: E402
from ccedi.fea.kernels import internal_forces_numba  # noqa: E402
from ccedi.fea.material import RUBBER  # noqa: E402
from ccedi.fea.mesh import sm_a  # noqa: E402
from ccedi.fea.model import cantilever_model, tip_pulse  # noqa: E402

OUT = Path(__file__).with_suffix(".json")


def kernel_ns_per_element(model, repeats=2000):
    g, mat = model.geometry, model.material
    x = model.mesh.nodes.copy()
    v = np.zeros_like(x)
    f = np.zeros_like(x)
    args = (x, v, model.mesh.hexes, g.b, g.volume, g.gamma, model.kappa, model.hex_length_factor, mat.mu, mat.lam,
            mat.rho, mat.wave_speed, f)
    internal_forces_numba(*args)
    t0 = time.perf_counter()
    for _ in range(repeats):
        internal_forces_numba(*args)
    return 1e9 * (time.perf_counter() - t0) / (repeats * model.mesh.n_elements)


def main():
    mesh = sm_a(length_in=4.5)
    model = cantilever_model(mesh, RUBBER, alpha=180.0, pulses=[tip_pulse(mesh, [0.0, 1.0, 0.0], 0.01)])
    run(model, 1e-3, n_outputs=1)                       # compile (numba cache) outside the timing
    best = None
    for _ in range(3):
        res = run(model, 0.2, n_outputs=400)
        if best is None or res.summary["wall_time_s"] < best.summary["wall_time_s"]:
            best = res
    s = best.summary
    figures = {
        "model": "SM-A 4.5 in, 725 hex8, alpha 180 1/s, 0.2 s",
        "wall_time_s": round(s["wall_time_s"], 3),
        "steps": s["steps"],
        "elements": s["elements"],
        "ns_per_element_cycle": round(s["ns_per_element_cycle"], 1),
        "kernel_ns_per_element": round(kernel_ns_per_element(model), 1),
        "target_ns_per_element_cycle": 100.0,
        "best_of": 3,
        "python": sys.version.split()[0],
        "machine": platform.machine(),
        "processor": platform.processor() or platform.machine(),
    }
    report(figures, OUT)


if __name__ == "__main__":
    main()
