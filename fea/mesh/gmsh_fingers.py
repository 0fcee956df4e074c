"""Tetrahedral finger meshes generated with Gmsh (the ``gmsh`` Python package): the paper's
SM-C, its detailed model DM and a finger that is not a prism.

* :func:`sm_c`: the paper's simplified model C, 10-node tetrahedra of the straight
  elliptical finger (semi-axes 12 mm along x, 8.45 mm along y, length along z, root at
  z = 0) at an average element length of 4 mm;
* :func:`detailed_model`: the paper's detailed model DM (Fig. 5(a)), a reconstruction of
  the real finger (circular end, tapering rectangular base, cone, thin plate, elliptical
  ribs) whose two free dimensions :func:`fit_detailed_model` fits to Table 1's volume
  and tip stiffness;
* :func:`tapered_finger`: an elliptical section tapering linearly from root to tip, with a
  transverse hole through it (along y, the bending direction) at mid-length: the
  imported finger of the tests and validation studies; :func:`write_tapered_finger` writes it as a
  ``.msh`` file (v4 or v2) with physical groups ``clamp`` (root face), ``tip`` (tip face)
  and ``finger`` (the volume).

Element size. The paper's "average length" of a tetrahedral mesh is read here as the edge
of the regular tetrahedron of the mean element volume, h = (6 sqrt(2) V / n)^(1/3) (the
paper's SM-C: 7481 nodes, 4682 elements, 4 mm -- that volume per element is a regular
tetrahedron of edge 4.04 mm). Gmsh's Delaunay tetrahedra at a target size s are not
regular: on the paper's finger their average length is 1.18 s (measured at s = 3.48 mm),
so the target given to Gmsh is :data:`GMSH_SIZE_RATIO` times the average length asked for.

Determinism: Gmsh runs with one thread, a fixed random seed and fixed algorithms
(Frontal-Delaunay surfaces, Delaunay volumes -- HXT for the DM, :data:`DM_ALGORITHM_3D` --,
high-order elements optimised until their Jacobians are positive), so a call gives the
same mesh every time. Gmsh is a process-wide
library that is not thread-safe and must be initialised once: each call takes a lock,
initialises Gmsh if nobody has (without the signal handler, so it also runs in a Dask
worker's thread), builds its own model, and finalises only what it initialised. The mesh
goes through a temporary ``.msh`` file and :func:`ccedi.fea.mesh.readers.read_finger_mesh`,
so a generated finger is read exactly as an imported one.
"""
import tempfile
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ccedi.errors import InputError, SolverError, require_finite_positive
from ccedi.fea.mesh import SEMI_AXES, _finger_length_m, finger_section
from ccedi.fea.mesh.readers import gmsh_session, read_finger_mesh

SM_C_ELEMENT_LENGTH = 4.0e-3
"""SM-C's average element length [m] (Table 1: "tetra (10-node), 4 mm")."""
GMSH_SIZE_RATIO = 0.87
"""Gmsh target size / average element length (module docstring): Gmsh's tetrahedra at
target s have an average length of 1.18 s on the paper's finger."""
MSH_VERSIONS = {4: 4.1, 2: 2.2}
"""Gmsh file format versions :func:`write_tapered_finger` writes, by major version."""


def _element_order(order):
    if order not in (1, 2):
        raise InputError(f"order = {order!r}: must be 1 (4-node tetrahedra) or 2 (10-node)")
    return order


def _mesh_and_write(gmsh, volume, length_m, element_size_m, order, path, msh_version=4, binary=False,
                    straight=False, algorithm_3d=1):
    """Name the root face ``clamp``, the tip face ``tip`` and ``volume`` ``finger``, mesh
    at the average element length ``element_size_m`` with Gmsh's 3D algorithm
    ``algorithm_3d`` (1 Delaunay, 10 HXT) and write ``path`` (``straight``: 10-node
    tetrahedra with straight edges, mid-edge nodes at the edges' midpoints)."""
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
    gmsh.option.setNumber("Mesh.Algorithm3D", algorithm_3d)
    gmsh.option.setNumber("Mesh.MshFileVersion", MSH_VERSIONS[msh_version])
    gmsh.option.setNumber("Mesh.Binary", int(bool(binary)))
    if straight:
        gmsh.option.setNumber("Mesh.SecondOrderLinear", 1)
        gmsh.option.setNumber("Mesh.HighOrderOptimize", 0)
    gmsh.model.mesh.generate(3)
    gmsh.write(str(path))


def _generated(build, length_m, element_size_m, order, name, straight=False, algorithm_3d=1):
    """Build the geometry with ``build(occ) -> volume tag``, mesh it, read it back as a
    :class:`ccedi.fea.mesh.Mesh` (node sets ``root`` and ``tip``)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"{name}.msh"
        with gmsh_session(name) as gmsh:
            _mesh_and_write(gmsh, build(gmsh.model.occ), length_m, element_size_m, order, path, straight=straight,
                            algorithm_3d=algorithm_3d)
        return read_finger_mesh(path, clamp="clamp", tip="tip")


def _elliptical_prism(a, b, length_m):
    def build(occ):
        disk = occ.addDisk(0.0, 0.0, 0.0, a, b)
        return [tag for dim, tag in occ.extrude([(2, disk)], 0.0, 0.0, length_m) if dim == 3][0]
    return build


def sm_c(length_in=4.5, *, element_size_m=SM_C_ELEMENT_LENGTH, semi_axes_m=SEMI_AXES, order=2):
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
    a, b = finger_section(semi_axes_m, length_m)
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
    root, tip = (finger_section(root_semi_axes_m, length_m, "root_semi_axes_m"),
                 finger_section(tip_semi_axes_m, length_m, "tip_semi_axes_m"))
    for name, (a, b) in (("root_semi_axes_m", root), ("tip_semi_axes_m", tip)):
        if a < b:
            raise InputError(f"{name} = {(a, b)!r}: a (along x) must be >= b (along y)")
    hole = require_finite_positive("hole_radius_m (m)", hole_radius_m, allow_zero=True)
    if hole >= 0.8 * min(root[0], tip[0], length_m / 4):
        raise InputError(f"hole_radius_m = {hole_radius_m!r}: must be < 0.8 of the smallest semi-axis along x "
                         "and of a quarter of the length")
    return length_m, root, tip, hole


def tapered_finger(element_size_m, *, length_in=4.5, root_semi_axes_m=TAPERED_ROOT_SEMI_AXES,
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


def write_tapered_finger(path, element_size_m, *, length_in=4.5, root_semi_axes_m=TAPERED_ROOT_SEMI_AXES,
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
    with gmsh_session("tapered_finger") as gmsh:
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
    (a0, b0), (a1, b1) = finger_section(root_semi_axes_m, length_m), finger_section(tip_semi_axes_m, length_m)
    da, db = a1 - a0, b1 - b0
    return float(np.pi * length_m * (a0 * b0 + (a0 * db + b0 * da) / 2 + da * db / 3))


DM_LENGTH_IN = 4.5
"""Length of the detailed model [in] (the paper's 4.5-in finger)."""
DM_ELEMENT_LENGTH = 2.8e-3
"""The detailed model's average element length [m] (Table 1: "tetra, 2.8 mm")."""
DM_ROOT_RADIUS = 17.5e-3
"""Radius of the DM's fixed circular end [m] (the paper's 17.5 mm)."""
DM_DISK_THICKNESS = 2.0e-3
"""Thickness along z of the DM's circular end [m] (chosen)."""
DM_BASE_ROOT_HALF = (15.0e-3, 6.0e-3)
"""Half-sides (x, y) of the DM's rectangular base section at the circular end [m]
(chosen: 30 mm x 12 mm, inside the 17.5-mm circle)."""
DM_BASE_END_HALF = (0.6, 0.3)
"""Half-sides (x, y) of the DM's rectangular base section where its taper ends, as
fractions of the cone's radius there (chosen: inside the cone, so that no face of the base
meets the cone at a grazing angle)."""
DM_BASE_LENGTH = 30.0e-3
"""Length along z of the DM's tapering rectangular base [m] (chosen)."""
DM_CONE_TAPER = 0.5
"""Tip radius / root radius of the DM's cone (chosen)."""
DM_PLATE_HALF_THICKNESS = 1.0e-3
"""Half-thickness (y) of the DM's thin horizontal plate [m] (chosen: 2 mm, thin in the
bending direction y)."""
DM_RIB_MARGINS = (4.0e-3, 2.0e-3)
"""A rib's semi-axes (x, y) exceed the cone's radius at the rib by these [m] (chosen);
the plate's half-width exceeds it by half the first. Every rib and the plate thus stand
clear of the cone by a millimetre or more, so that no two faces meet at a grazing angle
(which would leave sliver tetrahedra and a tiny explicit time step)."""
DM_RIBS = 8
"""Number of ribs of the DM (chosen), evenly spaced from the end of the base to the tip;
the last one is flush with the tip."""
DM_CONE_RADIUS_RANGE = (8.0e-3, 12.5e-3)
"""Root radii [m] of the cone :func:`detailed_model` accepts."""
DM_ALGORITHM_3D = 10
"""Gmsh's 3D algorithm for the DM: HXT (10), not Delaunay (1). Where a rib (0.81 mm thick,
one element across) meets the plate and the cone, four boundary nodes lie on a plane (two
on the rib's rim, two on the plate-cone edge, one pair on each rib face); Delaunay
tetrahedralised such planar quadrilaterals into slivers that its optimiser cannot move
(boundary nodes): at 10 mm, 6 elements with a minimum altitude below 1 % of their
longest edge (0.04 mm against 5.9 mm), one of which inverted in an explicit impulse run
at 2.19 ms. HXT's optimiser removes them by edge and face swaps (measured minimum
altitude / longest edge: Delaunay 0.0066 / 0.0081 / 0.0105, HXT 0.032 / 0.043 / 0.055 at
10 / 8 / 6 mm; the element spans the rib, so about 0.1 is the best there is)."""


def _ruled_box(occ, z0, z1, half0, half1):
    """The solid ruled between the rectangles ``|x| <= half[0], |y| <= half[1]`` at z0 and z1."""
    wires = []
    for z, (hx, hy) in ((z0, half0), (z1, half1)):
        corners = [occ.addPoint(x, y, z) for x, y in ((-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy))]
        wires.append(occ.addWire([occ.addLine(corners[i], corners[(i + 1) % 4]) for i in range(4)]))
    return [(d, t) for d, t in occ.addThruSections(wires, makeSolid=True, makeRuled=True) if d == 3]


def _dm_geometry(length_m, cone_radius_m, rib_thickness_m):
    """``build(occ)`` of the detailed model (:func:`detailed_model`): the union of the
    circular end, the tapering rectangular base, the cone, the plate and the ribs. Only the
    circular end reaches z = 0 and only the last rib z = L (the other parts start and end
    inside them), so that OpenCASCADE's union sees no coincident faces."""
    def radius(z):
        return cone_radius_m * (1.0 - (1.0 - DM_CONE_TAPER) * z / length_m)

    def build(occ):
        inset = DM_DISK_THICKNESS / 2
        end = length_m - rib_thickness_m / 2
        mx, my = DM_RIB_MARGINS
        disk = [(3, occ.addCylinder(0.0, 0.0, 0.0, 0.0, 0.0, DM_DISK_THICKNESS, DM_ROOT_RADIUS))]
        r_base = radius(DM_BASE_LENGTH)
        parts = _ruled_box(occ, inset, DM_BASE_LENGTH, DM_BASE_ROOT_HALF,
                           (DM_BASE_END_HALF[0] * r_base, DM_BASE_END_HALF[1] * r_base))
        parts.append((3, occ.addCone(0.0, 0.0, inset, 0.0, 0.0, end - inset, radius(inset), radius(end))))
        parts += _ruled_box(occ, inset, end, (radius(inset) + mx / 2, DM_PLATE_HALF_THICKNESS),
                            (radius(end) + mx / 2, DM_PLATE_HALF_THICKNESS))
        pitch = (length_m - DM_BASE_LENGTH) / DM_RIBS
        for k in range(1, DM_RIBS + 1):
            z0 = DM_BASE_LENGTH + k * pitch - rib_thickness_m
            r = radius(z0 + rib_thickness_m / 2)
            rib = occ.addDisk(0.0, 0.0, z0, r + mx, r + my)
            parts += [(d, t) for d, t in occ.extrude([(2, rib)], 0.0, 0.0, rib_thickness_m) if d == 3]
        body, _ = occ.fuse(parts[:1], parts[1:])
        out, _ = occ.fuse(disk, body)
        solids = [t for d, t in out if d == 3]
        if len(solids) != 1:
            raise InputError(f"detailed model: the parts' union gave {len(solids)} solids, not one "
                             f"(cone_radius_m = {cone_radius_m!r}, rib_thickness_m = {rib_thickness_m!r})")
        return solids[0]
    return build


def _dm_inputs(cone_radius_m, rib_thickness_m):
    length_m = _finger_length_m(length_in=DM_LENGTH_IN)
    cone = require_finite_positive("cone_radius_m (m)", cone_radius_m)
    lo, hi = DM_CONE_RADIUS_RANGE
    if not lo <= cone <= hi:
        raise InputError(f"cone_radius_m = {cone_radius_m!r}: must be in {lo:.4g}..{hi:.4g} (m)")
    rib = require_finite_positive("rib_thickness_m (m)", rib_thickness_m)
    if not 0.5e-3 <= rib <= 0.8 * (length_m - DM_BASE_LENGTH) / DM_RIBS:
        raise InputError(f"rib_thickness_m = {rib_thickness_m!r}: must be in 0.0005..{0.8 * (length_m - DM_BASE_LENGTH) / DM_RIBS:.4g} "
                         "(m), below 0.8 of the rib pitch")
    return length_m, cone, rib


DM_CONE_RADIUS = 11.2186e-3
"""Root radius of the DM's cone [m]: fitted to Table 1's stiffness by
:func:`fit_detailed_model` in ``validation/dm_fit.py`` at 2.8 mm, the stiffness evaluated
as the linear one at 2.8 mm times the nonlinear-to-linear ratio of a 6-mm DM (its
nonlinear solves take a minute or two there, some 20 minutes at 2.8 mm). Fitted on the
Delaunay mesh, re-measured on HXT's (:data:`DM_ALGORITHM_3D`): from this radius the fit's
first evaluation is within its 1 % of 81.2 N/m (ratio 1.0496, 76.99 / 73.35 N/m at 6 mm;
80.94 N/m), and the nonlinear Table 1 solve at 2.8 mm gives 80.49 N/m (-0.88 %,
``validation/dm_row.json``)."""
DM_RIB_THICKNESS = 0.8138e-3
"""Thickness along z of the DM's ribs [m]: fitted to Table 1's volume (30 cm^3, CAD) at
:data:`DM_CONE_RADIUS` (:func:`rib_thickness_for_volume`)."""
DM_TABLE1 = {"volume_m3": 30.0e-6, "stiffness_N_per_m": 81.2}
"""The DM's Table 1 figures the free dimensions are fitted to."""


def detailed_model(element_size_m=DM_ELEMENT_LENGTH, *, cone_radius_m=DM_CONE_RADIUS,
                   rib_thickness_m=DM_RIB_THICKNESS, order=2):
    """The paper's detailed model DM (Fig. 5(a), Table 1): a reconstruction of the real
    4.5-in finger (WK52H), meshed with tetrahedra.

    Length 4.5 in along z, root at z = 0, bending along y. The solid is the union of
    (paper's words in quotes, everything else chosen here since the paper gives no
    dimension):

    * "the fixed circular end (of 17.5 mm radius)": a disk of radius
      :data:`DM_ROOT_RADIUS`, :data:`DM_DISK_THICKNESS` thick, whose face z = 0 is the
      clamp;
    * "a rectangular section tapering from the fixed circular end": a ruled block from
      :data:`DM_BASE_ROOT_HALF` at the disk to :data:`DM_BASE_END_HALF` (of the cone's
      radius) at z = :data:`DM_BASE_LENGTH`;
    * "a cone": circular, root radius ``cone_radius_m``, tip radius
      :data:`DM_CONE_TAPER` times that;
    * "a thin horizontal plate": 2 x :data:`DM_PLATE_HALF_THICKNESS` thick in y (the
      bending direction, "designed to bend easily" in it), its half-width the cone's
      radius + :data:`DM_RIB_MARGINS` [0] / 2;
    * "evenly spaced elliptical ribs": :data:`DM_RIBS` elliptical disks ``rib_thickness_m``
      thick, semi-axes the cone's radius + :data:`DM_RIB_MARGINS`, evenly spaced from the
      base to the tip, the last one's face being the tip face.

    Matched to Table 1 (:func:`fit_detailed_model`): the volume (30 cm^3) by the rib
    thickness and the nonlinear static tip stiffness (81.2 N/m, 1 N and 2 N as the paper)
    by the cone's root radius. Everything else is a prediction: the time step, steps to
    0.2 s, step ratio, node and element counts, omega_1, the damping behaviour of Fig. 6
    and the stresses.

    Gmsh's HXT volume mesher (:data:`DM_ALGORITHM_3D`: Delaunay's left slivers where the
    ribs meet the plate and the cone). The 10-node tetrahedra have straight edges
    (mid-edge nodes at the midpoints): Gmsh's
    curved ones need its high-order optimisation on this geometry's thin parts (at 10, 8
    and 6 mm, 59, 46 and 7 elements have a negative Jacobian without it), which was seen
    to give different meshes from run to run on a loaded machine and once to abort the
    process ("Failed to reach critical value ... ScaledJac").

    Parameters
    ----------
    element_size_m : float, optional
        Average element length [m], 1e-4..0.05 (module docstring). Default 2.8 mm (Table 1).
    cone_radius_m : float, optional
        Root radius of the cone [m], within :data:`DM_CONE_RADIUS_RANGE`. Default the
        fitted :data:`DM_CONE_RADIUS`.
    rib_thickness_m : float, optional
        Rib thickness [m], 0.5 mm..0.8 of the rib pitch. Default the fitted
        :data:`DM_RIB_THICKNESS`.
    order : int, optional
        2: 10-node tetrahedra (the paper's DM); 1: 4-node. Default 2.

    Returns
    -------
    Mesh
        ``tets10`` (or ``tets4``), node sets ``root`` (the circular end, z = 0) and ``tip``
        (the last rib's face, z = L). At the defaults (measured, ``validation/dm_row.json``):
        28512 nodes, 16389 elements, mesh volume 29.78 cm^3, stable step 0.585 us, nonlinear
        tip stiffness 80.49 N/m (paper: 36782, 23147, 30 cm^3, 0.22 us, 81.2 N/m).

    Raises
    ------
    InputError
        A size, radius, thickness or order out of range.
    """
    length_m, cone, rib = _dm_inputs(cone_radius_m, rib_thickness_m)
    return _generated(_dm_geometry(length_m, cone, rib), length_m, _element_size(element_size_m),
                      _element_order(order), "detailed_model", straight=True, algorithm_3d=DM_ALGORITHM_3D)


def detailed_model_volume(cone_radius_m=DM_CONE_RADIUS, rib_thickness_m=DM_RIB_THICKNESS):
    """CAD volume of :func:`detailed_model` (OpenCASCADE's mass property, no mesh).

    Parameters
    ----------
    cone_radius_m, rib_thickness_m : float, optional
        As :func:`detailed_model`.

    Returns
    -------
    float
        Volume [m^3].

    Raises
    ------
    InputError
        A radius or thickness out of range.
    """
    length_m, cone, rib = _dm_inputs(cone_radius_m, rib_thickness_m)
    with gmsh_session("detailed_model_volume") as gmsh:
        volume = _dm_geometry(length_m, cone, rib)(gmsh.model.occ)
        gmsh.model.occ.synchronize()
        return gmsh.model.occ.getMass(3, volume)


def rib_thickness_for_volume(volume_m3, cone_radius_m):
    """The rib thickness [m] that gives :func:`detailed_model` the CAD volume ``volume_m3``
    at cone radius ``cone_radius_m``: the volume is affine in the rib thickness (a rib adds
    its ellipse less the cone's and the plate's sections, constant across its thickness
    to within the cone's taper), so two CAD volumes (1 mm and 2 mm ribs) give it.

    Parameters
    ----------
    volume_m3 : float
        Target volume [m^3].
    cone_radius_m : float
        Root radius of the cone [m].

    Returns
    -------
    float
        Rib thickness [m].

    Raises
    ------
    InputError
        The thickness needed is out of :func:`detailed_model`'s range.
    """
    v1, v2 = (detailed_model_volume(cone_radius_m, t) for t in (1.0e-3, 2.0e-3))
    thickness = 1.0e-3 + (volume_m3 - v1) / (v2 - v1) * 1.0e-3
    _dm_inputs(cone_radius_m, thickness)
    return float(thickness)


class DetailedModelFit(NamedTuple):
    """Result of :func:`fit_detailed_model`.

    Parameters
    ----------
    cone_radius_m, rib_thickness_m : float
        The fitted dimensions [m].
    volume_m3 : float
        CAD volume at them [m^3].
    stiffness_N_per_m : float
        Tip stiffness at them [N/m].
    evaluations : list
        ``(cone_radius_m, rib_thickness_m, stiffness_N_per_m)`` of every stiffness solve.
    """

    cone_radius_m: float
    rib_thickness_m: float
    volume_m3: float
    stiffness_N_per_m: float
    evaluations: list


def fit_detailed_model(stiffness_of, *, volume_m3=DM_TABLE1["volume_m3"],
                       stiffness_N_per_m=DM_TABLE1["stiffness_N_per_m"], element_size_m=DM_ELEMENT_LENGTH,
                       cone_radius_m=DM_CONE_RADIUS, rtol=0.005, max_evaluations=6):
    """Fit the DM's two free dimensions to Table 1: the rib thickness to the volume
    (:func:`rib_thickness_for_volume`, at every cone radius) and the cone's root radius to
    the tip stiffness, by a secant search on log k against log r (k ~ r^4 of a cone in
    bending for the first step, the measured slope after).

    Parameters
    ----------
    stiffness_of : callable
        ``stiffness_of(mesh) -> float``, tip stiffness [N/m] of a DM mesh (Table 1's:
        :func:`ccedi.fea.solvers.static.tip_stiffness` of its cantilever model).
    volume_m3 : float, optional
        Target volume [m^3]. Default Table 1's 30 cm^3.
    stiffness_N_per_m : float, optional
        Target stiffness [N/m]. Default Table 1's 81.2 N/m.
    element_size_m : float, optional
        Average element length [m] of the meshes solved. Default 2.8 mm.
    cone_radius_m : float, optional
        First cone radius [m].
    rtol : float, optional
        Relative tolerance on the stiffness. Default 0.5 %.
    max_evaluations : int, optional
        Stiffness solves allowed.

    Returns
    -------
    DetailedModelFit

    Raises
    ------
    SolverError
        The stiffness is not within ``rtol`` after ``max_evaluations`` solves.
    InputError
        A dimension leaves the generator's range on the way.
    """
    evaluations = []
    r = cone_radius_m
    for _ in range(max_evaluations):
        thickness = rib_thickness_for_volume(volume_m3, r)
        k = float(stiffness_of(detailed_model(element_size_m, cone_radius_m=r, rib_thickness_m=thickness)))
        evaluations.append((r, thickness, k))
        if abs(k / stiffness_N_per_m - 1.0) <= rtol:
            return DetailedModelFit(r, thickness, detailed_model_volume(r, thickness), k, evaluations)
        slope = 4.0
        if len(evaluations) > 1:
            (r0, _, k0), (r1, _, k1) = evaluations[-2:]
            slope = np.log(k1 / k0) / np.log(r1 / r0)
        r = float(np.clip(r * (stiffness_N_per_m / k) ** (1.0 / slope), *DM_CONE_RADIUS_RANGE))
    raise SolverError(f"fit_detailed_model: stiffness {k:.4g} N/m not within {rtol:g} of {stiffness_N_per_m:g} N/m "
                      f"after {max_evaluations} solves {evaluations}")
