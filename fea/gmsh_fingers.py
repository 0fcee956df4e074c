"""Tetrahedral finger meshes generated with Gmsh (the ``gmsh`` Python package): the paper's
SM-C and a finger that is not a prism.

* :func:`sm_c`: the paper's simplified model C, 10-node tetrahedra of the straight
  elliptical finger (semi-axes 12 mm along x, 8.45 mm along y, length along z, root at
  z = 0) at an average element length of 4 mm;
* :func:`tapered_finger`: an elliptical section tapering linearly from root to tip, with a
  transverse hole through it (along y, the bending direction) at mid-length: the
  imported finger of the tests and benchmarks; :func:`write_tapered_finger` writes it as a
  ``.msh`` file (v4 or v2) with physical groups ``clamp`` (root face), ``tip`` (tip face)
  and ``finger`` (the volume).

Element size. The paper's "average length" of a tetrahedral mesh is read here as the edge
of the regular tetrahedron of the mean element volume, h = (6 sqrt(2) V / n)^(1/3) (the
paper's SM-C: 7481 nodes, 4682 elements, 4 mm -- that volume per element is a regular
tetrahedron of edge 4.04 mm). Gmsh's Delaunay tetrahedra at a target size s are not
regular: on the paper's finger their average length is 1.18 s (measured at s = 3.48 mm),
so the target given to Gmsh is :data:`GMSH_SIZE_RATIO` times the average length asked for.

Determinism: Gmsh runs with one thread, a fixed random seed and fixed algorithms
(Frontal-Delaunay surfaces, Delaunay volumes, high-order elements optimised until their
Jacobians are positive), so a call gives the same mesh every time. Gmsh is a process-wide
library that is not thread-safe and must be initialised once: each call takes a lock,
initialises Gmsh if nobody has (without the signal handler, so it also runs in a Dask
worker's thread), builds its own model, and finalises only what it initialised. The mesh
goes through a temporary ``.msh`` file and :func:`ccedi.fea.mesh_io.read_finger_mesh`,
so a generated finger is read exactly as an imported one.
"""
import contextlib
import tempfile
import threading
from pathlib import Path

import numpy as np

from ccedi.errors import InputError, require_finite_positive

from .mesh import SEMI_AXES, _finger_length_m, _finger_section
from .mesh_io import read_finger_mesh

SM_C_ELEMENT_LENGTH = 4.0e-3
"""SM-C's average element length [m] (Table 1: "tetra (10-node), 4 mm")."""
GMSH_SIZE_RATIO = 0.87
"""Gmsh target size / average element length (module docstring): Gmsh's tetrahedra at
target s have an average length of 1.18 s on the paper's finger."""
MSH_VERSIONS = {4: 4.1, 2: 2.2}
"""Gmsh file format versions :func:`write_tapered_finger` writes, by major version."""
_LOCK = threading.Lock()


@contextlib.contextmanager
def _gmsh_model(name):
    """A fresh Gmsh model, quiet and deterministic; Gmsh initialised (and finalised) here
    only if it was not already."""
    import gmsh

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


def _element_order(order):
    if order not in (1, 2):
        raise InputError(f"order = {order!r}: must be 1 (4-node tetrahedra) or 2 (10-node)")
    return order


def _mesh_and_write(gmsh, volume, length_m, element_size_m, order, path, msh_version=4, binary=False):
    """Name the root face ``clamp``, the tip face ``tip`` and ``volume`` ``finger``, mesh
    at the average element length ``element_size_m`` and write ``path``."""
    gmsh.model.occ.synchronize()
    faces = gmsh.model.getBoundary([(3, volume)], oriented=False)
    z = {tag: gmsh.model.occ.getCenterOfMass(dim, tag)[2] for dim, tag in faces}
    for name, at in (("clamp", 0.0), ("tip", length_m)):
        gmsh.model.addPhysicalGroup(2, [t for t, zc in z.items() if abs(zc - at) < 1e-9 * length_m], name=name)
    gmsh.model.addPhysicalGroup(3, [volume], name="finger")
    size = GMSH_SIZE_RATIO * element_size_m
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
    gmsh.option.setNumber("Mesh.ElementOrder", order)
    gmsh.option.setNumber("Mesh.MshFileVersion", MSH_VERSIONS[msh_version])
    gmsh.option.setNumber("Mesh.Binary", int(bool(binary)))
    gmsh.model.mesh.generate(3)
    gmsh.write(str(path))


def _generated(build, length_m, element_size_m, order, name):
    """Build the geometry with ``build(occ) -> volume tag``, mesh it, read it back as a
    :class:`ccedi.fea.mesh.Mesh` (node sets ``root`` and ``tip``)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"{name}.msh"
        with _gmsh_model(name) as gmsh:
            _mesh_and_write(gmsh, build(gmsh.model.occ), length_m, element_size_m, order, path)
        return read_finger_mesh(path, clamp="clamp", tip="tip")


def _elliptical_prism(a, b, length_m):
    def build(occ):
        disk = occ.addDisk(0.0, 0.0, 0.0, a, b)
        return [tag for dim, tag in occ.extrude([(2, disk)], 0.0, 0.0, length_m) if dim == 3][0]
    return build


def sm_c(length_in=4.5, element_size_m=SM_C_ELEMENT_LENGTH, semi_axes_m=SEMI_AXES, order=2):
    """The paper's simplified model C: tetrahedra of the straight elliptical finger.

    Parameters
    ----------
    length_in : float, optional
        Finger length [in], 1..12. Default 4.5.
    element_size_m : float, optional
        Average element length [m] (module docstring), 1e-4..0.05. Default 4 mm.
    semi_axes_m : tuple of float, optional
        Section semi-axes (a along x, b along y, the bending direction) [m], a >= b.
        Default (12 mm, 8.45 mm).
    order : int, optional
        2: 10-node tetrahedra (the paper's SM-C); 1: 4-node. Default 2.

    Returns
    -------
    Mesh
        ``tets10`` (or ``tets4``), node sets ``root`` (z = 0) and ``tip`` (z = L).
        At the defaults: 7638 nodes, 4465 elements, average length 4.11 mm
        (paper: 7481, 4682, 4 mm).

    Raises
    ------
    InputError
        A length, semi-axis, size or order out of range, or a < b.
    """
    length_m = _finger_length_m(length_in=length_in)
    a, b = _finger_section(semi_axes_m)
    if a < b:
        raise InputError(f"semi_axes_m = {semi_axes_m!r}: a (along x) must be >= b (along y)")
    size = _element_size(element_size_m)
    return _generated(_elliptical_prism(a, b, length_m), length_m, size, _element_order(order), "sm_c")


def _element_size(element_size_m):
    size = require_finite_positive("element_size_m (average element length, m)", element_size_m)
    if not 1e-4 <= size <= 0.05:
        raise InputError(f"element_size_m = {element_size_m!r}: must be in 0.0001..0.05 (m)")
    return size


TAPERED_ROOT_SEMI_AXES = (12.0e-3, 8.45e-3)
"""Root section semi-axes of :func:`tapered_finger` [m] (the paper's section)."""
TAPERED_TIP_SEMI_AXES = (8.0e-3, 5.6e-3)
"""Tip section semi-axes of :func:`tapered_finger` [m] (two thirds of the root's)."""
TAPERED_HOLE_RADIUS = 3.0e-3
"""Radius of :func:`tapered_finger`'s transverse hole [m]."""
TAPERED_REFINEMENT_SIZES = (6.0e-3, 4.0e-3, 3.0e-3)
"""Average element lengths [m] of the tapered finger's refinement study: 2683, 6639 and
13116 nodes (1376, 3714, 7796 10-node tetrahedra); mesh volumes within 1.7e-4, 1.9e-5 and
5.4e-6 of the CAD volume 25.174 cm^3 (measured)."""


def _tapered_geometry(length_m, root, tip, hole_radius_m):
    """``build(occ)`` of the tapered finger: a ruled loft between the root and tip ellipses
    (semi-axes linear in z) less a cylinder along y through (0, 0, L/2)."""
    def build(occ):
        wires = [occ.addCurveLoop([occ.addEllipse(0.0, 0.0, z, a, b)]) for z, (a, b) in ((0.0, root),
                                                                                         (length_m, tip))]
        body = [t for d, t in occ.addThruSections(wires, makeSolid=True, makeRuled=True) if d == 3][0]
        if hole_radius_m == 0.0:
            return body
        reach = 2 * max(root[1], tip[1])
        hole = occ.addCylinder(0.0, -reach, length_m / 2, 0.0, 2 * reach, 0.0, hole_radius_m)
        cut, _ = occ.cut([(3, body)], [(3, hole)])
        return [t for d, t in cut if d == 3][0]
    return build


def _tapered_inputs(length_in, root_semi_axes_m, tip_semi_axes_m, hole_radius_m):
    length_m = _finger_length_m(length_in=length_in)
    root, tip = _finger_section(root_semi_axes_m), _finger_section(tip_semi_axes_m)
    for name, (a, b) in (("root_semi_axes_m", root), ("tip_semi_axes_m", tip)):
        if a < b:
            raise InputError(f"{name} = {(a, b)!r}: a (along x) must be >= b (along y)")
    hole = require_finite_positive("hole_radius_m (m)", hole_radius_m, allow_zero=True)
    if hole >= 0.8 * min(root[0], tip[0], length_m / 4):
        raise InputError(f"hole_radius_m = {hole_radius_m!r}: must be < 0.8 of the smallest semi-axis along x "
                         "and of a quarter of the length")
    return length_m, root, tip, hole


def tapered_finger(element_size_m, length_in=4.5, root_semi_axes_m=TAPERED_ROOT_SEMI_AXES,
                   tip_semi_axes_m=TAPERED_TIP_SEMI_AXES, hole_radius_m=TAPERED_HOLE_RADIUS, order=2):
    """A finger that is not a prism: an elliptical section tapering linearly from root to
    tip, with a transverse hole along y (the bending direction) at mid-length.

    Parameters
    ----------
    element_size_m : float
        Average element length [m], 1e-4..0.05 (module docstring).
    length_in : float, optional
        Finger length [in], 1..12. Default 4.5.
    root_semi_axes_m, tip_semi_axes_m : tuple of float, optional
        Section semi-axes (a along x, b along y) at z = 0 and z = L [m], a >= b.
        Default (12, 8.45) mm and (8, 5.6) mm.
    hole_radius_m : float, optional
        Radius of the hole [m], 0 for none, below 0.8 of the smallest semi-axis along x.
        Default 3 mm.
    order : int, optional
        2: 10-node tetrahedra; 1: 4-node. Default 2.

    Returns
    -------
    Mesh
        Tetrahedra, node sets ``root`` (z = 0) and ``tip`` (z = L).

    Raises
    ------
    InputError
        A length, semi-axis, radius, size or order out of range.
    """
    length_m, root, tip, hole = _tapered_inputs(length_in, root_semi_axes_m, tip_semi_axes_m, hole_radius_m)
    return _generated(_tapered_geometry(length_m, root, tip, hole), length_m, _element_size(element_size_m),
                      _element_order(order), "tapered_finger")


def write_tapered_finger(path, element_size_m, length_in=4.5, root_semi_axes_m=TAPERED_ROOT_SEMI_AXES,
                         tip_semi_axes_m=TAPERED_TIP_SEMI_AXES, hole_radius_m=TAPERED_HOLE_RADIUS, order=2,
                         msh_version=4, binary=False):
    """Write :func:`tapered_finger` as a Gmsh file with physical groups ``clamp`` (the root
    face, z = 0), ``tip`` (z = L) and ``finger`` (the volume); coordinates in metres.

    Parameters
    ----------
    path : str or pathlib.Path
        The ``.msh`` file to write.
    element_size_m, length_in, root_semi_axes_m, tip_semi_axes_m, hole_radius_m, order
        As :func:`tapered_finger`.
    msh_version : int, optional
        4 (format 4.1) or 2 (format 2.2). Default 4.
    binary : bool, optional
        Binary instead of ASCII. Default False.

    Returns
    -------
    float
        The CAD volume of the finger [m^3] (OpenCASCADE's mass property).

    Raises
    ------
    InputError
        As :func:`tapered_finger`, or a ``msh_version`` other than 2 or 4.
    """
    length_m, root, tip, hole = _tapered_inputs(length_in, root_semi_axes_m, tip_semi_axes_m, hole_radius_m)
    if msh_version not in MSH_VERSIONS:
        raise InputError(f"msh_version = {msh_version!r}: must be 4 or 2")
    size, order = _element_size(element_size_m), _element_order(order)
    with _gmsh_model("tapered_finger") as gmsh:
        volume = _tapered_geometry(length_m, root, tip, hole)(gmsh.model.occ)
        _mesh_and_write(gmsh, volume, length_m, size, order, path, msh_version, binary)
        return gmsh.model.occ.getMass(3, volume)


def tapered_volume(length_in=4.5, root_semi_axes_m=TAPERED_ROOT_SEMI_AXES, tip_semi_axes_m=TAPERED_TIP_SEMI_AXES):
    """Volume of the tapered finger without its hole: semi-axes linear in z,
    V = pi L (a0 b0 + (a0 db + b0 da) / 2 + da db / 3), da = a1 - a0, db = b1 - b0.

    Parameters
    ----------
    length_in : float, optional
        Finger length [in]. Default 4.5.
    root_semi_axes_m, tip_semi_axes_m : tuple of float, optional
        Semi-axes at the root and the tip [m].

    Returns
    -------
    float
        Volume [m^3].
    """
    length_m = _finger_length_m(length_in=length_in)
    (a0, b0), (a1, b1) = _finger_section(root_semi_axes_m), _finger_section(tip_semi_axes_m)
    da, db = a1 - a0, b1 - b0
    return float(np.pi * length_m * (a0 * b0 + (a0 * db + b0 * da) / 2 + da * db / 3))
