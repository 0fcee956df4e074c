"""Compressible neo-Hookean material (reduces to isotropic linear elasticity at small strain).

Strain energy per unit reference volume (Bonet & Wood, Eq. 6.27)::

    W(F) = mu/2 (tr(F^T F) - 3) - mu ln J + lam/2 (ln J)^2,      J = det F

First Piola-Kirchhoff stress::

    P = mu (F - F^-T) + lam ln(J) F^-T                           [Pa]

Cauchy stress ``sigma = P F^T / J``. Lame constants from Young's modulus E and
Poisson's ratio nu: ``mu = E / (2 (1 + nu))``, ``lam = E nu / ((1 + nu)(1 - 2 nu))``.
"""
from dataclasses import dataclass

import numpy as np

from ccedi.errors import InputError, require_finite_positive


@dataclass(frozen=True)
class NeoHookean:
    """Isotropic compressible neo-Hookean solid.

    Parameters
    ----------
    E : Young's modulus [Pa], > 0.
    nu : Poisson's ratio [-], in (-1, 0.5).
    rho : mass density [kg/m^3], > 0.
    """

    E: float
    nu: float
    rho: float

    def __post_init__(self):
        object.__setattr__(self, "E", require_finite_positive("E (Young's modulus, Pa)", self.E))
        object.__setattr__(self, "rho", require_finite_positive("rho (density, kg/m^3)", self.rho))
        try:
            nu = float(self.nu)
        except (TypeError, ValueError):
            raise InputError(f"nu (Poisson's ratio) must be a real number, got {self.nu!r}") from None
        if not (-1.0 < nu < 0.5):
            raise InputError(f"nu (Poisson's ratio) must lie in (-1, 0.5), got {self.nu!r}")
        object.__setattr__(self, "nu", nu)

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
    """First Piola-Kirchhoff stress P [Pa] for deformation gradients ``F`` of shape (..., 3, 3)."""
    J = np.linalg.det(F)
    FinvT = np.linalg.inv(F).swapaxes(-1, -2)
    return mu * (F - FinvT) + (lam * np.log(J))[..., None, None] * FinvT


def strain_energy_density(F, mu, lam):
    """Neo-Hookean strain energy per unit reference volume W(F) [J/m^3]."""
    J = np.linalg.det(F)
    lnJ = np.log(J)
    I1 = np.einsum("...ij,...ij->...", F, F)
    return 0.5 * mu * (I1 - 3.0) - mu * lnJ + 0.5 * lam * lnJ**2


def cauchy_stress(F, mu, lam):
    """Cauchy stress sigma = P F^T / J = (mu (F F^T - I) + lam ln(J) I) / J [Pa]."""
    J = np.linalg.det(F)
    sigma = mu * (F @ F.swapaxes(-1, -2) - np.eye(3))
    sigma += (lam * np.log(J))[..., None, None] * np.eye(3)
    return sigma / J[..., None, None]


def von_mises(sigma):
    """Equivalent (von Mises) stress of Cauchy stresses (..., 3, 3), paper Eq. (9) [Pa].

    sqrt(((s1-s2)^2 + (s2-s3)^2 + (s3-s1)^2) / 2), written in components so no
    eigen-decomposition is needed.
    """
    s = sigma
    return np.sqrt(0.5 * ((s[..., 0, 0] - s[..., 1, 1]) ** 2 + (s[..., 1, 1] - s[..., 2, 2]) ** 2
                          + (s[..., 2, 2] - s[..., 0, 0]) ** 2)
                   + 3.0 * (s[..., 0, 1] ** 2 + s[..., 1, 2] ** 2 + s[..., 2, 0] ** 2))
