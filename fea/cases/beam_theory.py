"""Euler-Bernoulli cantilever formulas, the analytic checks of the FE finger models.

Elliptical section with semi-axes a (along x) and b (along y, the bending direction)::

    A = pi a b            I = pi a b^3 / 4                        [m^2], [m^4]
    k_tip = 3 E I / L^3                                           [N/m]
    omega_i = (beta_i L)^2 sqrt(E I / (rho A L^4))                [rad/s]

with beta_i L = 1.8751, 4.6941, 7.8548 (clamped-free).

A tapered cantilever whose section stays similar to its root's, every length scaled by
s(z) = 1 - (1 - lambda) z / L (lambda the taper ratio, tip over root), has
A(z) = A_0 s^2 and I(z) = I_0 s^4; its tip stiffness is then exactly lambda times the
prism's, k_tip = 3 E I_0 lambda / L^3 (:func:`tapered_tip_stiffness_eb`), and its
frequencies are solved numerically (:func:`tapered_cantilever_frequencies`).
"""
import numpy as np
import scipy.linalg

from ccedi.errors import InputError, require_finite_positive
from ccedi.fea.mesh import SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR

CANTILEVER_BETA_L = (1.8751040687, 4.6940911330, 7.8547574382)
"""Roots beta_i L of cos(bL) cosh(bL) = -1 (clamped-free Euler-Bernoulli beam)."""


def ellipse_section_properties(a=SEMI_AXIS_MAJOR, b=SEMI_AXIS_MINOR):
    """Area and second moment of area of an elliptical section.

    The section is the ellipse x^2/a^2 + y^2/b^2 <= 1; bending is in the y direction
    (about the x axis)::

        A = pi a b        I_x = pi a b^3 / 4

    Parameters
    ----------
    a : float, optional
        Semi-axis along x [m], > 0. Default: the paper's 12 mm.
    b : float, optional
        Semi-axis along y, the bending direction [m], > 0. Default: the paper's 8.45 mm.

    Returns
    -------
    area : float
        Section area A [m^2].
    second_moment : float
        Second moment of area about the x axis, I_x [m^4].

    Raises
    ------
    InputError
        If ``a`` or ``b`` is not a finite number > 0.
    """
    a = require_finite_positive("a (semi-axis, m)", a)
    b = require_finite_positive("b (semi-axis, m)", b)
    return np.pi * a * b, np.pi * a * b**3 / 4.0


def tip_stiffness_eb(E, length_m, second_moment):
    """Euler-Bernoulli cantilever tip stiffness ``k = 3 E I / L^3``.

    Parameters
    ----------
    E : float
        Young's modulus [Pa].
    length_m : float
        Cantilever length L [m].
    second_moment : float
        Second moment of area I of the section about the bending axis [m^4].

    Returns
    -------
    float or numpy.ndarray
        Tip stiffness k [N/m] (broadcast over array arguments).
    """
    return 3.0 * E * second_moment / length_m**3


def tapered_tip_stiffness_eb(E, length_m, second_moment, *, taper_ratio):
    """Euler-Bernoulli tip stiffness of the similar-section tapered cantilever,
    ``k = 3 E I_0 lambda / L^3`` (module docstring): the tip deflection
    P / (E I_0) int_0^L (L - z)^2 / s(z)^4 dz = P L^3 / (3 E I_0 lambda).

    Parameters
    ----------
    E : float
        Young's modulus [Pa].
    length_m : float
        Cantilever length L [m].
    second_moment : float
        Second moment of area I_0 of the root section [m^4].
    taper_ratio : float
        lambda, the tip's lengths over the root's [-], > 0.

    Returns
    -------
    float
        Tip stiffness k [N/m].
    """
    return tip_stiffness_eb(E, length_m, second_moment) * taper_ratio


def tapered_cantilever_frequencies(E, rho, length_m, *, area, second_moment, taper_ratio, n_modes=1,
                                   n_elements=50):
    """The first ``n_modes`` clamped-free Euler-Bernoulli bending frequencies of the
    similar-section tapered cantilever (module docstring), from ``n_elements`` cubic
    Hermite beam elements whose section varies within each element, integrated exactly
    (5-point Gauss). At the default 50 elements the first frequency is converged to
    1e-7 (the prism's against :func:`cantilever_frequencies`; lambda = 0.4 against 25 and
    100 elements); many more elements lose digits to the stiffness matrix's conditioning.

    Parameters
    ----------
    E : float
        Young's modulus [Pa].
    rho : float
        Density [kg/m^3].
    length_m : float
        Cantilever length L [m].
    area : float
        Root section area A_0 [m^2].
    second_moment : float
        Root second moment of area I_0 about the bending axis [m^4].
    taper_ratio : float
        lambda, the tip's lengths over the root's [-], > 0.
    n_modes : int, optional
        Number of frequencies. Default 1.
    n_elements : int, optional
        Beam elements. Default 50.

    Returns
    -------
    numpy.ndarray
        Angular frequencies omega_i, shape (n_modes,), ascending [rad/s].

    Raises
    ------
    InputError
        ``taper_ratio`` not a finite number > 0.
    """
    lam = require_finite_positive("taper_ratio (tip over root)", taper_ratio)
    h = 1.0 / n_elements                                 # in units of L, E I_0 and rho A_0: well conditioned
    xi, w = np.polynomial.legendre.leggauss(5)
    t = 0.5 * (xi + 1.0)                                 # Gauss points on the element, 0..1
    N = np.stack([1 - 3 * t**2 + 2 * t**3, h * (t - 2 * t**2 + t**3), 3 * t**2 - 2 * t**3, h * (t**3 - t**2)])
    B = np.stack([-6 + 12 * t, h * (-4 + 6 * t), 6 - 12 * t, h * (6 * t - 2)]) / h**2
    n = 2 * (n_elements + 1)
    K, M = np.zeros((n, n)), np.zeros((n, n))
    for e in range(n_elements):
        s = 1.0 - (1.0 - lam) * (e + t) * h
        dofs = slice(2 * e, 2 * e + 4)
        K[dofs, dofs] += (B * (0.5 * h * w * s**4)) @ B.T
        M[dofs, dofs] += (N * (0.5 * h * w * s**2)) @ N.T
    free = slice(2, n)                                   # the root's deflection and slope clamped
    omega2 = scipy.linalg.eigh(K[free, free], M[free, free], eigvals_only=True, subset_by_index=(0, n_modes - 1))
    return np.sqrt(omega2 * E * second_moment / (rho * area * length_m**4))


def cantilever_frequencies(E, rho, length_m, *, area, second_moment, n_modes=1):
    """The first ``n_modes`` clamped-free Euler-Bernoulli bending frequencies.

    ::

        omega_i = (beta_i L)^2 sqrt(E I / (rho A L^4)),   beta_i L = 1.8751, 4.6941, 7.8548

    Parameters
    ----------
    E : float
        Young's modulus [Pa].
    rho : float
        Density [kg/m^3].
    length_m : float
        Cantilever length L [m].
    area : float
        Section area A [m^2].
    second_moment : float
        Second moment of area I about the bending axis [m^4].
    n_modes : int, optional
        Number of frequencies, 1 to 3. Default 1.

    Returns
    -------
    numpy.ndarray
        Angular frequencies omega_i, shape (n_modes,), ascending [rad/s].

    Raises
    ------
    InputError
        If ``n_modes`` is not in 1..3.
    """
    if not 1 <= n_modes <= len(CANTILEVER_BETA_L):
        raise InputError(f"n_modes must be in 1..{len(CANTILEVER_BETA_L)}, got {n_modes}")
    root = np.sqrt(E * second_moment / (rho * area * length_m**4))
    return np.array(CANTILEVER_BETA_L[:n_modes])**2 * root


def drum_drag_tip_deflection(alpha, rho, area, *, omega, drum_radius_m, length_m, E, second_moment):
    """Steady tip deflection of a cantilever standing radially on a turning drum.

    Under global mass damping alpha the drag per unit length is
    q(r) = alpha rho A omega r, growing linearly with the radius r = R + s
    (s the distance from the root), and Euler-Bernoulli gives::

        delta = alpha rho A omega (R L^4 / 8 + 11 L^5 / 120) / (E I)

    Parameters
    ----------
    alpha : float
        Mass-proportional (global) damping coefficient [1/s].
    rho : float
        Density [kg/m^3].
    area : float
        Section area A [m^2].
    omega : float
        Drum angular velocity [rad/s].
    drum_radius_m : float
        Drum radius R at the finger root [m].
    length_m : float
        Finger length L [m].
    E : float
        Young's modulus [Pa].
    second_moment : float
        Second moment of area I about the bending axis [m^4].

    Returns
    -------
    float
        Tip deflection delta, tangential, against the direction of rotation [m].
    """
    q = alpha * rho * area * omega
    return q * (drum_radius_m * length_m**4 / 8 + 11 * length_m**5 / 120) / (E * second_moment)
