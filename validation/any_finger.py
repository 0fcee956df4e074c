"""A finger that is not a prism, imported from a Gmsh file, through ccedi and a peer solver.

The tapered finger with a transverse hole of :func:`ccedi.fea.mesh.gmsh_fingers.tapered_finger`
(10-node tetrahedra) at the three sizes of ``TAPERED_REFINEMENT_SIZES`` and at 2 mm
(:data:`SIZES_M`), each written to a
``.msh`` file and read back through the importer, as a user's finger would be:

* ccedi: the Table 1 row (nodes, elements, stable step, nonlinear tip stiffness at 1 and
  2 N, left out at 2 mm for time), the linear tip stiffness and the first natural
  frequency (lumped mass);
* CalculiX 2.20 on the same mesh (C3D10, the same tip weights): linear tip stiffness and
  first frequency (consistent mass);
* with ``--full-fe``, on the coarsest mesh: the explicit impulse response (1 N for 10 ms,
  alpha = 180 1/s) and alpha_cr by the CCEDI bisection on the full FE model beside the
  same search on its 6-mode modal ROM.

Prints and writes validation/any_finger.json, row by row as each size finishes (the
figures of sizes not run this time are kept from the file).

Run: ``.venv/bin/python validation/any_finger.py [--sizes-mm 6 4 3 2] [--full-fe]``.
"""
import argparse
import json
import platform
import sys
import tempfile
import time
from pathlib import Path

from ccedi.fea.cases.studies import finger_impulse_model, table1_row
from ccedi.fea.io.calculix import ccx_version, run_calculix
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh.gmsh_fingers import TAPERED_REFINEMENT_SIZES, write_tapered_finger
from ccedi.fea.mesh.readers import read_finger_mesh
from ccedi.fea.model import cantilever_model, face_node_weights
from ccedi.fea.solvers.static import tip_deflection
from ccedi.outputs import report_figures
from ccedi.rom.finger_identification import finger_alpha_cr
from ccedi.rom.modal import reduce_impulse_model

OUT = Path(__file__).with_suffix(".json")
SIZES_M = TAPERED_REFINEMENT_SIZES + (2e-3,)
"""Element sizes of the refinement study [m]."""
NONLINEAR_MIN_SIZE_M = 3e-3
"""Smallest element size whose nonlinear Table 1 stiffness is solved [m] (a 2 mm mesh has
about 80 000 DOFs, some minutes of sparse direct solves per Newton iteration here)."""


def _relative(a, b):
    return round(100.0 * (a / b - 1.0), 3)


def measure(size_m, directory):
    """ccedi and CalculiX figures of the finger meshed at ``size_m`` [m]."""
    path = Path(directory) / f"tapered_{1e3 * size_m:g}mm.msh"
    cad_volume = write_tapered_finger(path, size_m)
    mesh = read_finger_mesh(path, clamp="clamp", tip="tip")
    model = cantilever_model(mesh, RUBBER)
    row = table1_row(mesh, RUBBER, stiffness=size_m >= NONLINEAR_MIN_SIZE_M, omega1=True)
    k_linear = 1.0 / tip_deflection(model, 1.0, linear=True)
    tip = mesh.node_sets["tip"]
    peer = run_calculix(mesh, RUBBER, n_modes=1, weights=face_node_weights(mesh, tip))
    f1 = row["omega1_rad_s"] / (2.0 * 3.141592653589793)
    return {"size_mm": 1e3 * size_m, **row, "cad_volume_cm3": 1e6 * cad_volume,
            "linear_stiffness_N_per_m": k_linear, "f1_Hz": f1,
            "calculix_linear_stiffness_N_per_m": peer.stiffness_N_per_m,
            "calculix_f1_Hz": float(peer.frequencies_hz[0]),
            "stiffness_vs_calculix_percent": _relative(k_linear, peer.stiffness_N_per_m),
            "f1_vs_calculix_percent": _relative(f1, float(peer.frequencies_hz[0])),
            "calculix_wall_s": round(peer.wall_time_s, 2)}, mesh


def full_fe(mesh):
    """Impulse response and alpha_cr (full FE and modal ROM) of ``mesh``."""
    full = finger_impulse_model(mesh=mesh)
    t0 = time.perf_counter()
    res = full.run(180.0, 0.2, n_outputs=400)
    impulse = {"impulse_alpha_per_s": 180.0, "impulse_peak_tip_uy_m": float(res.history.tip_uy_m.max()),
               "impulse_steps": res.summary["steps"], "impulse_wall_s": round(time.perf_counter() - t0, 1),
               "impulse_warnings": res.summary["warnings"]}
    out = {}
    for name, model in (("rom", reduce_impulse_model(full, n_modes=6)), ("fea", full)):
        t0 = time.perf_counter()
        crit, omega1 = finger_alpha_cr(model=model, mesh=mesh, rtol=0.02)
        out.update({f"alpha_cr_{name}_per_s": crit.alpha_cr_per_s, f"alpha_cr_{name}_runs": crit.n_runs,
                    f"alpha_cr_{name}_wall_s": round(time.perf_counter() - t0, 1)})
    out["two_omega1_per_s"] = 2.0 * omega1
    return {**impulse, **out}


def main(sizes_m=SIZES_M, with_full_fe=False):
    figures = json.loads(OUT.read_text()) if OUT.exists() else {}
    figures.update({"finger": "tapered_finger (Gmsh, 10-node tetrahedra), imported from .msh",
                    "ccx_version": ccx_version(), "python": sys.version.split()[0],
                    "machine": platform.machine()})
    with tempfile.TemporaryDirectory() as tmp:
        meshes = []
        for size in sizes_m:
            t0 = time.perf_counter()
            row, mesh = measure(size, tmp)
            meshes.append(mesh)
            row["row_wall_s"] = round(time.perf_counter() - t0, 1)
            figures.update({f"{row['size_mm']:g}mm_{k}": v for k, v in row.items() if k != "size_mm"})
            report_figures(figures, OUT)
        if with_full_fe:
            figures.update({f"{1e3 * sizes_m[0]:g}mm_{k}": v
                            for k, v in full_fe(meshes[0]).items()})
            report_figures(figures, OUT)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes-mm", type=float, nargs="+", default=[1e3 * s for s in SIZES_M],
                        help="element sizes to (re-)measure [mm]; the other sizes' figures stay in the JSON")
    parser.add_argument("--full-fe", action="store_true",
                        help="also the explicit impulse and alpha_cr runs, on the first size given")
    args = parser.parse_args()
    main(tuple(1e-3 * s for s in args.sizes_mm), args.full_fe)
