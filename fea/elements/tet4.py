"""4-node tetrahedron with node-smoothed shear and volume: the average nodal pressure
tetrahedron of Bonet & Burton (1998), "A simple average nodal pressure tetrahedral
element for incompressible and nearly incompressible dynamic explicit applications",
Commun. Numer. Meth. Engng 14:437-449 (the LS-DYNA solid 13 analogue), with its shear
energy split as in the alpha finite element method (alpha-FEM-T4) of Liu, Nguyen-Thoi &
Lam (2008), "A novel alpha finite element method (alphaFEM) for exact solution to
mechanics problems using triangular and tetrahedral elements", Comput. Methods Appl.
Mech. Engrg. 197:3883-3897.

The constant-strain tetrahedron locks for nearly incompressible rubber: its volume
constraints (one per element, about 5-6 per node in a tetrahedral mesh) outnumber the
3 displacement DOFs of a node. Averaging the volume change over the elements around
each node leaves one constraint per node (Bonet & Burton). Free of locking, the linear
tetrahedron is still stiff in bending at any nu (+94 / +24 % tip stiffness at 4 / 2 mm
on the 60 x 12 x 8 mm test cantilever, ``validation/tet_locking.py``), and the
node-based smoothed FEM (NS-FEM: strains averaged over the elements around each node)
as soft; alpha-FEM takes the fraction alpha of the energy on the node-smoothed
deformation gradients and 1 - alpha on the elements' own, alpha = 0.7 for tetrahedra
(:data:`NODAL_SHEAR_FRACTION`, Nguyen-Thoi & Nguyen-Xuan, Vietnam J. Mech. 32 (2010)
235-246). Here that split applies to the shear (mu) part of ccedi's compressible
neo-Hookean law and the lam term stays wholly nodal, as Bonet & Burton's (a selective
NS-FEM for the volume, alpha-FEM for the shear; :mod:`ccedi.fea.elements.tetra`, with
``S_ae = 1/4`` for the corners a of e)::

    Pi = sum_e (1 - alpha) V0_e W_mu(F_e) + sum_a V0_a [alpha W_mu(Fbar_a) + lam/2 (ln Jbar_a)^2]
    W_mu(F) = mu/2 (I1 - 3) - mu ln J
    V0_a = sum_{e at a} V0_e / 4,   Jbar_a = (sum_{e at a} J_e V0_e / 4) / V0_a
    Fbar_a = sum_{e at a} F_e V0_e / 4 / V0_a

Fbar_a is linear in the nodal positions (the deformation gradient of node a's smoothing
domain), so a homogeneous deformation is reproduced exactly, a rigid rotation costs
nothing, and the (1 - alpha) element part leaves no zero-energy mode. The forces are
exact derivatives of Pi (the energy balances); each element carries the mean ``pbar_e`` of
its 4 nodal pressures ``p_a = lam ln(Jbar_a) / Jbar_a`` and the mean ``Pbar_e`` of its 4
nodal shear stresses ``P_a = alpha mu (Fbar_a - Fbar_a^-T)``::

    f_k = V0_e [(1 - alpha) mu (F - F^-T) + Pbar_e + (pbar_e - q_e) J F^-T] grad0 N_k

Measured on that cantilever at nu = 0.499 against the converged hexahedra
(``validation/tet_locking.py``): +13.7 / +1.8 / +0.3 % at 4 / 2 / 1 mm (alpha = 0.7),
against +94 / +24.5 / +6.5 % with the element shear alone (alpha = 0).

Lumped mass rho V0 / 4 per corner. Critical step: paper Eq. (6) with
``Le = kappa_e h_e``, h the current minimum altitude 3 V / A_max and kappa_e set at
construction from the element's largest eigenvalue (with its own, un-averaged shear and
lam terms, which bound the averaged ones) and the assembled mesh's
(:func:`ccedi.fea.elements.tetra.time_step_length_factors`): the assembled scale brings the
estimate at rest to the real limit 2/omega_max (never above it). The bulk viscosity q_e is
taken on h_e, not on Le (:func:`ccedi.fea.elements.tetra.bulk_viscosity`), so that it damps the
highest modes at its nominal ratio.
"""
from collections import namedtuple

import numba as nb
import numpy as np
import scipy.sparse as sp

from ccedi.fea.elements.fastmath import FASTMATH
from ccedi.fea.elements.tetra import (
    add_point_forces,
    averaged_forces_numpy,
    averaged_tangent,
    averaging_matrix,
    bulk_viscosity,
    corner_min_altitude,
    corner_volume,
    deformation_gradients,
    inverse3,
    min_altitude,
    point_gradients,
    time_step_length_factors,
)
from ccedi.fea.material import strain_energy_density

NODAL_SHEAR_FRACTION = 0.7
"""alpha of alpha-FEM-T4: the share of the shear energy taken on the node-smoothed
deformation gradients [-] (0: Bonet & Burton's element, 1: NS-FEM's shear); 0.7 is the
value recommended for tetrahedra (module docstring)."""

Tet4Group = namedtuple("Tet4Group", "tets grad volume node_volume length_factor nodal_shear "
                                    "node_now node_pressure node_F node_stress bulk_force")
Tet4Group.__doc__ = """Node-smoothed 4-node tetrahedra (structure of arrays), as
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
    (:func:`ccedi.fea.elements.tetra.time_step_length_factors`).
nodal_shear : float
    alpha, the share of the shear energy on the node-smoothed F [-].
node_now : (n_nodes,) ndarray
    Work array: current nodal volumes [m^3].
node_pressure : (n_nodes,) ndarray
    Work array: nodal pressures lam ln(Jbar_a) / Jbar_a [Pa].
node_F : (n_nodes, 3, 3) ndarray
    Work array: sum_e V0_e F_e / 4 over the elements at each node, V0_a Fbar_a [m^3].
node_stress : (n_nodes, 3, 3) ndarray
    Work array: nodal shear stresses alpha mu (Fbar_a - Fbar_a^-T) [Pa].
bulk_force : (n_nodes, 3) ndarray
    Output of the kernels: the bulk-viscosity part of the nodal forces [N].
"""


def tet4_group(nodes, tets, material, *, nodal_shear=NODAL_SHEAR_FRACTION, density=None):
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
    nodal_shear : float, optional
        alpha in [0, 1], the share of the shear energy on the node-smoothed deformation
        gradients. Default :data:`NODAL_SHEAR_FRACTION`.
    density : numpy.ndarray, optional
        Density of each element, shape (e,) [kg/m^3], for the time-step length factors
        (a mass-scaled mesh, :mod:`ccedi.fea.solvers.mass_scaling`). Default: the
        material's.

    Returns
    -------
    Tet4Group
        Gradients, volumes, nodal volumes, length factors and work arrays.

    Raises
    ------
    ValueError
        Naming the first inverted or degenerate element (volume <= 1e-12 of the
        cube of its longest edge), or an alpha outside [0, 1].
    """
    if not 0.0 <= nodal_shear <= 1.0:
        raise ValueError(f"nodal_shear = {nodal_shear}: must be in [0, 1]")
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
    group = Tet4Group(tets, grad, volume, average @ volume, np.zeros(len(tets)), float(nodal_shear), np.zeros(n),
                      np.zeros(n), np.zeros((n, 3, 3)), np.zeros((n, 3, 3)), np.zeros((n, 3)))
    if len(tets):
        rho = material.rho if density is None else density
        element_mass = np.repeat((rho * volume / 4.0)[:, None], 4, axis=1)
        group.length_factor[:] = time_step_length_factors(
            nodes, tets, grad[:, None], weight=volume[:, None], average=average, element_mass=element_mass,
            mu=material.mu, lam=material.lam, c=material.wave_speed, tangent=tangent_stiffness(nodes, group, material))
    return group


def lumped_mass(group, n_nodes, rho):
    """Lumped nodal masses, rho V0 / 4 per corner.

    Parameters
    ----------
    group : Tet4Group
        The tetrahedra.
    n_nodes : int
        Number of mesh nodes.
    rho : float or numpy.ndarray
        Density [kg/m^3], of all elements or of each, shape (e,).

    Returns
    -------
    numpy.ndarray
        Nodal masses, shape (n_nodes,) [kg].
    """
    m = np.zeros(n_nodes)
    np.add.at(m, group.tets, np.repeat((rho * group.volume / 4.0)[:, None], 4, axis=1))
    return m


def smoothing_operator(group, n_nodes):
    """The linear map from nodal positions to the node-smoothed deformation gradients,
    ``vec(Fbar_a) = B x`` (module docstring).

    Parameters
    ----------
    group : Tet4Group
        The tetrahedra.
    n_nodes : int
        Number of mesh nodes.

    Returns
    -------
    scipy.sparse.csr_matrix
        B, shape (9 n_nodes, 3 n_nodes) [1/m]: row 9 a + 3 i + j is d(Fbar_a)_ij / dx,
        column 3 k + i; the rows of nodes of no tetrahedron are zero.
    """
    tets, grad = group.tets, group.grad
    ne = len(tets)
    row = np.arange(3)[:, None] * 3 + np.arange(3)                        # (i, j) -> 3 i + j
    # element operator: vec(F_e) = Be x, entries grad_kj at (9 e + 3 i + j, 3 k + i)
    rows = np.broadcast_to(9 * np.arange(ne)[:, None, None, None] + row[None, None], (ne, 4, 3, 3))
    cols = np.broadcast_to((3 * tets)[:, :, None, None] + np.arange(3)[None, None, :, None], (ne, 4, 3, 3))
    vals = np.broadcast_to(grad[:, :, None, :], (ne, 4, 3, 3))
    Be = sp.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())), shape=(9 * ne, 3 * n_nodes))
    weight = np.divide(1.0, group.node_volume, out=np.zeros(n_nodes), where=group.node_volume > 0.0)
    W = sp.diags(weight) @ averaging_matrix(tets, n_nodes, nodal=True) @ sp.diags(group.volume)
    return (sp.kron(W, sp.identity(9), format="csr") @ Be).tocsr()


def smoothed_deformation_gradients(x, group):
    """Node-smoothed deformation gradients ``Fbar_a = sum_e F_e V0_e / 4 / V0_a``.

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    group : Tet4Group
        The tetrahedra.

    Returns
    -------
    numpy.ndarray
        Fbar, shape (n, 3, 3) [-]; the identity at nodes of no tetrahedron.
    """
    F = deformation_gradients(x, group.tets, group.grad[:, None])[:, 0]
    Fb = np.zeros((len(x), 3, 3))
    np.add.at(Fb, group.tets, np.repeat((0.25 * group.volume[:, None, None] * F)[:, None], 4, axis=1))
    used = group.node_volume > 0.0
    Fb[used] /= group.node_volume[used, None, None]
    Fb[~used] = np.eye(3)
    return Fb


def _first_element_at(tets, nodes):
    """Index of the first element using one of ``nodes`` (boolean mask over the nodes)."""
    return int(np.argmax(nodes[tets].any(axis=1)))


def tangent_stiffness(x, group, material):
    """Consistent tangent stiffness of the tetrahedra at ``x``: the element shear and the
    nodal volume term (:func:`ccedi.fea.elements.tetra.averaged_tangent` with the nodal averaging and
    mu scaled by 1 - alpha) plus the node-smoothed shear ``B^T diag(alpha V0_a A(Fbar_a)) B``
    (B of :func:`smoothing_operator`, ``A_ijmL = mu (d_im d_jL + Fbar^-1_Li Fbar^-1_jm)``).

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

    Raises
    ------
    ValueError
        Naming the first element with J <= 0, or at a node with det Fbar <= 0.
    """
    n, alpha = len(x), group.nodal_shear
    K = averaged_tangent(x, group.tets, group.grad[:, None], weight=group.volume[:, None],
                         average=averaging_matrix(group.tets, n, nodal=True), mu=(1.0 - alpha) * material.mu,
                         lam=material.lam)
    if alpha == 0.0 or len(group.tets) == 0:
        return K
    B = smoothing_operator(group, n)
    Fb = (B @ x.ravel()).reshape(n, 3, 3)
    used = group.node_volume > 0.0
    Fb[~used] = np.eye(3)
    J = np.linalg.det(Fb)
    if np.any(J <= 0.0):
        raise ValueError(f"element {_first_element_at(group.tets, J <= 0.0)} inverted (det Fbar <= 0 at a node)")
    Fi = np.linalg.inv(Fb)
    eye = np.eye(3)
    A = eye[None, :, None, :, None] * eye[None, None, :, None, :] + np.einsum("nLi,njm->nijmL", Fi, Fi)
    A *= (alpha * material.mu * group.node_volume)[:, None, None, None, None]
    blocks = sp.bsr_matrix((A.reshape(n, 9, 9), np.arange(n), np.arange(n + 1)), shape=(9 * n, 9 * n))
    return (K + B.T @ blocks @ B).tocsr()


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
        :func:`ccedi.fea.elements.tetra.averaged_forces_numpy`.
    """
    tets, alpha = group.tets, group.nodal_shear
    if len(tets) == 0:
        return np.inf, 0.0, 0.0, -1
    J = np.linalg.det(deformation_gradients(x, tets, group.grad[:, None])[:, 0])
    if np.any(J <= 0.0):
        return 0.0, 0.0, 0.0, int(np.argmax(J <= 0.0))
    Fb = smoothed_deformation_gradients(x, group)
    Jb = np.linalg.det(Fb)
    if np.any(Jb <= 0.0):
        return 0.0, 0.0, 0.0, _first_element_at(tets, Jb <= 0.0)
    h = min_altitude(x[tets])
    dt, energy, power, status = averaged_forces_numpy(
        x, v, tets, grad=group.grad[:, None], weight=group.volume[:, None],
        average=averaging_matrix(tets, len(x), nodal=True), Le=group.length_factor * h,
        mu=(1.0 - alpha) * material.mu, lam=material.lam, rho=material.rho, c=material.c, f=f,
        bulk_force=group.bulk_force, viscous_length=h)
    P = alpha * material.mu * (Fb - np.linalg.inv(Fb).swapaxes(1, 2))
    np.add.at(f, tets, np.einsum("e,eij,ekj->eki", group.volume, P[tets].mean(axis=1), group.grad))
    energy += alpha * float(group.node_volume @ strain_energy_density(Fb, material.mu, 0.0))
    return dt, energy, power, status


@nb.njit(cache=True, fastmath=FASTMATH)
def _add_stress_forces(f, tets, grad_e, e, w, P):
    """Add ``w P grad0 N_k`` to the 4 corners of element ``e`` (P a (3, 3) stress [Pa],
    w a volume [m^3])."""
    for k in range(4):
        nd = tets[e, k]
        for i in range(3):
            f[nd, i] += w * (P[i, 0] * grad_e[k, 0] + P[i, 1] * grad_e[k, 1] + P[i, 2] * grad_e[k, 2])


@nb.njit(cache=True, fastmath=FASTMATH)
def internal_forces_numba(x, v, group, material, f):
    """Internal forces of the node-smoothed tetrahedra, compiled.

    Three passes: the current nodal volumes ``sum J_e V0_e / 4`` and the sums
    ``sum F_e V0_e / 4``; per node the pressure ``p_a = lam ln(Jbar_a) / Jbar_a``, the
    shear stress ``P_a = alpha mu (Fbar_a - Fbar_a^-T)`` and their energies; the element
    forces ``V0 [(1 - alpha) mu (F - F^-T) + Pbar_e + (pbar_e - q_e) J F^-T] grad0 N_k``
    (module docstring), with the bulk viscosity q_e and the critical step of paper Eq. (6).
    Same contract as :func:`internal_forces_numpy`; the forces are added to ``f``, their
    bulk-viscosity part written to ``group.bulk_force``.

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
        -1, or the index of the first inverted element (J <= 0; or the first element at a
        node with det Fbar <= 0); ``f`` then holds a partial sum to be discarded.
    """
    tets, grad, volume = group.tets, group.grad, group.volume
    ne = tets.shape[0]
    if ne == 0:
        return np.inf, 0.0, 0.0, -1
    mu, lam, rho, c = material.mu, material.lam, material.rho, material.c
    alpha = group.nodal_shear
    mu_e = (1.0 - alpha) * mu
    V0n, now, pres, fb = group.node_volume, group.node_now, group.node_pressure, group.bulk_force
    Fn, Pn = group.node_F, group.node_stress
    fb[:, :] = 0.0
    F = np.empty((3, 3)); Fdot = np.empty((3, 3)); G = np.empty((3, 3)); P = np.empty((3, 3))
    now[:] = 0.0
    Fn[:, :, :] = 0.0
    for e in range(ne):
        point_gradients(x, v, tets, grad[e], e, F, Fdot)
        J = inverse3(F, G)
        if not (J > 0.0):
            return 0.0, 0.0, 0.0, e
        for a in range(4):
            nd = tets[e, a]
            now[nd] += 0.25 * J * volume[e]
            for i in range(3):
                for j in range(3):
                    Fn[nd, i, j] += 0.25 * volume[e] * F[i, j]
    w = 0.0
    for nd in range(now.shape[0]):
        if V0n[nd] > 0.0:
            Jb = now[nd] / V0n[nd]
            lnJ = np.log(Jb)
            pres[nd] = lam * lnJ / Jb
            w += 0.5 * lam * V0n[nd] * lnJ * lnJ
            if alpha > 0.0:
                I1 = 0.0
                for i in range(3):
                    for j in range(3):
                        F[i, j] = Fn[nd, i, j] / V0n[nd]
                        I1 += F[i, j] * F[i, j]
                Jf = inverse3(F, G)
                if not (Jf > 0.0):
                    for e in range(ne):
                        for a in range(4):
                            if tets[e, a] == nd:
                                return 0.0, 0.0, 0.0, e
                for i in range(3):
                    for j in range(3):
                        Pn[nd, i, j] = alpha * mu * (F[i, j] - G[j, i])
                w += alpha * V0n[nd] * (0.5 * mu * (I1 - 3.0) - mu * np.log(Jf))
    dt_min = np.inf
    p_b = 0.0
    for e in range(ne):
        point_gradients(x, v, tets, grad[e], e, F, Fdot)
        J = inverse3(F, G)
        e_v = 0.0
        for i in range(3):
            for j in range(3):
                e_v += Fdot[i, j] * G[j, i]
        h = corner_min_altitude(x, tets, e)
        q, dte = bulk_viscosity(group.length_factor[e] * h, h, e_v, rho, c)
        dt_min = min(dt_min, dte)
        p_b -= q * e_v * J * volume[e]
        if q > 0.0:
            add_point_forces(fb, tets, grad[e], e, volume[e], F, G, J, 0.0, -q)
        pbar = 0.25 * (pres[tets[e, 0]] + pres[tets[e, 1]] + pres[tets[e, 2]] + pres[tets[e, 3]])
        w += add_point_forces(f, tets, grad[e], e, volume[e], F, G, J, mu_e, pbar - q)
        if alpha > 0.0:
            for i in range(3):
                for j in range(3):
                    P[i, j] = 0.25 * (Pn[tets[e, 0], i, j] + Pn[tets[e, 1], i, j] + Pn[tets[e, 2], i, j]
                                      + Pn[tets[e, 3], i, j])
            _add_stress_forces(f, tets, grad[e], e, volume[e], P)
    return dt_min, w, p_b, -1
