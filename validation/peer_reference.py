"""Peer-solver reference of the finger: CalculiX on ccedi's meshes, refined until converged.

The 4.5-in finger of the paper (rubber E = 6.1 MPa, nu = 0.49, rho = 1000 kg/m^3), root
clamped, 1 N along y spread over the tip face (:func:`ccedi.fea.io.calculix.tip_weights`).
For each mesh CalculiX 2.20 gives the linear tip stiffness F / delta and the first natural
frequency f1 (consistent mass):

(i)   SM-A, each hexahedron split n x n x n (trilinear map, so the polygonal geometry of
      SM-A is kept), written as C3D20R (hex8 -> hex20, mid-edge nodes at edge midpoints) and
      C3D8I; n = 1, 2, 3;
(ii)  SM-B the same (n = 1, 2);
      C3D20R meshes of more than BIG_C3D20R hexahedra only with ``--big``;
(iii) 10-node tetrahedra as C3D10: SM-A's hexahedra each split into six (Kuhn) tetrahedra
      (:mod:`ccedi.fea.mesh.tet_mesh`), and SM-C, the Gmsh mesh of the elliptical prism (curved
      surface, :func:`ccedi.fea.mesh.gmsh_fingers.sm_c`) at 4 mm and 2 mm average length.

A finger that is not a prism is compared with CalculiX mesh for mesh in
validation/any_finger.py.

Prints a table and writes validation/peer_reference.json (wall times of the ccx runs, one
thread, and the ccx version).

Run: ``.venv/bin/python validation/peer_reference.py [--quick] [--big]`` (``--quick``:
n = 1 and 2 of SM-A only, about 100 s).
"""
import json
import platform
import sys
import time
from pathlib import Path

import numpy as np

from ccedi.fea.io.calculix import ccx_version, run_calculix
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import refine_hexes, sm_a, sm_b
from ccedi.fea.mesh.gmsh_fingers import sm_c
from ccedi.fea.mesh.tet_mesh import quadratic_tets, split_hexes

OUT = Path(__file__).with_suffix(".json")
LENGTH_IN = 4.5
N_MODES = 2
BIG_C3D20R = 10000
"""Hexahedra above which C3D20R runs only with ``--big`` (SPOOLES on one thread: SM-A split
2x2x2, 5800 hexahedra, takes about 80 s; 3x3x3 would take many minutes)."""

def measure(label, mesh, hex_element=None, series=None, refinement=1.0):
    """One CalculiX run: linear tip stiffness and f1, with sizes and wall time; ``series``
    and ``refinement`` place it in a refinement sequence (:func:`richardson`)."""
    t0 = time.perf_counter()
    r = run_calculix(mesh, RUBBER, force_N=1.0, direction=1, n_modes=N_MODES, hex_element=hex_element or "C3D20R")
    row = {"model": label, "element": r.element_type, "series": f"{series or label} {r.element_type}",
           "refinement": round(refinement, 4), "nodes": r.n_nodes, "elements": r.n_elements,
           "dofs": 3 * r.n_nodes, "stiffness_N_per_m": round(r.stiffness_N_per_m, 4),
           "f1_hz": round(float(r.frequencies_hz[0]), 5), "omega1_rad_s": round(float(r.omega_rad_s[0]), 4),
           "f2_hz": round(float(r.frequencies_hz[1]), 5), "ccx_wall_time_s": round(r.wall_time_s, 2),
           "total_wall_time_s": round(time.perf_counter() - t0, 2)}
    print(f"{label:34s} {row['element']:7s} {row['nodes']:7d} {row['elements']:6d} "
          f"{row['stiffness_N_per_m']:9.3f} {row['f1_hz']:9.4f} {row['ccx_wall_time_s']:8.1f}", flush=True)
    return row


def richardson(rows):
    """For each series refined three times (hexahedra split 1x, 2x, 3x):
    the observed convergence order p of k(r) = k_inf + c r^-p (r the refinement factor: the
    split n, or 4 mm / size; from the three stiffnesses) and the extrapolated stiffness and
    f1 at that order."""
    from scipy.optimize import brentq
    series = {}
    for row in rows:
        series.setdefault(row["series"], []).append(row)
    result = {}
    for key, runs in series.items():
        if len(runs) != 3:
            continue
        r = np.array([run["refinement"] for run in runs])
        k = np.array([run["stiffness_N_per_m"] for run in runs])
        f = np.array([run["f1_hz"] for run in runs])
        ratio = (k[0] - k[1]) / (k[1] - k[2])
        try:
            p = brentq(lambda q: (r[0]**-q - r[1]**-q) / (r[1]**-q - r[2]**-q) - ratio, 0.2, 12.0)
        except ValueError:                       # not monotone: no order to observe
            continue
        scale = r[2]**-p / (r[1]**-p - r[2]**-p)
        result[key] = {"observed_order": round(p, 2),
                       "stiffness_N_per_m": round(k[2] - (k[1] - k[2]) * scale, 3),
                       "f1_hz": round(f[2] - (f[1] - f[2]) * scale, 4)}
    return result


def main(quick=False, big=False):
    print(f"{'model':34s} {'element':7s} {'nodes':>7s} {'elem':>6s} {'k [N/m]':>9s} {'f1 [Hz]':>9s} {'ccx [s]':>8s}")
    rows = []
    for name, base, splits in (("SM-A", sm_a(length_in=LENGTH_IN), (1, 2) if quick else (1, 2, 3)),
                               ("SM-B", sm_b(length_in=LENGTH_IN), () if quick else (1, 2))):
        for n in splits:
            mesh = refine_hexes(base, n)
            for element in ("C3D20R", "C3D8I"):
                if element == "C3D20R" and mesh.n_elements > BIG_C3D20R and not big:
                    continue
                rows.append(measure(f"{name} split {n}x{n}x{n}", mesh, element, name, n))
    if not quick:
        rows.append(measure("SM-A Kuhn 6 tets per hex", quadratic_tets(split_hexes(sm_a(length_in=LENGTH_IN)))))
        for size_mm in (4.0, 2.0):
            rows.append(measure(f"SM-C (Gmsh elliptical prism) {size_mm:g} mm",
                                sm_c(length_in=LENGTH_IN, element_size_m=1e-3 * size_mm)))
    figures = {"finger": f"{LENGTH_IN} in elliptical prism, E 6.1 MPa, nu 0.49, rho 1000 kg/m^3, "
                         f"1 N along y over the tip face, root clamped",
               "solver": f"CalculiX {ccx_version()} (linear static + *FREQUENCY, consistent mass), 1 thread",
               "machine": f"{platform.machine()} {platform.python_implementation()} {platform.python_version()}",
               "note": "ccx wall times are of one thread on a shared 2-core machine (other jobs running)",
               "rows": rows, "extrapolated": richardson(rows)}
    OUT.write_text(json.dumps(figures, indent=2) + "\n")
    for key, value in figures["extrapolated"].items():
        print(f"{key} extrapolated (order {value['observed_order']}): k = {value['stiffness_N_per_m']} N/m, "
              f"f1 = {value['f1_hz']} Hz")
    print(f"wrote {OUT}")
    return figures


if __name__ == "__main__":
    main(quick="--quick" in sys.argv, big="--big" in sys.argv)
