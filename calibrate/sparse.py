"""Beyond the catalogue: the best sparse data-driven force term on a residual.

When no catalogued effect explains what is left, the residual r(t) = y(t) - u(t) [m] is
read as the response of the fitted finger to a missing tip force f(t) = sum_k xi_k
theta_k(u, v), a combination of candidate terms in the tip displacement u = sum b_i q_i
[m] and velocity v = u' [m/s] of the fitted model (the modal coordinates as the tip,
where the force acts, sees them; :data:`LIBRARY`). To first order in f::

    r(t) = sum_k xi_k R_k(t),   R_k = h * theta_k   (convolution)
    h(t) = sum_i b_i^2 exp(-zeta_i w_i t) sin(w_di t) / w_di     (tip impulse response [m/(N s)])

with the fitted modes (omega_i, zeta_i, b_i). The coefficients are found by sequentially
thresholded least squares (STLSQ, Brunton et al. 2016) on the columns scaled to unit
norm: solve, drop the terms whose scaled coefficient is below ``THRESHOLD`` times the
largest, solve again on the rest, until nothing is dropped; at most ``MAX_TERMS`` terms
(the strongest) are kept. The library's terms are nearly collinear (u^2, |u| u, u^3), and
thresholding can keep the wrong one of a correlated pair: when the best single term alone
leaves a smaller residual than the STLSQ combination, that term is the result (on the
bundled magnet record STLSQ kept |u| u, removing 1.3 % of the residual, where u^2 alone
removes 9.4 %). The result names the terms, their coefficients in SI units
(N per unit of the term) and the error reduction 1 - RMS(r - R xi) / RMS(r).
"""
from dataclasses import dataclass

import numpy as np
from scipy.signal import fftconvolve

LIBRARY = {
    "u^2": (lambda u, v: u**2, "N/m^2"),
    "|u| u": (lambda u, v: np.abs(u) * u, "N/m^2"),
    "u^3": (lambda u, v: u**3, "N/m^3"),
    "sign(v)": (lambda u, v: np.tanh(v / 1e-3), "N"),
    "|u| sign(v)": (lambda u, v: np.abs(u) * np.tanh(v / 1e-3), "N/m"),
    "|v| v": (lambda u, v: np.abs(v) * v, "N s^2/m^2"),
    "u |v|": (lambda u, v: u * np.abs(v), "N s/m^2"),
    "v^3": (lambda u, v: v**3, "N s^3/m^3"),
}
"""Candidate missing tip forces: name -> (theta(u [m], v [m/s]), unit of the coefficient)."""
THRESHOLD = 0.3
MAX_TERMS = 2


@dataclass(frozen=True)
class SparseTerm:
    """The sparse force term found on a residual (module docstring).

    Parameters
    ----------
    terms : dict
        {term name: coefficient} in SI units (``units``), the tip force being
        sum coefficient x term.
    units : dict
        {term name: unit of its coefficient}.
    error_reduction : float
        1 - RMS(r - fit) / RMS(r) [-].
    rms_before_m, rms_after_m : float
        RMS of the residual before and after the term [m].
    single_term_reductions : dict
        Error reduction of every library term alone [-] (the ranking evidence).
    """

    terms: dict
    units: dict
    error_reduction: float
    rms_before_m: float
    rms_after_m: float
    single_term_reductions: dict

    def summary(self):
        """The JSON-ready term.

        Returns
        -------
        dict
            ``terms``, ``units``, ``error_reduction``, ``rms_before_m``, ``rms_after_m``,
            ``single_term_reductions`` and ``force`` (the term as one formula).
        """
        force = " + ".join(f"{c:.4g} {name}" for name, c in self.terms.items()) or "none"
        return {"force": f"f_tip = {force}", "terms": self.terms, "units": self.units,
                "error_reduction": self.error_reduction, "rms_before_m": self.rms_before_m,
                "rms_after_m": self.rms_after_m, "single_term_reductions": self.single_term_reductions}


def impulse_response(modes, zeta, time_s):
    """Tip displacement per unit tip impulse of the damped modes, h(t) [m/(N s)].

    Parameters
    ----------
    modes : ccedi.calibrate.finger_modes.Modes
        omega_i [rad/s] and tip values b_i [1/sqrt(kg)].
    zeta : numpy.ndarray
        Damping ratios [-] (below 1 for the modes that ring; an over-damped mode uses
        the real-exponential form).
    time_s : numpy.ndarray
        Times from the impulse, >= 0 [s].

    Returns
    -------
    numpy.ndarray
        h at ``time_s``.
    """
    t = np.asarray(time_s)[None, :]
    w, z = modes.omega_rad_s[:, None], np.asarray(zeta)[:, None]
    mu = w * np.sqrt(np.abs(1.0 - z**2))
    shape = np.exp(-z * w * t) * t * np.sinc(mu * t / np.pi)
    over = z[:, 0] >= 1.0
    if over.any():
        zw, m = (z * w)[over], np.maximum(mu[over], 1e-300)
        shape[over] = (np.exp((m - zw) * t) - np.exp(-(m + zw) * t)) / (2.0 * m)
    return (modes.tip[:, None] ** 2 * shape).sum(axis=0)


def _stlsq(A, r):
    """Sparse coefficients of r ~ A x on unit-norm columns (module docstring)."""
    scale = np.linalg.norm(A, axis=0)
    scale[scale == 0.0] = 1.0
    An = A / scale
    active = np.ones(A.shape[1], dtype=bool)
    x = np.zeros(A.shape[1])
    for _ in range(A.shape[1]):
        x[:] = 0.0
        x[active] = np.linalg.lstsq(An[:, active], r, rcond=None)[0]
        big = np.abs(x) >= THRESHOLD * np.max(np.abs(x))
        if active.sum() > MAX_TERMS:
            big &= np.abs(x) >= np.sort(np.abs(x))[-MAX_TERMS]
        if np.array_equal(big, active):
            break
        active = big
    return x / scale


def sparse_term(time_s, residual_m, u_m, *, modes, zeta):
    """The best sparse tip-force term explaining a residual (module docstring).

    Parameters
    ----------
    time_s : numpy.ndarray
        Uniform sample times [s].
    residual_m : numpy.ndarray
        Residual r = record - model [m].
    u_m : numpy.ndarray
        Tip displacement of the fitted model [m] (its velocity by finite differences).
    modes : ccedi.calibrate.finger_modes.Modes
        The fitted model's modes.
    zeta : numpy.ndarray
        Their damping ratios [-].

    Returns
    -------
    SparseTerm
        Terms, coefficients and error reduction.
    """
    t = np.asarray(time_s)
    dt = float(np.median(np.diff(t)))
    v = np.gradient(u_m, t)
    h = impulse_response(modes, zeta, t - t[0])
    cols = np.column_stack([fftconvolve(theta(u_m, v), h)[:len(t)] * dt for theta, _ in LIBRARY.values()])
    names = list(LIBRARY)
    r = np.asarray(residual_m, dtype=float)
    rms = float(np.sqrt(np.mean(r**2)))
    single, alone = {}, np.zeros((len(names), len(names)))
    for k, name in enumerate(names):
        c = cols[:, k]
        alone[k, k] = float(c @ r / (c @ c)) if c @ c > 0 else 0.0
        single[name] = 1.0 - float(np.sqrt(np.mean((r - alone[k, k] * c) ** 2))) / rms
    x = _stlsq(cols, r)
    after = float(np.sqrt(np.mean((r - cols @ x) ** 2)))
    best = alone[max(range(len(names)), key=lambda k: single[names[k]])]
    best_after = float(np.sqrt(np.mean((r - cols @ best) ** 2)))
    if best_after < after:
        x, after = best, best_after
    kept = {names[k]: float(x[k]) for k in np.flatnonzero(x)}
    return SparseTerm(terms=kept, units={k: LIBRARY[k][1] for k in kept}, error_reduction=1.0 - after / rms,
                      rms_before_m=rms, rms_after_m=after, single_term_reductions=single)
