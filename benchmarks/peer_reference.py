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
      and Gmsh meshes of the elliptical prism (curved surface) at 4 mm and 2 mm.

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


def gmsh_prism_tet10(length_m, size_m):
    """Gmsh (OpenCASCADE) 10-node tetrahedra of the elliptical prism at target size
    ``size_m``; mid-edge nodes on the curved surface."""
    import gmsh
    gmsh.initialize(["-noenv"])
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.add("finger")
        disk = gmsh.model.occ.addDisk(0.0, 0.0, 0.0, SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR)
        gmsh.model.occ.extrude([(2, disk)], 0.0, 0.0, length_m)
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


def measure(label, mesh, hex_element=None):
    """One CalculiX run: linear tip stiffness and f1, with sizes and wall time."""
    t0 = time.perf_counter()
    r = run_calculix(mesh, RUBBER, 1.0, 1, N_MODES, hex_element or "C3D20R")
    row = {"model": label, "element": r.element_type, "nodes": r.n_nodes, "elements": r.n_elements,
           "dofs": 3 * r.n_nodes, "stiffness_N_per_m": round(r.stiffness_N_per_m, 4),
           "f1_hz": round(float(r.frequencies_hz[0]), 5), "omega1_rad_s": round(float(r.omega_rad_s[0]), 4),
           "f2_hz": round(float(r.frequencies_hz[1]), 5), "ccx_wall_time_s": round(r.wall_time_s, 2),
           "total_wall_time_s": round(time.perf_counter() - t0, 2)}
    print(f"{label:34s} {row['element']:7s} {row['nodes']:7d} {row['elements']:6d} "
          f"{row['stiffness_N_per_m']:9.3f} {row['f1_hz']:9.4f} {row['ccx_wall_time_s']:8.1f}", flush=True)
    return row


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
                rows.append(measure(f"{name} split {n}x{n}x{n}", mesh, element))
    if not quick:
        rows.append(measure("SM-A Kuhn 6 tets per hex", kuhn_tet10(sm_a(length_in=LENGTH_IN), L)))
        for size_mm in (4.0, 2.0):
            rows.append(measure(f"Gmsh elliptical prism {size_mm:g} mm", gmsh_prism_tet10(L, 1e-3 * size_mm)))
    figures = {"finger": f"{LENGTH_IN} in elliptical prism, E 6.1 MPa, nu 0.49, rho 1000 kg/m^3, "
                         f"1 N along y over the tip face, root clamped",
               "solver": f"CalculiX {ccx_version()} (linear static + *FREQUENCY, consistent mass), 1 thread",
               "machine": f"{platform.machine()} {platform.python_implementation()} {platform.python_version()}",
               "rows": rows}
    OUT.write_text(json.dumps(figures, indent=2) + "\n")
    print(f"wrote {OUT}")
    return figures


if __name__ == "__main__":
    main(quick="--quick" in sys.argv, big="--big" in sys.argv)
