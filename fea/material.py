"""Compressible neo-Hookean material (reduces to isotropic linear elasticity at small strain).

Strain energy per unit reference volume (Bonet & Wood, Eq. 6.27)::

    W(F) = mu/2 (tr(F^T F) - 3) - mu ln J + lam/2 (ln J)^2,      J = det F

First Piola-Kirchhoff stress::

    P = mu (F - F^-T) + lam ln(J) F^-T                           [Pa]

Cauchy stress ``sigma = P F^T / J = (mu (F F^T - I) + lam ln(J) I) / J``: compiled once
(:func:`neo_hookean_cauchy`, on one F) for the stress recovery of the FE model
(:func:`cauchy_von_mises`) and of the reduced model (:mod:`ccedi.rom.superelement`); the
numpy :func:`cauchy_stress` is its reference. Lame constants from Young's modulus E and
Poisson's ratio nu: ``mu = E / (2 (1 + nu))``, ``lam = E nu / ((1 + nu)(1 - 2 nu))``.
"""
from dataclasses import dataclass

import numba as nb
import numpy as np

from ccedi.fea.elements.fastmath import FASTMATH
from ccedi.quantities import QUANTITIES


@dataclass(frozen=True)
class NeoHookean:
    """Isotropic compressible neo-Hookean solid.

    Parameters
    ----------
    E : float
        Young's modulus [Pa], 1e4..1e12.
    nu : float
        Poisson's ratio [-], 0..0.499.
    rho : float
        Mass density [kg/m^3], 1..1e5.

    Raises
    ------
    ccedi.errors.InputError
        If E, nu or rho is not a number within its range of
        :data:`ccedi.quantities.QUANTITIES` (the one every input source uses).
    """

    E: float
    nu: float
    rho: float

    def __post_init__(self):
        for name, quantity in (("E", "E_Pa"), ("nu", "nu"), ("rho", "rho_kg_m3")):
            value = QUANTITIES[quantity].check(getattr(self, name), f"NeoHookean {name}")
            object.__setattr__(self, name, value)

    @property
    def mu(self):
        """Shear modulus [Pa]."""
        return self.E / (2.0 * (1.0 + self.nu))

    @property
    def lam(self):
        """First Lame constant [Pa]."""
        return self.E * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu))

    @property
    def constrained_modulus(self):
        """P-wave (constrained) modulus lam + 2 mu = E (1-nu) / ((1+nu)(1-2nu)) [Pa]."""
        return self.lam + 2.0 * self.mu

    @property
    def wave_speed(self):
        """Dilatational wave speed c_w = sqrt(E(1-nu) / (rho (1+nu)(1-2nu))) [m/s], paper Eq. (6)."""
        return float(np.sqrt(self.constrained_modulus / self.rho))


RUBBER = NeoHookean(E=6.1e6, nu=0.49, rho=1000.0)
"""The paper's finger rubber (Table 1): E = 6.1 MPa, nu = 0.49, rho = 1000 kg/m^3."""


def first_piola(F, mu, lam):
    """First Piola-Kirchhoff stress of the neo-Hookean solid.

    ``P = mu (F - F^-T) + lam ln(J) F^-T`` with ``J = det F``.

    Parameters
    ----------
    F : (..., 3, 3) ndarray
        Deformation gradients [-], with det F > 0.
    mu : float
        Shear modulus [Pa].
    lam : float
        First Lame constant [Pa].

    Returns
    -------
    (..., 3, 3) ndarray
        First Piola-Kirchhoff stress P [Pa] (NaN where det F <= 0).
    """
    J = np.linalg.det(F)
    FinvT = np.linalg.inv(F).swapaxes(-1, -2)
    return mu * (F - FinvT) + (lam * np.log(J))[..., None, None] * FinvT


def strain_energy_density(F, mu, lam):
    """Neo-Hookean strain energy per unit reference volume.

    ``W(F) = mu/2 (tr(F^T F) - 3) - mu ln J + lam/2 (ln J)^2`` with ``J = det F``.

    Parameters
    ----------
    F : (..., 3, 3) ndarray
        Deformation gradients [-], with det F > 0.
    mu : float
        Shear modulus [Pa].
    lam : float
        First Lame constant [Pa].

    Returns
    -------
    (...,) ndarray
        Strain energy density W(F) [J/m^3] (NaN where det F <= 0).
    """
    J = np.linalg.det(F)
    lnJ = np.log(J)
    I1 = np.einsum("...ij,...ij->...", F, F)
    return 0.5 * mu * (I1 - 3.0) - mu * lnJ + 0.5 * lam * lnJ**2


def cauchy_stress(F, mu, lam):
    """Neo-Hookean Cauchy stress; the numpy reference of :func:`neo_hookean_cauchy`.

    ``sigma = P F^T / J = (mu (F F^T - I) + lam ln(J) I) / J`` with ``J = det F``.

    Parameters
    ----------
    F : (..., 3, 3) ndarray
        Deformation gradients [-], with det F > 0.
    mu : float
        Shear modulus [Pa].
    lam : float
        First Lame constant [Pa].

    Returns
    -------
    (..., 3, 3) ndarray
        Cauchy (true) stress sigma [Pa] (NaN where det F <= 0).
    """
    J = np.linalg.det(F)
    sigma = mu * (F @ F.swapaxes(-1, -2) - np.eye(3))
    sigma += (lam * np.log(J))[..., None, None] * np.eye(3)
    return sigma / J[..., None, None]


def von_mises(sigma):
    """Equivalent (von Mises) stress, paper Eq. (9).

    ``sqrt(((s1-s2)^2 + (s2-s3)^2 + (s3-s1)^2) / 2)`` of the principal stresses, written
    in components, ``sqrt(((s00-s11)^2 + (s11-s22)^2 + (s22-s00)^2) / 2
    + 3 (s01^2 + s12^2 + s20^2))``, so no eigen-decomposition is needed.

    Parameters
    ----------
    sigma : (..., 3, 3) ndarray
        Symmetric Cauchy stresses [Pa].

    Returns
    -------
    (...,) ndarray
        Von Mises stress [Pa].
    """
    s = sigma
    return np.sqrt(0.5 * ((s[..., 0, 0] - s[..., 1, 1]) ** 2 + (s[..., 1, 1] - s[..., 2, 2]) ** 2
                          + (s[..., 2, 2] - s[..., 0, 0]) ** 2)
                   + 3.0 * (s[..., 0, 1] ** 2 + s[..., 1, 2] ** 2 + s[..., 2, 0] ** 2))


@nb.njit(cache=True, fastmath=FASTMATH)
def neo_hookean_cauchy(F, mu, lam):
    """Neo-Hookean Cauchy stress of one deformation gradient.

    Parameters
    ----------
    F : ndarray, shape (3, 3)
        Deformation gradient [-].
    mu, lam : float
        Lame constants [Pa].

    Returns
    -------
    J : float
        det F [-]; when J <= 0 (inverted) the stresses are NaN.
    s00, s11, s22, s01, s12, s20 : float
        Components of sigma = (mu (F F^T - I) + lam ln(J) I) / J [Pa].
    """
    J = (F[0, 0] * (F[1, 1] * F[2, 2] - F[1, 2] * F[2, 1])
         - F[0, 1] * (F[1, 0] * F[2, 2] - F[1, 2] * F[2, 0])
         + F[0, 2] * (F[1, 0] * F[2, 1] - F[1, 1] * F[2, 0]))
    if not J > 0.0:
        return J, np.nan, np.nan, np.nan, np.nan, np.nan, np.nan
    p = lam * np.log(J) - mu
    s00 = (mu * (F[0, 0] ** 2 + F[0, 1] ** 2 + F[0, 2] ** 2) + p) / J
    s11 = (mu * (F[1, 0] ** 2 + F[1, 1] ** 2 + F[1, 2] ** 2) + p) / J
    s22 = (mu * (F[2, 0] ** 2 + F[2, 1] ** 2 + F[2, 2] ** 2) + p) / J
    s01 = mu * (F[0, 0] * F[1, 0] + F[0, 1] * F[1, 1] + F[0, 2] * F[1, 2]) / J
    s12 = mu * (F[1, 0] * F[2, 0] + F[1, 1] * F[2, 1] + F[1, 2] * F[2, 2]) / J
    s20 = mu * (F[2, 0] * F[0, 0] + F[2, 1] * F[0, 1] + F[2, 2] * F[0, 2]) / J
    return J, s00, s11, s22, s01, s12, s20


@nb.njit(cache=True, fastmath=FASTMATH)
def von_mises_components(s00, s11, s22, s01, s12, s20):
    """Equivalent (von Mises) stress of one symmetric stress, paper Eq. (9).

    Parameters
    ----------
    s00, s11, s22, s01, s12, s20 : float
        Stress components [Pa].

    Returns
    -------
    float
        sqrt(((s00-s11)^2 + (s11-s22)^2 + (s22-s00)^2) / 2 + 3 (s01^2 + s12^2 + s20^2)) [Pa].
    """
    return np.sqrt(0.5 * ((s00 - s11) ** 2 + (s11 - s22) ** 2 + (s22 - s00) ** 2)
                   + 3.0 * (s01 * s01 + s12 * s12 + s20 * s20))


@nb.njit(cache=True, fastmath=FASTMATH)
def cauchy_von_mises(F, mu, lam):
    """Von Mises stress of the neo-Hookean Cauchy stress of each deformation gradient.

    Parameters
    ----------
    F : ndarray, shape (e, 3, 3)
        Deformation gradients [-].
    mu, lam : float
        Lame constants [Pa].

    Returns
    -------
    ndarray, shape (e,)
        Von Mises stress [Pa] (:func:`neo_hookean_cauchy`, :func:`von_mises_components`);
        NaN for an inverted F (J <= 0), as :func:`von_mises` of :func:`cauchy_stress` gives.
    """
    out = np.empty(F.shape[0])
    for e in range(F.shape[0]):
        J, s00, s11, s22, s01, s12, s20 = neo_hookean_cauchy(F[e], mu, lam)
        out[e] = von_mises_components(s00, s11, s22, s01, s12, s20)
    return out


def max_von_mises_of(F, mu, lam):
    """Largest von Mises stress of the neo-Hookean Cauchy stresses of ``F``.

    Parameters
    ----------
    F : ndarray, shape (e, 3, 3)
        Deformation gradients [-].
    mu, lam : float
        Lame constants [Pa].

    Returns
    -------
    float
        max over the elements of :func:`cauchy_von_mises` [Pa] (NaN if any is inverted).
    """
    return float(cauchy_von_mises(F, mu, lam).max())
