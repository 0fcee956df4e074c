"""8-node hexahedron with one-point integration and physical hourglass stabilisation
(LS-DYNA "solid #1" with hourglass type 6 analogue), total-Lagrangian.

Reference-configuration quantities (computed once, :func:`element_geometry` and
:func:`hourglass_stiffness`):

* uniform strain gradient ``b_k = int_V0 dN_k/dX dV`` (Flanagan & Belytschko 1981),
  exact by 2x2x2 Gauss quadrature for a trilinear element; reference volume
  ``V0 = sum_k detJ w``.
* hourglass shape vectors ``gamma_a = h_a - (1/V0) sum_i b_i (h_a . X_i)`` for the four
  base vectors h_a; gamma_a is orthogonal to every linear field, so rigid motions and
  homogeneous deformations (however large) produce no hourglass force.
* hourglass stiffness K_hg, 12 x 12 over the generalised hourglass displacements
  (4 modes x 3 directions), the hourglass-subspace projection of the Wilson-Taylor
  incompatible-modes hexahedron (Wilson et al. 1973, Taylor, Beresford & Wilson 1976;
  Abaqus C3D8I analogue)::

      K_hg = H^T K_IM H / 64,        H_(k i)(a j) = h_ak delta_ij

  with K_IM the 24 x 24 stiffness of the element with the nine incompatible modes
  (1 - xi^2, 1 - eta^2, 1 - zeta^2 per direction) condensed out, small-strain isotropic
  elasticity with the material's Lame constants, 2x2x2 Gauss quadrature, evaluated on the
  parallelepiped with the element's centre Jacobian (see :func:`hourglass_stiffness`).
  This is Belytschko & Bindeman's physical (assumed-strain) stabilisation
  (Comput. Methods Appl. Mech. Engrg. 105, 1993; LS-DYNA hourglass type 6 with QM = 1):
  the stabilisation of the element's parallelepiped approximation. On a parallelepiped
  (``gamma_a = h_a`` there) the one-point element plus K_hg is the incompatible-modes
  element, exact in pure bending for any aspect ratio and free of volumetric locking as
  nu -> 0.5; aspect ratio and orientation enter through the element's own Jacobian, so
  no calibration is involved.

Per step, for nodal positions x (3, 8 per element):

* deformation gradient ``F = sum_k x_k (x) b_k / V0``, ``J = det F``;
* hourglass displacements ``q_a = sum_k gamma_ak x_k`` pulled back to the reference
  frame by the element's own deformation, ``qt_a = F^-1 q_a`` (objective: a rigid
  rotation of the deformed element leaves qt unchanged, so large rotations are exact);
* hourglass energy ``W_hg = Q_hg/2 qt^T K_hg qt`` -- hyperelastic, so the forces below
  are its exact gradient and the energy balance holds with it;
* nodal internal force, with ``Qt = Q_hg K_hg qt`` (the hourglass generalised forces in
  the reference frame) and ``S = sum_a Qt_a (x) qt_a``::

      f_k = (P(F) - F^-T S / V0) b_k + sum_a gamma_ak F^-T Qt_a

  (the ``F^-T S`` term is the derivative of the pull-back with respect to F);
* strain energy ``V0 W(F)`` and hourglass energy ``W_hg``.

Q_hg (:attr:`ccedi.fea.model.Model.hourglass_coefficient`, default 1) scales the
physical stabilisation; 1 is the incompatible-modes stiffness.

Bulk viscosity (LS-DYNA defaults C0 = 1.5, C1 = 0.06), active in compression only::

    q = rho Le (C0 Le e_v^2 - C1 c e_v)   for volumetric strain rate e_v = J'/J < 0

adds the pressure q to the Cauchy stress and enters the critical time step, paper
Eq. (6): ``dt_e = Le / (Q + sqrt(Q^2 + c^2))``, ``Q = C1 c + C0 Le |e_v|``, with the
characteristic length ``Le = V / A_max`` (current volume over the largest face area).
"""
from dataclasses import dataclass

import numpy as np

from ccedi.errors import SolverError
from ccedi.fea.elements.assembly import assemble
from ccedi.fea.material import first_piola, strain_energy_density

NATURAL = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                    [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
"""Natural coordinates (xi, eta, zeta) of the 8 nodes."""

HOURGLASS_BASE = np.array([[1, 1, -1, -1, -1, -1, 1, 1],
                           [1, -1, -1, 1, -1, 1, 1, -1],
                           [1, -1, 1, -1, 1, -1, 1, -1],
                           [-1, 1, -1, 1, 1, -1, 1, -1]], dtype=float)
"""Flanagan-Belytschko hourglass base vectors h_a (4, 8)."""

FACES = np.array([[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4],
                  [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]])
"""The six quadrilateral faces (local node ids)."""

BULK_VISCOSITY_C0 = 1.5
BULK_VISCOSITY_C1 = 0.06


@dataclass(frozen=True)
class ElementGeometry:
    """Reference-configuration data of all elements (see the module docstring).

    Parameters
    ----------
    b : numpy.ndarray
        Uniform strain gradients b_k = int_V0 dN_k/dX dV, shape (e, 8, 3) [m^2].
    volume : numpy.ndarray
        Reference volumes V0, shape (e,) [m^3].
    gamma : numpy.ndarray
        Flanagan-Belytschko hourglass shape vectors, shape (e, 4, 8) [-].
    """

    b: np.ndarray
    volume: np.ndarray
    gamma: np.ndarray


def shape_derivatives_natural(xi):
    """Derivatives of the 8 trilinear shape functions in natural coordinates.

    N_k = (1 + s_k1 xi)(1 + s_k2 eta)(1 + s_k3 zeta) / 8 with s_k the node's
    natural coordinates (:data:`NATURAL`).

    Parameters
    ----------
    xi : numpy.ndarray
        Natural point (xi, eta, zeta), shape (3,), each in [-1, 1].

    Returns
    -------
    numpy.ndarray
        dN_k/dxi_j, shape (8, 3).
    """
    s = NATURAL
    t = 1.0 + s * xi  # (8, 3)
    d = np.empty((8, 3))
    d[:, 0] = s[:, 0] * t[:, 1] * t[:, 2]
    d[:, 1] = s[:, 1] * t[:, 0] * t[:, 2]
    d[:, 2] = s[:, 2] * t[:, 0] * t[:, 1]
    return d / 8.0


def element_geometry(nodes, hexes):
    """Uniform gradients, volumes and hourglass vectors of all elements.

    b_k and V0 are integrated exactly by 2x2x2 Gauss quadrature; the hourglass vectors
    are gamma_a = h_a - (1/V0) sum_i b_i (h_a . X_i).

    Parameters
    ----------
    nodes : numpy.ndarray
        Reference nodal positions X, shape (n, 3) [m].
    hexes : numpy.ndarray
        Element connectivity, shape (e, 8), node order as in :mod:`ccedi.fea.mesh`.

    Returns
    -------
    ElementGeometry
        b (e, 8, 3) [m^2], volume (e,) [m^3], gamma (e, 4, 8).

    Raises
    ------
    ValueError
        Naming the first element with a non-positive Jacobian at a Gauss point
        (inverted or degenerate element).
    """
    X = nodes[hexes]  # (e, 8, 3)
    g = 1.0 / np.sqrt(3.0)
    b = np.zeros_like(X)
    volume = np.zeros(len(hexes))
    for gp in NATURAL * g:
        dN = shape_derivatives_natural(gp)             # (8, 3)
        J = np.einsum("eki,kj->eij", X, dN)            # dX_i/dxi_j
        detJ = np.linalg.det(J)
        if np.any(detJ <= 0.0):
            bad = int(np.argmax(detJ <= 0.0))
            raise ValueError(f"element {bad} is inverted or degenerate (Jacobian <= 0 at a Gauss point)")
        dNdX = np.einsum("kj,eji->eki", dN, np.linalg.inv(J))
        b += dNdX * detJ[:, None, None]
        volume += detJ
    gamma = (HOURGLASS_BASE[None]
             - np.einsum("eki,eai->eak", b, np.einsum("ak,eki->eai", HOURGLASS_BASE, X)) / volume[:, None, None])
    return ElementGeometry(b=b, volume=volume, gamma=gamma)


def _strain_operator(G):
    """Small-strain operator (Voigt order xx, yy, zz, yz, xz, xy; engineering shears) of
    functions with gradients G (e, m, 3): shape (e, 6, 3 m), column index function*3 + direction."""
    e, m, _ = G.shape
    B = np.zeros((e, 6, m, 3))
    for i in range(3):
        B[:, i, :, i] = G[:, :, i]
    for row, (i, j) in zip((3, 4, 5), ((1, 2), (0, 2), (0, 1))):
        B[:, row, :, i] = G[:, :, j]
        B[:, row, :, j] = G[:, :, i]
    return B.reshape(e, 6, 3 * m)


def _isotropic_elasticity(mu, lam):
    """6 x 6 small-strain isotropic elasticity matrix (Voigt, engineering shears) [Pa]."""
    D = np.zeros((6, 6))
    D[:3, :3] = lam
    D[np.arange(3), np.arange(3)] += 2.0 * mu
    D[np.arange(3, 6), np.arange(3, 6)] = mu
    return D


def incompatible_modes_stiffness(X, mu, lam):
    """Stiffness of the Wilson-Taylor incompatible-modes hexahedron, modes condensed out.

    Displacement ``u = sum_k N_k u_k + sum_m P_m alpha_m`` with the trilinear N_k and the
    incompatible modes P_m = 1 - xi_m^2 (m = xi, eta, zeta; a 3-vector alpha_m each);
    small-strain isotropic elasticity, 2x2x2 Gauss quadrature; the gradients of P_m are
    taken with the centre Jacobian J0 and scaled by det J0 / det J (Taylor, Beresford &
    Wilson 1976), so that they integrate to zero over any element (patch test) and the
    33 x 33 matrix stays a Gram matrix (positive semi-definite). The nine alpha are
    condensed statically: ``K_IM = K_uu - K_ua K_aa^-1 K_au``.

    Parameters
    ----------
    X : numpy.ndarray
        Reference nodal positions per element, shape (e, 8, 3) [m].
    mu : float
        Shear modulus [Pa].
    lam : float
        Lame's first parameter [Pa].

    Returns
    -------
    numpy.ndarray
        K_IM, shape (e, 24, 24) [N/m], DOF index node*3 + direction.
    """
    J0 = np.einsum("eki,kj->eij", X, shape_derivatives_natural(np.zeros(3)))
    J0inv, detJ0 = np.linalg.inv(J0), np.linalg.det(J0)
    D = _isotropic_elasticity(mu, lam)
    K = np.zeros((len(X), 33, 33))
    for gp in NATURAL / np.sqrt(3.0):
        dN = shape_derivatives_natural(gp)
        J = np.einsum("eki,kj->eij", X, dN)
        detJ = np.linalg.det(J)
        B_nodes = _strain_operator(np.einsum("kj,eji->eki", dN, np.linalg.inv(J)))     # dN_k/dX
        B_modes = _strain_operator(-2.0 * gp[None, :, None] * J0inv)                    # dP_m/dX with J0
        DB_nodes, DB_modes = D @ B_nodes, D @ B_modes
        K[:, :24, :24] += detJ[:, None, None] * (B_nodes.swapaxes(1, 2) @ DB_nodes)
        K[:, :24, 24:] += detJ0[:, None, None] * (B_nodes.swapaxes(1, 2) @ DB_modes)
        K[:, 24:, 24:] += (detJ0**2 / detJ)[:, None, None] * (B_modes.swapaxes(1, 2) @ DB_modes)
    K[:, 24:, :24] = K[:, :24, 24:].swapaxes(1, 2)
    return K[:, :24, :24] - K[:, :24, 24:] @ np.linalg.solve(K[:, 24:, 24:], K[:, 24:, :24])


def hourglass_stiffness(nodes, hexes, *, mu, lam, q_hg=1.0, chunk=4096):
    """Physical hourglass stiffness of every element, ``Q_hg H^T K_IM H / 64``.

    ``K_IM`` is the incompatible-modes stiffness (:func:`incompatible_modes_stiffness`)
    of the element's centre parallelepiped ``X0_k = Xc + J0 xi_k`` (the parallelepiped
    with the element's centre Jacobian J0; the element itself when it is a
    parallelepiped), H_(k i)(a j) = h_ak delta_ij: the hourglass displacements
    q_a = gamma_a . u of the element act as the hourglass fields ``h_a q_a / 8`` of that
    parallelepiped, whose gamma are the h. This is Belytschko & Bindeman's construction
    (the stabilisation of the element's parallelepiped approximation) in a frame-free form:
    aspect ratio and orientation enter through J0, K_hg is positive semi-definite for any
    element shape, and on a parallelepiped the one-point element plus K_hg is the
    incompatible-modes element (exact in pure bending at any aspect ratio, no volumetric
    locking).

    Parameters
    ----------
    nodes : numpy.ndarray
        Reference nodal positions, shape (n, 3) [m].
    hexes : numpy.ndarray
        Connectivity, shape (e, 8).
    mu : float
        Shear modulus [Pa].
    lam : float
        Lame's first parameter [Pa].
    q_hg : float, optional
        Scale Q_hg on the physical stiffness [-]. Default 1.
    chunk : int, optional
        Elements processed at once (bounds the memory). Default 4096.

    Returns
    -------
    numpy.ndarray
        K_hg, shape (e, 12, 12) [N/m], index mode*3 + direction (modes in the order of
        :data:`HOURGLASS_BASE`); symmetric positive semi-definite.
    """
    H = np.kron(HOURGLASS_BASE.T, np.eye(3)) / 8.0                          # u = h q / 8, (24, 12)
    dN0 = shape_derivatives_natural(np.zeros(3))
    out = np.zeros((len(hexes), 12, 12))
    for s in range(0, len(hexes), chunk):
        X = nodes[hexes[s:s + chunk]]
        J0 = np.einsum("eki,kj->eij", X, dN0)
        X0 = X.mean(axis=1)[:, None, :] + np.einsum("kj,eij->eki", NATURAL, J0)   # centre parallelepiped
        out[s:s + chunk] = q_hg * H.T @ incompatible_modes_stiffness(X0, mu, lam) @ H
    return 0.5 * (out + out.swapaxes(1, 2))


def deformation_gradient(x_e, geometry):
    """Deformation gradient ``F = sum_k x_k (x) b_k / V0`` of every element.

    Given velocities instead of positions it returns the rate dF/dt.

    Parameters
    ----------
    x_e : numpy.ndarray
        Element nodal positions [m] (or velocities [m/s]), shape (e, 8, 3).
    geometry : ElementGeometry
        Reference geometry (``b`` and ``volume`` are used).

    Returns
    -------
    numpy.ndarray
        F [-] (or dF/dt [1/s]), shape (e, 3, 3).
    """
    return np.matmul(x_e.swapaxes(1, 2), geometry.b) / geometry.volume[:, None, None]


def characteristic_length(x_e, volume):
    """Characteristic element length ``Le = V / A_max``.

    Parameters
    ----------
    x_e : numpy.ndarray
        Current element nodal positions, shape (e, 8, 3) [m].
    volume : numpy.ndarray
        Current element volumes V = J V0, shape (e,) [m^3].

    Returns
    -------
    numpy.ndarray
        Le, the volume over the largest face area, shape (e,) [m].
    """
    p = x_e[:, FACES]  # (e, 6, 4, 3)
    area = 0.5 * np.linalg.norm(np.cross(p[:, :, 2] - p[:, :, 0], p[:, :, 3] - p[:, :, 1]), axis=-1)
    return volume / area.max(axis=1)


def element_time_step(Le, wave_speed, strain_rate_vol, *, viscous_length=None):
    """Critical time step of each element, paper Eq. (6).

    ::

        dt_e = Le / (Q + sqrt(Q^2 + c^2)),   Q = (h / Le) (C1 c + C0 h |e_v|)  (e_v < 0, else Q = 0)

    with the bulk-viscosity constants C0 = 1.5, C1 = 0.06 and h the length the viscosity
    pressure is taken on (h = Le for the hexahedron, as in the paper): a viscosity
    ``q = rho h (C0 h e_v^2 - C1 c e_v)`` gives the mode of frequency 2 c / Le the damping
    ratio xi = C1 h / Le, and ``Le / (Q + sqrt(Q^2 + c^2)) = (Le / c)(sqrt(1 + xi^2) - xi)``
    is the central-difference limit of that damped mode.

    Parameters
    ----------
    Le : numpy.ndarray
        Characteristic lengths, shape (e,) [m].
    wave_speed : float
        Dilatational wave speed c of the material [m/s].
    strain_rate_vol : numpy.ndarray
        Volumetric strain rate e_v = J'/J, shape (e,) [1/s]; bulk viscosity acts only
        in compression (e_v < 0).
    viscous_length : numpy.ndarray, optional
        h, the length of the viscosity pressure, shape (e,) [m] (default: Le).

    Returns
    -------
    numpy.ndarray
        dt_e, shape (e,) [s].
    """
    h = Le if viscous_length is None else viscous_length
    Q = np.where(strain_rate_vol < 0.0,
                 h / Le * (BULK_VISCOSITY_C1 * wave_speed + BULK_VISCOSITY_C0 * h * np.abs(strain_rate_vol)), 0.0)
    return Le / (Q + np.sqrt(Q * Q + wave_speed**2))


def hourglass_displacements(x_e, gamma, kappa, *, Finv):
    """Pulled-back hourglass displacements and their generalised forces.

    ``qt_a = F^-1 sum_k gamma_ak x_k`` and ``Qt = K_hg qt`` (12-vectors, index
    mode*3 + direction), see the module docstring.

    Parameters
    ----------
    x_e : numpy.ndarray
        Element nodal positions, shape (e, 8, 3) [m].
    gamma : numpy.ndarray
        Hourglass shape vectors, shape (e, 4, 8).
    kappa : numpy.ndarray
        Hourglass stiffness K_hg, shape (e, 12, 12) [N/m].
    Finv : numpy.ndarray
        Inverse deformation gradients F^-1, shape (e, 3, 3).

    Returns
    -------
    qt : numpy.ndarray
        Pulled-back hourglass displacements, shape (e, 4, 3) [m].
    Qt : numpy.ndarray
        Hourglass generalised forces K_hg qt, shape (e, 4, 3) [N].
    """
    qt = np.einsum("eij,eaj->eai", Finv, np.einsum("eak,eki->eai", gamma, x_e))
    Qt = np.einsum("eab,eb->ea", kappa, qt.reshape(len(qt), 12)).reshape(qt.shape)
    return qt, Qt


def internal_forces_numpy(x, v, hexes, *, b, volume, gamma, kappa, length_factor, mu, lam, rho, c, f):
    """Internal forces of all elements, pure numpy; the reference for the numba kernel.

    Nodal force ``f_k = (P(F) - F^-T S / V0) b_k + sum_a gamma_ak F^-T Qt_a`` with the
    pulled-back hourglass displacements ``qt_a = F^-1 gamma_a . x``, ``Qt = K_hg qt`` and
    ``S = sum_a Qt_a (x) qt_a``, and the bulk-viscosity pressure added to the Cauchy stress
    in compression (see the module docstring).

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    v : numpy.ndarray
        Nodal velocities, shape (n, 3) [m/s] (for the bulk viscosity).
    hexes : numpy.ndarray
        Connectivity, shape (e, 8).
    b : numpy.ndarray
        Uniform gradients, shape (e, 8, 3) [m^2].
    volume : numpy.ndarray
        Reference volumes, shape (e,) [m^3].
    gamma : numpy.ndarray
        Hourglass shape vectors, shape (e, 4, 8).
    kappa : numpy.ndarray
        Hourglass stiffness K_hg (:func:`hourglass_stiffness`), shape (e, 12, 12) [N/m].
    length_factor : float
        Scale on the characteristic length V / A_max [-].
    mu : float
        Shear modulus [Pa].
    lam : float
        Lame's first parameter [Pa].
    rho : float
        Density [kg/m^3].
    c : float
        Dilatational wave speed [m/s].
    f : numpy.ndarray
        Nodal forces, shape (n, 3) [N]; the internal forces are ADDED to it.

    Returns
    -------
    dt_min : float
        Smallest element critical time step [s].
    strain_energy : float
        sum V0 W(F) [J].
    hourglass_energy : float
        sum over the elements of qt^T K_hg qt / 2 [J].
    bulk_viscous_power : float
        Power dissipated by the bulk viscosity [W].
    status : int
        -1 when every element has J > 0; else the index of the first inverted element
        (J <= 0), in which case the other values are 0 and ``f`` is untouched.
    """
    geometry = ElementGeometry(b=b, volume=volume, gamma=gamma)
    x_e, v_e = x[hexes], v[hexes]
    F = deformation_gradient(x_e, geometry)
    J = np.linalg.det(F)
    if np.any(J <= 0.0):
        return 0.0, 0.0, 0.0, 0.0, int(np.argmax(J <= 0.0))
    Finv = np.linalg.inv(F)
    Fdot = deformation_gradient(v_e, geometry)
    e_v = np.einsum("eij,eji->e", Fdot, Finv)              # J'/J
    Le = length_factor * characteristic_length(x_e, J * volume)
    q_bv = np.where(e_v < 0.0, rho * Le * (BULK_VISCOSITY_C0 * Le * e_v**2 - BULK_VISCOSITY_C1 * c * e_v), 0.0)
    qt, Qt = hourglass_displacements(x_e, gamma, kappa, Finv=Finv)
    S = np.einsum("eai,eaj->eij", Qt, qt)
    FinvT = Finv.swapaxes(1, 2)
    P = (first_piola(F, mu, lam) - (q_bv * J)[:, None, None] * FinvT
         - np.matmul(FinvT, S) / volume[:, None, None])
    fe = np.einsum("eij,ekj->eki", P, b) + np.einsum("eak,eai->eki", gamma, np.einsum("eji,eaj->eai", Finv, Qt))
    np.add.at(f, hexes, fe)
    dt_min = float(element_time_step(Le, c, e_v).min())
    strain_energy = float(np.sum(volume * strain_energy_density(F, mu, lam)))
    hourglass_energy = float(0.5 * np.sum(qt * Qt))
    bulk_power = float(np.sum(-q_bv * e_v * J * volume))
    return dt_min, strain_energy, hourglass_energy, bulk_power, -1


def tangent_stiffness(x, hexes, geometry, *, kappa, material):
    """Consistent tangent stiffness of one-point hexahedra at positions ``x``:
    ``K_(ki)(lm) = (1/V0) sum_jL b_kj A_ijmL b_lL + d f_hg,ki / d x_lm`` with the
    neo-Hookean elasticity tensor ``A = dP/dF`` (:mod:`ccedi.fea.solvers.static`) and the exact
    hourglass derivative (:func:`hourglass_tangent`).

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    hexes : numpy.ndarray
        Connectivity (e, 8).
    geometry : ElementGeometry
        Reference geometry of the elements (b, volume, gamma).
    kappa : numpy.ndarray
        Hourglass stiffness K_hg, shape (e, 12, 12) [N/m].
    material : ccedi.fea.material.NeoHookean
        The solid (its Lame constants mu, lam).

    Returns
    -------
    scipy.sparse.csr_matrix
        K, shape (3 n, 3 n) [N/m], DOF index node*3 + direction, no constraints applied.

    Raises
    ------
    SolverError
        If an element is inverted (J <= 0) at ``x``.
    """
    g, mat = geometry, material
    F = deformation_gradient(x[hexes], g)
    J = np.linalg.det(F)
    if np.any(J <= 0.0):
        raise SolverError(f"element {int(np.argmax(J <= 0.0))} inverted (J <= 0)")
    Fi = np.linalg.inv(F)
    # b_kj A_ijml b_bl with c_k = F^-T b_k: mu (b_k . b_b) d_im + c1 c_bi c_km + lam c_ki c_bm
    c = g.b @ Fi                                                  # (e, 8, 3): c_k,i = b_kj Fi_ji
    c1 = (mat.mu - mat.lam * np.log(J))[:, None, None, None, None]
    Ke = (mat.mu * (g.b @ g.b.transpose(0, 2, 1)))[:, :, None, :, None] * np.eye(3)[None, None, :, None, :]
    Ke += c1 * c.transpose(0, 2, 1)[:, None, :, :, None] * c[:, :, None, None, :]
    Ke += mat.lam * c[:, :, :, None, None] * c[:, None, None, :, :]
    Ke /= g.volume[:, None, None, None, None]
    Ke += hourglass_tangent(x[hexes], g, kappa, Finv=Fi)
    return assemble(Ke, hexes, len(x))


def hourglass_tangent(x_e, geometry, kappa, *, Finv):
    """Exact derivative of the hourglass nodal forces of :mod:`ccedi.fea.elements.hex8`.

    With ``qt_a = F^-1 q_a``, ``Qt = K_hg qt``, ``A_a = F^-T Qt_a``, ``T = F^-T S``,
    ``S = sum_a Qt_a (x) qt_a``, the forces are ``f_k = sum_a gamma_ak A_a - T b_k / V0``.
    For a perturbation of node l along m (``dF = e_m (x) b_l / V0``)::

        dqt_a = F^-1 e_m (gamma_al - b_l . qt_a / V0),        dQt = K_hg dqt
        dA_a  = F^-T dQt_a - (F^-T b_l) A_am / V0
        dT    = F^-T dS - (F^-T b_l) (x) T_m. / V0,   dS = sum_a dQt_a (x) qt_a + Qt_a (x) dqt_a

    Parameters
    ----------
    x_e : numpy.ndarray
        Element nodal positions, shape (e, 8, 3) [m].
    geometry : ElementGeometry
        Reference geometry (b, volume, gamma).
    kappa : numpy.ndarray
        Hourglass stiffness K_hg, shape (e, 12, 12) [N/m].
    Finv : numpy.ndarray
        Inverse deformation gradients, shape (e, 3, 3).

    Returns
    -------
    numpy.ndarray
        d f_(ki) / d x_(lm), shape (e, 8, 3, 8, 3) [N/m].
    """
    b, V, gamma = geometry.b, geometry.volume[:, None, None], geometry.gamma
    e = len(x_e)
    qt, Qt = hourglass_displacements(x_e, gamma, kappa, Finv=Finv)
    # batched matrix products over the element axis, (l, m) flattened to 24 rows
    FiT = Finv.transpose(0, 2, 1)[:, None]
    A = Qt @ Finv                                                         # A_a = F^-T Qt_a
    T = FiT[:, 0] @ (Qt.transpose(0, 2, 1) @ qt)                          # F^-T S
    Fb = b @ Finv / V                                                     # F^-T b_l / V0
    c = gamma.swapaxes(1, 2) - b @ qt.transpose(0, 2, 1) / V              # (e, l, a)
    dqt = np.einsum("eim,ela->elmai", Finv, c).reshape(e, 24, 4, 3)       # (e, lm, a, i)
    dQt = (dqt.reshape(e, 24, 12) @ kappa.transpose(0, 2, 1)).reshape(e, 24, 4, 3)
    dA = dQt @ Finv[:, None] - (Fb[:, :, None, None, :] * A.transpose(0, 2, 1)[:, None, :, :, None]).reshape(e, 24, 4, 3)
    dS = dQt.transpose(0, 1, 3, 2) @ qt[:, None] + Qt.transpose(0, 2, 1)[:, None] @ dqt
    dT = FiT @ dS - (Fb[:, :, None, :, None] * T[:, None, :, None, :]).reshape(e, 24, 3, 3)
    df = gamma.transpose(0, 2, 1)[:, None] @ dA - (dT @ b.transpose(0, 2, 1)[:, None]).transpose(0, 1, 3, 2) / V[:, :, :, None]
    return df.reshape(e, 8, 3, 8, 3).transpose(0, 3, 4, 1, 2)
