"""The finger as a chain of Craig-Bampton superelements.

The straight finger mesh (along z, soft bending along y, see :mod:`ccedi.fea.mesh`) is cut at
n + 1 stations z_0 = 0 < z_1 < ... < z_n = L (planes of mesh nodes) into n segments.
Each segment keeps its two end sections as boundary; in the bending plane a section
moves rigidly, so the boundary of a segment is six planar DOFs::

    d = [U_a, V_a, theta_a, U_b, V_b, theta_b]     (along the finger, across it, rotation)
    face node at height y:   u_z = U - theta y,   u_y = V,   u_x free (interior)

The motion is symmetric about the finger's mid-plane x = 0, so nodes on that plane keep
u_x = 0 (an exact symmetry condition, which also removes the out-of-plane rigid motions
a planar interface cannot hold).

Every other DOF of the segment is interior and is condensed by
:func:`ccedi.rom.craig_bampton.craig_bampton` with no fixed-interface modes (a segment's
first fixed-interface mode lies above 10 kHz, far above anything the contact excites):
``K_e = T^T K T``, ``M_e = T^T M T`` (6 x 6), and ``T`` recovers the segment's full
displacement field, hence its stresses.

A free segment moves rigidly with three of its six DOFs, so K_e = G^T K_n G with the
natural deformations of the segment (chord of length l0 along z)::

    e = G d = [U_b - U_a,  theta_a - (V_b - V_a)/l0,  theta_b - (V_b - V_a)/l0]

and the 3 x 3 natural stiffness ``K_n`` (axial force, end moments) is what the co-rotational
dynamics in :mod:`ccedi.rom.chain_dynamics` uses. Station masses are the row sums of the
translational Guyan mass (they add up to the finger's mass); the rotary inertia of a
station is the diagonal rotation entry of M_e (the section's second moment of mass).

A rigid section is stiffer than the real one (it stops the section's in-plane
distortion at each cut), so the chain is "fitted from the FEA": the bending block of
K_n is scaled by ``kappa = k_tip(FE) / k_tip(chain)`` so that the chain's linear tip
stiffness equals the full FE model's (:func:`fit_tip_stiffness`). Stresses follow the
section forces, not the constrained deformation (:func:`stress_recovery`).
"""
from dataclasses import dataclass, replace

import numba as nb
import numpy as np
import scipy.sparse as sp
from scipy.linalg import eigh

from ccedi.errors import InputError
from ccedi.fea.elements.fastmath import FASTMATH
from ccedi.fea.elements.hex8 import deformation_gradient, element_geometry
from ccedi.fea.material import NeoHookean, cauchy_stress, neo_hookean_cauchy, von_mises, von_mises_components
from ccedi.fea.mesh import Mesh
from ccedi.fea.model import Model, cantilever_model
from ccedi.fea.solvers.static import tangent_stiffness, tip_deflection
from ccedi.rom.craig_bampton import craig_bampton


@dataclass(frozen=True)
class FingerChain:
    """Reduced finger: n segments between n + 1 stations (station 0 is the root).

    Parameters
    ----------
    station_z_m : (n+1,) ndarray
        Station distances from the root along the finger [m], increasing from 0.
    mass_kg : (n+1,) ndarray
        Station masses [kg] (row sums of the translational Guyan mass).
    inertia_kg_m2 : (n+1,) ndarray
        Station rotary inertias about the section's x axis [kg m^2].
    natural_stiffness : (n, 3, 3) ndarray
        Natural stiffness K_n of each segment [N/m, N, N m], acting on
        e = [elongation [m], end rotations theta_a, theta_b relative to the chord [rad]].
    half_thickness_m : float
        Largest half thickness of the finger [m] (the reach of its contact points).
    stress_zones : tuple of StressZone
        The stress recovery zones of :func:`finger_chain`.
    face_offsets_m : (n+1, 2) ndarray
        Distances of the +y and -y faces from the axis at each station [m] (columns in
        that order): the contact points sit there.
    stiffness_scale : float, optional
        The fitted bending factor kappa [-] (1 before fitting, default).
    """

    station_z_m: np.ndarray
    mass_kg: np.ndarray
    inertia_kg_m2: np.ndarray
    natural_stiffness: np.ndarray
    half_thickness_m: float
    stress_zones: tuple
    face_offsets_m: np.ndarray
    stiffness_scale: float = 1.0

    @property
    def n_segments(self):
        """Number of segments n (stations minus one)."""
        return len(self.station_z_m) - 1

    @property
    def segment_length_m(self):
        """Segment rest lengths l0, shape (n,) [m]."""
        return np.diff(self.station_z_m)


def deformation_map(l0):
    """Map G from a segment's planar end DOFs to its natural deformations, e = G d.

    ``e = [U_b - U_a, theta_a - (V_b - V_a)/l0, theta_b - (V_b - V_a)/l0]`` for
    ``d = [U_a, V_a, theta_a, U_b, V_b, theta_b]`` (module docstring).

    Parameters
    ----------
    l0 : float
        Segment (chord) length [m].

    Returns
    -------
    (3, 6) ndarray
        G [-, 1/m] (rows: elongation [m], end rotations [rad]).
    """
    return np.array([[-1.0, 0.0, 0.0, 1.0, 0.0, 0.0],
                     [0.0, 1.0 / l0, 1.0, 0.0, -1.0 / l0, 0.0],
                     [0.0, 1.0 / l0, 0.0, 0.0, -1.0 / l0, 1.0]])


def natural_stiffness(K_e, l0):
    """Natural stiffness K_n of a free segment, with ``K_e = G^T K_n G``.

    ``K_n = G^+T K_e G^+`` (G^+ the pseudo-inverse of :func:`deformation_map`),
    symmetrised. Valid when K_e has the three planar rigid motions in its null space.

    Parameters
    ----------
    K_e : (6, 6) ndarray
        Segment stiffness on d = [U_a, V_a, theta_a, U_b, V_b, theta_b] [N/m, N, N m].
    l0 : float
        Segment (chord) length [m].

    Returns
    -------
    (3, 3) ndarray
        Symmetric natural stiffness K_n [N/m, N, N m] on e = [elongation, theta_a,
        theta_b].

    Raises
    ------
    InputError
        If ``G^T K_n G`` misses K_e by a relative residual above 1e-6, i.e. the
        segment is not free or not straight.
    """
    G = deformation_map(l0)
    Gp = np.linalg.pinv(G)
    K_n = Gp.T @ K_e @ Gp
    err = np.linalg.norm(G.T @ K_n @ G - K_e) / np.linalg.norm(K_e)
    if err > 1e-6:
        raise InputError(f"segment stiffness is not rigid-motion invariant (residual {err:.2e})")
    return 0.5 * (K_n + K_n.T)


def _section_transform(nodes, faces, clamp_a, symmetric):
    """Sparse map from [d (6), interior DOFs] to all 3 N DOFs of a segment whose end
    faces are ``faces = ((z_a, node ids), (z_b, node ids))`` (local z): face nodes move as
    rigid sections in the y-z plane about the station (u_z = U - theta y,
    u_y = V + theta (z - z_face), the second term zero on a node plane); everything else
    is interior. The out-of-plane rigid motion a planar interface cannot hold is removed
    by u_x = 0 on the mid-plane x = 0 of a ``symmetric`` finger (an exact symmetry
    condition), else by u_x = 0 at one node of face a (a determinate support: no in-plane
    load reaches it); with ``clamp_a``, u_x = 0 on face a (the finger's clamped root face)."""
    n = len(nodes)
    tied = np.zeros((n, 3), dtype=bool)
    if symmetric:
        tied[np.abs(nodes[:, 0]) < 1e-9 * np.ptp(nodes[:, 0]), 0] = True
    face_a = faces[0][1]
    if clamp_a:
        tied[face_a, 0] = True
    elif not symmetric:
        tied[face_a[np.argmin(np.abs(nodes[face_a, 0] - nodes[face_a, 0].mean()))], 0] = True
    rows, cols, vals = [], [], []
    tol = 1e-12 * np.ptp(nodes[:, 2])
    for k, (z_face, face) in enumerate(faces):
        for node in face:
            rows += [3 * node + 2, 3 * node + 2, 3 * node + 1]
            cols += [3 * k, 3 * k + 2, 3 * k + 1]
            vals += [1.0, -nodes[node, 1], 1.0]
            if abs(nodes[node, 2] - z_face) > tol:
                rows.append(3 * node + 1)
                cols.append(3 * k + 2)
                vals.append(nodes[node, 2] - z_face)
            tied[node, 1:] = True
    interior = np.flatnonzero(~tied.ravel())
    rows += list(interior)
    cols += list(6 + np.arange(len(interior)))
    vals += [1.0] * len(interior)
    return sp.csr_matrix((vals, (rows, cols)), shape=(3 * n, 6 + len(interior)))


ELEMENT_ARRAYS = ("hexes", "tets4", "tets10")
"""The solid element arrays of :class:`ccedi.fea.mesh.Mesh`, in the order the chain keeps
per-element data (stress recovery)."""


def _element_centroid_z(mesh: Mesh):
    """{element array name: centroid z of each element [m]}."""
    return {name: mesh.nodes[getattr(mesh, name), 2].mean(axis=1) for name in ELEMENT_ARRAYS}


def _is_layered(mesh: Mesh):
    """Every element of ``mesh`` is a hexahedron spanning two node planes z = const (the
    generated, structured finger)."""
    if mesh.element_type != "hex8":
        return False
    z = mesh.nodes[mesh.hexes, 2]
    tol = 1e-9 * np.ptp(mesh.nodes[:, 2])
    return bool(np.all(np.abs(z[:, :4] - z[:, :1]) < tol) and np.all(np.abs(z[:, 4:] - z[:, 4:5]) < tol))


def _is_mirror_symmetric(nodes):
    """The node cloud maps onto itself under x -> -x (to 1e-9 of its size)."""
    q = np.round(nodes / (1e-9 * np.ptp(nodes, axis=0).max())).astype(np.int64)
    m = q * np.array([-1, 1, 1])
    return bool(np.array_equal(q[np.lexsort(q.T)], m[np.lexsort(m.T)]))


@dataclass(frozen=True)
class Cuts:
    """Where a chain cuts a finger mesh (:func:`chain_cuts`).

    Parameters
    ----------
    z : (n+1,) ndarray
        Station positions along the finger [m], root 0 to tip.
    faces : tuple of ndarray
        Node ids of each station's interface: the root node set, the nodes shared by the
        elements of neighbouring segments, the tip face.
    centroid_z : dict
        ``{element array name: centroid z [m]}``: an element belongs to the segment
        (z_i, z_{i+1}] holding its centroid.
    symmetric : bool
        The mesh is mirror-symmetric about x = 0 (:func:`_section_transform`).
    planes : bool
        The interfaces are node planes (a structured hexahedral finger), not bands.
    """

    z: np.ndarray
    faces: tuple
    centroid_z: dict
    symmetric: bool
    planes: bool


def chain_cuts(mesh: Mesh, n_segments):
    """Cut a straight finger mesh (along z, root at z = 0, node sets ``root`` and ``tip``)
    into ``n_segments`` segments.

    A structured hexahedral finger is cut at its node planes (:func:`station_planes`); any
    other mesh (tetrahedra, an imported or Gmsh finger) at evenly spaced stations, its
    elements assigned to segments by their centroids, and the interface of two segments
    is the set of nodes their elements share (a jagged band one element thick, moved as a
    rigid section). The tip station is the tip face: the nodes at the largest z.

    Parameters
    ----------
    mesh : Mesh
        Straight finger mesh along z with a ``root`` node set.
    n_segments : int
        Number of segments.

    Returns
    -------
    Cuts

    Raises
    ------
    InputError
        Bad ``n_segments`` (more segments than element layers, or segments shorter than
        an element: two interfaces share a node, or a segment has no elements), a mesh
        without a ``root`` node set, or a tip face that is not a section (fewer than three
        nodes, or all at one height y).
    """
    if "root" not in mesh.node_sets:
        raise InputError("the finger mesh has no 'root' node set (the clamped face): the chain is clamped there")
    L = float(mesh.nodes[:, 2].max())
    planes = _is_layered(mesh)
    if planes:
        z = station_planes(mesh, n_segments)
    else:
        if int(n_segments) != n_segments or n_segments < 1:
            raise InputError(f"n_segments must be an integer >= 1, got {n_segments!r}")
        z = np.linspace(0.0, L, int(n_segments) + 1)
    centroid_z = _element_centroid_z(mesh)
    segment_nodes = []
    for a, b in zip(z[:-1], z[1:]):
        used = [getattr(mesh, k)[(zc > a) & (zc <= b)] for k, zc in centroid_z.items()]
        nodes = np.unique(np.concatenate([u.ravel() for u in used]))
        if not len(nodes):
            raise InputError(f"n_segments = {n_segments}: the segment from z = {a:.4g} to {b:.4g} m holds no "
                             f"element centroid; use fewer segments")
        segment_nodes.append(nodes)
    tip = np.flatnonzero(mesh.nodes[:, 2] > L - 1e-6 * L)
    if len(tip) < 3 or np.ptp(mesh.nodes[tip, 1]) <= 1e-6 * L:
        raise InputError(f"the finger's tip at z = {L:.4g} m is not a flat face across its thickness ({len(tip)} "
                         f"nodes there): the reduced model ends in a section; run the full FEA")
    faces = [np.asarray(mesh.node_sets["root"])]
    faces += [np.intersect1d(segment_nodes[i - 1], segment_nodes[i]) for i in range(1, len(z) - 1)]
    faces.append(tip)
    for i in range(len(faces) - 1):
        if np.intersect1d(faces[i], faces[i + 1]).size:
            raise InputError(f"n_segments = {n_segments}: segments of {np.diff(z).min() * 1e3:.3g} mm are shorter "
                             f"than this mesh's elements (the interfaces at z = {z[i]:.4g} and {z[i + 1]:.4g} m "
                             f"share nodes); use fewer segments")
    return Cuts(z=z, faces=tuple(faces), centroid_z=centroid_z, symmetric=_is_mirror_symmetric(mesh.nodes),
                planes=planes)


@dataclass(frozen=True)
class Segment:
    """One reduced (Craig-Bampton, Guyan) segment.

    Parameters
    ----------
    K_e : (6, 6) ndarray
        Reduced stiffness on d = [U_a, V_a, theta_a, U_b, V_b, theta_b] [N/m, N, N m].
    M_e : (6, 6) ndarray
        Reduced mass on d [kg, kg m, kg m^2].
    field : (3 N, 6) ndarray
        Recovery of the segment's nodal displacements (x, y, z per node) [m] from d.
    mesh : Mesh
        The segment's own mesh (N nodes, z measured from its face a).
    """

    K_e: np.ndarray
    M_e: np.ndarray
    field: np.ndarray
    mesh: Mesh


def fitting_segments(mesh: Mesh, n_max):
    """The most segments, at most ``n_max``, that :func:`chain_cuts` can cut ``mesh`` into
    (segments longer than the mesh's elements).

    Parameters
    ----------
    mesh : Mesh
        Straight finger mesh along z.
    n_max : int
        Largest number of segments wanted, >= 1.

    Returns
    -------
    int

    Raises
    ------
    InputError
        Not even one segment fits (from :func:`chain_cuts`: no root set, no tip face).
    """
    for n in range(int(n_max), 1, -1):
        try:
            chain_cuts(mesh, n)
            return n
        except InputError:
            continue
    chain_cuts(mesh, 1)
    return 1


def reduce_segment(mesh: Mesh, material: NeoHookean, cuts: Cuts, *, a, b):
    """Craig-Bampton (Guyan) reduction of the elements of ``mesh`` between stations a and b.

    The interfaces at stations a and b move as rigid sections in the y-z plane (module
    docstring; station 0 is the clamped root), the interior, stations between a and b
    included, is condensed statically (no fixed-interface modes):
    ``K_e = T^T K T``, ``M_e = T^T M T``.

    Parameters
    ----------
    mesh : Mesh
        Straight finger mesh along z.
    material : NeoHookean
        Finger material (linearised at the reference state).
    cuts : Cuts
        The chain's cut of ``mesh`` (:func:`chain_cuts`).
    a, b : int
        First and last station, a < b.

    Returns
    -------
    Segment
        Reduced matrices, displacement recovery and sub-mesh.
    """
    z_a, z_b = cuts.z[a], cuts.z[b]
    kept = {k: getattr(mesh, k)[(zc > z_a) & (zc <= z_b)] for k, zc in cuts.centroid_z.items()}
    used = np.unique(np.concatenate([c.ravel() for c in kept.values()]))
    local = np.full(mesh.n_nodes, -1, dtype=np.int64)
    local[used] = np.arange(len(used))
    nodes = mesh.nodes[used] - [0.0, 0.0, z_a]
    sub = Mesh(nodes=nodes, **{k: local[c] for k, c in kept.items()})
    model = Model(mesh=sub, material=material)
    faces = ((0.0, local[cuts.faces[a]]), (z_b - z_a, local[cuts.faces[b]]))
    T_c = _section_transform(nodes, faces, a == 0, cuts.symmetric)
    K = (T_c.T @ tangent_stiffness(model) @ T_c).tocsc()
    M = (T_c.T @ sp.diags(np.repeat(model.mass, 3)) @ T_c).tocsc()
    cb = craig_bampton(K, M, np.arange(K.shape[0]), boundary_dofs=np.arange(6), n_modes=0)
    return Segment(K_e=cb.K_r, M_e=cb.M_r, field=T_c @ cb.T, mesh=sub)


def centre_gradients(mesh: Mesh, u):
    """Displacement gradient at the centre of every element (hexahedra, then 4-node, then
    10-node tetrahedra): the hexahedron's uniform gradient, a tetrahedron's from its four
    corners (a 10-node tetrahedron's mid-edge nodes are left out: the gradient of its
    linear part, exact for a linear field).

    Parameters
    ----------
    mesh : Mesh
    u : (n, 3) ndarray
        Nodal displacements [m].

    Returns
    -------
    (e, 3, 3) ndarray
        du_i / dX_j [-].
    """
    out = []
    if len(mesh.hexes):
        out.append(deformation_gradient(u[mesh.hexes], element_geometry(mesh.nodes, mesh.hexes)))
    for conn in (mesh.tets4, mesh.tets10):
        if len(conn):
            c = conn[:, :4]
            D = (mesh.nodes[c[:, 1:]] - mesh.nodes[c[:, :1]]).swapaxes(1, 2)      # columns X_k - X_0
            dU = (u[c[:, 1:]] - u[c[:, :1]]).swapaxes(1, 2)
            out.append(np.linalg.solve(D.swapaxes(1, 2), dU.swapaxes(1, 2)).swapaxes(1, 2))
    return np.concatenate(out)


def _gradient_modes(segment: Segment):
    """Displacement gradient (elements, 3, 3, 3) at the element centres of each unit natural
    deformation e_j, realised as d = [0, 0, e2, e1, 0, e3] (any d with the same e differs
    by a rigid motion)."""
    d = np.zeros((6, 3))
    d[3, 0] = d[2, 1] = d[5, 2] = 1.0
    u = (segment.field @ d).reshape(-1, 3, 3)                 # (nodes, xyz, mode)
    return np.stack([centre_gradients(segment.mesh, u[:, :, j]) for j in range(3)], axis=1)


def station_planes(mesh: Mesh, n_segments):
    """Station planes of a chain: node planes of ``mesh`` as evenly spaced as possible.

    Parameters
    ----------
    mesh : Mesh
        Straight finger mesh along z.
    n_segments : int
        Number of segments, from 1 to the number of element layers.

    Returns
    -------
    (n_segments + 1,) ndarray
        Node-plane positions z [m], root and tip included.

    Raises
    ------
    InputError
        If ``n_segments`` is not an integer in 1..(number of element layers).
    """
    z = np.unique(mesh.nodes[:, 2])
    if int(n_segments) != n_segments or not 1 <= n_segments <= len(z) - 1:
        raise InputError(f"n_segments must be an integer in 1..{len(z) - 1} (element layers), got {n_segments!r}")
    return z[np.round(np.linspace(0, len(z) - 1, int(n_segments) + 1)).astype(int)]


ROOT_ZONE_DEPTHS = 1.0
"""Length of the root stress zone in section depths (2 x the half thickness). The zone
must be long enough that the clamp's stress does not feel how the load enters at its far
end (Saint-Venant). On the 8-in SM-A finger, one depth (the zone then ends at the first
station past it, 24 mm) gives the FE clamp stress under a static tip load within 1.6 %
(36 mm: 0.3 %, 12 mm: +4.4 %). The zone is loaded by its end segments' section forces
(:meth:`StressRecovery.deformations`), so a longer zone, whose ends turn by up to a
radian against its chord in the contact case, no longer overstates the stress (read from
the zone's chord deformation, the 36 mm zone's stress came out 7-11 % above the full
FEA's on the 8-in finger, and the 33 mm zone of a 5-in finger 26 mm thick 8 %)."""


@dataclass(frozen=True)
class StressZone:
    """Stress recovery zone over stations a..b of a chain.

    Parameters
    ----------
    a : int
        First station of the zone.
    b : int
        Last station of the zone (> a).
    gradients : (n_elem, 3, 3, 3) ndarray
        Displacement gradient at each element centre of each unit natural deformation
        of the zone's chord, indexed (element, mode j, 3, 3) [-/m or -/rad].
    stiffness : (3, 3) ndarray
        Natural stiffness of the zone's own reduced model [N/m, N, N m].
    """

    a: int
    b: int
    gradients: np.ndarray
    stiffness: np.ndarray


def _stress_zone(mesh, material, cuts, a, b):
    seg = reduce_segment(mesh, material, cuts, a=a, b=b)
    l0 = cuts.z[b] - cuts.z[a]
    return seg, StressZone(a=a, b=b, gradients=_gradient_modes(seg), stiffness=natural_stiffness(seg.K_e, l0))


def finger_chain(mesh: Mesh, material: NeoHookean, n_segments=17):
    """Reduce a straight, clamped finger mesh to a chain of superelements (unfitted).

    The mesh is cut by :func:`chain_cuts` (node planes of a structured hexahedral finger,
    evenly spaced stations otherwise). The contact points sit on the mesh's faces: each
    station's half thicknesses (:attr:`FingerChain.face_offsets_m`) are the largest +y and
    -y of the nodes within half a segment of it (+-b on the elliptical prism; a tapered
    finger's faces follow its taper). Stresses are recovered per zone: the root zone
    (stations 0..r, at least ``ROOT_ZONE_DEPTHS`` section depths long, its root face
    clamped like the FE model's) and every segment beyond it, so the clamp's stress does
    not depend on where the segments are cut. An interface that is a band of elements
    (any mesh but the structured one) moves rigidly and holds no stress, so there every
    pair of segments beyond the root zone is a zone too, with the band in its middle: a
    hole or notch at a station keeps its stress concentration. Fit the bending stiffness
    with :func:`fit_tip_stiffness`.

    Parameters
    ----------
    mesh : Mesh
        Straight finger mesh along z, root at z = 0 (clamped, node set ``root``).
    material : NeoHookean
        Finger material.
    n_segments : int, optional
        Number of superelements (see :func:`chain_cuts`). Default 17.

    Returns
    -------
    FingerChain
        The reduced chain, ``stiffness_scale`` 1.

    Raises
    ------
    InputError
        From :func:`chain_cuts` (bad ``n_segments``, no root set, no tip face) or
        :func:`natural_stiffness`.
    """
    cuts = chain_cuts(mesh, n_segments)
    z = cuts.z
    offsets = _face_offsets(mesh.nodes, z)
    half_thickness_m = float(offsets.max())
    rigid_u = np.array([1.0, 0.0, 0.0, 1.0, 0.0, 0.0])
    mass, inertia = np.zeros(len(z)), np.zeros(len(z))
    K_n, zones = [], []
    root_end = int(np.searchsorted(z, ROOT_ZONE_DEPTHS * offsets[0].sum()))
    root_end = min(max(root_end, 1), len(z) - 1)
    zones.append(_stress_zone(mesh, material, cuts, 0, root_end)[1])
    for s in range(len(z) - 1):
        seg, zone = _stress_zone(mesh, material, cuts, s, s + 1)
        K_n.append(zone.stiffness)
        if s >= root_end:
            zones.append(zone)
        if not cuts.planes and root_end <= s < len(z) - 2:      # a zone across the band at station s + 1
            zones.append(_stress_zone(mesh, material, cuts, s, s + 2)[1])
        for end, (u, th) in enumerate(((0, 2), (3, 5))):
            mass[s + end] += (seg.M_e @ rigid_u)[u]
            inertia[s + end] += seg.M_e[th, th]
    return FingerChain(station_z_m=z, mass_kg=mass, inertia_kg_m2=inertia, natural_stiffness=np.array(K_n),
                       half_thickness_m=half_thickness_m, stress_zones=tuple(zones), face_offsets_m=offsets)


def _face_offsets(nodes, z):
    """(n+1, 2) distances [m] of the +y and -y faces from the finger's axis at each
    station: the largest +y and -y of the nodes within half a segment of it."""
    half = 0.5 * np.diff(z).min()
    out = np.zeros((len(z), 2))
    for i, zi in enumerate(z):
        near = nodes[np.abs(nodes[:, 2] - zi) <= half * (1.0 + 1e-9), 1]
        out[i] = near.max(), -near.min()
    return out


def _assembled_stiffness(chain: FingerChain, a, b):
    """Linear stiffness of the chain's segments between stations a and b on the planar DOFs
    [U_i, V_i, theta_i] of stations a..b, all free: sum of G^T K_n G per segment."""
    K = np.zeros((3 * (b - a + 1),) * 2)
    for s in range(a, b):
        G = deformation_map(chain.segment_length_m[s])
        i = 3 * (s - a)
        K[i:i + 6, i:i + 6] += G.T @ chain.natural_stiffness[s] @ G
    return K


def linear_matrices(chain: FingerChain):
    """Assembled linear stiffness and lumped mass of the clamped chain.

    ``K = sum_s G_s^T K_n,s G_s`` on the planar DOFs [U_i, V_i, theta_i] of stations
    1..n (station 0 clamped, its rows and columns removed).

    Parameters
    ----------
    chain : FingerChain
        The chain.

    Returns
    -------
    K : (3n, 3n) ndarray
        Stiffness [N/m, N, N m].
    M : (3n, 3n) ndarray
        Diagonal lumped mass (mass, mass, rotary inertia per station) [kg, kg m^2].
    """
    K = _assembled_stiffness(chain, 0, chain.n_segments)
    m = np.column_stack([chain.mass_kg, chain.mass_kg, chain.inertia_kg_m2]).ravel()
    return K[3:, 3:], np.diag(m[3:])


def chain_tip_stiffness(chain: FingerChain):
    """Linear tip stiffness of the clamped chain under a transverse tip force.

    Parameters
    ----------
    chain : FingerChain
        The chain.

    Returns
    -------
    float
        ``1 / V_tip`` for a unit force across the finger at the tip [N/m].
    """
    K, _ = linear_matrices(chain)
    f = np.zeros(len(K))
    f[-2] = 1.0
    return 1.0 / np.linalg.solve(K, f)[-2]


def chain_frequencies(chain: FingerChain, n_modes=None):
    """Natural frequencies of the clamped chain, linearised about the straight finger.

    Solves ``K phi = omega^2 M phi`` with :func:`linear_matrices`.

    Parameters
    ----------
    chain : FingerChain
        The chain.
    n_modes : int, optional
        Number of lowest frequencies to return. Default None: all 3n.

    Returns
    -------
    ndarray
        Ascending natural frequencies omega [rad/s] (negative eigenvalues clipped to 0).
    """
    K, M = linear_matrices(chain)
    w2 = eigh(K, M, eigvals_only=True)
    return np.sqrt(np.clip(w2, 0.0, None))[:n_modes]


def fe_tip_stiffness(mesh: Mesh, material: NeoHookean):
    """Linear tip stiffness of the full clamped FE finger under a tip-face load along y.

    Parameters
    ----------
    mesh : Mesh
        Straight finger mesh along z, root at z = 0.
    material : NeoHookean
        Finger material.

    Returns
    -------
    float
        Tip force over tip deflection of the linear static cantilever [N/m].
    """
    return 1.0 / tip_deflection(cantilever_model(mesh, material), 1.0, linear=True)


def fit_tip_stiffness(chain: FingerChain, k_tip_target):
    """The chain with its bending stiffness scaled to a target tip stiffness.

    With ``kappa = k_tip_target / k_tip(chain)`` every K_n becomes ``D K_n D``,
    ``D = diag(1, sqrt(kappa), sqrt(kappa))``: the bending block is multiplied by kappa,
    the axial-bending coupling by sqrt(kappa), so the bending compliance is divided by
    kappa. A transverse tip force loads the straight cantilever in bending only, so its
    linear tip stiffness becomes ``k_tip_target``.

    Parameters
    ----------
    chain : FingerChain
        The chain to fit.
    k_tip_target : float
        Target linear tip stiffness [N/m], e.g. :func:`fe_tip_stiffness`.

    Returns
    -------
    FingerChain
        A copy with the scaled ``natural_stiffness`` and ``stiffness_scale`` multiplied
        by kappa.
    """
    kappa = k_tip_target / chain_tip_stiffness(chain)
    K_n = chain.natural_stiffness.copy()
    K_n[:, 1:, 1:] *= kappa
    K_n[:, 1:, 0] *= np.sqrt(kappa)
    K_n[:, 0, 1:] *= np.sqrt(kappa)
    return replace(chain, natural_stiffness=K_n, stiffness_scale=kappa * chain.stiffness_scale)


def zone_stiffness(chain: FingerChain, a, b):
    """Natural stiffness of the chain's segments between two stations.

    The stations strictly between a and b are condensed out statically (Schur
    complement) and the remaining 6 x 6 end stiffness is passed to
    :func:`natural_stiffness`.

    Parameters
    ----------
    chain : FingerChain
        The chain.
    a : int
        First station.
    b : int
        Last station (> a).

    Returns
    -------
    (3, 3) ndarray
        Natural stiffness over the chord from station a to b [N/m, N, N m].

    Raises
    ------
    InputError
        From :func:`natural_stiffness`.
    """
    K = _assembled_stiffness(chain, a, b)
    ends = np.r_[0:3, len(K) - 3:len(K)]
    mid = np.arange(3, len(K) - 3)
    K6 = K[np.ix_(ends, ends)] - K[np.ix_(ends, mid)] @ np.linalg.solve(K[np.ix_(mid, mid)], K[np.ix_(mid, ends)])
    return natural_stiffness(K6, chain.station_z_m[b] - chain.station_z_m[a])


@dataclass(frozen=True)
class StressRecovery:
    """Stress operator of a chain (built by :func:`stress_recovery`).

    Parameters
    ----------
    zone_a, zone_b : (z,) int ndarray
        First and last station of each zone (zones may overlap).
    zone_of_element : (n_elem,) int ndarray
        Zone of each recovery element.
    gradients : (n_elem, 3, 3, 3) ndarray
        Displacement gradient of each element per unit natural deformation of the
        chain over its zone, indexed (element, mode j, 3, 3).
    material : NeoHookean
        The finger material.
    segment_stiffness : (n, 3, 3) ndarray
        The chain's (fitted) natural stiffness per segment [N/m, N, N m]
        (:attr:`FingerChain.natural_stiffness`).
    zone_compliance : (z, 3, 3) ndarray
        Inverse of the chain's natural stiffness over each zone
        (:func:`zone_stiffness`) [m/N, 1/N, 1/(N m)].
    """

    zone_a: np.ndarray
    zone_b: np.ndarray
    zone_of_element: np.ndarray
    gradients: np.ndarray
    material: NeoHookean
    segment_stiffness: np.ndarray
    zone_compliance: np.ndarray

    def deformations(self, P, TH, station_z_m, *, nonlinear=True):
        """Natural deformations of every zone from station states: those of the chain over
        the zone that carry the section forces at its two ends.

        Each segment's natural deformations ``e = [l - l0, theta_a - psi, theta_b - psi]``
        of its chord (length l, angle psi; linear: ``l - l0 = dx - l0``, ``psi = dy / l0``),
        as :func:`ccedi.rom.chain_dynamics._internal_forces` takes them, give its section
        forces ``K_n e`` (axial force N, end moments M_a, M_b). A zone of one segment keeps
        that segment's e. A zone over stations a..b is loaded by the moment at its root end
        (M_a of segment a), the moment at its far end (M_b of segment b - 1) and the axial
        force of segment b - 1 at station b along the zone's chord, and its deformation is
        the zone compliance times these forces. Not the chord deformation of the zone: the
        end sections of a zone a few segments long turn by up to a radian against its chord
        in the contact case, which the zone's linear modes read as stretch (the root stress
        of a 5-in finger of section 12 x 13 mm, alpha 60 1/s, came out 8 % above the full
        FEA's with a 33 mm root zone, and 2.90 / 3.13 / 3.39 / 3.70 MPa with zones of 20.5 /
        33 / 45 / 66 mm; from the end forces 2.92 / 2.92 / 2.85 / 2.79 MPa, the FEA
        2.90 MPa).

        Parameters
        ----------
        P : (t, n+1, 2) ndarray
            Station centres at t times [m].
        TH : (t, n+1) ndarray
            Station rotations [rad].
        station_z_m : (n+1,) ndarray
            Station positions along the straight finger [m].
        nonlinear : bool, optional
            Co-rotational (default) or linear chords.

        Returns
        -------
        (t, z, 3) ndarray
            [m, rad, rad] per zone.
        """
        l0 = np.diff(station_z_m)
        d = P[:, 1:] - P[:, :-1]
        if nonlinear:
            ln = np.hypot(d[..., 0], d[..., 1])
            c, s = d[..., 0] / ln, d[..., 1] / ln
            psi = np.arctan2(d[..., 1], d[..., 0])
            e1 = ln - l0
        else:
            ln, c, s = np.broadcast_to(l0, d.shape[:-1]), np.ones(d.shape[:-1]), np.zeros(d.shape[:-1])
            psi = d[..., 1] / l0
            e1 = d[..., 0] - l0
        e = np.stack([e1, TH[:, :-1] - psi, TH[:, 1:] - psi], axis=-1)
        N, Ma, Mb = np.moveaxis(np.einsum("sij,tsj->tsi", self.segment_stiffness, e), -1, 0)
        shear = (Ma + Mb) / ln
        fx, fy = c * N + s * shear, s * N - c * shear              # force of each segment at its end b
        a, b = self.zone_a, self.zone_b
        dz = P[:, b] - P[:, a]
        if nonlinear:
            lz = np.hypot(dz[..., 0], dz[..., 1])
            axial = (fx[:, b - 1] * dz[..., 0] + fy[:, b - 1] * dz[..., 1]) / lz
        else:
            axial = fx[:, b - 1]
        f = np.stack([axial, Ma[:, a], Mb[:, b - 1]], axis=-1)
        return np.where((b - a == 1)[None, :, None], e[:, a], np.einsum("zij,tzj->tzi", self.zone_compliance, f))

    def max_von_mises(self, e, nonlinear=True, backend="numba"):
        """Largest von Mises stress over the elements at each time.

        Each element's displacement gradient is ``H = sum_j e_j H_j`` of its zone's
        natural deformations e. Nonlinear: the neo-Hookean Cauchy stress of
        ``F = I + H``, as the FE model evaluates it (a linear stress of the same field
        overstates the stress of a root zone bent by half a radian by about 20 %).
        Linear: ``sigma = mu (H + H^T) + lam tr(H) I`` of the small-displacement model.

        Parameters
        ----------
        e : (n_times, n_zones, 3) ndarray
            Natural deformations of each zone's chord [m, rad, rad].
        nonlinear : bool, optional
            Neo-Hookean (default) or linear stress.
        backend : {"numba", "numpy"}, optional
            Compiled path (default), or the numpy reference it is tested against.

        Returns
        -------
        (n_times,) ndarray
            Largest von Mises stress [Pa]; NaN at times where the field inverts an
            element (nonlinear only).
        """
        if backend == "numba":
            return _max_von_mises(np.ascontiguousarray(e), self.zone_of_element, self.gradients,
                                  self.material.mu, self.material.lam, nonlinear)
        H = np.einsum("tej,ejab->teab", e[:, self.zone_of_element], self.gradients)
        mu, lam = self.material.mu, self.material.lam
        if nonlinear:
            sigma = cauchy_stress(np.eye(3) + H, mu, lam)
        else:
            sigma = mu * (H + H.swapaxes(-1, -2)) + lam * np.trace(H, axis1=-2, axis2=-1)[..., None, None] * np.eye(3)
        return von_mises(sigma).max(axis=1)


@nb.njit(cache=True, fastmath=FASTMATH)
def _max_von_mises(e, zone_of, H, mu, lam, nonlinear):
    """Compiled :meth:`StressRecovery.max_von_mises` (same formulas, element by element;
    the neo-Hookean stress is the FE model's, :func:`ccedi.fea.material.neo_hookean_cauchy`)."""
    out = np.zeros(e.shape[0])
    F = np.empty((3, 3))
    for t in range(e.shape[0]):
        worst = 0.0
        for el in range(zone_of.shape[0]):
            z = zone_of[el]
            for a in range(3):
                for b in range(3):
                    F[a, b] = (1.0 if a == b else 0.0) + (e[t, z, 0] * H[el, 0, a, b] + e[t, z, 1] * H[el, 1, a, b]
                                                          + e[t, z, 2] * H[el, 2, a, b])
            if nonlinear:
                J, s00, s11, s22, s01, s12, s20 = neo_hookean_cauchy(F, mu, lam)
                if not J > 0.0:                           # inverted: no stress to report
                    worst = np.nan
                    break
            else:
                tr = lam * (F[0, 0] + F[1, 1] + F[2, 2] - 3.0)
                s00 = 2.0 * mu * (F[0, 0] - 1.0) + tr
                s11 = 2.0 * mu * (F[1, 1] - 1.0) + tr
                s22 = 2.0 * mu * (F[2, 2] - 1.0) + tr
                s01 = mu * (F[0, 1] + F[1, 0])
                s12 = mu * (F[1, 2] + F[2, 1])
                s20 = mu * (F[2, 0] + F[0, 2])
            vm = von_mises_components(s00, s11, s22, s01, s12, s20)
            if vm > worst:
                worst = vm
        out[t] = worst
    return out


def stress_recovery(chain: FingerChain, material: NeoHookean):
    """Stress operator of a chain: stresses follow the section forces.

    The chain's force over a zone, ``K_chain e`` (e from :meth:`StressRecovery.deformations`:
    the deformation of the chain over the zone that carries its end segments' section
    forces), is applied to the zone's own model, whose deformation is
    ``K_zone^-1 K_chain e`` (e itself for an unfitted segment; bending scaled by kappa for
    a fitted one); the zone's gradient modes are mapped accordingly.

    Parameters
    ----------
    chain : FingerChain
        The (fitted) chain with its stress zones.
    material : NeoHookean
        The finger material.

    Returns
    -------
    StressRecovery
        The stress operator over all zones.

    Raises
    ------
    InputError
        From :func:`natural_stiffness` (via :func:`zone_stiffness`).
    """
    gradients, zone_of, compliance = [], [], []
    for k, z in enumerate(chain.stress_zones):
        K = zone_stiffness(chain, z.a, z.b)
        compliance.append(np.linalg.inv(K))
        C = np.linalg.solve(z.stiffness, K)
        gradients.append(np.einsum("ejab,jm->emab", z.gradients, C))
        zone_of.append(np.full(len(z.gradients), k))
    return StressRecovery(zone_a=np.array([z.a for z in chain.stress_zones]),
                          zone_b=np.array([z.b for z in chain.stress_zones]), zone_of_element=np.concatenate(zone_of),
                          gradients=np.concatenate(gradients), material=material,
                          segment_stiffness=chain.natural_stiffness, zone_compliance=np.array(compliance))
