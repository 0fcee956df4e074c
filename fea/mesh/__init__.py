"""Hexahedral meshes of the paper's simplified finger: a straight cantilever of
constant elliptical cross-section (semi-axes a = 12 mm along x, b = 8.45 mm along y;
length L along z, root at z = 0). The soft bending plane is y-z (bending about the
major axis x, second moment I = pi a b^3 / 4).

Cross-section: an n x n mapped (transfinite) mesh of the ellipse whose four grid
corners sit on the ellipse axes, as a mapped mesh of an ANSYS ellipse area bounded by
four quarter arcs; boundary nodes are spaced evenly by arc length. The elements at
the four grid corners are wedge-like (one interior angle near 180 deg); as in the
paper they govern the critical time step.

Table 1 meshes (4.5-in finger):
  SM-A  5 x 5 in section, 29 along  -> 1080 nodes,  725 elements
  SM-B  9 x 9 in section, 58 along  -> 5900 nodes, 4698 elements
For other lengths SM-A keeps its ~4 mm element length, ``n_along = round(L / 4 mm)``
(4.5 in -> 29, 8 in -> 51 as in the paper's Table 2), and SM-B doubles it.

Hexahedron node order (LS-DYNA / VTK): nodes 0-3 on the face at the lower z, counter-
clockwise seen from +z, nodes 4-7 above them.
"""
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import cumulative_trapezoid
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from ccedi.errors import InputError, require_finite_positive
from ccedi.quantities import QUANTITIES
from ccedi.units import inch_to_m

SEMI_AXIS_MAJOR = 12.0e-3
"""Finger cross-section semi-axis along x [m] (paper: 'major radius 12 mm')."""
SEMI_AXIS_MINOR = 8.45e-3
"""Finger cross-section semi-axis along y, the bending direction [m]."""
SM_A_ELEMENT_LENGTH = 4.0e-3
"""Nominal SM-A element length along the finger [m] (Table 1: 'average length 4 mm')."""
SM_A_ROOT_REFINEMENT = 0.5
"""SM-A's root refinement g (:func:`along_lengths`): the element at the clamp is half as
long as those at the tip. The clamped root face holds the nearly incompressible rubber's
Poisson contraction, a stress boundary layer about one section depth long; with uniform
4 mm elements the 4.5-in SM-A was 1.43 % stiffer than the converged solution of its
geometry (linear tip stiffness against CalculiX C3D20R on SM-A split 2 x 2 x 2,
69.248 N/m), with g = 0.5 0.56 % (first frequency +0.82 % -> +0.26 %), for the same
nodes and elements and a stable step 1 % shorter (``validation/hex_convergence.json``)."""
ROOT_REFINEMENT_DECAY = 1.5
"""Decay length tau of the root refinement, in elements (:func:`along_lengths`)."""


_TET_EDGES = [[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]]
EDGES = {"hex8": np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4],
                           [0, 4], [1, 5], [2, 6], [3, 7]]),
         "tet4": np.array(_TET_EDGES), "tet10": np.array(_TET_EDGES)}
"""Corner-to-corner edges (local node pairs) of each element type."""


@dataclass
class Mesh:
    """A solid mesh (hexahedra, 4-node and 10-node tetrahedra) with named node sets.

    Node orders are those of VTK (and meshio, LS-DYNA, CalculiX): hexahedron nodes 0-3
    on the face at the lower z, counter-clockwise seen from +z, nodes 4-7 above them;
    tetrahedron corners 0-3 with the positive orientation
    ``(x1 - x0) . ((x2 - x0) x (x3 - x0)) > 0``; the 10-node tetrahedron's mid-edge
    nodes 4-9 on the edges 0-1, 1-2, 0-2, 0-3, 1-3, 2-3.

    Parameters
    ----------
    nodes : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    hexes : numpy.ndarray
        8-node hexahedra, shape (e, 8).
    node_sets : dict, optional
        {name: array of node ids}, e.g. ``"root"`` and ``"tip"``. Default empty.
    tets4 : numpy.ndarray, optional
        4-node tetrahedra, shape (e4, 4). Default none.
    tets10 : numpy.ndarray, optional
        10-node tetrahedra, shape (e10, 10). Default none.
    """

    nodes: np.ndarray
    hexes: np.ndarray = field(default_factory=lambda: np.zeros((0, 8), dtype=np.int64))
    node_sets: dict = field(default_factory=dict)
    tets4: np.ndarray = field(default_factory=lambda: np.zeros((0, 4), dtype=np.int64))
    tets10: np.ndarray = field(default_factory=lambda: np.zeros((0, 10), dtype=np.int64))

    def __post_init__(self):
        self.hexes = np.asarray(self.hexes, dtype=np.int64).reshape(-1, 8)
        self.tets4 = np.asarray(self.tets4, dtype=np.int64).reshape(-1, 4)
        self.tets10 = np.asarray(self.tets10, dtype=np.int64).reshape(-1, 10)

    @property
    def n_nodes(self):
        """Number of nodes n."""
        return len(self.nodes)

    @property
    def n_elements(self):
        """Number of solid elements of every type."""
        return len(self.hexes) + len(self.tets4) + len(self.tets10)

    @property
    def element_type(self):
        """The solid element type: ``"hex8"``, ``"tet4"``, ``"tet10"``, ``"mixed"`` or
        ``"none"`` (rods and point masses only)."""
        kinds = [k for k, c in (("hex8", self.hexes), ("tet4", self.tets4), ("tet10", self.tets10)) if len(c)]
        return kinds[0] if len(kinds) == 1 else ("none" if not kinds else "mixed")

    def average_edge_length(self):
        """Mean length of the element edges, each edge counted once (the paper's Table 1
        "average length"); a 10-node tetrahedron's edge runs corner to corner.

        Returns
        -------
        float
            Mean edge length [m] (NaN for a mesh without solid elements).
        """
        edges = [c[:, EDGES[kind]].reshape(-1, 2)
                 for kind, c in (("hex8", self.hexes), ("tet4", self.tets4), ("tet10", self.tets10)) if len(c)]
        if not edges:
            return float("nan")
        unique = np.unique(np.sort(np.concatenate(edges), axis=1), axis=0)
        return float(np.linalg.norm(self.nodes[unique[:, 1]] - self.nodes[unique[:, 0]], axis=1).mean())


def _ellipse_arc_points(a, b, theta0, theta1, n):
    """n+1 points on the ellipse (a cos t, b sin t) from t=theta0 to theta1, even in arc length."""
    t = np.linspace(theta0, theta1, 2001)
    speed = np.hypot(a * np.sin(t), b * np.cos(t))
    s = np.abs(cumulative_trapezoid(speed, t, initial=0.0))
    ts = np.interp(np.linspace(0.0, s[-1], n + 1), s, t)
    return np.column_stack([a * np.cos(ts), b * np.sin(ts)])


def ellipse_section(a, b, n):
    """Mapped n x n quadrilateral grid of the ellipse x^2/a^2 + y^2/b^2 <= 1.

    Grid corners lie at the ellipse axis points and the boundary nodes are even in arc
    length; the interior is the transfinite (Coons) interpolation
    P(s, t) = (1-t) B(s) + t T(s) + (1-s) L(t) + s R(t) - bilinear corner term.

    Parameters
    ----------
    a : float
        Semi-axis along x [m].
    b : float
        Semi-axis along y [m].
    n : int
        Quadrilaterals per grid direction, >= 1.

    Returns
    -------
    numpy.ndarray
        Grid points, shape (n+1, n+1, 2) [m], index [j, i].
    """
    h = np.pi / 2
    bottom = _ellipse_arc_points(a, b, -h, 0.0, n)          # (0,-b) -> (a,0)
    right = _ellipse_arc_points(a, b, 0.0, h, n)            # (a,0) -> (0,b)
    top = _ellipse_arc_points(a, b, 2 * h, h, n)            # (-a,0) -> (0,b)
    left = _ellipse_arc_points(a, b, -h, -2 * h, n)         # (0,-b) -> (-a,0)
    s = np.linspace(0.0, 1.0, n + 1)[None, :, None]         # along i
    t = np.linspace(0.0, 1.0, n + 1)[:, None, None]         # along j
    B, T = bottom[None, :, :], top[None, :, :]
    Lf, R = left[:, None, :], right[:, None, :]
    p00, p10, p01, p11 = bottom[0], bottom[-1], top[0], top[-1]
    grid = ((1 - t) * B + t * T + (1 - s) * Lf + s * R
            - ((1 - s) * (1 - t) * p00 + s * (1 - t) * p10 + (1 - s) * t * p01 + s * t * p11))
    return grid


def along_lengths(length_m, n_along, root_refinement=0.0):
    """Element lengths along a cantilever, shorter at the clamped root.

    ``h_i = C (1 - g exp(-i / tau))``, i = 0 .. n-1 from the root, C such that they sum to
    L, tau = :data:`ROOT_REFINEMENT_DECAY` elements: the root element is 1 - g of the tip
    ones, and from the fifth element on they are within 4 % of uniform.

    Parameters
    ----------
    length_m : float
        Length L [m], > 0.
    n_along : int
        Number of elements, >= 1.
    root_refinement : float, optional
        g in [0, 1): 0 gives uniform elements. Default 0.

    Returns
    -------
    numpy.ndarray
        Element lengths h_i [m], shape (n_along,), summing to L.

    Raises
    ------
    InputError
        If ``root_refinement`` is not in [0, 1).
    """
    if not 0.0 <= root_refinement < 1.0:
        raise InputError(f"root_refinement must be in [0, 1), got {root_refinement!r}")
    w = 1.0 - root_refinement * np.exp(-np.arange(n_along) / ROOT_REFINEMENT_DECAY)
    return length_m * w / w.sum()


def elliptical_cantilever(length_m, n_section, n_along, *, a=SEMI_AXIS_MAJOR, b=SEMI_AXIS_MINOR, root_refinement=0.0,
                          taper_ratio=1.0):
    """Hex mesh of a straight elliptical cantilever along +z, root face at z = 0.

    Its section is the ellipse of semi-axes (a, b) at the root, scaled along the length by
    s(z) = 1 - (1 - lambda) z / L, lambda the taper ratio: the tip's semi-axes are
    (lambda a, lambda b), every section is similar to the root's and the volume is the
    prism's times (1 + lambda + lambda^2) / 3.

    Node sets: ``root`` (z = 0, clamped) and ``tip`` (z = L).

    Parameters
    ----------
    length_m : float
        Length L [m], > 0.
    n_section : int
        Elements per direction of the n x n section grid, >= 1.
    n_along : int
        Elements along the length, >= 1.
    a : float, optional
        Section semi-axis along x [m], > 0. Default 12 mm.
    b : float, optional
        Section semi-axis along y, the bending direction [m], > 0. Default 8.45 mm.
    root_refinement : float, optional
        Root refinement g of the element lengths along the length (:func:`along_lengths`),
        in [0, 1). Default 0 (uniform).
    taper_ratio : float, optional
        lambda, the tip's semi-axes over the root's, within
        :data:`ccedi.quantities.QUANTITIES` ``taper_ratio``. Default 1 (the prism).

    Returns
    -------
    Mesh
        (n_section+1)^2 (n_along+1) nodes and n_section^2 n_along hexahedra.

    Raises
    ------
    InputError
        If a length or semi-axis is not a finite number > 0, an element count is not an
        integer >= 1, ``root_refinement`` is not in [0, 1) or ``taper_ratio`` is out of
        its range.
    """
    length_m = require_finite_positive("length_m (finger length, m)", length_m)
    for name, n in (("n_section", n_section), ("n_along", n_along)):
        if int(n) != n or n < 1:
            raise InputError(f"{name} must be an integer >= 1, got {n!r}")
    a = require_finite_positive("a (section semi-axis along x, m)", a)
    b = require_finite_positive("b (section semi-axis along y, m)", b)
    taper_ratio = QUANTITIES["taper_ratio"].check(taper_ratio, "taper_ratio (tip over root semi-axes)")
    n, nz = int(n_section), int(n_along)
    sec = ellipse_section(a, b, n).reshape(-1, 2)
    z = np.concatenate([[0.0], np.cumsum(along_lengths(length_m, nz, root_refinement))])
    z[-1] = length_m
    scale = np.repeat(1.0 - (1.0 - taper_ratio) * z / length_m, len(sec))
    nodes = np.column_stack([np.tile(sec, (nz + 1, 1)) * scale[:, None], np.repeat(z, len(sec))])
    m = n + 1
    k, j, i = np.meshgrid(np.arange(nz), np.arange(n), np.arange(n), indexing="ij")
    base = (k * m * m + j * m + i).ravel()
    quad = np.array([0, 1, m + 1, m])
    hexes = np.concatenate([base[:, None] + quad, base[:, None] + quad + m * m], axis=1)
    ids = np.arange(len(nodes))
    node_sets = {"root": ids[nodes[:, 2] == 0.0], "tip": ids[nodes[:, 2] == z[-1]]}
    return Mesh(nodes=nodes, hexes=hexes.astype(np.int64), node_sets=node_sets)


def _finger_length_m(length_in=None, length_m=None):
    """The finger length [m] from exactly one of ``length_in`` and ``length_m``, checked
    against :data:`ccedi.quantities.QUANTITIES` ``length_in`` (1..12 in)."""
    if (length_in is None) == (length_m is None):
        raise InputError("give exactly one of length_in (inches) or length_m (metres)")
    if length_in is not None:
        return inch_to_m(QUANTITIES["length_in"].check(length_in, "length_in"))
    return QUANTITIES["length_m"].check(length_m, "length_m")


def finger_section(semi_axes_m, length_m, name="semi_axes_m"):
    """A finger's section semi-axes as (a, b) [m], each within :data:`ccedi.quantities.QUANTITIES`
    ``section_semi_axis_m`` and both shorter than the finger.

    Parameters
    ----------
    semi_axes_m : sequence of float
        (a along x, b along y) [m].
    length_m : float
        The finger's length [m].
    name : str, optional
        How a message names the semi-axes.

    Returns
    -------
    tuple of float

    Raises
    ------
    InputError
        Not a pair, a semi-axis out of range, or one as long as the finger or longer (a
        finger is a cantilever longer than it is thick: a unit slip, or the wrong key).
    """
    if not isinstance(semi_axes_m, (tuple, list, np.ndarray)) or len(semi_axes_m) != 2:
        raise InputError(f"{name} = {semi_axes_m!r}: must be a pair (a, b) of semi-axes in metres")
    a, b = (QUANTITIES["section_semi_axis_m"].check(x, name) for x in semi_axes_m)
    if max(a, b) >= length_m:
        raise InputError(f"{name} = ({1e3 * a:.4g}, {1e3 * b:.4g}) mm: a semi-axis as long as the "
                         f"{1e3 * length_m:.4g} mm finger or longer; a finger is a cantilever longer than its section "
                         "(units? the right length?)")
    return a, b


def sm_a_elements_along(length_m):
    """SM-A element count along the finger: round(L / 4 mm), at least 1.

    Parameters
    ----------
    length_m : float
        Finger length L [m].

    Returns
    -------
    int
        Number of elements along the finger.
    """
    return max(1, int(round(length_m / SM_A_ELEMENT_LENGTH)))


SEMI_AXES = (SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR)
"""The paper's finger section (a along x, b along y) [m]."""


def sm_a(length_in=None, length_m=None, semi_axes_m=SEMI_AXES):
    """The paper's simplified model A: 5 x 5 hexahedra in the section, ~4 mm along,
    half-length elements at the clamped root (:data:`SM_A_ROOT_REFINEMENT`).

    Give exactly one of ``length_in`` and ``length_m``.

    Parameters
    ----------
    length_in : float, optional
        Finger length [in], > 0.
    length_m : float, optional
        Finger length [m], > 0.
    semi_axes_m : tuple of float, optional
        Section semi-axes (a along x, b along y, the bending direction) [m].
        Default (12 mm, 8.45 mm).

    Returns
    -------
    Mesh
        The SM-A mesh (1080 nodes, 725 elements at 4.5 in).

    Raises
    ------
    InputError
        If neither or both lengths are given, or the length (1..12 in) or a semi-axis
        (1e-4..0.1 m) is outside :data:`ccedi.quantities.QUANTITIES`.
    """
    L = _finger_length_m(length_in, length_m)
    a, b = finger_section(semi_axes_m, L)
    return elliptical_cantilever(L, 5, sm_a_elements_along(L), a=a, b=b, root_refinement=SM_A_ROOT_REFINEMENT)


def sm_b(length_in=None, length_m=None, semi_axes_m=SEMI_AXES):
    """The paper's refined simplified model B: 9 x 9 in the section, twice SM-A along.

    Give exactly one of ``length_in`` and ``length_m``.

    Parameters
    ----------
    length_in : float, optional
        Finger length [in], > 0.
    length_m : float, optional
        Finger length [m], > 0.
    semi_axes_m : tuple of float, optional
        Section semi-axes (a along x, b along y, the bending direction) [m].
        Default (12 mm, 8.45 mm).

    Returns
    -------
    Mesh
        The SM-B mesh (5900 nodes, 4698 elements at 4.5 in).

    Raises
    ------
    InputError
        If neither or both lengths are given, or the length (1..12 in) or a semi-axis
        (1e-4..0.1 m) is outside :data:`ccedi.quantities.QUANTITIES`.
    """
    L = _finger_length_m(length_in, length_m)
    a, b = finger_section(semi_axes_m, L)
    return elliptical_cantilever(L, 9, 2 * sm_a_elements_along(L), a=a, b=b)


def refine_hexes(mesh, n):
    """Split every hexahedron into n x n x n, keeping the mesh's polygonal geometry.

    The new nodes sit at the parent element's trilinear map of an even n-grid in natural
    coordinates, so faces and edges shared by neighbours receive the same nodes (merged)
    and the refined mesh fills exactly the same volume. A new node belongs to a node set
    when every parent node it is interpolated from does (a face of the set is refined
    into faces of the set); the original nodes keep their ids and sets.

    Parameters
    ----------
    mesh : Mesh
        A hexahedral mesh (no tetrahedra).
    n : int
        Subdivisions per element edge, >= 1.

    Returns
    -------
    Mesh
        n^3 times the elements; node order of every child as its parent's.

    Raises
    ------
    InputError
        If ``n`` is not an integer >= 1 or the mesh has tetrahedra.
    """
    if int(n) != n or n < 1:
        raise InputError(f"n (subdivisions per element edge) must be an integer >= 1, got {n!r}")
    if len(mesh.tets4) or len(mesh.tets10):
        raise InputError("refine_hexes: the mesh has tetrahedra; only hexahedral meshes are refined")
    n = int(n)
    s = np.linspace(-1.0, 1.0, n + 1)
    k, j, i = np.meshgrid(np.arange(n + 1), np.arange(n + 1), np.arange(n + 1), indexing="ij")
    grid = np.column_stack([s[i.ravel()], s[j.ravel()], s[k.ravel()]])          # (m, 3)
    corners = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                        [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
    N = np.prod(1.0 + grid[:, None, :] * corners[None], axis=2) / 8.0             # (m, 8)
    points = np.einsum("pk,ekd->epd", N, mesh.nodes[mesh.hexes]).reshape(-1, 3)
    m1 = n + 1
    cell = (np.arange(n)[:, None, None] * m1 * m1 + np.arange(n)[None, :, None] * m1
            + np.arange(n)[None, None, :]).ravel()
    local = np.array([0, 1, m1 + 1, m1, m1 * m1, m1 * m1 + 1, m1 * m1 + m1 + 1, m1 * m1 + m1])
    children = (np.arange(len(mesh.hexes))[:, None, None] * len(grid)
                + cell[None, :, None] + local[None, None, :]).reshape(-1, 8)
    # merge coincident points (shared faces and edges), keeping the original nodes first
    all_points = np.concatenate([mesh.nodes, points])
    span = np.ptp(mesh.nodes, axis=0).max() if len(mesh.nodes) else 1.0
    pairs = cKDTree(all_points).query_pairs(1e-9 * span, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(all_points),) * 2)
    _, label = connected_components(graph, directed=False)
    first = np.full(label.max() + 1, len(all_points))
    np.minimum.at(first, label, np.arange(len(all_points)))
    keep = np.unique(first)                      # one representative per merged point, originals first
    new_id = np.searchsorted(keep, first[label])
    hexes = new_id[len(mesh.nodes) + children]
    support = N > 1e-12
    node_sets = {}
    for name, ids in mesh.node_sets.items():
        member = np.zeros(len(mesh.nodes), dtype=bool)
        member[ids] = True
        inside = np.all(member[mesh.hexes][:, None, :] | ~support[None], axis=2).ravel()
        node_sets[name] = np.unique(np.concatenate([new_id[np.asarray(ids)],
                                                    new_id[len(mesh.nodes) + np.flatnonzero(inside)]]))
    return Mesh(nodes=all_points[keep], hexes=hexes, node_sets=node_sets)


def element_name(mesh, index):
    """Name of a solid element from its index over the hexahedra, then the 4-node, then
    the 10-node tetrahedra.

    Parameters
    ----------
    mesh : Mesh
        The mesh.
    index : int
        Element index over all solid elements, 0 <= index < ``mesh.n_elements``.

    Returns
    -------
    str
        E.g. ``"element 12"`` (a hexahedron, as before tetrahedra existed),
        ``"tet4 element 3"`` or ``"tet10 element 0"`` (index within its type).
    """
    n_hex, n_tet4 = len(mesh.hexes), len(mesh.tets4)
    if index < n_hex:
        return f"element {index}"
    if index < n_hex + n_tet4:
        return f"tet4 element {index - n_hex}"
    return f"tet10 element {index - n_hex - n_tet4}"
