"""SM-C's stable step against element estimates of paper Eq. (6), and against Table 1's 1.26 us.

ccedi's step for 10-node tetrahedra is the real limit of central differences on the mesh
at rest (2 / omega_max, :func:`ccedi.fea.elements.tetra.time_step_length_factors`), reported x 0.9
(TSSFAC) in Table 1: 1.616 us on the Gmsh SM-C against the paper's 1.26 us (+28 %). This
script measures, on the same mesh (:func:`ccedi.fea.mesh.gmsh_fingers.sm_c`, nu = 0.49):

* the real limit (ccedi's step at rest) and two element estimates of Eq. (6),
  ``dt = L_e / c``: L_e = the smallest corner altitude h_min (the 4-node rule), and
  L_e = h_min / 2 (the altitude of the 8 sub-tetrahedra of a 10-node element, whose
  nodes are half as far apart), each x 0.9 against Table 1's 1.26 us;
* undamped central differences from small random velocities (the 1.3 x check of
  ``tests/unit/fea/test_tet4.py``, 4000 steps) at 1.3 x the half-altitude estimate and at 1.02 x
  the real limit: whether each diverges, and at which step.

Prints and writes validation/smc_step.json. Run: ``.venv/bin/python validation/smc_step.py``
(a few minutes).
"""
import platform
import time
from pathlib import Path

import numpy as np

from ccedi.fea.cases.studies import PAPER_TABLE1
from ccedi.fea.elements import tet10
from ccedi.fea.elements.tetra import min_altitude
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh.gmsh_fingers import sm_c
from ccedi.fea.model import cantilever_model
from ccedi.fea.solvers.explicit import TSSFAC, SolidMaterial, critical_time_step
from ccedi.outputs import report_figures

OUT = Path(__file__).with_suffix(".json")
STEPS = 4000


def divergence_step(model, dt, steps=STEPS):
    """First step at which undamped central differences from 1 mm/s random velocities move
    a node by 1 cm (blown up), or -1 when bounded for ``steps`` steps."""
    X = model.mesh.nodes
    free = np.ones(len(X))
    free[model.fixed_nodes] = 0.0
    v = 1e-3 * np.random.default_rng(0).standard_normal(X.shape) * free[:, None]
    x, f = X.copy(), np.zeros_like(X)
    material = SolidMaterial(*model.solid_constants)
    for n in range(steps):
        f[:] = 0.0
        tet10.internal_forces_numba(x, v, model.tet10, material, f)
        v -= dt * f / model.mass[:, None] * free[:, None]
        x += dt * v
        if not np.abs(x - X).max() < 1e-2:
            return n
    return -1


def main():
    mesh = sm_c()
    model = cantilever_model(mesh, RUBBER)
    c = RUBBER.wave_speed
    h_min = float(min_altitude(mesh.nodes[mesh.tets10[:, :4]]).min())
    limit = critical_time_step(model)
    paper = PAPER_TABLE1["SM-C"]["dt_us"]
    fig = {"mesh": "sm_c() (Gmsh, 10-node tetrahedra, 4 mm)", "nodes": mesh.n_nodes, "elements": mesh.n_elements,
           "wave_speed_m_s": c, "min_altitude_mm": 1e3 * h_min, "paper_dt_us": paper,
           "limit_us": 1e6 * limit, "table1_dt_us": 1e6 * TSSFAC * limit}
    for name, length in (("altitude", h_min), ("half_altitude", h_min / 2)):
        estimate = length / c
        fig |= {f"{name}_estimate_us": 1e6 * estimate, f"{name}_estimate_over_limit": estimate / limit,
                f"{name}_table1_dt_us": 1e6 * TSSFAC * estimate,
                f"{name}_vs_paper_percent": round(100 * (1e6 * TSSFAC * estimate / paper - 1), 2)}
    fig["table1_dt_vs_paper_percent"] = round(100 * (1e6 * TSSFAC * limit / paper - 1), 2)
    for name, dt in (("1.3_half_altitude", 1.3 * h_min / 2 / c), ("1.02_limit", 1.02 * limit)):
        t0 = time.perf_counter()
        fig |= {f"{name}_dt_us": 1e6 * dt, f"{name}_diverged_at_step": divergence_step(model, dt),
                f"{name}_wall_s": round(time.perf_counter() - t0, 1)}
    fig |= {"steps_checked": STEPS, "python": platform.python_version(), "machine": platform.machine()}
    report_figures(fig, OUT)


if __name__ == "__main__":
    main()
