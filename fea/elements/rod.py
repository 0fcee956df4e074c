"""Slender rods: a geometrically exact discrete Kirchhoff rod on nodal positions only.

The rod is a chain of nodes x_0 ... x_N with edges e_i = x_{i+1} - x_i of rest length
l_i. Its energy is stretching plus bending (Bergou et al., "Discrete elastic rods",
SIGGRAPH 2008, without twist)::

    U = sum_i EA (|e_i| - l_i)^2 / (2 l_i)
      + sum_hinges EI |kb|^2 / (l_{i-1} + l_i)
    kb = 2 e_{i-1} x e_i / (|e_{i-1}| |e_i| + e_{i-1} . e_i)        |kb| = 2 tan(phi/2)

with phi the turning angle at the hinge. U depends only on lengths and angles, so it is
exact under rigid motions of any size (large rotations), and for small angles it is the
Euler-Bernoulli energy EI/2 int kappa^2 ds. Torsion is not modelled: the rod must be
naturally straight with an isotropic (circular) section and no applied twist, as the
paper's steel rod. A clamp is two fixed nodes: the root and a ghost node one element
behind it, which fix position and slope. The ghost element carries no mass and the root
hinge takes only the physical half of its Voronoi length (stiffness EI / l_1 instead of
EI / (l_0 + l_1)), which makes the discrete bending energy a trapezoid rule: the tip
deflection under a tip load converges as 1/N^2 (error 0.13 % with 20 elements).

Nodal forces are the exact gradient dU/dx (tested against finite differences). For
kb = 2 c / d with c = e1 x e2 and d = |e1||e2| + e1.e2::

    d|kb|^2/de1 = (4/d) e2 x kb - (2 |kb|^2 / d) (|e2| e1/|e1| + e2)
    d|kb|^2/de2 = (4/d) kb x e1 - (2 |kb|^2 / d) (|e1| e2/|e2| + e1)

Stable time step (lumped mass rho A l per node): axial ``l / sqrt(E / rho)``, bending
``l^2 / (2 sqrt(EI / (rho A)))`` (the highest mode of the three-node bending stencil has
omega = 4 sqrt(EI / rho A) / l^2); the smaller governs.
"""
from dataclasses import dataclass

import numba as nb
import numpy as np

from ccedi.errors import InputError, require_finite_positive
from ccedi.fea.elements.fastmath import FASTMATH


@dataclass(frozen=True)
class RodSection:
    """Linear elastic rod of circular cross-section.

    Parameters
    ----------
    E : float
        Young's modulus [Pa], > 0.
    rho : float
        Density [kg/m^3], > 0.
    diameter_m : float
        Section diameter d [m], > 0.

    Raises
    ------
    InputError
        If a value is not a finite number > 0.
    """

    E: float
    rho: float
    diameter_m: float

    def __post_init__(self):
        object.__setattr__(self, "E", require_finite_positive("E (Young's modulus, Pa)", self.E))
        object.__setattr__(self, "rho", require_finite_positive("rho (density, kg/m^3)", self.rho))
        object.__setattr__(self, "diameter_m", require_finite_positive("diameter_m (rod diameter, m)",
                                                                       self.diameter_m))

    @property
    def area(self):
        """Cross-section area pi d^2 / 4 [m^2]."""
        return np.pi * self.diameter_m**2 / 4.0

    @property
    def second_moment(self):
        """Second moment of area pi d^4 / 64 [m^4]."""
        return np.pi * self.diameter_m**4 / 64.0


@dataclass(frozen=True)
class Rod:
    """A chain of node ids, in order along the rod, with its section.

    Parameters
    ----------
    nodes : numpy.ndarray
        At least two distinct node ids, in order (stored as int64).
    section : RodSection
        The rod's material and section.
    ghost_root : bool, optional
        The first node is a clamp ghost one element behind the root: its element has
        no mass and the root hinge takes half its Voronoi length (module docstring).
        Default False.

    Raises
    ------
    InputError
        If ``nodes`` is not a 1-D sequence of at least two distinct ids.
    """

    nodes: np.ndarray
    section: RodSection
    ghost_root: bool = False

    def __post_init__(self):
        nodes = np.asarray(self.nodes, dtype=np.int64)
        if nodes.ndim != 1 or len(nodes) < 2 or len(np.unique(nodes)) != len(nodes):
            raise InputError("a rod needs at least two distinct node ids in order")
        object.__setattr__(self, "nodes", nodes)


@dataclass(frozen=True)
class RodArrays:
    """Flat arrays of all rods of a model, the form the force kernels take.

    m is the number of rod elements (segments), h the number of hinges.

    Parameters
    ----------
    segments : numpy.ndarray
        Node-id pairs, shape (m, 2).
    rest_length : numpy.ndarray
        Rest lengths l, shape (m,) [m].
    axial_stiffness : numpy.ndarray
        EA, shape (m,) [N].
    segment_time_step : numpy.ndarray
        Critical axial time step l / sqrt(E / rho), before TSSFAC, shape (m,) [s].
    segment_E : numpy.ndarray
        Young's modulus per segment, shape (m,) [Pa] (for stresses).
    hinges : numpy.ndarray
        Node-id triples, shape (h, 3).
    bending_stiffness : numpy.ndarray
        EI / (l_a + l_b) (EI / l_b at a ghost root), shape (h,) [N m].
    hinge_time_step : numpy.ndarray
        Critical bending time step l^2 / (2 sqrt(EI / (rho A))) with l the mean rest
        length, before TSSFAC, shape (h,) [s].
    hinge_rest : numpy.ndarray
        Mean rest length of the two edges (l_a + l_b) / 2, shape (h,) [m].
    hinge_radius : numpy.ndarray
        Section radius d / 2 at the hinge, shape (h,) [m] (for stresses).
    hinge_E : numpy.ndarray
        Young's modulus at the hinge, shape (h,) [Pa] (for stresses).
    """

    segments: np.ndarray
    rest_length: np.ndarray
    axial_stiffness: np.ndarray
    segment_time_step: np.ndarray
    segment_E: np.ndarray
    hinges: np.ndarray
    bending_stiffness: np.ndarray
    hinge_time_step: np.ndarray
    hinge_rest: np.ndarray
    hinge_radius: np.ndarray
    hinge_E: np.ndarray


def rod_arrays(nodes, rods):
    """Assemble the :class:`RodArrays` of ``rods`` at the reference positions.

    Parameters
    ----------
    nodes : numpy.ndarray
        Reference nodal positions, shape (n, 3) [m].
    rods : sequence of Rod
        The rods (may be empty: the arrays are then empty).

    Returns
    -------
    RodArrays
        Segments and hinges of all rods, concatenated in order.

    Raises
    ------
    InputError
        If a rod has a zero-length element (two coincident nodes).
    """
    seg, l0, EA, dts, Es, hin, kb, dth, lh, rad, Eh = ([] for _ in range(11))
    for rod in rods:
        s = rod.section
        pts = nodes[rod.nodes]
        lengths = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        if np.any(lengths <= 0.0):
            raise InputError("rod has a zero-length element (two coincident nodes)")
        seg.append(np.column_stack([rod.nodes[:-1], rod.nodes[1:]]))
        l0.append(lengths)
        EA.append(np.full(len(lengths), s.E * s.area))
        dts.append(lengths / np.sqrt(s.E / s.rho))
        Es.append(np.full(len(lengths), s.E))
        if len(rod.nodes) >= 3:
            hin.append(np.column_stack([rod.nodes[:-2], rod.nodes[1:-1], rod.nodes[2:]]))
            pair = lengths[:-1] + lengths[1:]
            if rod.ghost_root:
                pair[0] = lengths[1]
            kb.append(s.E * s.second_moment / pair)
            mean = 0.5 * pair
            dth.append(mean**2 / (2.0 * np.sqrt(s.E * s.second_moment / (s.rho * s.area))))
            lh.append(mean)
            rad.append(np.full(len(mean), 0.5 * s.diameter_m))
            Eh.append(np.full(len(mean), s.E))

    def cat(parts, shape, dtype=float):
        return np.concatenate(parts).astype(dtype) if parts else np.zeros(shape, dtype)

    return RodArrays(segments=cat(seg, (0, 2), np.int64), rest_length=cat(l0, 0), axial_stiffness=cat(EA, 0),
                     segment_time_step=cat(dts, 0), segment_E=cat(Es, 0),
                     hinges=cat(hin, (0, 3), np.int64), bending_stiffness=cat(kb, 0), hinge_time_step=cat(dth, 0),
                     hinge_rest=cat(lh, 0), hinge_radius=cat(rad, 0), hinge_E=cat(Eh, 0))


def rod_lumped_mass(nodes, rods):
    """Lumped nodal masses of the rods.

    Each element's mass rho A l is split half to each end node; a ghost-root element has
    no mass.

    Parameters
    ----------
    nodes : numpy.ndarray
        Reference nodal positions, shape (n, 3) [m].
    rods : sequence of Rod
        The rods.

    Returns
    -------
    numpy.ndarray
        Nodal masses, shape (n,) [kg].
    """
    m = np.zeros(len(nodes))
    for rod in rods:
        pts = nodes[rod.nodes]
        half = 0.5 * rod.section.rho * rod.section.area * np.linalg.norm(np.diff(pts, axis=0), axis=1)
        if rod.ghost_root:
            half[0] = 0.0
        np.add.at(m, rod.nodes[:-1], half)
        np.add.at(m, rod.nodes[1:], half)
    return m


def _curvature_binormal(e1, e2):
    """kb = 2 e1 x e2 / (|e1||e2| + e1.e2) for rows of e1, e2 (h, 3); also returns |e1|, |e2|, d."""
    n1 = np.linalg.norm(e1, axis=1)
    n2 = np.linalg.norm(e2, axis=1)
    d = n1 * n2 + np.einsum("hi,hi->h", e1, e2)
    return 2.0 * np.cross(e1, e2) / d[:, None], n1, n2, d


def rod_forces_numpy(x, segments, rest_length, axial_stiffness, hinges, bending_stiffness, f):
    """Rod internal forces, pure numpy: the reference for :func:`rod_forces_numba`.

    Forces are the exact gradient of the stretching-plus-bending energy U of the module
    docstring.

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    segments : numpy.ndarray
        Rod elements as node-id pairs, shape (m, 2).
    rest_length : numpy.ndarray
        Rest lengths l_i, shape (m,) [m].
    axial_stiffness : numpy.ndarray
        EA per element, shape (m,) [N].
    hinges : numpy.ndarray
        Node-id triples (i, j, k) of consecutive nodes, shape (h, 3).
    bending_stiffness : numpy.ndarray
        EI / (l_a + l_b) per hinge (EI / l_1 at a ghost root), shape (h,) [N m].
    f : numpy.ndarray
        Nodal forces, shape (n, 3) [N]; the rod internal forces dU/dx are ADDED into it.

    Returns
    -------
    strain_energy : float
        Stretching plus bending energy U [J] (of the segments and hinges processed).
    status : int
        -1 when every hinge is valid; else the index of the first hinge folded back on
        itself (turning angle >= 180 deg, d <= 0), where the computation stops.
    """
    e = x[segments[:, 1]] - x[segments[:, 0]]
    length = np.linalg.norm(e, axis=1)
    stretch = length - rest_length
    tension = axial_stiffness * stretch / rest_length              # N
    fa = (tension / length)[:, None] * e                            # dU/dx_1 of each segment
    np.add.at(f, segments[:, 1], fa)
    np.add.at(f, segments[:, 0], -fa)
    energy = float(np.sum(0.5 * axial_stiffness * stretch**2 / rest_length))
    if len(hinges) == 0:
        return energy, -1
    e1 = x[hinges[:, 1]] - x[hinges[:, 0]]
    e2 = x[hinges[:, 2]] - x[hinges[:, 1]]
    kb, n1, n2, d = _curvature_binormal(e1, e2)
    if np.any(d <= 0.0):
        return energy, int(np.argmax(d <= 0.0))
    k2 = np.einsum("hi,hi->h", kb, kb)
    g1 = (4.0 / d)[:, None] * np.cross(e2, kb) - (2.0 * k2 / d)[:, None] * ((n2 / n1)[:, None] * e1 + e2)
    g2 = (4.0 / d)[:, None] * np.cross(kb, e1) - (2.0 * k2 / d)[:, None] * ((n1 / n2)[:, None] * e2 + e1)
    kk = bending_stiffness[:, None]
    np.add.at(f, hinges[:, 0], -kk * g1)
    np.add.at(f, hinges[:, 1], kk * (g1 - g2))
    np.add.at(f, hinges[:, 2], kk * g2)
    return energy + float(np.sum(bending_stiffness * k2)), -1


@nb.njit(cache=True, fastmath=FASTMATH)
def rod_forces_numba(x, segments, rest_length, axial_stiffness, hinges, bending_stiffness, f):
    """Rod internal forces, compiled: the same contract as :func:`rod_forces_numpy`.

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    segments : numpy.ndarray
        Rod elements as node-id pairs, shape (m, 2).
    rest_length : numpy.ndarray
        Rest lengths l_i, shape (m,) [m].
    axial_stiffness : numpy.ndarray
        EA per element, shape (m,) [N].
    hinges : numpy.ndarray
        Node-id triples (i, j, k) of consecutive nodes, shape (h, 3).
    bending_stiffness : numpy.ndarray
        EI / (l_a + l_b) per hinge (EI / l_1 at a ghost root), shape (h,) [N m].
    f : numpy.ndarray
        Nodal forces, shape (n, 3) [N]; the rod internal forces dU/dx are ADDED into it.

    Returns
    -------
    strain_energy : float
        Stretching plus bending energy U [J] (of the segments and hinges processed).
    status : int
        -1 when every hinge is valid; else the index of the first hinge folded back on
        itself (turning angle >= 180 deg, d <= 0), where the computation stops.
    """
    energy = 0.0
    for s in range(segments.shape[0]):
        a = segments[s, 0]
        b = segments[s, 1]
        e0 = x[b, 0] - x[a, 0]
        e1 = x[b, 1] - x[a, 1]
        e2 = x[b, 2] - x[a, 2]
        length = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        stretch = length - rest_length[s]
        k = axial_stiffness[s] / rest_length[s]
        t = k * stretch / length
        f[b, 0] += t * e0
        f[b, 1] += t * e1
        f[b, 2] += t * e2
        f[a, 0] -= t * e0
        f[a, 1] -= t * e1
        f[a, 2] -= t * e2
        energy += 0.5 * k * stretch * stretch
    for h in range(hinges.shape[0]):
        i = hinges[h, 0]
        j = hinges[h, 1]
        k = hinges[h, 2]
        a0 = x[j, 0] - x[i, 0]
        a1 = x[j, 1] - x[i, 1]
        a2 = x[j, 2] - x[i, 2]
        b0 = x[k, 0] - x[j, 0]
        b1 = x[k, 1] - x[j, 1]
        b2 = x[k, 2] - x[j, 2]
        na = np.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        nb_ = np.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
        d = na * nb_ + a0 * b0 + a1 * b1 + a2 * b2
        if not (d > 0.0):
            return energy, h
        c = 2.0 / d
        k0 = c * (a1 * b2 - a2 * b1)
        k1 = c * (a2 * b0 - a0 * b2)
        k2_ = c * (a0 * b1 - a1 * b0)
        kk = k0 * k0 + k1 * k1 + k2_ * k2_
        p = 4.0 / d
        q = 2.0 * kk / d
        ra = nb_ / na
        rb = na / nb_
        g10 = p * (b1 * k2_ - b2 * k1) - q * (ra * a0 + b0)
        g11 = p * (b2 * k0 - b0 * k2_) - q * (ra * a1 + b1)
        g12 = p * (b0 * k1 - b1 * k0) - q * (ra * a2 + b2)
        g20 = p * (k1 * a2 - k2_ * a1) - q * (rb * b0 + a0)
        g21 = p * (k2_ * a0 - k0 * a2) - q * (rb * b1 + a1)
        g22 = p * (k0 * a1 - k1 * a0) - q * (rb * b2 + a2)
        s = bending_stiffness[h]
        f[i, 0] -= s * g10
        f[i, 1] -= s * g11
        f[i, 2] -= s * g12
        f[j, 0] += s * (g10 - g20)
        f[j, 1] += s * (g11 - g21)
        f[j, 2] += s * (g12 - g22)
        f[k, 0] += s * g20
        f[k, 1] += s * g21
        f[k, 2] += s * g22
        energy += s * kk
    return energy, -1


def rod_max_stress(x, arrays: RodArrays):
    """Upper bound of the largest normal stress in the rods.

    The largest axial stress E |strain| plus the largest bending stress E r |kappa|, with
    the curvature kappa = |kb| / mean rest length at each hinge (uniaxial stress, so von
    Mises equals it).

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    arrays : RodArrays
        The model's rods.

    Returns
    -------
    float
        Stress bound [Pa]; 0 without rods.
    """
    if len(arrays.segments) == 0:
        return 0.0
    e = x[arrays.segments[:, 1]] - x[arrays.segments[:, 0]]
    strain = np.abs(np.linalg.norm(e, axis=1) / arrays.rest_length - 1.0)
    sigma = arrays.segment_E * strain
    if len(arrays.hinges):
        kb, *_ = _curvature_binormal(x[arrays.hinges[:, 1]] - x[arrays.hinges[:, 0]],
                                     x[arrays.hinges[:, 2]] - x[arrays.hinges[:, 1]])
        bend = arrays.hinge_E * arrays.hinge_radius * np.linalg.norm(kb, axis=1) / arrays.hinge_rest
        return float(max(sigma.max(), bend.max() + sigma.max()))
    return float(sigma.max())


def straight_rod(length_m, n_elements, section, *, direction=(0.0, 0.0, 1.0), ghost=True):
    """Nodes and the :class:`Rod` of a straight rod from the origin along ``direction``.

    Parameters
    ----------
    length_m : float
        Rod length [m], > 0.
    n_elements : int
        Number of elements, an integer >= 1.
    section : RodSection
        Material and section.
    direction : array_like, optional
        Rod direction, a non-zero 3-vector (normalised). Default +z.
    ghost : bool, optional
        Add a ghost node one element behind the root (node 0), so that fixing nodes 0
        and 1 clamps the root. Default True.

    Returns
    -------
    nodes : numpy.ndarray
        Nodal positions, shape (n_elements + 1 (+1 with ghost), 3) [m].
    rod : Rod
        The rod over all nodes, ``ghost_root = ghost``.
    root_ids : numpy.ndarray
        The node ids to fix to clamp the root ([0, 1] with ghost, else [0]).
    tip_id : int
        The tip node id.

    Raises
    ------
    InputError
        If ``length_m`` is not > 0 or ``n_elements`` is not an integer >= 1.
    """
    length_m = require_finite_positive("length_m (rod length, m)", length_m)
    if int(n_elements) != n_elements or n_elements < 1:
        raise InputError(f"n_elements must be an integer >= 1, got {n_elements!r}")
    u = np.asarray(direction, dtype=float)
    u = u / np.linalg.norm(u)
    h = length_m / int(n_elements)
    s = np.arange(-1 if ghost else 0, int(n_elements) + 1) * h
    nodes = s[:, None] * u[None, :]
    ids = np.arange(len(nodes))
    root = ids[:2] if ghost else ids[:1]
    return nodes, Rod(nodes=ids, section=section, ghost_root=ghost), root, int(ids[-1])
