"""Speed of the explicit solver, on one and on two threads.

SM-A 4.5-in finger, 1 N tip impulse for 10 ms, alpha = 180 1/s, 0.2 s simulated. The
whole run is timed best of 3 on one thread and on two (``run(..., threads=N)``), the two
interleaved so that a busy machine slows both alike; the internal-force kernel alone is
timed as the best of many short batches (which filters out the moments the process was
not running). The same run on the pure-numpy reference path (``backend="numpy"``, once,
untimed) gives the tip history the compiled one is compared with: the largest difference
relative to the reference's peak (target: 1e-9). Prints and writes to
benchmarks/fea_speed.json: wall time [s], steps, nanoseconds per element-cycle for the
whole run and for the kernel alone, on 1 and 2 threads, that difference, and the load
average (``os.getloadavg``) before and after: on a machine shared with other jobs the run
figures are upper bounds. Target: < 100 ns per element-cycle on one thread.

Run: ``make bench`` or ``.venv/bin/python benchmarks/fea_speed.py``.
"""
import os
import platform
import sys
import time
from pathlib import Path

import numba as nb
import numpy as np

from ccedi.fea.elements.hex8_kernels import internal_forces_numba  # noqa: E402
from ccedi.fea.material import RUBBER  # noqa: E402
from ccedi.fea.mesh import sm_a  # noqa: E402
from ccedi.fea.model import cantilever_model, tip_pulse  # noqa: E402
from ccedi.fea.solvers.explicit import SolidMaterial, run  # noqa: E402
from ccedi.outputs import report_figures  # noqa: E402

OUT = Path(__file__).with_suffix(".json")
THREADS = (1, 2)


def kernel_ns_per_element(model, threads, batches=400, calls=5):
    """Internal-force kernel alone at a perturbed state, best of ``batches`` batches of
    ``calls`` calls [ns per element]."""
    rng = np.random.default_rng(0)
    x = model.mesh.nodes + 1e-4 * rng.standard_normal(model.mesh.nodes.shape)
    v = 0.1 * rng.standard_normal(x.shape)
    f = np.zeros_like(x)
    material = SolidMaterial(*model.solid_constants)
    nb.set_num_threads(threads)
    internal_forces_numba(x, v, model.hexahedra, material, f)
    best = np.inf
    for _ in range(batches):
        t0 = time.perf_counter()
        for _ in range(calls):
            internal_forces_numba(x, v, model.hexahedra, material, f)
        best = min(best, (time.perf_counter() - t0) / calls)
    return 1e9 * best / model.mesh.n_elements


def tip_difference(compiled, reference):
    """Largest |difference| of the two runs' tip deflection histories over the reference's
    largest |deflection| [-]."""
    a = compiled.history["tip_uy_m"].to_numpy()
    b = reference.history["tip_uy_m"].to_numpy()
    if a.shape != b.shape:
        raise ValueError(f"the runs' histories have {a.shape[0]} and {b.shape[0]} samples; expected the same")
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def main():
    mesh = sm_a(length_in=4.5)
    model = cantilever_model(mesh, RUBBER, alpha=180.0, pulses=[tip_pulse(mesh, [0.0, 1.0, 0.0], 0.01)])
    threads = [n for n in THREADS if n <= nb.config.NUMBA_NUM_THREADS]
    for n in threads:
        run(model, 1e-3, n_outputs=1, threads=n)        # compile (numba cache) outside the timing
    load_before = os.getloadavg()[0]
    best = {}
    for _ in range(3):
        for n in threads:
            res = run(model, 0.2, n_outputs=400, threads=n)
            if n not in best or res.summary["wall_time_s"] < best[n].summary["wall_time_s"]:
                best[n] = res
    kernel = {n: kernel_ns_per_element(model, n) for n in threads}
    reference = run(model, 0.2, n_outputs=400, backend="numpy")
    s = best[1].summary
    figures = {
        "model": "SM-A 4.5 in, 725 hex8, alpha 180 1/s, 0.2 s",
        "steps": s["steps"],
        "elements": s["elements"],
        "target_ns_per_element_cycle": 100.0,
        "best_of": 3,
    }
    for n in threads:
        figures[f"wall_time_s_{n}_threads"] = round(best[n].summary["wall_time_s"], 3)
        figures[f"ns_per_element_cycle_{n}_threads"] = round(best[n].summary["ns_per_element_cycle"], 1)
        figures[f"kernel_ns_per_element_{n}_threads"] = round(kernel[n], 1)
    figures["tip_history_difference_to_numpy_reference"] = float(f"{tip_difference(best[1], reference):.3g}")
    figures["target_tip_history_difference"] = 1e-9
    if 2 in best:
        figures["speedup_2_threads"] = round(s["wall_time_s"] / best[2].summary["wall_time_s"], 2)
        figures["same_tip_history_1_and_2_threads"] = bool(best[1].history["tip_uy_m"].equals(
            best[2].history["tip_uy_m"]))
    figures.update({
        "load_average_before": round(load_before, 2),
        "load_average_after": round(os.getloadavg()[0], 2),
        "cores": os.cpu_count(),
        "python": sys.version.split()[0],
        "machine": platform.machine(),
        "processor": platform.processor() or platform.machine(),
    })
    report_figures(figures, OUT)


if __name__ == "__main__":
    main()
