"""10-node quadratic tetrahedron, total Lagrangian (the paper's SOLID168, LS-DYNA solid 16
analogue), with a mean-dilatation volumetric term.

Quadratic shape functions in the barycentric coordinates L0 = 1 - r - s - t, L1 = r,
L2 = s, L3 = t (VTK node order, :class:`ccedi.fea.mesh.Mesh`): corners
``N_i = L_i (2 L_i - 1)``, mid-edge nodes ``N = 4 L_i L_j`` on the edges 0-1, 1-2, 0-2,
0-3, 1-3, 2-3. Integrated with the 4-point rule (degree 2, exact for the stiffness of a
straight-edged element; barycentric points (a, b, b, b) and permutations,
a = (5 + 3 sqrt 5) / 20, b = (5 - sqrt 5) / 20, weight V/4 each).

ccedi's neo-Hookean law is taken at the 4 points for its shear part and on the element's
mean dilatation for its lam term (:mod:`ccedi.fea.elements.tetra` with one group per element),
which keeps the element free of volumetric locking at nu = 0.499 (the P2-P0
displacement-pressure pair of mean-dilatation / B-bar elements, Nagtegaal, Parks & Rice
1974; Hughes 1980)::

    Pi_e = sum_g w_g [mu/2 (I1 - 3) - mu ln J_g] + V0_e lam/2 (ln Jbar_e)^2,
    Jbar_e = (sum_g w_g J_g) / V0_e

Lumped mass: HRZ diagonal scaling (Hinton, Rock & Zienkiewicz 1976) of the consistent
mass, integrated with a collapsed Gauss rule exact for curved elements; for a
straight-edged element corners get 6/216 and mid-edge nodes 32/216 of rho V (all
positive, unlike the row sum, which gives the corners negative mass).

Critical step: paper Eq. (6) with ``Le = kappa_e h_e``, h the current minimum altitude
of the corner tetrahedron and kappa_e set at construction from the element's largest
eigenvalue (HRZ mass, mean-dilatation term included) and the assembled mesh's
(:func:`ccedi.fea.elements.tetra.time_step_length_factors`). Measured at nu = 0.49, the element
bound alone is 1.27-1.67 times below the real limit 2/omega_max on straight-edged box
meshes (kappa_e 0.29-0.39), 1.94 on SM-C (0.28-0.40) and 1.27 on a curved Gmsh finger
(0.18-0.45, its stiffest curved elements far below any fixed factor of h): the
assembled scale brings the estimate at rest to the real limit (within 0.3 %, never
above it).
"""
from collections import namedtuple

import numba as nb
import numpy as np

from ccedi.fea.elements.fastmath import FASTMATH
from ccedi.fea.elements.tetra import (
    add_point_forces,
    averaged_forces_numpy,
    averaged_tangent,
    averaging_matrix,
    bulk_viscosity,
    corner_min_altitude,
    inverse3,
    min_altitude,
    point_gradients,
    time_step_length_factors,
)

_A = (5.0 + 3.0 * np.sqrt(5.0)) / 20.0
_B = (5.0 - np.sqrt(5.0)) / 20.0
QUADRATURE_POINTS = np.array([[_B, _B, _B], [_A, _B, _B], [_B, _A, _B], [_B, _B, _A]])
"""The 4 integration points (r, s, t) = (L1, L2, L3); weights 1/24 each (of the unit
tetrahedron's volume 1/6)."""

Tet10Group = namedtuple("Tet10Group", "tets grad weight volume length_factor bulk_force")
Tet10Group.__doc__ = """Quadratic tetrahedra (structure of arrays), as
:func:`internal_forces_numba` takes them.

Attributes
----------
tets : (e, 10) int ndarray
    Connectivity (VTK order).
grad : (e, 4, 10, 3) ndarray
    Reference shape-function gradients dN_k/dX at the 4 points [1/m].
weight : (e, 4) ndarray
    Reference volume of each point, quadrature weight times det(dX/dxi) [m^3].
volume : (e,) ndarray
    Reference volumes V0_e = sum of the weights [m^3].
length_factor : (e,) ndarray
    kappa_e of the characteristic length ``Le = kappa_e h_e`` [-]
    (:func:`ccedi.fea.elements.tetra.time_step_length_factors`).
bulk_force : (n_nodes, 3) ndarray
    Output of the kernels: the bulk-viscosity part of the nodal forces [N].
"""


def shape_functions(p):
    """The 10 quadratic shape functions at natural points.

    Parameters
    ----------
    p : numpy.ndarray
        Points (r, s, t), shape (m, 3).

    Returns
    -------
    numpy.ndarray
        N_k, shape (m, 10).
    """
    r, s, t = p[:, 0], p[:, 1], p[:, 2]
    L0 = 1.0 - r - s - t
    return np.column_stack([L0 * (2 * L0 - 1), r * (2 * r - 1), s * (2 * s - 1), t * (2 * t - 1),
                            4 * L0 * r, 4 * r * s, 4 * L0 * s, 4 * L0 * t, 4 * r * t, 4 * s * t])


def shape_derivatives(p):
    """Derivatives of the 10 shape functions in natural coordinates.

    Parameters
    ----------
    p : numpy.ndarray
        Points (r, s, t), shape (m, 3).

    Returns
    -------
    numpy.ndarray
        dN_k/d(r, s, t), shape (m, 10, 3).
    """
    r, s, t = p[:, 0], p[:, 1], p[:, 2]
    L0 = 1.0 - r - s - t
    z = np.zeros_like(r)
    d0 = -(4 * L0 - 1)
    rows = [(d0, d0, d0), (4 * r - 1, z, z), (z, 4 * s - 1, z), (z, z, 4 * t - 1),
            (4 * (L0 - r), -4 * r, -4 * r), (4 * s, 4 * r, z), (-4 * s, 4 * (L0 - s), -4 * s),
            (-4 * t, -4 * t, 4 * (L0 - t)), (4 * t, z, 4 * r), (z, 4 * t, 4 * s)]
    return np.stack([np.stack(row, axis=-1) for row in rows], axis=1)


def _reference_jacobians(X, points):
    """dX/dxi (e, m, 3, 3), its determinant (e, m) and dN/dX (e, m, 10, 3) at ``points``."""
    dN = shape_derivatives(points)                            # (m, 10, 3)
    Jm = np.tensordot(X, dN, axes=([1], [1])).transpose(0, 2, 1, 3)   # sum_k X_ki dN_mkj
    det = np.einsum("...i,...i->...", Jm[..., 0, :], np.cross(Jm[..., 1, :], Jm[..., 2, :]))   # triple product
    return det, dN, Jm


def collapsed_rule(n):
    """Collapsed (Duffy) Gauss rule on the unit tetrahedron.

    ``r = u, s = v (1 - u), t = w (1 - u)(1 - v)`` with n Gauss-Legendre points per
    direction on [0, 1]^3; exact for polynomials of degree <= 2 n - 3.

    Parameters
    ----------
    n : int
        Points per direction, >= 1.

    Returns
    -------
    points : numpy.ndarray
        (r, s, t), shape (n^3, 3).
    weights : numpy.ndarray
        Weights summing to 1/6, shape (n^3,).
    """
    g, w = np.polynomial.legendre.leggauss(n)
    g, w = 0.5 * (g + 1.0), 0.5 * w
    u, v, t = (a.ravel() for a in np.meshgrid(g, g, g, indexing="ij"))
    wu, wv, wt = (a.ravel() for a in np.meshgrid(w, w, w, indexing="ij"))
    points = np.column_stack([u, v * (1 - u), t * (1 - u) * (1 - v)])
    return points, wu * wv * wt * (1 - u) ** 2 * (1 - v)


def tet10_group(nodes, tets, material, *, density=None):
    """Reference geometry of 10-node tetrahedra at the 4 integration points and their
    time-step length factors.

    Parameters
    ----------
    nodes : numpy.ndarray
        Reference nodal positions, shape (n, 3) [m].
    tets : numpy.ndarray
        Connectivity, shape (e, 10).
    material : NeoHookean
        ``mu``, ``lam`` [Pa], ``rho`` [kg/m^3], ``wave_speed`` [m/s] (unused without
        elements, may then be None).
    density : numpy.ndarray, optional
        Density of each element, shape (e,) [kg/m^3], for the time-step length factors
        (a mass-scaled mesh, :mod:`ccedi.fea.solvers.mass_scaling`). Default: the
        material's.

    Returns
    -------
    Tet10Group
        Gradients, point volumes, element volumes and length factors.

    Raises
    ------
    ValueError
        Naming the first inverted or degenerate element (det(dX/dxi) <= 0 at an
        integration point or a corner, or a corner volume <= 1e-12 of the cube of the
        longest corner edge).
    """
    tets = np.asarray(tets, dtype=np.int64).reshape(-1, 10)
    if len(tets) == 0:
        return Tet10Group(tets, np.zeros((0, 4, 10, 3)), np.zeros((0, 4)), np.zeros(0), np.zeros(0),
                          np.zeros((len(nodes), 3)))
    X = nodes[tets]
    corners = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    det_c, _, _ = _reference_jacobians(X, corners)
    det, dN, Jm = _reference_jacobians(X, QUADRATURE_POINTS)
    edge = np.linalg.norm(X[:, :4, None] - X[:, None, :4], axis=-1).max(axis=(1, 2))
    bad = (det <= 1e-12 * edge[:, None] ** 3).any(axis=1) | (det_c <= 1e-12 * edge[:, None] ** 3).any(axis=1)
    if np.any(bad):
        e = int(np.argmax(bad))
        raise ValueError(f"tet10 element {e} is inverted or degenerate (det dX/dxi <= 0 at a point or corner)")
    grad = np.einsum("mkj,emji->emki", dN, np.linalg.inv(Jm))
    weight = det / 24.0
    volume = weight.sum(axis=1)
    rho = material.rho if density is None else np.asarray(density)[:, None]
    element_mass = rho * volume[:, None] * hrz_fractions(X)
    kappa = time_step_length_factors(nodes, tets, grad, weight=weight,
                                     average=averaging_matrix(tets, len(nodes), nodal=False),
                                     element_mass=element_mass, mu=material.mu, lam=material.lam, c=material.wave_speed)
    return Tet10Group(tets, grad, weight, volume, kappa, np.zeros((len(nodes), 3)))


def hrz_fractions(X):
    """HRZ shares of the element mass: the consistent mass diagonal ``M_kk = int N_k^2 dV``
    (collapsed Gauss rule, exact for curved elements) over its sum.

    Parameters
    ----------
    X : numpy.ndarray
        Reference positions of the elements' nodes, shape (e, 10, 3) [m].

    Returns
    -------
    numpy.ndarray
        Fractions summing to 1 per element, shape (e, 10); corners 6/216 and mid-edge
        nodes 32/216 for a straight-edged element.
    """
    points, w = collapsed_rule(5)
    det, _, _ = _reference_jacobians(X, points)
    diag = np.einsum("m,em,mk->ek", w, det, shape_functions(points) ** 2)
    return diag / diag.sum(axis=1, keepdims=True)


def lumped_mass(nodes, group, rho):
    """HRZ lumped nodal masses: the consistent mass diagonal scaled to the element mass.

    ``m_k = rho V0 M_kk / sum_j M_jj`` with ``M_kk = int N_k^2 dV`` (collapsed Gauss rule,
    exact for curved elements); corners 6/216 and mid-edge nodes 32/216 of rho V0 for a
    straight-edged element.

    Parameters
    ----------
    nodes : numpy.ndarray
        Reference nodal positions, shape (n, 3) [m].
    group : Tet10Group
        The tetrahedra.
    rho : float or numpy.ndarray
        Density [kg/m^3], of all elements or of each, shape (e,).

    Returns
    -------
    numpy.ndarray
        Nodal masses, shape (n,) [kg].
    """
    m = np.zeros(len(nodes))
    if len(group.tets):
        rho_e = np.broadcast_to(np.asarray(rho, dtype=float), group.volume.shape)[:, None]
        np.add.at(m, group.tets, rho_e * group.volume[:, None] * hrz_fractions(nodes[group.tets]))
    return m


def characteristic_length(x, group):
    """``Le = kappa_e x`` the minimum altitude of the corner tetrahedra.

    Parameters
    ----------
    x : numpy.ndarray
        Current nodal positions, shape (n, 3) [m].
    group : Tet10Group
        The tetrahedra.

    Returns
    -------
    numpy.ndarray
        Le, shape (e,) [m].
    """
    return group.length_factor * min_altitude(x[group.tets[:, :4]])


def tangent_stiffness(x, group, material):
    """Consistent tangent stiffness of the quadratic tetrahedra at ``x``
    (:func:`ccedi.fea.elements.tetra.averaged_tangent`, one mean dilatation per element).

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    group : Tet10Group
        The tetrahedra.
    material : SolidMaterial
        ``mu`` and ``lam`` [Pa] are used.

    Returns
    -------
    scipy.sparse.csr_matrix
        K, shape (3 n, 3 n) [N/m].
    """
    return averaged_tangent(x, group.tets, group.grad, weight=group.weight,
                            average=averaging_matrix(group.tets, len(x), nodal=False), mu=material.mu, lam=material.lam)


def internal_forces_numpy(x, v, group, material, f):
    """Internal forces of the quadratic tetrahedra, pure numpy; the reference of
    :func:`internal_forces_numba`.

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    v : numpy.ndarray
        Nodal velocities, shape (n, 3) [m/s].
    group : Tet10Group
        The tetrahedra.
    material : SolidMaterial
        ``mu``, ``lam`` [Pa], ``rho`` [kg/m^3], ``c`` [m/s].
    f : numpy.ndarray
        Nodal forces (n, 3) [N], added to.

    Returns
    -------
    tuple
        (dt_min [s], strain_energy [J], bulk_viscous_power [W], status), see
        :func:`ccedi.fea.elements.tetra.averaged_forces_numpy`.
    """
    if len(group.tets) == 0:
        return np.inf, 0.0, 0.0, -1
    return averaged_forces_numpy(x, v, group.tets, grad=group.grad, weight=group.weight,
                                 average=averaging_matrix(group.tets, len(x), nodal=False),
                                 Le=characteristic_length(x, group), mu=material.mu, lam=material.lam,
                                 rho=material.rho, c=material.c, f=f, bulk_force=group.bulk_force)


@nb.njit(cache=True, fastmath=FASTMATH)
def internal_forces_numba(x, v, group, material, f):
    """Internal forces of the quadratic tetrahedra, compiled.

    Per element: F, dF/dt and J at the 4 points; the mean dilatation
    ``Jbar = sum_g w_g J_g / V0`` and its pressure ``lam ln(Jbar) / Jbar``; the bulk
    viscosity q of the element's volumetric strain rate and its critical step (paper
    Eq. 6); the point forces ``w_g [mu (F - F^-T) + (pbar - q) J F^-T] grad0 N_k``. Same
    contract as :func:`internal_forces_numpy`; the forces are added to ``f``, their
    bulk-viscosity part written to ``group.bulk_force``.

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    v : numpy.ndarray
        Nodal velocities, shape (n, 3) [m/s].
    group : Tet10Group
        The tetrahedra.
    material : SolidMaterial
        ``mu``, ``lam`` [Pa], ``rho`` [kg/m^3], ``c`` [m/s].
    f : numpy.ndarray
        Nodal forces (n, 3) [N], added to.

    Returns
    -------
    dt_min : float
        Smallest element critical step [s] (inf without elements).
    strain_energy : float
        Pi [J].
    bulk_viscous_power : float
        Power dissipated by the bulk viscosity [W].
    status : int
        -1, or the index of the first element with J <= 0 at a point; ``f`` then holds
        a partial sum to be discarded.
    """
    tets, grad, weight, volume = group.tets, group.grad, group.weight, group.volume
    ne = tets.shape[0]
    if ne == 0:
        return np.inf, 0.0, 0.0, -1
    mu, lam, rho, c = material.mu, material.lam, material.rho, material.c
    Fs = np.empty((4, 3, 3)); Gs = np.empty((4, 3, 3)); Js = np.empty(4); Fdot = np.empty((3, 3))
    fb = group.bulk_force
    fb[:, :] = 0.0
    dt_min = np.inf
    w = 0.0
    p_b = 0.0
    for e in range(ne):
        vol = 0.0
        vol_rate = 0.0
        for g in range(4):
            point_gradients(x, v, tets, grad[e, g], e, Fs[g], Fdot)
            J = inverse3(Fs[g], Gs[g])
            if not (J > 0.0):
                return 0.0, 0.0, 0.0, e
            Js[g] = J
            tr = 0.0
            for i in range(3):
                for j in range(3):
                    tr += Fdot[i, j] * Gs[g, j, i]
            vol += weight[e, g] * J
            vol_rate += weight[e, g] * J * tr
        Jb = vol / volume[e]
        lnJ = np.log(Jb)
        w += 0.5 * lam * volume[e] * lnJ * lnJ
        e_v = vol_rate / vol
        Le = group.length_factor[e] * corner_min_altitude(x, tets, e)
        q, dte = bulk_viscosity(Le, Le, e_v, rho, c)
        dt_min = min(dt_min, dte)
        p_b -= q * vol_rate
        p = lam * lnJ / Jb - q
        for g in range(4):
            w += add_point_forces(f, tets, grad[e, g], e, weight[e, g], Fs[g], Gs[g], Js[g], mu, p)
            if q > 0.0:
                add_point_forces(fb, tets, grad[e, g], e, weight[e, g], Fs[g], Gs[g], Js[g], 0.0, -q)
    return dt_min, w, p_b, -1
