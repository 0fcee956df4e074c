"""Cost of the three solid elements in one run: one-point hexahedron, 4-node tetrahedron
(averaged nodal pressure) and 10-node tetrahedron (mean dilatation), one core.

The same geometry for all three: SM-A of the 4.5-in finger (725 hexahedra), each
hexahedron split into 6 tetrahedra (4350 tet4), and those made quadratic (4350 tet10).
Each model runs the paper's impulse (1 N for 10 ms, alpha = 180 1/s) for a fixed number
of steps, best of 3; the internal-force kernel is also timed alone. Prints and writes
benchmarks/tet_speed.json: nanoseconds per element-cycle (whole step loop, and the
element kernel alone), stable step and cost per simulated second. For reference,
OpenRadioss's published per-element costs are about 165 ns (tet4) and 676 ns (tet10) for
the element routines alone, plus the material.

Run: ``.venv/bin/python benchmarks/tet_speed.py``.
"""
import os
import platform
import sys
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from ccedi.fea.elements import tet4, tet10  # noqa: E402
from ccedi.fea.elements.hex8_kernels import internal_forces_numba  # noqa: E402
from ccedi.fea.material import RUBBER  # noqa: E402
from ccedi.fea.mesh import sm_a  # noqa: E402
from ccedi.fea.mesh.tet_mesh import quadratic_tets, split_hexes  # noqa: E402
from ccedi.fea.model import cantilever_model, tip_pulse  # noqa: E402
from ccedi.fea.solvers.explicit import TSSFAC, SolidMaterial, critical_time_step, run  # noqa: E402
from ccedi.outputs import report_figures  # noqa: E402

OUT = Path(__file__).with_suffix(".json")
STEPS = 4000
"""Steps per timed run."""


def _kernel_call(model):
    """A closure that evaluates the model's element kernel once at its reference state."""
    x = model.mesh.nodes.copy()
    v = np.zeros_like(x)
    f = np.zeros_like(x)
    kind = model.mesh.element_type
    material = SolidMaterial(*model.solid_constants)
    if kind == "hex8":
        return lambda: internal_forces_numba(x, v, model.hexahedra, material, f)
    kernel, group = (tet4.internal_forces_numba, model.tet4) if kind == "tet4" else \
        (tet10.internal_forces_numba, model.tet10)
    return lambda: kernel(x, v, group, material, f)


def kernel_ns_per_element(model, repeats=300):
    """Best of 3 of the element kernel alone [ns per element]."""
    call = _kernel_call(model)
    call()
    best = np.inf
    for _ in range(3):
        t0 = time.perf_counter()
        for _ in range(repeats):
            call()
        best = min(best, (time.perf_counter() - t0) / repeats)
    return 1e9 * best / model.mesh.n_elements


def measure(name, mesh):
    """Whole-run and kernel figures of one mesh."""
    model = cantilever_model(mesh, RUBBER, alpha=180.0, pulses=[tip_pulse(mesh, [0.0, 1.0, 0.0], 0.01)])
    dt = TSSFAC * critical_time_step(model)
    run(model, 10 * dt, n_outputs=1)                    # compile outside the timing
    best = min((run(model, STEPS * dt, n_outputs=20) for _ in range(3)), key=lambda r: r.summary["wall_time_s"])
    s = best.summary
    ns = s["ns_per_element_cycle"]
    return {f"{name}_elements": mesh.n_elements, f"{name}_nodes": mesh.n_nodes,
            f"{name}_dt_us": round(1e6 * dt, 4), f"{name}_steps": s["steps"],
            f"{name}_ns_per_element_cycle": round(ns, 1),
            f"{name}_kernel_ns_per_element": round(kernel_ns_per_element(model), 1),
            f"{name}_wall_s_per_simulated_s": round(s["wall_time_s"] / s["t_final_s"], 1)}


def main():
    hexes = sm_a(length_in=4.5)
    tets = split_hexes(hexes)
    figures = {"geometry": "SM-A 4.5 in; tet4 = each hexahedron split in 6; tet10 = those made quadratic",
               "load": "1 N tip pulse for 10 ms, alpha 180 1/s", "steps_per_run": STEPS, "best_of": 3}
    for name, mesh in (("hex8", hexes), ("tet4", tets), ("tet10", quadratic_tets(tets))):
        figures.update(measure(name, mesh))
    figures.update({"openradioss_tet4_element_ns": 165.0, "openradioss_tet10_element_ns": 676.0,
                    "python": sys.version.split()[0], "machine": platform.machine(),
                    "processor": platform.processor() or platform.machine()})
    report_figures(figures, OUT)


if __name__ == "__main__":
    main()
