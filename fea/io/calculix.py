"""CalculiX as a peer solver: write a ccedi mesh as a CalculiX (Abaqus-format) input deck,
run ``ccx`` on it and read back the linear tip stiffness and the natural frequencies.

The deck (:func:`calculix_deck`) holds, in SI units (m, kg, s, N, Pa):

* *NODE, then one *ELEMENT block per element type: hexahedra as C3D8I (incompatible modes,
  free of shear locking and hourglass modes), C3D8 (full integration) or, after
  :func:`hex8_to_hex20`, C3D20R / C3D20 (quadratic, 2x2x2 reduced or 3x3x3 full integration);
  4-node tetrahedra as C3D4, 10-node tetrahedra as C3D10. ccedi's node orders are VTK's,
  which for these elements coincide with CalculiX's (and Abaqus's): hexahedron corners 1-4
  on one face and 5-8 above them, the 20-node hexahedron's mid-edge nodes 9-20 on the edges
  1-2, 2-3, 3-4, 4-1, 5-6, 6-7, 7-8, 8-5, 1-5, 2-6, 3-7, 4-8, the 10-node tetrahedron's 5-10
  on 1-2, 2-3, 1-3, 1-4, 2-4, 3-4. ``tests/unit/fea/test_calculix.py`` reads decks back with meshio's
  Abaqus reader (which maps these types without reordering) and runs C3D20R and C3D10
  cantilevers against beam theory (a mid-edge order swapped between the top face and the
  vertical edges makes ccx stop: "nonpositive jacobian");
* *NSET ROOT and TIP (the mesh's ``root`` and ``tip`` node sets), *MATERIAL with *ELASTIC
  (E, nu) and *DENSITY (rho): the small-strain limit of ccedi's neo-Hookean solid
  (:class:`ccedi.fea.material.NeoHookean`);
* *BOUNDARY: every degree of freedom of ROOT fixed (the clamp);
* a linear *STATIC step (no NLGEOM) with the tip force F along one axis as *CLOAD, node i
  carrying w_i F, and *NODE PRINT of U on TIP; the tip deflection is the weighted mean
  delta = sum_i w_i u_i, so F delta is the work of the load and k = F / delta the linear
  tip stiffness;
* a *FREQUENCY step for the lowest n modes (the eigenproblem K phi = omega^2 M phi with
  CalculiX's consistent mass matrix; ccedi's :func:`ccedi.fea.solvers.modal.natural_frequencies`
  uses a lumped one, so coarse meshes differ a little in frequency between the two).

The tip weights w (summing to 1) are those of a uniform traction on the tip faces: for
8-node hexahedra ccedi's own :func:`ccedi.fea.model.face_node_weights`; for the quadratic
faces of C3D20 and C3D10 elements and the triangles of C3D4 the consistent ones,
w_i = int N_i dA / A over the faces lying wholly in the tip set (for a flat 6-node
triangle 0 at the corners and A/3 at each mid-edge node; for a rectangular 8-node face
-A/12 at the corners and A/3 at the mid-edge nodes).

``ccx`` runs in a temporary directory (``ccx -i job``, ``OMP_NUM_THREADS`` = 1 by default);
:func:`run_calculix` parses its ``job.dat``. Without ``ccx`` on the PATH every call that
runs it raises :class:`ccedi.errors.SolverError` naming the package to install.
"""
import os
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from ccedi.errors import InputError, SolverError, one_line
from ccedi.fea.elements.hex8 import FACES as HEX_FACES
from ccedi.fea.model import face_node_weights

CCX_INSTALL_HINT = "install CalculiX: apt-get install calculix-ccx (or put ccx on the PATH)"
"""What a missing ``ccx`` error message tells the user to do."""

HEX_ELEMENTS = ("C3D8I", "C3D8", "C3D20R", "C3D20")
"""CalculiX element types a hexahedral mesh can be written as; the 20-node ones after
:func:`hex8_to_hex20`. (C3D8R is left out: its hourglass control is defective in
CalculiX 2.20.)"""

HEX_EDGES = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4],
                      [0, 4], [1, 5], [2, 6], [3, 7]])
"""The twelve edges of a hexahedron (local corner ids), in the order of the 20-node
hexahedron's mid-edge nodes 8-19 (VTK and CalculiX)."""

TET10_EDGES = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])
"""The six edges of a tetrahedron (local corner ids), in the order of the 10-node
tetrahedron's mid-edge nodes 4-9 (VTK and CalculiX)."""

TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
"""The four triangular faces of a tetrahedron (local corner ids)."""

_LINE_ENTRIES = 16
"""Most entries CalculiX reads from one data line of an *ELEMENT card."""
_FIELD_WIDTH = 20
"""Most characters CalculiX reads from one number."""


class Hex20Mesh(NamedTuple):
    """A mesh of 20-node hexahedra (made by :func:`hex8_to_hex20`).

    Attributes
    ----------
    nodes : numpy.ndarray
        Nodal positions, shape (n, 3) [m]: the corner nodes of the 8-node mesh first, in
        their order, then the mid-edge nodes.
    hexes20 : numpy.ndarray
        Connectivity, shape (e, 20): corners 0-7 as the 8-node hexahedra, mid-edge nodes
        8-19 on the edges :data:`HEX_EDGES`.
    node_sets : dict
        {name: node ids}: each set of the 8-node mesh plus the mid-edge nodes of the edges
        whose both ends are in it.
    """
    nodes: np.ndarray
    hexes20: np.ndarray
    node_sets: dict


class CalculixDeck(NamedTuple):
    """An input deck written by :func:`calculix_deck`.

    Attributes
    ----------
    text : str
        The deck.
    tip_ids : numpy.ndarray
        Tip node ids (0-based: the deck's ids less 1).
    tip_weights : numpy.ndarray
        Their weights w_i (share of the force, and of the tip deflection), summing to 1.
    n_nodes : int
        Nodes of the deck.
    element_types : tuple of str
        The CalculiX element types written.
    """
    text: str
    tip_ids: np.ndarray
    tip_weights: np.ndarray
    n_nodes: int
    element_types: tuple


class CalculixResult(NamedTuple):
    """What one CalculiX run measured.

    Attributes
    ----------
    element_type : str
        The CalculiX element type(s) written, e.g. ``"C3D20R"`` (``"+"``-joined if several).
    n_nodes : int
        Nodes of the deck.
    n_elements : int
        Elements of the deck.
    tip_deflection_m : float
        Weighted mean tip displacement delta along the load [m] (nan without a static step).
    stiffness_N_per_m : float
        Linear tip stiffness F / delta [N/m] (nan without a static step).
    frequencies_hz : numpy.ndarray
        The lowest natural frequencies f [Hz], ascending (empty without a frequency step).
    omega_rad_s : numpy.ndarray
        The same as angular frequencies omega = 2 pi f [rad/s].
    wall_time_s : float
        Wall time of the ``ccx`` process [s].
    """
    element_type: str
    n_nodes: int
    n_elements: int
    tip_deflection_m: float
    stiffness_N_per_m: float
    frequencies_hz: np.ndarray
    omega_rad_s: np.ndarray
    wall_time_s: float


def hex8_to_hex20(mesh):
    """Quadratic 20-node hexahedra on an 8-node hexahedral mesh, same polygonal geometry.

    Each edge gets one node at its midpoint, shared by every hexahedron holding the edge,
    so the faces stay the bilinear faces of the 8-node mesh and the volume is unchanged.
    A structured block of nx x ny x nz hexahedra gets
    (nx+1)(ny+1)(nz+1) + nx(ny+1)(nz+1) + (nx+1)ny(nz+1) + (nx+1)(ny+1)nz nodes.

    Parameters
    ----------
    mesh : Mesh
        A mesh of 8-node hexahedra only (:class:`ccedi.fea.mesh.Mesh`).

    Returns
    -------
    Hex20Mesh
        Nodes, 20-node connectivity and the node sets extended by their mid-edge nodes.

    Raises
    ------
    InputError
        If the mesh has no hexahedra or also holds tetrahedra.
    """
    if mesh.element_type != "hex8":
        raise InputError(f"hex8_to_hex20 needs a mesh of 8-node hexahedra only, got element type "
                         f"{mesh.element_type!r}")
    n = mesh.n_nodes
    edges = np.sort(mesh.hexes[:, HEX_EDGES].reshape(-1, 2), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    mid = mesh.nodes[unique].mean(axis=1)
    hexes20 = np.concatenate([mesh.hexes, n + inverse.reshape(len(mesh.hexes), 12)], axis=1)
    node_sets = {}
    for name, ids in mesh.node_sets.items():
        in_set = np.zeros(n, dtype=bool)
        in_set[ids] = True
        node_sets[name] = np.concatenate([np.asarray(ids, dtype=np.int64),
                                          n + np.flatnonzero(in_set[unique].all(axis=1))])
    return Hex20Mesh(nodes=np.concatenate([mesh.nodes, mid]), hexes20=hexes20, node_sets=node_sets)


def _quad8_shape(xi, eta):
    """Serendipity 8-node quadrilateral: N (q, 8), dN/dxi and dN/deta (q, 8); corners
    (-1,-1), (1,-1), (1,1), (-1,1), then the mid-edge nodes of the edges 0-1, 1-2, 2-3, 3-0."""
    cx = np.array([-1.0, 1.0, 1.0, -1.0])
    cy = np.array([-1.0, -1.0, 1.0, 1.0])
    x, y = xi[:, None], eta[:, None]
    a, b = 1 + x * cx, 1 + y * cy
    n_c = 0.25 * a * b * (x * cx + y * cy - 1)
    dx_c = 0.25 * cx * b * (2 * x * cx + y * cy)
    dy_c = 0.25 * cy * a * (x * cx + 2 * y * cy)
    one = np.ones_like(x)
    n_m = np.concatenate([0.5 * (1 - x**2) * (1 - y), 0.5 * (1 + x) * (1 - y**2),
                          0.5 * (1 - x**2) * (1 + y), 0.5 * (1 - x) * (1 - y**2)], axis=1)
    dx_m = np.concatenate([-x * (1 - y), 0.5 * (1 - y**2) * one, -x * (1 + y), -0.5 * (1 - y**2) * one], axis=1)
    dy_m = np.concatenate([-0.5 * (1 - x**2) * one, -y * (1 + x), 0.5 * (1 - x**2) * one, -y * (1 - x)], axis=1)
    return (np.concatenate([n_c, n_m], axis=1), np.concatenate([dx_c, dx_m], axis=1),
            np.concatenate([dy_c, dy_m], axis=1))


def _quad4_shape(xi, eta):
    """Bilinear 4-node quadrilateral: N (q, 4), dN/dxi and dN/deta (q, 4); corners (-1,-1),
    (1,-1), (1,1), (-1,1)."""
    cx = np.array([-1.0, 1.0, 1.0, -1.0])
    cy = np.array([-1.0, -1.0, 1.0, 1.0])
    x, y = xi[:, None], eta[:, None]
    return 0.25 * (1 + x * cx) * (1 + y * cy), 0.25 * cx * (1 + y * cy), 0.25 * cy * (1 + x * cx)


def _tri_shape(r, s, quadratic):
    """3- or 6-node triangle: N (q, k), dN/dr and dN/ds (q, k); corners (0,0), (1,0), (0,1),
    then the mid-edge nodes of the edges 0-1, 1-2, 2-0."""
    L = np.stack([1 - r - s, r, s], axis=1)
    dL_r = np.array([-1.0, 1.0, 0.0])
    dL_s = np.array([-1.0, 0.0, 1.0])
    if not quadratic:
        return L, np.broadcast_to(dL_r, L.shape), np.broadcast_to(dL_s, L.shape)
    i, j = np.array([0, 1, 2]), np.array([1, 2, 0])
    n = np.concatenate([L * (2 * L - 1), 4 * L[:, i] * L[:, j]], axis=1)
    d_r = np.concatenate([(4 * L - 1) * dL_r, 4 * (dL_r[i] * L[:, j] + L[:, i] * dL_r[j])], axis=1)
    d_s = np.concatenate([(4 * L - 1) * dL_s, 4 * (dL_s[i] * L[:, j] + L[:, i] * dL_s[j])], axis=1)
    return n, d_r, d_s


def _face_rule(n_face_nodes):
    """Quadrature points and weights on the reference face, and the shape functions there:
    3 x 3 Gauss on quadrilaterals, the 6-point degree-4 rule on triangles."""
    if n_face_nodes in (4, 8):
        g, wg = np.polynomial.legendre.leggauss(3)
        xi, eta = (a.ravel() for a in np.meshgrid(g, g))
        return (_quad8_shape if n_face_nodes == 8 else _quad4_shape)(xi, eta), np.outer(wg, wg).ravel()
    a, b = 0.445948490915965, 0.091576213509771
    r = np.array([a, 1 - 2 * a, a, b, 1 - 2 * b, b])
    s = np.array([a, a, 1 - 2 * a, b, b, 1 - 2 * b])
    w = 0.5 * np.array([0.223381589678011] * 3 + [0.109951743655322] * 3)
    return _tri_shape(r, s, n_face_nodes == 6), w


def _faces_in_set(cells, local_faces, in_set):
    """The faces (global node ids, rows) of ``cells`` whose nodes all lie in the set."""
    faces = cells[:, local_faces].reshape(-1, local_faces.shape[1])
    return faces[in_set[faces].all(axis=1)]


def _quadratic_faces(corner_faces, edges, first_mid):
    """Local node ids of the quadratic faces: the corners, then the mid-edge node of each
    face edge (the edge list ``edges`` numbers them from ``first_mid``)."""
    lookup = {tuple(sorted(e)): first_mid + k for k, e in enumerate(edges.tolist())}
    k = corner_faces.shape[1]
    return np.array([list(f) + [lookup[tuple(sorted((f[i], f[(i + 1) % k])))] for i in range(k)]
                     for f in corner_faces.tolist()])


def _consistent_face_loads(nodes, faces):
    """int N_i dA of every node over the faces (rows of 3, 6 or 8 global node ids) [m^2]."""
    (N, dN_a, dN_b), w = _face_rule(faces.shape[1])
    x = nodes[faces]                                        # (f, k, 3)
    t_a = np.einsum("qk,fkd->fqd", dN_a, x)
    t_b = np.einsum("qk,fkd->fqd", dN_b, x)
    dA = np.linalg.norm(np.cross(t_a, t_b), axis=-1) * w    # (f, q)
    load = np.zeros(len(nodes))
    np.add.at(load, faces, np.einsum("fq,qk->fk", dA, N))
    return load


class _Blocks(NamedTuple):
    """A mesh as CalculiX element blocks: nodes, {type: connectivity}, node sets, and
    (connectivity, local face node ids) pairs of each block's faces."""

    nodes: np.ndarray
    cells: dict
    node_sets: dict
    faces: list


def _cell_blocks(mesh, hex_element, extra=()):
    """``mesh`` as :class:`_Blocks`, hexahedra written as ``hex_element`` (one of
    :data:`HEX_ELEMENTS` or ``extra``)."""
    allowed = HEX_ELEMENTS + tuple(extra)
    if hex_element not in allowed:
        raise InputError(f"hex_element must be one of {', '.join(allowed)}, got {hex_element!r}")
    cells, faces = {}, []
    nodes, node_sets = mesh.nodes, mesh.node_sets
    if len(mesh.hexes) and hex_element.startswith("C3D20"):
        if len(mesh.tets4) or len(mesh.tets10):
            raise InputError(f"hex_element {hex_element} needs a mesh of hexahedra only (got "
                             f"{mesh.element_type!r}); write mixed meshes with C3D8I")
        quad = hex8_to_hex20(mesh)
        nodes, node_sets = quad.nodes, quad.node_sets
        cells[hex_element] = quad.hexes20
        faces.append((quad.hexes20, _quadratic_faces(HEX_FACES, HEX_EDGES, 8)))
    elif len(mesh.hexes):
        cells[hex_element] = mesh.hexes
        faces.append((mesh.hexes, HEX_FACES))
    if len(mesh.tets4):
        cells["C3D4"] = mesh.tets4
        faces.append((mesh.tets4, TET_FACES))
    if len(mesh.tets10):
        cells["C3D10"] = mesh.tets10
        faces.append((mesh.tets10, _quadratic_faces(TET_FACES, TET10_EDGES, 4)))
    if not cells:
        raise InputError("mesh has no solid elements (hexahedra or tetrahedra) to write")
    return _Blocks(nodes, cells, node_sets, faces)


def _block_tip_weights(mesh, blocks, tip):
    """Tip node ids of ``blocks`` and their weights (see :func:`tip_weights`)."""
    if tip not in mesh.node_sets:
        raise InputError(f"mesh has no node set {tip!r} (has {sorted(mesh.node_sets)})")
    ids = np.asarray(blocks.node_sets[tip], dtype=np.int64)
    if set(blocks.cells) <= {"C3D8I", "C3D8", "C3D8R"}:
        return ids, face_node_weights(mesh, ids)
    in_set = np.zeros(len(blocks.nodes), dtype=bool)
    in_set[ids] = True
    load = np.zeros(len(blocks.nodes))
    for cells, local in blocks.faces:
        faces = _faces_in_set(cells, local, in_set)
        if len(faces):
            load += _consistent_face_loads(blocks.nodes, faces)
    if not load.any():
        raise InputError(f"node set {tip!r} contains no complete element face")
    return ids, load[ids] / load[ids].sum()


def tip_weights(mesh, hex_element="C3D20R", tip="tip"):
    """Weights w_i (summing to 1) of the tip nodes for a uniform traction on the tip faces,
    as the deck of :func:`calculix_deck` writes the mesh.

    A mesh of 8-node hexahedra only (C3D8I, C3D8): ccedi's
    :func:`ccedi.fea.model.face_node_weights`. Otherwise the consistent
    w_i = int N_i dA / A over the faces lying wholly in the set (3 x 3 Gauss points on
    quadrilaterals, 6 points on triangles).

    Parameters
    ----------
    mesh : Mesh
        The ccedi mesh (:class:`ccedi.fea.mesh.Mesh`) with the node set ``tip``.
    hex_element : str, optional
        How hexahedra are written, one of :data:`HEX_ELEMENTS`. Default ``"C3D20R"``.
    tip : str, optional
        Name of the loaded node set. Default ``"tip"``.

    Returns
    -------
    ids : numpy.ndarray
        Tip node ids of the written mesh (for C3D20: with its mid-edge nodes).
    weights : numpy.ndarray
        One weight per id, summing to 1.

    Raises
    ------
    InputError
        If the node set is missing or holds no complete element face, or
        ``hex_element`` is unknown.
    """
    return _block_tip_weights(mesh, _cell_blocks(mesh, hex_element), tip)


def _real(value):
    """A real number as CalculiX reads it: shortest exact text if it fits its 20-character
    fields, else 13 significant digits."""
    text = repr(float(value))
    return text if len(text) <= _FIELD_WIDTH else f"{float(value):.12e}"


def _id_lines(ids, per_line=_LINE_ENTRIES):
    """1-based ids, ``per_line`` a line, comma-separated (a trailing comma continues a line)."""
    ids = [str(int(i) + 1) for i in ids]
    return [", ".join(ids[i:i + per_line]) + ("," if i + per_line < len(ids) else "")
            for i in range(0, len(ids), per_line)]


def _element_lines(first_id, cells):
    """*ELEMENT data lines: the element id then its nodes, at most 16 entries a line."""
    lines = []
    for k, cell in enumerate(cells):
        entries = [str(first_id + k)] + [str(int(i) + 1) for i in cell]
        chunks = [entries[i:i + _LINE_ENTRIES] for i in range(0, len(entries), _LINE_ENTRIES)]
        lines += [", ".join(c) + ("," if j < len(chunks) - 1 else "") for j, c in enumerate(chunks)]
    return lines


def calculix_deck(mesh, material, *, force_N=1.0, direction=1, n_modes=0, hex_element="C3D20R",
                  weights=None, clamp="root", tip="tip", store_matrices=False):
    """A CalculiX input deck of a clamped finger: a linear tip-load step and/or a frequency step.

    Parameters
    ----------
    mesh : Mesh
        The ccedi mesh (:class:`ccedi.fea.mesh.Mesh`): hexahedra, 4- and/or 10-node
        tetrahedra, with the node sets ``clamp`` and ``tip``.
    material : NeoHookean
        Its E [Pa], nu and rho [kg/m^3] (:class:`ccedi.fea.material.NeoHookean`), written
        as the linear elastic material it reduces to at small strain.
    force_N : float or None, optional
        Total tip force F [N], finite and non-zero; None for no static step. Default 1.
    direction : int, optional
        0, 1 or 2: the force's axis (x, y, z). Default 1 (y, the finger's bending direction).
    n_modes : int, optional
        Natural frequencies to compute, >= 0 (0: no frequency step). Default 0.
    hex_element : str, optional
        How hexahedra are written, one of :data:`HEX_ELEMENTS`. Default ``"C3D20R"``.
    weights : array_like, optional
        Share of F of each node of ``mesh.node_sets[tip]`` (in its order), summing to 1;
        not with the 20-node types, whose mid-edge nodes the mesh does not have.
        Default :func:`tip_weights`.
    clamp : str, optional
        Node set whose every degree of freedom is fixed. Default ``"root"``.
    tip : str, optional
        Node set carrying the force. Default ``"tip"``.
    store_matrices : bool, optional
        Make the frequency step ``SOLVER=MATRIXSTORAGE``: CalculiX then writes the stiffness
        and mass matrices of the free degrees of freedom (``job.sti``, ``job.mas``,
        ``job.dof``) instead of solving. Default False.

    Returns
    -------
    CalculixDeck
        The deck text, tip node ids and weights, node count and element types.

    Raises
    ------
    InputError
        If a node set is missing, the weights do not match the tip set or sum to 1, the
        force, direction, mode count or element type is out of range, or there is no step.
    """
    for name in (clamp, tip):
        if name not in mesh.node_sets:
            raise InputError(f"mesh has no node set {name!r} (has {sorted(mesh.node_sets)})")
    if direction not in (0, 1, 2):
        raise InputError(f"direction must be 0, 1 or 2 (x, y, z), got {direction!r}")
    if int(n_modes) != n_modes or n_modes < 0:
        raise InputError(f"n_modes must be an integer >= 0, got {n_modes!r}")
    if force_N is not None and (not np.isfinite(force_N) or force_N == 0.0):
        raise InputError(f"force_N must be a finite non-zero force in N (or None), got {force_N!r}")
    if force_N is None and n_modes == 0:
        raise InputError("nothing to compute: give force_N (static step) or n_modes >= 1 (frequency step)")
    if store_matrices and (force_N is not None or n_modes == 0):
        raise InputError("store_matrices needs force_N=None and n_modes >= 1 (a frequency step alone)")
    blocks = _cell_blocks(mesh, hex_element)
    if weights is None:
        ids, weights = _block_tip_weights(mesh, blocks, tip)
    else:
        if hex_element.startswith("C3D20") and len(mesh.hexes):
            raise InputError(f"weights cannot be given with {hex_element} (its mid-edge tip nodes are "
                             f"made here); leave weights out")
        ids = np.asarray(mesh.node_sets[tip], dtype=np.int64)
        weights = np.asarray(weights, dtype=float)
        if weights.shape != ids.shape or not np.isfinite(weights).all() or abs(weights.sum() - 1.0) > 1e-9:
            raise InputError(f"weights must be {len(ids)} finite numbers (one per {tip} node) summing "
                             f"to 1, got shape {weights.shape} summing to {weights.sum():.6g}")
    lines = _model_lines(blocks, material, clamp, tip)
    if force_N is not None:
        lines += ["*STEP", "*STATIC", "*CLOAD"]
        lines += [f"{i + 1}, {direction + 1}, {_real(w * force_N)}" for i, w in zip(ids, weights) if w != 0.0]
        lines += ["*NODE PRINT, NSET=TIP", "U", "*END STEP"]
    if n_modes:
        lines += ["*STEP", "*FREQUENCY" + (", SOLVER=MATRIXSTORAGE" if store_matrices else ""),
                  f"{int(n_modes)}", "*END STEP"]
    return CalculixDeck("\n".join(lines) + "\n", ids, weights, len(blocks.nodes), tuple(blocks.cells))


def _model_lines(blocks, material, clamp, tip):
    """The deck's model data: *NODE, *ELEMENT blocks, *NSET ROOT (``clamp``) and TIP
    (``tip``), the linear elastic *MATERIAL with *DENSITY, and ROOT clamped."""
    lines = ["*HEADING", "ccedi clamped finger (SI units: m, kg, s, N, Pa)", "*NODE, NSET=NALL"]
    lines += [f"{i + 1}, {_real(x)}, {_real(y)}, {_real(z)}" for i, (x, y, z) in enumerate(blocks.nodes.tolist())]
    first = 1
    for etype, cells in blocks.cells.items():
        lines += [f"*ELEMENT, TYPE={etype}, ELSET=EALL"] + _element_lines(first, cells)
        first += len(cells)
    for name, set_name in ((clamp, "ROOT"), (tip, "TIP")):
        lines += [f"*NSET, NSET={set_name}"] + _id_lines(blocks.node_sets[name])
    return lines + ["*MATERIAL, NAME=RUBBER", "*ELASTIC", f"{_real(material.E)}, {_real(material.nu)}",
                    "*DENSITY", _real(material.rho), "*SOLID SECTION, ELSET=EALL, MATERIAL=RUBBER",
                    "*BOUNDARY", "ROOT, 1, 3"]


def calculix_impulse_deck(mesh, material, alpha, *, force_N=1.0, duration_s=0.01, t_end_s=0.2, output_every=100,
                          hex_element="C3D8R", direction=1):
    """A CalculiX explicit dynamic deck of the paper's impulse test on a clamped finger.

    The model data of :func:`calculix_deck` (linear elastic material, the small-strain
    limit of ccedi's neo-Hookean solid), then one ``*STEP, NLGEOM`` with
    ``*DYNAMIC, EXPLICIT`` (CalculiX's central differences, lumped mass, its own stable
    increment), mass-proportional Rayleigh damping ``*DAMPING, ALPHA=alpha`` (C = alpha M,
    as ccedi's), the tip force F along ``direction`` spread over the tip nodes with the
    weights of :func:`tip_weights`, held for ``duration_s`` (``*AMPLITUDE``), and
    ``*NODE PRINT`` of U on TIP every ``output_every`` increments (CalculiX 2.20's explicit
    step ignores ``*TIME POINTS`` and prints every increment otherwise).

    Parameters
    ----------
    mesh : Mesh
        The ccedi mesh with node sets ``root`` (clamped) and ``tip`` (loaded).
    material : NeoHookean
        E [Pa], nu, rho [kg/m^3].
    alpha : float
        Mass-proportional damping coefficient [1/s], >= 0.
    force_N : float, optional
        Total tip force [N], finite and non-zero. Default 1.
    duration_s : float, optional
        How long the force is held [s], in (0, t_end_s). Default 0.01.
    t_end_s : float, optional
        Simulated time [s], > 0. Default 0.2.
    output_every : int, optional
        Increments between outputs, >= 1. Default 100.
    hex_element : str, optional
        How hexahedra are written: ``"C3D8R"`` (one-point, the explicit element) or one of
        :data:`HEX_ELEMENTS`. Default ``"C3D8R"``.
    direction : int, optional
        Axis of the force, 0, 1 or 2. Default 1 (y).

    Returns
    -------
    CalculixDeck
        The deck text, tip node ids and weights, node count and element types.

    Raises
    ------
    InputError
        If an input is out of range or a node set is missing.
    """
    if not (np.isfinite(alpha) and alpha >= 0.0):
        raise InputError(f"alpha must be a finite damping coefficient >= 0 in 1/s, got {alpha!r}")
    if not (np.isfinite(t_end_s) and t_end_s > 0.0):
        raise InputError(f"t_end_s must be a finite time > 0 in s, got {t_end_s!r}")
    if not (np.isfinite(duration_s) and 0.0 < duration_s < t_end_s):
        raise InputError(f"duration_s must be in (0, t_end_s = {t_end_s:g}) s, got {duration_s!r}")
    if not (np.isfinite(force_N) and force_N != 0.0):
        raise InputError(f"force_N must be a finite non-zero force in N, got {force_N!r}")
    if int(output_every) != output_every or output_every < 1:
        raise InputError(f"output_every must be an integer >= 1, got {output_every!r}")
    if direction not in (0, 1, 2):
        raise InputError(f"direction must be 0, 1 or 2 (x, y, z), got {direction!r}")
    blocks = _cell_blocks(mesh, hex_element, extra=("C3D8R",))
    ids, weights = _block_tip_weights(mesh, blocks, "tip")
    lines = _model_lines(blocks, material, "root", "tip")
    t_off = duration_s * (1.0 + 1e-9)
    lines += ["*AMPLITUDE, NAME=PULSE", f"0., 1., {_real(duration_s)}, 1., {_real(t_off)}, 0., {_real(t_end_s)}, 0.",
              "*STEP, NLGEOM, INC=100000000", "*DYNAMIC, EXPLICIT", f"{_real(t_end_s / 1000)}, {_real(t_end_s)}",
              f"*DAMPING, ALPHA={_real(alpha)}, BETA=0.", "*CLOAD, AMPLITUDE=PULSE"]
    lines += [f"{i + 1}, {direction + 1}, {_real(w * force_N)}" for i, w in zip(ids, weights) if w != 0.0]
    lines += [f"*NODE PRINT, NSET=TIP, FREQUENCY={int(output_every)}", "U", "*END STEP"]
    return CalculixDeck("\n".join(lines) + "\n", ids, weights, len(blocks.nodes), tuple(blocks.cells))


def parse_tip_history(dat_text, ids, weights, *, direction=1):
    """Every *NODE PRINT block of U in a CalculiX ``.dat`` file, as the weighted tip
    displacement ``sum_i w_i u_i`` along ``direction`` over time.

    Parameters
    ----------
    dat_text : str
        Contents of the ``.dat`` file.
    ids : numpy.ndarray
        0-based ids of the tip nodes.
    weights : numpy.ndarray
        Their weights (summing to 1).
    direction : int, optional
        Axis, 0, 1 or 2. Default 1.

    Returns
    -------
    time_s : numpy.ndarray
        Output times [s].
    u_m : numpy.ndarray
        Weighted tip displacement [m] at those times.

    Raises
    ------
    SolverError
        If the file holds no displacement block.
    """
    blocks = _displacement_blocks(dat_text)
    if not blocks:
        raise SolverError("CalculiX .dat holds no displacement output (the dynamic step did not run)")
    time_s = np.array([t for t, _ in blocks])
    u_m = np.array([sum(w * u[i][direction] for i, w in zip(ids, weights)) for _, u in blocks])
    return time_s, u_m


def _displacement_blocks(dat_text):
    """Every *NODE PRINT block of U in a ``.dat`` file: [(time [s], {0-based node id: u (3,) [m]})]."""
    blocks = re.findall(r"displacements \(vx,vy,vz\) for set \S+ and time\s+(\S+)\s*\n\s*\n(.*?)(?:\n\s*\n|\Z)",
                        dat_text, re.S)
    return [(float(t), {int(r[0]) - 1: np.array([float(v) for v in r[1:4]])
                        for r in (line.split() for line in body.strip().splitlines())}) for t, body in blocks]


def parse_tip_displacements(dat_text):
    """The first *NODE PRINT block of U in a CalculiX ``.dat`` file.

    Parameters
    ----------
    dat_text : str
        Contents of the ``.dat`` file.

    Returns
    -------
    dict
        {0-based node id: displacement (3,) [m]}.

    Raises
    ------
    SolverError
        If the file holds no displacement block.
    """
    blocks = _displacement_blocks(dat_text)
    if not blocks:
        raise SolverError("CalculiX .dat holds no displacement output (the static step did not finish)")
    return blocks[0][1]


def parse_frequencies(dat_text):
    """The eigenvalue table of a CalculiX ``.dat`` file.

    Parameters
    ----------
    dat_text : str
        Contents of the ``.dat`` file.

    Returns
    -------
    omega_rad_s : numpy.ndarray
        Angular frequencies omega [rad/s], in mode order.
    frequencies_hz : numpy.ndarray
        Frequencies f = omega / (2 pi) [Hz] as CalculiX prints them.

    Raises
    ------
    SolverError
        If the file holds no eigenvalue output.
    """
    head = dat_text.find("E I G E N V A L U E   O U T P U T")
    if head < 0:
        raise SolverError("CalculiX .dat holds no eigenvalue output (the frequency step did not finish)")
    rows = []
    for line in dat_text[head:].splitlines()[1:]:
        fields = line.split()
        if len(fields) == 5 and fields[0].isdigit():
            rows.append([float(v) for v in fields[2:4]])
        elif rows and line.strip():
            break
    if not rows:
        raise SolverError("CalculiX .dat eigenvalue table is empty")
    rows = np.array(rows)
    return rows[:, 0], rows[:, 1]


def ccx_executable(executable="ccx"):
    """Full path of the CalculiX solver.

    Parameters
    ----------
    executable : str, optional
        Name or path of the ``ccx`` program. Default ``"ccx"``.

    Returns
    -------
    str
        Its path.

    Raises
    ------
    SolverError
        If it is not found, with how to install it.
    """
    path = shutil.which(executable)
    if path is None:
        raise SolverError(f"CalculiX solver {executable!r} not found: {CCX_INSTALL_HINT}")
    return path


def ccx_version(executable="ccx"):
    """The version CalculiX reports (``ccx -v``), e.g. ``"2.20"``.

    Parameters
    ----------
    executable : str, optional
        Name or path of the ``ccx`` program. Default ``"ccx"``.

    Returns
    -------
    str
        The version number.

    Raises
    ------
    SolverError
        If ``ccx`` is missing or prints no version.
    """
    out = subprocess.run([ccx_executable(executable), "-v"], capture_output=True, text=True).stdout
    match = re.search(r"Version\s+(\S+)", out)
    if match is None:
        raise SolverError(f"ccx -v printed no version: {one_line(out)}")
    return match.group(1)


def run_ccx(deck, *, executable="ccx", threads=1, keep_dir=None, read=("dat",)):
    """Run CalculiX on a deck in a temporary directory and return its ``.dat`` output.

    Parameters
    ----------
    deck : str
        The input deck text (:attr:`CalculixDeck.text` of :func:`calculix_deck`).
    executable : str, optional
        Name or path of the ``ccx`` program. Default ``"ccx"``.
    threads : int, optional
        ``OMP_NUM_THREADS`` of the run, >= 1. Default 1.
    keep_dir : str or pathlib.Path, optional
        Run there instead (``job.inp``, ``job.dat``, ... are kept). Default a temporary
        directory, removed afterwards.
    read : tuple of str, optional
        Extensions of the output files to return (``"dat"``; ``"sti"``, ``"mas"``, ``"dof"``
        of a matrix-storage frequency step). Default ``("dat",)``.

    Returns
    -------
    outputs : dict
        {extension: contents of ``job.<extension>``}.
    wall_time_s : float
        Wall time of the ``ccx`` process [s].

    Raises
    ------
    SolverError
        If ``ccx`` is missing, fails, or reports an error.
    InputError
        If ``threads`` is not an integer >= 1.
    """
    if int(threads) != threads or threads < 1:
        raise InputError(f"threads must be an integer >= 1, got {threads!r}")
    exe = ccx_executable(executable)
    env = dict(os.environ, OMP_NUM_THREADS=str(int(threads)), CCX_NPROC_EQUATION_SOLVER=str(int(threads)))
    with tempfile.TemporaryDirectory(prefix="ccedi_ccx_") as tmp:
        work = Path(keep_dir) if keep_dir is not None else Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        (work / "job.inp").write_text(deck)
        t0 = time.perf_counter()
        proc = subprocess.run([exe, "-i", "job"], cwd=work, env=env, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        errors = [line.strip() for line in proc.stdout.splitlines() if "*ERROR" in line]
        missing = [ext for ext in read if not (work / f"job.{ext}").exists()]
        if proc.returncode != 0 or errors or missing:
            detail = errors[0] if errors else (proc.stderr.strip() or proc.stdout.strip()[-200:]
                                               or f"no job.{missing[0]} written")
            raise SolverError(f"ccx failed (exit status {proc.returncode}): {one_line(detail)}")
        return {ext: (work / f"job.{ext}").read_text() for ext in read}, wall


def run_calculix(mesh, material, *, force_N=1.0, direction=1, n_modes=0, hex_element="C3D20R",
                 weights=None, executable="ccx", threads=1, keep_dir=None):
    """Linear tip stiffness and natural frequencies of a clamped finger by CalculiX.

    Writes :func:`calculix_deck`, runs it (:func:`run_ccx`) and reads the weighted tip
    deflection delta = sum_i w_i u_i (along ``direction``), the stiffness k = F / delta
    and the lowest ``n_modes`` frequencies (consistent mass).

    Parameters
    ----------
    mesh : Mesh
        The ccedi mesh (:class:`ccedi.fea.mesh.Mesh`) with node sets ``root`` (clamped)
        and ``tip`` (loaded).
    material : NeoHookean
        E, nu, rho of the solid (:class:`ccedi.fea.material.NeoHookean`).
    force_N : float or None, optional
        Total tip force [N]; None for no static step. Default 1.
    direction : int, optional
        Axis of the force and deflection, 0, 1 or 2. Default 1 (y).
    n_modes : int, optional
        Frequencies to compute, >= 0. Default 0.
    hex_element : str, optional
        How hexahedra are written, one of :data:`HEX_ELEMENTS`. Default ``"C3D20R"``.
    weights : array_like, optional
        Tip node weights (see :func:`calculix_deck`). Default :func:`tip_weights`.
    executable : str, optional
        Name or path of ``ccx``. Default ``"ccx"``.
    threads : int, optional
        Threads of the run, >= 1. Default 1.
    keep_dir : str or pathlib.Path, optional
        Directory to run in and keep. Default a temporary one.

    Returns
    -------
    CalculixResult
        Deflection, stiffness, frequencies, deck size and wall time.

    Raises
    ------
    InputError
        If an input is out of range (see :func:`calculix_deck`).
    SolverError
        If ``ccx`` is missing or fails.
    """
    deck = calculix_deck(mesh, material, force_N=force_N, direction=direction, n_modes=n_modes,
                         hex_element=hex_element, weights=weights)
    outputs, wall = run_ccx(deck.text, executable=executable, threads=threads, keep_dir=keep_dir)
    dat = outputs["dat"]
    delta = stiffness = float("nan")
    if force_N is not None:
        u = parse_tip_displacements(dat)
        delta = float(sum(w * u[i][direction] for i, w in zip(deck.tip_ids, deck.tip_weights)))
        stiffness = force_N / delta
    omega = f = np.zeros(0)
    if n_modes:
        omega, f = parse_frequencies(dat)
    return CalculixResult(element_type="+".join(deck.element_types), n_nodes=deck.n_nodes,
                          n_elements=mesh.n_elements, tip_deflection_m=delta, stiffness_N_per_m=stiffness,
                          frequencies_hz=f, omega_rad_s=omega, wall_time_s=wall)


class CalculixMatrices(NamedTuple):
    """Stiffness and mass matrices CalculiX assembles, on the free degrees of freedom.

    Attributes
    ----------
    stiffness : scipy.sparse.csr_matrix
        K, symmetric, shape (m, m) [N/m].
    mass : scipy.sparse.csr_matrix
        M (CalculiX's consistent mass, integrated at the element's stiffness integration
        points: singular for C3D20R's 2 x 2 x 2), symmetric, shape (m, m) [kg].
    dofs : numpy.ndarray
        (m, 2): the node id (0-based, of the written mesh) and direction (0, 1, 2) of each
        row; ids >= ``n_nodes`` are nodes CalculiX adds itself (the internal
        incompatible-mode nodes of C3D8I).
    n_nodes : int
        Nodes of the written mesh (with the mid-edge nodes of C3D20 types).
    """
    stiffness: object
    mass: object
    dofs: np.ndarray
    n_nodes: int


def _symmetric_from_upper(text, size):
    """A symmetric sparse matrix from CalculiX's 1-based ``row col value`` upper triangle."""
    data = np.loadtxt(text.splitlines(), ndmin=2)
    i, j, v = data[:, 0].astype(np.int64) - 1, data[:, 1].astype(np.int64) - 1, data[:, 2]
    off = i != j
    return sp.coo_matrix((np.concatenate([v, v[off]]), (np.concatenate([i, j[off]]), np.concatenate([j, i[off]]))),
                         shape=(size, size)).tocsr()


def calculix_matrices(mesh, material, *, hex_element="C3D20R", executable="ccx", threads=1):
    """The stiffness and consistent mass matrices CalculiX assembles for the clamped mesh.

    Runs a ``*FREQUENCY, SOLVER=MATRIXSTORAGE`` step (:func:`calculix_deck` with
    ``store_matrices``), so a peer K can be paired with another mass matrix (e.g. ccedi's
    lumped one) or compared entry by entry.

    Parameters
    ----------
    mesh : Mesh
        The ccedi mesh (:class:`ccedi.fea.mesh.Mesh`) with node sets ``root`` and ``tip``.
    material : NeoHookean
        E, nu, rho of the solid (:class:`ccedi.fea.material.NeoHookean`).
    hex_element : str, optional
        How hexahedra are written, one of :data:`HEX_ELEMENTS`. Default ``"C3D20R"``.
    executable : str, optional
        Name or path of ``ccx``. Default ``"ccx"``.
    threads : int, optional
        Threads of the run, >= 1. Default 1.

    Returns
    -------
    CalculixMatrices
        K, M and the degree of freedom of each row.

    Raises
    ------
    InputError
        If an input is out of range (see :func:`calculix_deck`).
    SolverError
        If ``ccx`` is missing or fails.
    """
    deck = calculix_deck(mesh, material, force_N=None, direction=1, n_modes=1, hex_element=hex_element,
                         store_matrices=True)
    outputs, _ = run_ccx(deck.text, executable=executable, threads=threads, read=("sti", "mas", "dof"))
    node_dir = np.array([line.split(".") for line in outputs["dof"].split()], dtype=np.int64) - 1
    m = len(node_dir)
    return CalculixMatrices(stiffness=_symmetric_from_upper(outputs["sti"], m),
                            mass=_symmetric_from_upper(outputs["mas"], m), dofs=node_dir, n_nodes=deck.n_nodes)
