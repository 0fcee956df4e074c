"""Finger meshes from outside: read a solid mesh from a file, check it, and name its clamped
root and its loaded tip.

Formats: Gmsh ``.msh`` (v2 and v4, ASCII and binary) and Gmsh ``.geo`` scripts (meshed by
Gmsh in 3D with the script's settings), Abaqus ``.inp``, VTK ``.vtu`` /
``.vtk`` (all through meshio) and LS-DYNA keyword decks (``.k``, ``.key``, ``.dyn``: *NODE
and *ELEMENT_SOLID, as :mod:`ccedi.fea.io.lsdyna` writes them, in the one-line 8-node format
or the two-line format of up to 10 nodes; a 4-node tetrahedron may be written as a
degenerate hexahedron N1 N2 N3 N4 N4 N4 N4 N4).

Solid cells: 8-node hexahedra, 4-node and 10-node tetrahedra, one type per finger; node
orders are VTK's (:class:`ccedi.fea.mesh.Mesh`), which meshio already gives for Gmsh's
(whose 10-node tetrahedron swaps the last two mid-edge nodes), and which Abaqus (C3D8,
C3D4, C3D10) and LS-DYNA share. Vertices, lines, triangles and quadrilaterals (linear or
quadratic) in the file are boundary cells, used only to name node sets.

Conventions:

* the finger's length runs along z and it bends along y; ``bending_direction = "x"``
  turns the mesh +90 deg about z at import, (x, y, z) -> (-y, x, z), so that the file's x
  becomes ccedi's y (loads and deflections along y) -- a proper rotation, element
  orientations are kept;
* ``clamp`` and ``tip`` name node sets in the file's own coordinates (before that turn):
  a set name, or a coordinate plane ``"x_min"``, ..., ``"z_max"``: the nodes within
  :data:`PLANE_TOLERANCE` of the bounding-box diagonal of the mesh's extreme coordinate.
  Set names are Gmsh physical groups (of any dimension: the nodes of their cells), Abaqus
  *NSET and *ELSET, meshio cell sets, and LS-DYNA *SET_NODE_LIST ids (``"1"``);
* ``mesh_unit`` is the unit of the file's coordinates (``"m"`` or ``"mm"``).

Points that no cell uses (a CAD file's geometry points) are dropped; a point used by a
boundary cell, or in the set named as clamp or tip, but by no solid element is an error. Every problem is one
:class:`ccedi.errors.InputError` line naming the file, the problem and where.
"""
import contextlib
import importlib
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ccedi.errors import InputError, brief_repr, one_line
from ccedi.fea.elements.tetra import corner_volume
from ccedi.fea.io.lsdyna import keyword_blocks, solid_element_rows, solid_kind
from ccedi.fea.mesh import Mesh
from ccedi.fea.model import face_node_weights
from ccedi.quantities import QUANTITIES

UNITS = {"m": 1.0, "mm": 1e-3}
"""Size of a file's coordinate unit in metres, by ``mesh_unit``."""
PLANES = tuple(f"{axis}_{end}" for axis in "xyz" for end in ("min", "max"))
"""The coordinate planes ``clamp`` and ``tip`` may name."""
BENDING_DIRECTIONS = ("y", "x")
"""The file axes a finger may bend along (``"x"``: turned +90 deg about z at import)."""
PLANE_TOLERANCE = 1e-5
"""A node lies on a plane ``x_min`` ... ``z_max`` when it is within this fraction of the
mesh's bounding-box diagonal of the extreme coordinate (1.4 um on the paper's finger): far
above the rounding of coordinates written with 7 or more significant digits, far below any
element size (an element would need an aspect ratio of 1e5 to put an interior node there)."""
DEGENERATE_VOLUME = 1e-6
"""An element is inverted or degenerate when its smallest local volume (Jacobian
determinant times the reference cell's volume, at its corners and integration points) is
at most this fraction of the mesh's mean element volume."""
KEYWORD_SUFFIXES = (".k", ".key", ".dyn")
"""File suffixes read as LS-DYNA keyword decks."""
MESHIO_SUFFIXES = {".msh": "gmsh", ".inp": "abaqus", ".vtu": "vtu", ".vtk": "vtk"}
"""File suffixes read through meshio, with the meshio reader of each."""
SOLID_CELLS = {"hexahedron": 8, "tetra": 4, "tetra10": 10}
"""meshio names of the solid cells ccedi reads, with their node counts."""
BOUNDARY_CELLS = {"vertex": 0, "line": 1, "line3": 1, "triangle": 2, "triangle6": 2, "quad": 2, "quad8": 2,
                  "quad9": 2}
"""meshio names of the lower-dimensional cells read as boundary cells, with their dimension."""
_FIELD = {"hexahedron": "hexes", "tetra": "tets4", "tetra10": "tets10"}
GMSH_SCRIPT_SUFFIX = ".geo"
"""A Gmsh script: meshed in 3D by Gmsh with the script's own settings, then read as its
``.msh``."""
_LOCK = threading.Lock()


@contextlib.contextmanager
def gmsh_session(name):
    """A fresh Gmsh model, quiet and deterministic; Gmsh initialised (and finalised) here
    only if it was not already.

    Parameters
    ----------
    name : str
        The model's name.

    Yields
    ------
    module
        The ``gmsh`` module, its current model the new one (one thread at a time).
    """
    import gmsh  # the Gmsh library loads only when a mesh is generated

    with _LOCK:
        own = not gmsh.isInitialized()
        if own:
            gmsh.initialize(readConfigFiles=False, interruptible=False)
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.option.setNumber("General.Verbosity", 0)
            gmsh.model.add(name)
            for option, value in (("General.NumThreads", 1), ("Mesh.MaxNumThreads3D", 1),
                                  ("Mesh.RandomSeed", 1), ("Mesh.Algorithm", 6), ("Mesh.Algorithm3D", 1),
                                  ("Mesh.HighOrderOptimize", 1), ("Mesh.MeshSizeFromPoints", 0),
                                  ("Mesh.MeshSizeExtendFromBoundary", 1), ("Mesh.MeshSizeFromCurvature", 0)):
                gmsh.option.setNumber(option, value)
            yield gmsh
        finally:
            if own:
                gmsh.finalize()
            else:
                gmsh.model.remove()


def _read_gmsh_script(path):
    """A Gmsh ``.geo`` script meshed in 3D (its own size and order settings apply) and read
    as the ``.msh`` it gives."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / (path.stem + ".msh")
        with gmsh_session(path.stem) as gmsh:
            try:
                gmsh.open(str(path))
                gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
                gmsh.model.mesh.generate(3)
                gmsh.write(str(out))
            except Exception as err:        # Gmsh raises a bare Exception with its own message
                raise InputError(f"{path}: Gmsh could not mesh the script ({one_line(err) or type(err).__name__})") \
                    from None
        return _read_meshio(out, "gmsh")


@dataclass(frozen=True)
class FingerMeshSpec:
    """An imported finger: the file and how to read it (:func:`read_finger_mesh`).

    Parameters
    ----------
    path : str or pathlib.Path
        The mesh file.
    mesh_unit : str, optional
        Unit of its coordinates, ``"m"`` or ``"mm"``. Default ``"m"``.
    clamp : str, optional
        The clamped root: a set name or a plane (``"z_min"``, ...). Default ``"z_min"``.
    tip : str, optional
        The loaded tip: a set name or a plane. Default ``"z_max"``.
    bending_direction : str, optional
        The file axis the finger bends along, ``"y"`` or ``"x"``. Default ``"y"``.
    """
    path: str
    mesh_unit: str = "m"
    clamp: str = "z_min"
    tip: str = "z_max"
    bending_direction: str = "y"

    def load(self):
        """Read the mesh (:func:`read_finger_mesh`).

        Returns
        -------
        Mesh
            The finger with node sets ``root`` and ``tip``.

        Raises
        ------
        InputError
            As :func:`read_finger_mesh`.
        """
        return read_finger_mesh(self.path, mesh_unit=self.mesh_unit, clamp=self.clamp, tip=self.tip,
                                bending_direction=self.bending_direction)


@dataclass
class _RawMesh:
    """A file's content: points, solid cells {meshio type: (e, k)}, boundary cells
    [(type, (e, k))], named node sets {name: point ids}."""

    points: np.ndarray
    solids: dict
    boundary: list
    sets: dict


def _choice(name, value, allowed):
    if not isinstance(value, str) or value not in allowed:
        raise InputError(f"{name} = {brief_repr(value)}: must be one of {', '.join(allowed)}")
    return value


def read_finger_mesh(path, *, mesh_unit="m", clamp="z_min", tip="z_max", bending_direction="y"):
    """Read and check a solid finger mesh; name its clamped root and loaded tip.

    Parameters
    ----------
    path : str or pathlib.Path
        Gmsh ``.msh``, Abaqus ``.inp``, ``.vtu`` / ``.vtk``, or an LS-DYNA deck (``.k``,
        ``.key``, ``.dyn``).
    mesh_unit : str, optional
        Unit of the file's coordinates: ``"m"`` or ``"mm"``. Default ``"m"``.
    clamp : str, optional
        The clamped nodes: a set name of the file or a plane of :data:`PLANES` (file
        coordinates). Default ``"z_min"``.
    tip : str, optional
        The loaded tip nodes, likewise. Default ``"z_max"``.
    bending_direction : str, optional
        The file axis the finger bends along: ``"y"``, or ``"x"`` (the mesh is turned
        +90 deg about z, (x, y, z) -> (-y, x, z)). Default ``"y"``.

    Returns
    -------
    Mesh
        Nodes [m] (only those of solid elements, renumbered in file order), the solid
        elements in VTK node order, node sets ``root`` (the clamp) and ``tip``.

    Raises
    ------
    InputError
        One line naming the file and the problem: no such file or not parseable; an
        unsupported cell type; mixed solid types; no solid cells; an inverted or degenerate
        element (index among the file's solid cells, and centroid); a node on a boundary cell
        or set but on no solid element; disconnected parts (their sizes); a finger length
        along z outside 1..12 in (is ``mesh_unit`` right?) or shorter than the mesh is wide
        (a finger lying along x or y); an unknown or empty clamp or tip (with the names
        available), or one that holds no complete element face (a rounded tip); clamp and
        tip sharing nodes; a bad argument value.
    """
    scale = UNITS[_choice("mesh_unit", mesh_unit, tuple(UNITS))]
    _choice("bending_direction", bending_direction, BENDING_DIRECTIONS)
    for name, value in (("clamp", clamp), ("tip", tip)):
        if not isinstance(value, str) or not value:
            raise InputError(f"{name} = {brief_repr(value)}: must be a set name or one of {', '.join(PLANES)}")
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such mesh file")
    suffix = path.suffix.lower()
    if suffix not in KEYWORD_SUFFIXES and suffix not in MESHIO_SUFFIXES and suffix != GMSH_SCRIPT_SUFFIX:
        raise InputError(f"{path}: unknown mesh format {suffix or '(no suffix)'!r}; ccedi reads "
                         f"{', '.join([*MESHIO_SUFFIXES, *KEYWORD_SUFFIXES, GMSH_SCRIPT_SUFFIX])}")
    if suffix in KEYWORD_SUFFIXES:
        raw = _read_keyword(path)
    elif suffix == GMSH_SCRIPT_SUFFIX:
        raw = _read_gmsh_script(path)
    else:
        raw = _read_meshio(path, MESHIO_SUFFIXES[suffix])
    kind, cells = _solid_cells(path, raw)
    used = np.unique(cells)
    _no_orphans(path, raw, used)
    renumber = np.full(len(raw.points), -1, dtype=np.int64)
    renumber[used] = np.arange(len(used))
    nodes = raw.points[used] * scale
    cells = renumber[cells]
    _check_elements(path, kind, nodes, cells)
    _one_part(path, len(nodes), cells)
    _length_along_z(path, nodes, mesh_unit)
    sets = {"root": _node_set(path, "clamp", clamp, raw, renumber, nodes),
            "tip": _node_set(path, "tip", tip, raw, renumber, nodes)}
    shared = np.intersect1d(sets["root"], sets["tip"])
    if len(shared):
        raise InputError(f"{path}: clamp {clamp!r} and tip {tip!r} share {len(shared)} nodes "
                         f"(e.g. node {shared[0]} at {_at(nodes[shared[0]])})")
    if bending_direction == "x":
        nodes = np.column_stack([-nodes[:, 1], nodes[:, 0], nodes[:, 2]])
    mesh = Mesh(nodes=nodes, node_sets=sets, **{_FIELD[kind]: cells})
    for role, name in (("clamp", clamp), ("tip", tip)):
        _whole_faces(path, mesh, role, name)
    return mesh


def _at(point, unit="m"):
    return "(" + ", ".join(f"{c:.4g}" for c in point) + f") {unit}"


def _read_meshio(path, reader):
    """A file read by meshio's ``reader`` module as a :class:`_RawMesh` (sets: cell sets,
    point sets and Gmsh physical groups). The format's reader is called directly:
    ``meshio.read`` prints and exits the process on a file it cannot read."""

    if path.stat().st_size == 0:
        raise InputError(f"{path}: the file is empty (0 bytes); export the finger mesh again")
    try:
        m = importlib.import_module(f"meshio.{reader}").read(str(path))
    except Exception as err:        # meshio raises ReadError, ValueError, KeyError, ... on a bad file
        raise InputError(f"{path}: cannot read the mesh ({one_line(err) or type(err).__name__}); is it a complete "
                         f"{reader} file?") from None
    points = np.asarray(m.points, dtype=float)
    if not len(points):
        raise InputError(f"{path}: no nodes in the file")
    bad = np.flatnonzero(~np.isfinite(points).all(axis=1))
    if len(bad):
        raise InputError(f"{path}: node {bad[0]} has a non-finite coordinate {brief_repr(points[bad[0], :3].tolist())} "
                         f"({len(bad)} such nodes)")
    solids, boundary = {}, []
    for block in m.cells:
        data = np.asarray(block.data, dtype=np.int64)
        if block.type in SOLID_CELLS:
            solids[block.type] = np.concatenate([solids[block.type], data]) if block.type in solids else data
        elif block.type in BOUNDARY_CELLS:
            boundary.append((block.type, data))
        else:
            raise InputError(f"{path}: unsupported cell type {block.type} ({len(data)} cells); ccedi reads "
                             f"{', '.join(SOLID_CELLS)} solids and {', '.join(BOUNDARY_CELLS)} boundary cells")
    sets = {name: np.asarray(ids, dtype=np.int64) for name, ids in m.point_sets.items()}
    for name, per_block in m.cell_sets.items():
        if not name.startswith("gmsh:"):
            sets[name] = _nodes_of(m.cells, lambda i, b: np.asarray(per_block[i], dtype=np.int64))
    physical = m.cell_data.get("gmsh:physical")
    for name, (tag, dim) in ((n, v[:2]) for n, v in m.field_data.items() if physical is not None and len(v) >= 2):
        if name not in sets:
            sets[name] = _nodes_of(m.cells, lambda i, b: np.flatnonzero(
                (np.asarray(physical[i]) == tag) & (_dimension(b.type) == dim)))
    return _RawMesh(np.asarray(m.points, dtype=float)[:, :3], solids, boundary, sets)


def _dimension(cell_type):
    return 3 if cell_type in SOLID_CELLS else BOUNDARY_CELLS.get(cell_type, -1)


def _nodes_of(blocks, pick):
    """The points of the cells ``pick(i, block)`` selects in each block."""
    parts = [np.asarray(b.data, dtype=np.int64)[pick(i, b)].ravel() for i, b in enumerate(blocks)]
    return np.unique(np.concatenate(parts)) if parts else np.zeros(0, dtype=np.int64)


def _keyword_fields(line, width):
    if "," in line:
        return [f.strip() for f in line.split(",")]
    return [line[i:i + width].strip() for i in range(0, len(line.rstrip()), width)]


def _read_keyword(path):
    """An LS-DYNA deck's *NODE and *ELEMENT_SOLID (one-line 8-node or two-line <= 10-node
    format) and *SET_NODE_LIST (named by their ids) as a :class:`_RawMesh`."""
    try:
        blocks = keyword_blocks(path.read_text(errors="strict"))
        ids, points = [], []
        for line in (ln for b in blocks.get("*NODE", []) for ln in b):
            f = (_keyword_fields(line, 8) if "," in line
                 else [line[:8]] + [line[8 + 16 * k:24 + 16 * k] for k in range(3)])
            ids.append(int(f[0]))
            points.append([float(c) for c in f[1:4]])
        elements = [nodes for block in blocks.get("*ELEMENT_SOLID", []) for _, _, nodes in solid_element_rows(block)]
        sets = {}
        for block in blocks.get("*SET_NODE_LIST", []):
            rows = [_keyword_fields(ln, 10) for ln in block]
            sets[rows[0][0]] = [int(v) for r in rows[1:] for v in r if v and int(v) != 0]
    except (ValueError, IndexError, StopIteration, UnicodeDecodeError) as err:
        raise InputError(f"{path}: cannot read the LS-DYNA deck ({one_line(err) or type(err).__name__})") from None
    if not ids:
        raise InputError(f"{path}: no *NODE card")
    index = {node_id: i for i, node_id in enumerate(ids)}

    def local(node_ids):
        missing = [n for n in node_ids if n not in index]
        if missing:
            raise InputError(f"{path}: node id {missing[0]} is used but not defined in *NODE")
        return [index[n] for n in node_ids]
    solids = {}
    for nodes in elements:
        kind, nodes = _keyword_solid(path, nodes)
        solids.setdefault(kind, []).append(local(nodes))
    return _RawMesh(np.asarray(points, dtype=float), {k: np.asarray(v, dtype=np.int64) for k, v in solids.items()},
                    [], {name: np.asarray(local(v), dtype=np.int64) for name, v in sets.items()})


def _keyword_solid(path, nodes):
    """(meshio type, node ids) of one *ELEMENT_SOLID node list (zeros dropped)."""
    kind, solid = solid_kind(nodes)
    if kind is not None:
        return {"tet4": "tetra", "hex8": "hexahedron", "tet10": "tetra10"}[kind], solid
    distinct = len(set(nodes))
    shape = {5: "pyramid", 6: "wedge"}.get(distinct, f"{len(nodes)}-node solid of {distinct} distinct nodes")
    raise InputError(f"{path}: unsupported cell type {shape} (an *ELEMENT_SOLID of nodes {nodes[:10]})")


def _solid_cells(path, raw):
    """(meshio type, connectivity) of the one solid type in ``raw``."""
    counts = {k: len(v) for k, v in raw.solids.items() if len(v)}
    if not counts:
        found = ", ".join(sorted({t for t, _ in raw.boundary})) or "no cells"
        raise InputError(f"{path}: no solid cells ({found}); ccedi needs {', '.join(SOLID_CELLS)} cells")
    if len(counts) > 1:
        raise InputError(f"{path}: mixes solid cell types ({', '.join(f'{n} {k}' for k, n in counts.items())}); "
                         "ccedi meshes a finger with one solid type")
    kind = next(iter(counts))
    cells = raw.solids[kind]
    if cells.min() < 0 or cells.max() >= len(raw.points):
        raise InputError(f"{path}: a {kind} cell uses a node that does not exist")
    return kind, cells


def _no_orphans(path, raw, used):
    """A point of a boundary cell must be on a solid element."""
    on_solid = np.zeros(len(raw.points), dtype=bool)
    on_solid[used] = True
    for cell_type, cells in raw.boundary:
        ids = cells.ravel()
        bad = ids[(ids < 0) | (ids >= len(on_solid))]
        if len(bad):
            raise InputError(f"{path}: a {cell_type} cell uses node {bad[0]}, which does not exist")
        free = ids[~on_solid[ids]]
        if len(free):
            where = _at(raw.points[free[0]], "file units")
            raise InputError(f"{path}: node {free[0]} (of a {cell_type} cell, at {where}) belongs to no solid element")


def _length_along_z(path, nodes, mesh_unit):
    """The finger's length runs along z: its z extent is its largest, within 1..12 in."""
    extent = np.ptp(nodes, axis=0)
    length, widest = float(extent[2]), int(np.argmax(extent[:2]))
    if extent[widest] > length:
        raise InputError(f"{path}: the finger is {length:.4g} m along z but {extent[widest]:.4g} m along "
                         f"{'xy'[widest]}: ccedi's finger runs along z (root at z_min, tip at z_max); rotate the "
                         "mesh so that its length runs along z")
    q = QUANTITIES["length_m"]
    if not q.lo <= length <= q.hi:
        raise InputError(f"{path}: the finger is {length:.4g} m long along z with mesh_unit = {mesh_unit!r}, "
                         f"outside {q.lo:g}..{q.hi:g} m (the length runs along z): is mesh_unit right?")


def _whole_faces(path, mesh, role, name):
    """A clamp or tip must hold at least one complete element face (a load or a support
    on separate nodes is no finger's)."""
    ids = mesh.node_sets["root" if role == "clamp" else "tip"]
    try:
        face_node_weights(mesh, ids)
    except InputError:
        tol_mm = 1e3 * PLANE_TOLERANCE * float(np.linalg.norm(np.ptp(mesh.nodes, axis=0)))
        plane = (f" ({name} takes only the nodes within {tol_mm:.2g} mm of the extreme {name[0]}: a rounded "
                 f"{role}?)" if name in PLANES else "")
        raise InputError(f"{path}: {role} = {name!r} picks {len(ids)} node(s), e.g. at {_at(mesh.nodes[ids[0]])}, "
                         f"which make no complete element face{plane}; name a node set (physical group) of the "
                         f"{role}'s faces in the mesh file as [finger] {role}, or give the finger a flat "
                         f"{role}") from None


# --- element geometry -------------------------------------------------------------------

_GL3 = (np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)]) + 1) / 2, np.array([5, 8, 5]) / 18
"""3-point Gauss-Legendre rule on [0, 1]."""


def _tet10_points():
    """Points (barycentric xi1..xi3) and weights of a rule exact for the cubic Jacobian
    determinant of a 10-node tetrahedron (the Duffy map of a 3 x 3 x 3 Gauss rule)."""
    g, w = _GL3
    u, v, s = (a.ravel() for a in np.meshgrid(g, g, g, indexing="ij"))
    weights = (w[:, None, None] * w[None, :, None] * w[None, None, :]).ravel() * (1 - u) ** 2 * (1 - v)
    return np.column_stack([u, v * (1 - u), s * (1 - u) * (1 - v)]), weights


def _tet10_gradients(xi):
    """Shape-function derivatives dN/dxi, shape (q, 10, 3), of the VTK-ordered 10-node
    tetrahedron at reference points ``xi`` (q, 3)."""
    L = np.column_stack([1 - xi.sum(axis=1), xi])                     # barycentric L0..L3
    dL = np.array([[-1, -1, -1], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    corners = (4 * L - 1)[:, :, None] * dL[None]                      # d(L_i (2 L_i - 1))
    edges = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
    mids = [4 * (L[:, i, None] * dL[j] + L[:, j, None] * dL[i]) for i, j in edges]
    return np.concatenate([corners, np.stack(mids, axis=1)], axis=1)


def _hex_gradients(xi):
    """dN/dxi, shape (q, 8, 3), of the VTK-ordered 8-node hexahedron on [-1, 1]^3."""
    s = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                  [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
    f = 1 + xi[:, None, :] * s[None]                                  # (q, 8, 3)
    return np.stack([s[None, :, k] * np.prod(np.delete(f, k, axis=2), axis=2) / 8 for k in range(3)], axis=2)


def _jacobians(nodes, cells, gradients):
    """det(dx/dxi) of every cell at every point, shape (e, q)."""
    return np.linalg.det(np.einsum("eai,qaj->eqij", nodes[cells], gradients))


def element_volumes(mesh):
    """Volume of every solid element, exact for the element's own geometry.

    Hexahedra: 2 x 2 x 2 Gauss points (exact for the trilinear map); 4-node tetrahedra:
    V = (x1 - x0) . ((x2 - x0) x (x3 - x0)) / 6; 10-node tetrahedra (curved edges):
    a 27-point rule exact for their cubic Jacobian determinant.

    Parameters
    ----------
    mesh : Mesh
        The mesh (one solid type or several).

    Returns
    -------
    numpy.ndarray
        Signed volumes [m^3], hexahedra, then 4-node, then 10-node tetrahedra.
    """
    g = np.array([-1, 1]) / np.sqrt(3)
    hex_points = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    tet_points, tet_weights = _tet10_points()
    x = mesh.nodes
    return np.concatenate([
        _jacobians(x, mesh.hexes, _hex_gradients(hex_points)).sum(axis=1),
        corner_volume(x[mesh.tets4]),
        _jacobians(x, mesh.tets10, _tet10_gradients(tet_points)) @ tet_weights])


def _smallest_local_volumes(kind, nodes, cells):
    """Per element, the smallest det(J) times the reference cell's volume at its corners
    (and, for the 10-node tetrahedron, its integration points): the element's volume for
    an undistorted element, <= 0 for an inverted one."""
    if kind == "tetra":
        return corner_volume(nodes[cells])
    if kind == "hexahedron":
        corners = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                            [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
        return 8 * _jacobians(nodes, cells, _hex_gradients(corners)).min(axis=1)
    corners = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    points = np.concatenate([corners, _tet10_points()[0]])
    return _jacobians(nodes, cells, _tet10_gradients(points)).min(axis=1) / 6


def _check_elements(path, kind, nodes, cells):
    """Every element's smallest local volume > :data:`DEGENERATE_VOLUME` x mean volume."""
    local = _smallest_local_volumes(kind, nodes, cells)
    mean = np.abs(element_volumes(Mesh(nodes, **{_FIELD[kind]: cells}))).mean()
    bad = np.flatnonzero(~(local > DEGENERATE_VOLUME * mean))
    if len(bad):
        e = bad[np.argmin(local[bad])]
        raise InputError(f"{path}: {len(bad)} inverted or degenerate {kind} elements, e.g. element {e} "
                         f"(0-based among the solid cells) at centroid {_at(nodes[cells[e]].mean(axis=0))}, "
                         f"local volume {local[e]:.3g} m^3 (mean element volume {mean:.3g} m^3)")


def _one_part(path, n_nodes, cells):
    """The elements form one connected part (sharing nodes)."""
    e = np.repeat(np.arange(len(cells)), cells.shape[1])
    graph = coo_matrix((np.ones(len(e)), (cells.ravel(), n_nodes + e)), shape=(n_nodes + len(cells),) * 2)
    n, labels = connected_components(graph, directed=False)
    if n > 1:
        sizes = np.sort(np.bincount(labels[n_nodes:], minlength=n))[::-1]
        shown = ", ".join(map(str, sizes[:5])) + (", ..." if n > 5 else "")
        raise InputError(f"{path}: the mesh has {n} disconnected parts ({shown} elements); "
                         "ccedi needs one connected finger")


def _node_set(path, role, name, raw, renumber, nodes):
    """Node ids (of ``nodes``) of the set or plane ``name``."""
    if name in PLANES:
        axis = "xyz".index(name[0])
        extreme = nodes[:, axis].min() if name.endswith("min") else nodes[:, axis].max()
        tol = PLANE_TOLERANCE * np.linalg.norm(np.ptp(nodes, axis=0))
        ids = np.flatnonzero(np.abs(nodes[:, axis] - extreme) <= tol)
    elif name in raw.sets:
        ids = np.asarray(raw.sets[name], dtype=np.int64)
        ids = np.unique(renumber[ids[(ids >= 0) & (ids < len(renumber))]])
        if len(ids) and ids[0] < 0:
            raise InputError(f"{path}: {role} = {name!r} holds nodes that belong to no solid element")
    else:
        known = ", ".join(sorted(raw.sets)) or "none"
        raise InputError(f"{path}: {role} = {name!r}: no such set (the file's sets: {known}; "
                         f"or a plane {', '.join(PLANES)})")
    if len(ids) == 0:
        raise InputError(f"{path}: {role} = {name!r} holds no node of the finger")
    return ids
