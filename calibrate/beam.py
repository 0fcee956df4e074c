"""Modes of the declared finger as an Euler-Bernoulli cantilever, by Rayleigh-Ritz on the
analytic clamped-free modes (the calibration's model; the data generator in
:mod:`ccedi.calibrate.synthetic` uses a finite-element beam instead).

Basis: the first ``n_basis`` clamped-free modes (x along the finger, 0 <= x <= L)::

    phi_j(x) = cosh(b_j x) - cos(b_j x) - s_j (sinh(b_j x) - sin(b_j x)),
    s_j = (cosh(b_j L) + cos(b_j L)) / (sinh(b_j L) + sin(b_j L)),   cos(b_j L) cosh(b_j L) = -1

plus, when the clamp has a finite rotational stiffness k_r [N m/rad], the rigid rotation
psi(x) = x / L about the root. Mass and stiffness matrices (rho A [kg/m], E I [N m^2])::

    M_jk = rho A int phi_j phi_k dx + m_tip phi_j(L) phi_k(L)
    K_jk = E I int phi_j'' phi_k'' dx + k_r phi_j'(0) phi_k'(0)

The generalised eigenproblem K v = omega^2 M v gives mass-normalised modes; the model keeps
the lowest ``n_modes``: their angular frequencies omega_i [rad/s], tip values b_i =
Phi_i(L) [1/sqrt(kg)] (tip force -> modal force and modal coordinate -> tip displacement),
and weight participations p_i = int rho A Phi_i dx + m_tip Phi_i(L) [sqrt(kg)] (a uniform
transverse acceleration g gives the modal force p_i g).
"""
from dataclasses import dataclass

import numpy as np
from scipy.linalg import eigh
from scipy.optimize import brentq

from ccedi.errors import InputError, require_finite_positive

N_QUADRATURE = 160
"""Gauss-Legendre points along the finger for the Ritz integrals."""
N_DRAG_POINTS = 8
"""Gauss-Legendre points along the finger at which distributed drag is evaluated."""


def cantilever_roots(n):
    """The first ``n`` roots b_j L of cos(x) cosh(x) = -1 (clamped-free beam).

    Parameters
    ----------
    n : int
        Number of roots, >= 0.

    Returns
    -------
    numpy.ndarray
        Roots 1.8751, 4.6941, 7.8548, ... (approaching (j + 1/2) pi), shape (n,) [-].
    """
    f = lambda x: np.cos(x) * np.cosh(x) + 1.0
    return np.array([brentq(f, (j + 0.5) * np.pi - 1.2, (j + 0.5) * np.pi + 1.2) if j else
                     brentq(f, 1.0, 2.5) for j in range(n)])


@dataclass(frozen=True)
class Modes:
    """Lowest mass-normalised modes of the Ritz cantilever (module docstring).

    Parameters
    ----------
    omega_rad_s : numpy.ndarray
        Angular frequencies omega_i, ascending, (n,) [rad/s].
    tip : numpy.ndarray
        Tip values b_i = Phi_i(L), (n,) [1/sqrt(kg)], signs chosen >= 0.
    weight : numpy.ndarray
        Weight participations p_i = int rho A Phi_i dx + m_tip Phi_i(L), (n,) [sqrt(kg)].
    shapes : numpy.ndarray
        Mode shapes at the drag points, (N_DRAG_POINTS, n) [1/sqrt(kg)].
    shape_weights : numpy.ndarray
        Gauss-Legendre weights of the drag points, (N_DRAG_POINTS,) [m].
    """

    omega_rad_s: np.ndarray
    tip: np.ndarray
    weight: np.ndarray
    shapes: np.ndarray
    shape_weights: np.ndarray

    @property
    def static_sag_per_g(self):
        """Static tip deflection per unit transverse acceleration [m / (m/s^2)]:
        sum b_i p_i / omega_i^2.
        """
        return float(np.sum(self.tip * self.weight / self.omega_rad_s**2))


class CantileverRitz:
    """Rayleigh-Ritz model of a uniform cantilever on the analytic clamped-free modes.

    Mass and bending matrices are built once (Gauss-Legendre quadrature, module
    docstring); Young's modulus, tip mass and clamp stiffness enter per call of
    :meth:`modes`.

    Parameters
    ----------
    length_m : float
        Finger length L [m], > 0.
    rho_a : float
        Mass per length rho A [kg/m], > 0.
    second_moment : float
        Second moment of area I [m^4], > 0.
    n_basis : int, optional
        Number of clamped-free basis modes (plus the root rotation). Default 10.

    Raises
    ------
    InputError
        If ``length_m``, ``rho_a`` or ``second_moment`` is not a finite number > 0.
    """

    def __init__(self, length_m, rho_a, second_moment, n_basis=10):
        self.length_m = require_finite_positive("finger length (m)", length_m)
        self.rho_a = require_finite_positive("mass per length (kg/m)", rho_a)
        self.second_moment = require_finite_positive("second moment (m^4)", second_moment)
        L = self.length_m
        beta = cantilever_roots(n_basis) / L
        x, w = _gauss(L, N_QUADRATURE)
        s = (np.cosh(beta * L) + np.cos(beta * L)) / (np.sinh(beta * L) + np.sin(beta * L))

        def basis_at(x):                                        # last column: root rotation
            bx = np.outer(x, beta)
            return np.column_stack([np.cosh(bx) - np.cos(bx) - s * (np.sinh(bx) - np.sin(bx)), x / L])

        basis = basis_at(x)
        bx = np.outer(x, beta)
        d2 = beta**2 * (np.cosh(bx) + np.cos(bx) - s * (np.sinh(bx) + np.sin(bx)))
        xd, self._drag_weights = _gauss(L, N_DRAG_POINTS)
        self._drag_basis = basis_at(xd)
        self._mass = rho_a * (basis * w[:, None]).T @ basis
        self._bending = np.zeros_like(self._mass)
        self._bending[:n_basis, :n_basis] = (d2 * w[:, None]).T @ d2   # times E I
        self._tip = basis_at(np.array([L]))[0]
        self._integral = rho_a * (w @ basis)
        self.n_basis = n_basis

    @property
    def mass_kg(self):
        """Finger mass rho A L [kg]."""
        return self.rho_a * self.length_m

    def modes(self, E, n_modes=6, tip_mass_kg=0.0, root_stiffness=None):
        """Lowest ``n_modes`` modes for a given modulus, tip mass and clamp stiffness.

        Parameters
        ----------
        E : float
            Young's modulus [Pa].
        n_modes : int, optional
            Number of modes, at most ``n_basis - 2``. Default 6.
        tip_mass_kg : float, optional
            Point mass at the tip [kg]. Default 0.
        root_stiffness : float or None, optional
            Rotational stiffness k_r of the clamp [N m/rad]; None for a rigid clamp (the
            root-rotation basis function is then dropped). Default None.

        Returns
        -------
        Modes
            Frequencies, tip values, weight participations and drag-point shapes.

        Raises
        ------
        InputError
            If ``n_modes > n_basis - 2``.
        """
        if n_modes > self.n_basis - 2:
            raise InputError(f"n_modes must be <= {self.n_basis - 2} for {self.n_basis} basis functions")
        keep = slice(None) if root_stiffness is not None else slice(0, self.n_basis)
        M = self._mass[keep, keep] + tip_mass_kg * np.outer(self._tip[keep], self._tip[keep])
        K = E * self.second_moment * self._bending[keep, keep]
        if root_stiffness is not None:
            K[-1, -1] += root_stiffness / self.length_m**2             # psi'(0) = 1 / L
        lam, vec = eigh(K, M, subset_by_index=[0, n_modes - 1])
        tip = self._tip[keep] @ vec
        sign = np.where(tip < 0.0, -1.0, 1.0)
        vec = vec * sign
        return Modes(omega_rad_s=np.sqrt(lam), tip=tip * sign,
                     weight=self._integral[keep] @ vec + tip_mass_kg * tip * sign,
                     shapes=self._drag_basis[:, keep] @ vec, shape_weights=self._drag_weights)


def _gauss(length, n):
    """Gauss-Legendre points and weights on [0, length] [m]."""
    xg, wg = np.polynomial.legendre.leggauss(n)
    return 0.5 * length * (xg + 1.0), 0.5 * length * wg
