"""Volumetric locking of the tetrahedra at nu = 0.499, on meshes fine enough to converge.

The test suite's BOX cantilever (60 mm along z, 12 mm along x, 8 mm along y, root
clamped, 0.01 N along y spread over the tip face, linear static tip stiffness F / delta)
at nu = 0.499 (E = 6.1 MPa): hexahedra at 2 and 1 mm (their Richardson limit is the
converged reference), the 4-node tetrahedron (hexahedra split into 6,
:func:`ccedi.fea.mesh.tet_mesh.split_hexes`) at 4, 2 and 1 mm, as ccedi builds it (``tet4``:
nodal pressure and alpha-FEM shear, alpha = 0.7) and with the element shear alone
(``tet4_alpha0``: Bonet & Burton's average nodal pressure element, LS-DYNA solid 13), and
the 10-node tetrahedron at 4 and 2 mm. The constant-strain shear is stiff in bending at
any nu (its error falls as h^2); a locking element would converge to a stiffer value, or
not at all.

Prints and writes validation/tet_locking.json (stiffness [N/m], error against the
converged hexahedral value [%], nodes, wall time of the solve [s]).

Run: ``.venv/bin/python validation/tet_locking.py`` (some minutes).
"""
import platform
import sys
import time
from pathlib import Path

from ccedi.fea.elements.tet4 import tet4_group
from ccedi.fea.material import NeoHookean
from ccedi.fea.mesh.tet_mesh import box_cantilever, quadratic_tets, split_hexes
from ccedi.fea.model import cantilever_model
from ccedi.fea.solvers.static import tip_deflection
from ccedi.outputs import report_figures

OUT = Path(__file__).with_suffix(".json")
BOX = (0.06, 0.012, 0.008)
"""Length, width (x), height (y, the bending direction) [m]."""
RUBBER_499 = NeoHookean(6.1e6, 0.499, 1000.0)
FORCE_N = 0.01


def _mesh(kind, divisions):
    """The BOX mesh with ``divisions`` x (3, 2, 15) hexahedra (4 mm / divisions), as kind."""
    hexes = box_cantilever(*BOX, nx=3 * divisions, ny=2 * divisions, nz=15 * divisions)
    if kind == "hex8":
        return hexes
    tets = split_hexes(hexes)
    return quadratic_tets(tets) if kind == "tet10" else tets


def stiffness(kind, divisions):
    """Linear tip stiffness [N/m], node count and solve time [s] of one mesh."""
    mesh = _mesh(kind, divisions)
    t0 = time.perf_counter()
    model = cantilever_model(mesh, RUBBER_499)
    if kind == "tet4_alpha0":
        model.tet4 = tet4_group(mesh.nodes, mesh.tets4, RUBBER_499, nodal_shear=0.0)
    k = FORCE_N / tip_deflection(model, FORCE_N, linear=True)
    return k, len(mesh.nodes), time.perf_counter() - t0


def main():
    figures = {"case": "BOX cantilever 60 x 12 x 8 mm, nu = 0.499, E = 6.1 MPa, linear tip stiffness"}
    runs = {("hex8", 2): None, ("hex8", 4): None, ("tet4", 1): None, ("tet4", 2): None, ("tet4", 4): None,
            ("tet4_alpha0", 1): None, ("tet4_alpha0", 2): None, ("tet4_alpha0", 4): None,
            ("tet10", 1): None, ("tet10", 2): None}
    for kind, divisions in runs:
        k, nodes, seconds = stiffness(kind, divisions)
        runs[kind, divisions] = k
        size = f"{4 / divisions:.3g}mm"
        figures |= {f"{kind}_{size}_stiffness_N_per_m": round(k, 4), f"{kind}_{size}_nodes": nodes,
                    f"{kind}_{size}_solve_s": round(seconds, 1)}
        print(kind, size, k, nodes, round(seconds, 1), flush=True)
    converged = (4 * runs["hex8", 4] - runs["hex8", 2]) / 3          # Richardson, h^2
    figures["hex8_richardson_limit_N_per_m"] = round(converged, 4)
    for (kind, divisions), k in runs.items():
        figures[f"{kind}_{4 / divisions:.3g}mm_vs_converged_percent"] = round(100 * (k / converged - 1), 2)
    figures |= {"python": sys.version.split()[0], "machine": platform.machine()}
    report_figures(figures, OUT)


if __name__ == "__main__":
    main()
