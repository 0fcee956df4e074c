"""4-node tetrahedron with nodally averaged pressure: the average nodal pressure
tetrahedron of Bonet & Burton (1998), "A simple average nodal pressure tetrahedral
element for incompressible and nearly incompressible dynamic explicit applications",
Commun. Numer. Meth. Engng 14:437-449 (the LS-DYNA solid 13 analogue).

The constant-strain tetrahedron locks for nearly incompressible rubber: its volume
constraints (one per element, about 5-6 per node in a tetrahedral mesh) outnumber the
3 displacement DOFs of a node. Averaging the volume change over the elements around
each node leaves one constraint per node. This variationally consistent form keeps
ccedi's compressible neo-Hookean law and averages only its lam term
(:mod:`ccedi.fea.tetra`, with ``S_ae = 1/4`` for the corners a of e)::

    Pi = sum_e V0_e [mu/2 (I1 - 3) - mu ln J_e] + sum_a V0_a lam/2 (ln Jbar_a)^2
    V0_a = sum_{e at a} V0_e / 4,   Jbar_a = (sum_{e at a} J_e V0_e / 4) / V0_a

so the forces are exact derivatives of Pi (the energy balances), and each element
carries the mean ``pbar_e`` of its 4 nodal pressures ``p_a = lam ln(Jbar_a) / Jbar_a``::

    f_k = V0_e [mu (F - F^-T) + (pbar_e - q_e) J F^-T] grad0 N_k

Lumped mass rho V0 / 4 per corner. Critical step: paper Eq. (6) with
``Le = kappa_e h_e``, h the current minimum altitude 3 V / A_max and kappa_e set at
construction from the element's largest eigenvalue (with its own, un-averaged lam term,
which bounds the averaged one) and the assembled mesh's
(:func:`ccedi.fea.tetra.time_step_length_factors`). Measured at nu = 0.49, the element
bound alone is 1.64-2.45 times below the real limit 2/omega_max on straight-edged box
meshes (kappa_e 0.54-0.72 before scaling): the assembled scale brings the estimate at
rest to the real limit (within 0.3 %, never above it).
"""
from collections import namedtuple

import numba as nb
import numpy as np

from .fastmath import FASTMATH
from .tetra import (
    add_point_forces,
    averaged_forces_numpy,
    averaged_tangent,
    averaging_matrix,
    bulk_viscosity,
    corner_min_altitude,
    corner_volume,
    inverse3,
    min_altitude,
    point_gradients,
    time_step_length_factors,
)

Tet4Group = namedtuple("Tet4Group", "tets grad volume node_volume length_factor node_now node_pressure bulk_force")
Tet4Group.__doc__ = """Average nodal pressure tetrahedra (structure of arrays), as
:func:`internal_forces_numba` takes them.

Attributes
----------
tets : (e, 4) int ndarray
    Connectivity (VTK order, positive orientation).
grad : (e, 4, 3) ndarray
    Reference shape-function gradients dN_k/dX [1/m].
volume : (e,) ndarray
    Reference volumes V0_e [m^3].
node_volume : (n_nodes,) ndarray
    Nodal reference volumes V0_a = sum V0_e / 4 [m^3] (0 on nodes of no tetrahedron).
length_factor : (e,) ndarray
    kappa_e of the characteristic length ``Le = kappa_e h_e`` [-]
    (:func:`ccedi.fea.tetra.time_step_length_factors`).
node_now : (n_nodes,) ndarray
    Work array: current nodal volumes [m^3].
node_pressure : (n_nodes,) ndarray
    Work array: nodal pressures lam ln(Jbar_a) / Jbar_a [Pa].
bulk_force : (n_nodes, 3) ndarray
    Output of the kernels: the bulk-viscosity part of the nodal forces [N].
"""


def tet4_group(nodes, tets, material):
    """Reference geometry and time-step length factors of 4-node tetrahedra.

    Parameters
    ----------
    nodes : numpy.ndarray
        Reference nodal positions, shape (n, 3) [m].
    tets : numpy.ndarray
        Connectivity, shape (e, 4).
    material : NeoHookean
        ``mu``, ``lam`` [Pa], ``rho`` [kg/m^3], ``wave_speed`` [m/s] (unused without
        elements, may then be None).

    Returns
    -------
    Tet4Group
        Gradients, volumes, nodal volumes, length factors and work arrays.

    Raises
    ------
    ValueError
        Naming the first inverted or degenerate element (volume <= 1e-12 of the
        cube of its longest edge).
    """
    tets = np.asarray(tets, dtype=np.int64).reshape(-1, 4)
    n = len(nodes)
    X = nodes[tets]
    D = (X[:, 1:] - X[:, :1]).swapaxes(1, 2)                 # dX/dxi, columns the edges from corner 0
    volume = corner_volume(X)
    edge = np.linalg.norm(X[:, :, None] - X[:, None, :], axis=-1).max(axis=(1, 2)) if len(tets) else np.zeros(0)
    if np.any(volume <= 1e-12 * edge**3):
        bad = int(np.argmax(volume <= 1e-12 * edge**3))
        raise ValueError(f"tet4 element {bad} is inverted or degenerate (volume {volume[bad]:.3g} m^3)")
    dN = np.array([[-1.0, -1.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    grad = np.einsum("kj,eji->eki", dN, np.linalg.inv(D)) if len(tets) else np.zeros((0, 4, 3))
    average = averaging_matrix(tets, n, nodal=True)
    kappa = np.zeros(0)
    if len(tets):
        element_mass = np.repeat((material.rho * volume / 4.0)[:, None], 4, axis=1)
        kappa = time_step_length_factors(nodes, tets, grad[:, None], volume[:, None], average, element_mass,
                                         material.mu, material.lam, material.wave_speed)
    return Tet4Group(tets, grad, volume, average @ volume, kappa, np.zeros(n), np.zeros(n), np.zeros((n, 3)))


def lumped_mass(group, n_nodes, rho):
    """Lumped nodal masses, rho V0 / 4 per corner.

    Parameters
    ----------
    group : Tet4Group
        The tetrahedra.
    n_nodes : int
        Number of mesh nodes.
    rho : float
        Density [kg/m^3].

    Returns
    -------
    numpy.ndarray
        Nodal masses, shape (n_nodes,) [kg].
    """
    m = np.zeros(n_nodes)
    np.add.at(m, group.tets, np.repeat((rho * group.volume / 4.0)[:, None], 4, axis=1))
    return m


def characteristic_length(x, group):
    """``Le = kappa_e x`` the minimum altitude of each element.

    Parameters
    ----------
    x : numpy.ndarray
        Current nodal positions, shape (n, 3) [m].
    group : Tet4Group
        The tetrahedra.

    Returns
    -------
    numpy.ndarray
        Le, shape (e,) [m].
    """
    return group.length_factor * min_altitude(x[group.tets])


def tangent_stiffness(x, group, material):
    """Consistent tangent stiffness of the tetrahedra at ``x``
    (:func:`ccedi.fea.tetra.averaged_tangent` with the nodal averaging).

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    group : Tet4Group
        The tetrahedra.
    material : SolidMaterial
        ``mu`` and ``lam`` [Pa] are used.

    Returns
    -------
    scipy.sparse.csr_matrix
        K, shape (3 n, 3 n) [N/m].
    """
    return averaged_tangent(x, group.tets, group.grad[:, None], group.volume[:, None],
                            averaging_matrix(group.tets, len(x), nodal=True), material.mu, material.lam)


def internal_forces_numpy(x, v, group, material, f):
    """Internal forces of the tetrahedra, pure numpy; the reference of
    :func:`internal_forces_numba`.

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    v : numpy.ndarray
        Nodal velocities, shape (n, 3) [m/s].
    group : Tet4Group
        The tetrahedra.
    material : SolidMaterial
        ``mu``, ``lam`` [Pa], ``rho`` [kg/m^3], ``c`` [m/s].
    f : numpy.ndarray
        Nodal forces (n, 3) [N], added to.

    Returns
    -------
    tuple
        (dt_min [s], strain_energy [J], bulk_viscous_power [W], status), see
        :func:`ccedi.fea.tetra.averaged_forces_numpy`.
    """
    if len(group.tets) == 0:
        return np.inf, 0.0, 0.0, -1
    return averaged_forces_numpy(x, v, group.tets, group.grad[:, None], group.volume[:, None],
                                 averaging_matrix(group.tets, len(x), nodal=True), characteristic_length(x, group),
                                 material.mu, material.lam, material.rho, material.c, f, group.bulk_force)


@nb.njit(cache=True, fastmath=FASTMATH)
def internal_forces_numba(x, v, group, material, f):
    """Internal forces of the average nodal pressure tetrahedra, compiled.

    Three passes: the current nodal volumes ``sum J_e V0_e / 4``; the nodal pressures
    ``p_a = lam ln(Jbar_a) / Jbar_a`` and the volumetric energy; the element forces
    ``V0 [mu (F - F^-T) + (pbar_e - q_e) J F^-T] grad0 N_k`` (module docstring), with the
    bulk viscosity q_e and the critical step of paper Eq. (6). Same contract as
    :func:`internal_forces_numpy`; the forces are added to ``f``, their bulk-viscosity part
    written to ``group.bulk_force``.

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    v : numpy.ndarray
        Nodal velocities, shape (n, 3) [m/s].
    group : Tet4Group
        The tetrahedra (its work arrays and ``bulk_force`` are overwritten).
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
        -1, or the index of the first inverted element (J <= 0); ``f`` then holds a
        partial sum to be discarded.
    """
    tets, grad, volume = group.tets, group.grad, group.volume
    ne = tets.shape[0]
    if ne == 0:
        return np.inf, 0.0, 0.0, -1
    mu, lam, rho, c = material.mu, material.lam, material.rho, material.c
    V0n, now, pres, fb = group.node_volume, group.node_now, group.node_pressure, group.bulk_force
    fb[:, :] = 0.0
    F = np.empty((3, 3)); Fdot = np.empty((3, 3)); G = np.empty((3, 3))
    now[:] = 0.0
    for e in range(ne):
        point_gradients(x, v, tets, grad[e], e, F, Fdot)
        J = inverse3(F, G)
        if not (J > 0.0):
            return 0.0, 0.0, 0.0, e
        for a in range(4):
            now[tets[e, a]] += 0.25 * J * volume[e]
    w = 0.0
    for nd in range(now.shape[0]):
        if V0n[nd] > 0.0:
            Jb = now[nd] / V0n[nd]
            lnJ = np.log(Jb)
            pres[nd] = lam * lnJ / Jb
            w += 0.5 * lam * V0n[nd] * lnJ * lnJ
    dt_min = np.inf
    p_b = 0.0
    for e in range(ne):
        point_gradients(x, v, tets, grad[e], e, F, Fdot)
        J = inverse3(F, G)
        e_v = 0.0
        for i in range(3):
            for j in range(3):
                e_v += Fdot[i, j] * G[j, i]
        Le = group.length_factor[e] * corner_min_altitude(x, tets, e)
        q, dte = bulk_viscosity(Le, e_v, rho, c)
        dt_min = min(dt_min, dte)
        p_b -= q * e_v * J * volume[e]
        if q > 0.0:
            add_point_forces(fb, tets, grad[e], e, volume[e], F, G, J, 0.0, -q)
        pbar = 0.25 * (pres[tets[e, 0]] + pres[tets[e, 1]] + pres[tets[e, 2]] + pres[tets[e, 3]])
        w += add_point_forces(f, tets, grad[e], e, volume[e], F, G, J, mu, pbar - q)
    return dt_min, w, p_b, -1
