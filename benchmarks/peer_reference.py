"""Peer-solver reference of the finger: CalculiX on ccedi's meshes, refined until converged.

The 4.5-in finger of the paper (rubber E = 6.1 MPa, nu = 0.49, rho = 1000 kg/m^3), root
clamped, 1 N along y spread over the tip face (:func:`ccedi.fea.calculix.tip_weights`).
For each mesh CalculiX 2.20 gives the linear tip stiffness F / delta and the first natural
frequency f1 (consistent mass):

(i)   SM-A, each hexahedron split n x n x n (trilinear map, so the polygonal geometry of
      SM-A is kept), written as C3D20R (hex8 -> hex20, mid-edge nodes at edge midpoints) and
      C3D8I; n = 1, 2, 3;
(ii)  SM-B the same (n = 1, 2);
      C3D20R meshes of more than BIG_C3D20R hexahedra only with ``--big``;
(iii) 10-node tetrahedra as C3D10: SM-A's hexahedra each split into six (Kuhn) tetrahedra,
      and Gmsh meshes of the elliptical prism (curved surface) at 4 mm and 2 mm;
(iv)  a finger that is not a prism (tapered, with a hole: :func:`_tapered_with_hole`) meshed
      by Gmsh with 10-node tetrahedra at 4, 3 and 2 mm, as C3D10.

Prints a table and writes benchmarks/peer_reference.json (wall times of the ccx runs, one
thread, and the ccx version).

Run: ``.venv/bin/python benchmarks/peer_reference.py [--quick] [--big]`` (``--quick``:
n = 1 and 2 of SM-A only, about 100 s).
"""
import json
import platform
import sys
import time
from pathlib import Path

import numpy as np

from ccedi.fea.calculix import TET10_EDGES, ccx_version, run_calculix
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR, Mesh, sm_a, sm_b
from ccedi.fea.units import inch_to_m

OUT = Path(__file__).with_suffix(".json")
LENGTH_IN = 4.5
N_MODES = 2
TAPER_TIP_SEMI_AXES = (7.5e-3, 5.5e-3)
"""Tip section semi-axes (x, y) of the tapered finger [m]."""
HOLE_RADIUS = 3.0e-3
"""Radius of the tapered finger's hole along x at mid-length [m]."""
BIG_C3D20R = 10000
"""Hexahedra above which C3D20R runs only with ``--big`` (SPOOLES on one thread: SM-A split
2x2x2, 5800 hexahedra, takes about 80 s; 3x3x3 would take many minutes)."""

# Unit-cube corners of a hexahedron in VTK order.
_CORNERS = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                     [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=float)
# Kuhn split of the unit cube into six tetrahedra around the diagonal 0-6.
_KUHN = np.array([[0, 1, 2, 6], [0, 1, 5, 6], [0, 3, 2, 6], [0, 3, 7, 6], [0, 4, 5, 6], [0, 4, 7, 6]])


def _merge_nodes(points, length_m):
    """Unique points (merged within 1e-9 of the finger length) and the index of each point."""
    key = np.round(points / (1e-9 * length_m)).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    return points[first], inverse.ravel()


def _end_sets(nodes, length_m):
    """``root`` (z = 0) and ``tip`` (z = L) node sets, within 1e-9 L."""
    ids = np.arange(len(nodes))
    tol = 1e-9 * length_m
    return {"root": ids[np.abs(nodes[:, 2]) < tol], "tip": ids[np.abs(nodes[:, 2] - length_m) < tol]}


def split_hexes(mesh, n, length_m):
    """Each hexahedron split into n x n x n by its trilinear map (same polygonal geometry)."""
    if n == 1:
        return mesh
    t = np.linspace(0.0, 1.0, n + 1)
    k, j, i = np.meshgrid(t, t, t, indexing="ij")
    p = np.column_stack([i.ravel(), j.ravel(), k.ravel()])                       # (m, 3) in [0,1]^3
    shape = np.prod(np.where(_CORNERS[None] == 1.0, p[:, None], 1.0 - p[:, None]), axis=2)   # (m, 8)
    points = np.einsum("mc,ecd->emd", shape, mesh.nodes[mesh.hexes]).reshape(-1, 3)
    nodes, index = _merge_nodes(points, length_m)
    m1 = n + 1
    kk, jj, ii = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    base = (kk * m1 * m1 + jj * m1 + ii).ravel()
    local = base[:, None] + (_CORNERS[:, 2] * m1 * m1 + _CORNERS[:, 1] * m1 + _CORNERS[:, 0]).astype(int)
    hexes = index.reshape(len(mesh.hexes), -1)[:, local].reshape(-1, 8)
    return Mesh(nodes=nodes, hexes=hexes, node_sets=_end_sets(nodes, length_m))


def _tet10_from_tet4(nodes, tets4):
    """10-node tetrahedra with straight edges: mid-edge nodes at edge midpoints, shared."""
    edges = np.sort(tets4[:, TET10_EDGES].reshape(-1, 2), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    all_nodes = np.concatenate([nodes, nodes[unique].mean(axis=1)])
    return all_nodes, np.concatenate([tets4, len(nodes) + inverse.reshape(-1, 6)], axis=1)


def _orient(nodes, tets):
    """Tetrahedra with positive volume (corners 1 and 2 swapped where it is negative)."""
    x = nodes[tets[:, :4]]
    vol = np.einsum("ij,ij->i", x[:, 1] - x[:, 0], np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 0]))
    tets = tets.copy()
    tets[vol < 0, 1], tets[vol < 0, 2] = tets[vol < 0, 2], tets[vol < 0, 1].copy()
    return tets


def kuhn_tet10(mesh, length_m):
    """SM-A's hexahedra each split into six tetrahedra (Kuhn: conforming on a structured
    mesh of like-oriented hexahedra), made 10-node with straight edges."""
    tets4 = _orient(mesh.nodes, mesh.hexes[:, _KUHN].reshape(-1, 4))
    nodes, tets10 = _tet10_from_tet4(mesh.nodes, tets4)
    return Mesh(nodes=nodes, tets10=tets10, node_sets=_end_sets(nodes, length_m))


def _prism(occ, length_m):
    """The paper's straight elliptical prism (OpenCASCADE)."""
    disk = occ.addDisk(0.0, 0.0, 0.0, SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR)
    occ.extrude([(2, disk)], 0.0, 0.0, length_m)


def _tapered_with_hole(occ, length_m):
    """A finger that is not a prism: the elliptical section tapering linearly from the
    paper's 12 x 8.45 mm at the root to 7.5 x 5.5 mm at the tip, with a 6 mm hole along x
    through the middle of its length."""
    root = occ.addWire([occ.addEllipse(0.0, 0.0, 0.0, SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR)])
    tip = occ.addWire([occ.addEllipse(0.0, 0.0, length_m, *TAPER_TIP_SEMI_AXES)])
    body = occ.addThruSections([root, tip], makeSolid=True, makeRuled=True)
    hole = occ.addCylinder(-0.02, 0.0, 0.5 * length_m, 0.04, 0.0, 0.0, HOLE_RADIUS)
    occ.cut(body, [(3, hole)])


def gmsh_tet10(geometry, length_m, size_m):
    """Gmsh (OpenCASCADE) 10-node tetrahedra of ``geometry`` (a function adding the solid)
    at target size ``size_m`` (smallest half of it); mid-edge nodes on curved surfaces."""
    import gmsh
    gmsh.initialize(["-noenv"])
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.add("finger")
        geometry(gmsh.model.occ, length_m)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", size_m)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 0.5 * size_m)
        gmsh.option.setNumber("Mesh.ElementOrder", 2)
        gmsh.model.mesh.generate(3)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        etags, enodes = gmsh.model.mesh.getElementsByType(11)      # 10-node tetrahedra
    finally:
        gmsh.finalize()
    index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    nodes = coords.reshape(-1, 3)
    tets = index[enodes.astype(np.int64).reshape(-1, 10)][:, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]]   # Gmsh -> VTK
    used = np.unique(tets)
    renumber = np.full(len(nodes), -1)
    renumber[used] = np.arange(len(used))
    nodes, tets = nodes[used], renumber[tets]
    mid = nodes[tets[:, 4:]]
    ends = nodes[tets[:, TET10_EDGES]].mean(axis=2)
    assert np.linalg.norm(mid - ends, axis=-1).max() < 0.25 * size_m, "Gmsh 10-node order not as expected"
    return Mesh(nodes=nodes, tets10=_orient(nodes, tets), node_sets=_end_sets(nodes, length_m))


def measure(label, mesh, hex_element=None, series=None, refinement=1.0):
    """One CalculiX run: linear tip stiffness and f1, with sizes and wall time; ``series``
    and ``refinement`` place it in a refinement sequence (:func:`richardson`)."""
    t0 = time.perf_counter()
    r = run_calculix(mesh, RUBBER, 1.0, 1, N_MODES, hex_element or "C3D20R")
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
    """For each series refined three times (hexahedra split 1x, 2x, 3x; Gmsh at 4, 3, 2 mm):
    the observed convergence order p of k(r) = k_inf + c r^-p (r the refinement factor: the
    split n, or 4 mm / size; from the three stiffnesses) and the extrapolated stiffness and
    f1 at that order. Nominal for the unstructured Gmsh meshes."""
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
    L = inch_to_m(LENGTH_IN)
    print(f"{'model':34s} {'element':7s} {'nodes':>7s} {'elem':>6s} {'k [N/m]':>9s} {'f1 [Hz]':>9s} {'ccx [s]':>8s}")
    rows = []
    for name, base, splits in (("SM-A", sm_a(length_in=LENGTH_IN), (1, 2) if quick else (1, 2, 3)),
                               ("SM-B", sm_b(length_in=LENGTH_IN), () if quick else (1, 2))):
        for n in splits:
            mesh = split_hexes(base, n, L)
            for element in ("C3D20R", "C3D8I"):
                if element == "C3D20R" and mesh.n_elements > BIG_C3D20R and not big:
                    continue
                rows.append(measure(f"{name} split {n}x{n}x{n}", mesh, element, name, n))
    if not quick:
        rows.append(measure("SM-A Kuhn 6 tets per hex", kuhn_tet10(sm_a(length_in=LENGTH_IN), L)))
        for size_mm in (4.0, 2.0):
            rows.append(measure(f"Gmsh elliptical prism {size_mm:g} mm", gmsh_tet10(_prism, L, 1e-3 * size_mm),
                                series="Gmsh elliptical prism", refinement=4.0 / size_mm))
        for size_mm in (4.0, 3.0, 2.0):
            mesh = gmsh_tet10(_tapered_with_hole, L, 1e-3 * size_mm)
            rows.append(measure(f"Gmsh tapered, hole {size_mm:g} mm", mesh, series="Gmsh tapered, hole",
                                refinement=4.0 / size_mm))
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
