"""8-node hexahedron with one-point integration and Flanagan-Belytschko hourglass
control (LS-DYNA "solid #1" family), total-Lagrangian.

Reference-configuration quantities (computed once, :func:`element_geometry`):

* uniform strain gradient ``b_k = int_V0 dN_k/dX dV`` (Flanagan & Belytschko 1981),
  exact by 2x2x2 Gauss quadrature for a trilinear element; reference volume
  ``V0 = sum_k detJ w``.
* hourglass shape vectors ``gamma_a = h_a - (1/V0) sum_i b_i (h_a . X_i)`` for the four
  base vectors h_a; gamma_a is orthogonal to every linear field, so rigid motions and
  homogeneous deformations (however large) produce no hourglass force.

Per step, for nodal positions x (3, 8 per element):

* deformation gradient ``F = sum_k x_k (x) b_k / V0``, ``J = det F``;
* nodal internal force ``f_k = P(F) b_k + kappa sum_a gamma_ak q_a`` with
  ``q_a = sum_k gamma_ak x_k`` (hourglass generalised displacement);
* strain energy ``V0 W(F)`` and hourglass energy ``kappa/2 sum_a |q_a|^2``.

Hourglass stiffness (stiffness form, total). Flanagan & Belytschko scale it by
lam + 2 mu, which for nu -> 0.5 makes the hourglass modes stiff enough to lock in
bending. ccedi scales it by Young's modulus::

    kappa = Q_hg E (b : b) / (72 V0)                                    [N/m]

normalised so that Q_hg = 1 gives a cube in pure bending (u_z = -c y z) exactly the
Euler-Bernoulli energy E c^2 V Ly^2 / 24; the default Q_hg = 1.

Bulk viscosity (LS-DYNA defaults C0 = 1.5, C1 = 0.06), active in compression only::

    q = rho Le (C0 Le e_v^2 - C1 c e_v)   for volumetric strain rate e_v = J'/J < 0

adds the pressure q to the Cauchy stress and enters the critical time step, paper
Eq. (6): ``dt_e = Le / (Q + sqrt(Q^2 + c^2))``, ``Q = C1 c + C0 Le |e_v|``, with the
characteristic length ``Le = V / A_max`` (current volume over the largest face area).
"""
from dataclasses import dataclass

import numpy as np

from .material import first_piola, strain_energy_density

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
    bb : numpy.ndarray or None
        b : b per element, shape (e,) [m^4] (None where only the force kernel needs the geometry).
    """

    b: np.ndarray
    volume: np.ndarray
    gamma: np.ndarray
    bb: np.ndarray


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
        b (e, 8, 3) [m^2], volume (e,) [m^3], gamma (e, 4, 8), bb (e,) [m^4].

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
    bb = np.einsum("eki,eki->e", b, b)
    return ElementGeometry(b=b, volume=volume, gamma=gamma, bb=bb)


def hourglass_stiffness(geometry, E, q_hg):
    """Hourglass stiffness per element, ``kappa = Q_hg E (b:b) / (72 V0)``.

    Normalised so that ``q_hg = 1`` gives a cube in pure bending the Euler-Bernoulli
    energy (see the module docstring).

    Parameters
    ----------
    geometry : ElementGeometry
        Reference geometry (``bb`` and ``volume`` are used).
    E : float
        Young's modulus [Pa].
    q_hg : float
        Hourglass coefficient Q_hg [-].

    Returns
    -------
    numpy.ndarray
        kappa, shape (e,) [N/m].
    """
    return q_hg * E * geometry.bb / (72.0 * geometry.volume)


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


def element_time_step(Le, wave_speed, strain_rate_vol):
    """Critical time step of each element, paper Eq. (6).

    ::

        dt_e = Le / (Q + sqrt(Q^2 + c^2)),   Q = C1 c + C0 Le |e_v|  (e_v < 0, else Q = 0)

    with the bulk-viscosity constants C0 = 1.5, C1 = 0.06.

    Parameters
    ----------
    Le : numpy.ndarray
        Characteristic lengths, shape (e,) [m].
    wave_speed : float
        Dilatational wave speed c of the material [m/s].
    strain_rate_vol : numpy.ndarray
        Volumetric strain rate e_v = J'/J, shape (e,) [1/s]; bulk viscosity acts only
        in compression (e_v < 0).

    Returns
    -------
    numpy.ndarray
        dt_e, shape (e,) [s].
    """
    Q = np.where(strain_rate_vol < 0.0,
                 BULK_VISCOSITY_C1 * wave_speed + BULK_VISCOSITY_C0 * Le * np.abs(strain_rate_vol), 0.0)
    return Le / (Q + np.sqrt(Q * Q + wave_speed**2))


def internal_forces_numpy(x, v, hexes, b, volume, gamma, kappa, mu, lam, rho, c, f):
    """Internal forces of all elements, pure numpy; the reference for the numba kernel.

    Nodal force f_k = P(F) b_k + kappa sum_a gamma_ak q_a, with the bulk-viscosity
    pressure q added to the Cauchy stress in compression (see the module docstring).

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
        Hourglass stiffness, shape (e,) [N/m].
    mu : float
        Shear modulus [Pa].
    lam : float
        Lame's first parameter [Pa].
    rho : float
        Density [kg/m^3].
    c : float
        Dilatational wave speed [m/s].
    f : numpy.ndarray
        Output, shape (n, 3): overwritten with the nodal internal forces [N].

    Returns
    -------
    dt_min : float
        Smallest element critical time step [s].
    strain_energy : float
        sum V0 W(F) [J].
    hourglass_energy : float
        kappa/2 sum_a |q_a|^2 summed over the elements [J].
    bulk_viscous_power : float
        Power dissipated by the bulk viscosity [W].
    status : int
        -1 when every element has J > 0; else the index of the first inverted element
        (J <= 0), in which case the other values are 0 and ``f`` is untouched.
    """
    geometry = ElementGeometry(b=b, volume=volume, gamma=gamma, bb=None)
    x_e, v_e = x[hexes], v[hexes]
    F = deformation_gradient(x_e, geometry)
    J = np.linalg.det(F)
    if np.any(J <= 0.0):
        return 0.0, 0.0, 0.0, 0.0, int(np.argmax(J <= 0.0))
    Finv = np.linalg.inv(F)
    Fdot = deformation_gradient(v_e, geometry)
    e_v = np.einsum("eij,eji->e", Fdot, Finv)              # J'/J
    Le = characteristic_length(x_e, J * volume)
    q_bv = np.where(e_v < 0.0, rho * Le * (BULK_VISCOSITY_C0 * Le * e_v**2 - BULK_VISCOSITY_C1 * c * e_v), 0.0)
    P = first_piola(F, mu, lam) - (q_bv * J)[:, None, None] * Finv.swapaxes(1, 2)
    fe = np.einsum("eij,ekj->eki", P, b)
    q = np.einsum("eak,eki->eai", gamma, x_e)
    fe += kappa[:, None, None] * np.einsum("eak,eai->eki", gamma, q)
    f[:] = 0.0
    np.add.at(f, hexes, fe)
    dt_min = float(element_time_step(Le, c, e_v).min())
    strain_energy = float(np.sum(volume * strain_energy_density(F, mu, lam)))
    hourglass_energy = float(0.5 * np.sum(kappa * np.einsum("eai,eai->e", q, q)))
    bulk_power = float(np.sum(-q_bv * e_v * J * volume))
    return dt_min, strain_energy, hourglass_energy, bulk_power, -1
