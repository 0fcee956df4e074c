"""Euler-Bernoulli cantilever formulas, the analytic checks of the FE finger models.

Elliptical section with semi-axes a (along x) and b (along y, the bending direction)::

    A = pi a b            I = pi a b^3 / 4                        [m^2], [m^4]
    k_tip = 3 E I / L^3                                           [N/m]
    omega_i = (beta_i L)^2 sqrt(E I / (rho A L^4))                [rad/s]

with beta_i L = 1.8751, 4.6941, 7.8548 (clamped-free).
"""
import numpy as np

from ccedi.errors import InputError, require_finite_positive
from .mesh import SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR

CANTILEVER_BETA_L = (1.8751040687, 4.6940911330, 7.8547574382)
"""Roots beta_i L of cos(bL) cosh(bL) = -1 (clamped-free Euler-Bernoulli beam)."""


def ellipse_section_properties(a=SEMI_AXIS_MAJOR, b=SEMI_AXIS_MINOR):
    """(area [m^2], second moment about the x axis [m^4]) of the ellipse x^2/a^2 + y^2/b^2 <= 1."""
    a = require_finite_positive("a (semi-axis, m)", a)
    b = require_finite_positive("b (semi-axis, m)", b)
    return np.pi * a * b, np.pi * a * b**3 / 4.0


def tip_stiffness_eb(E, length_m, second_moment):
    """Euler-Bernoulli cantilever tip stiffness 3 E I / L^3 [N/m]."""
    return 3.0 * E * second_moment / length_m**3


def cantilever_frequencies(E, rho, length_m, area, second_moment, n_modes=1):
    """The first ``n_modes`` (<= 3) clamped-free bending frequencies [rad/s]."""
    if not 1 <= n_modes <= len(CANTILEVER_BETA_L):
        raise InputError(f"n_modes must be in 1..{len(CANTILEVER_BETA_L)}, got {n_modes}")
    root = np.sqrt(E * second_moment / (rho * area * length_m**4))
    return np.array(CANTILEVER_BETA_L[:n_modes])**2 * root


def drum_drag_tip_deflection(alpha, rho, area, omega, drum_radius_m, length_m, E, second_moment):
    """Steady tip deflection [m] of a cantilever standing radially on a drum turning at
    omega [rad/s] under global mass damping alpha [1/s]: the drag per length
    q(r) = alpha rho A omega r grows linearly with the radius r = R + s, and
    Euler-Bernoulli gives delta = alpha rho A omega (R L^4 / 8 + 11 L^5 / 120) / (E I)."""
    q = alpha * rho * area * omega
    return q * (drum_radius_m * length_m**4 / 8 + 11 * length_m**5 / 120) / (E * second_moment)
