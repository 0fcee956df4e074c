"""The likelihood the calibration scores models by: Gaussian autoregressive noise, estimated
from the residual's rough part, and the Laplace approximation of a model's evidence.

The residual of a contact record is not white: the friction chatter of the finger on the
object, read through the transducer, is correlated over a few samples (lag-1
autocorrelation about 0.5 at 1 kHz), so a white-noise likelihood counts ~1 500 samples
where there are a few hundred independent ones, and any effect that follows the chatter a
little gains tens of BIC. The noise is modelled as autoregressive of order p::

    r_t = sum_{k=1..p} phi_k r_{t-k} + e_t,    e_t white, variance s^2

The coefficients are estimated on the residual's *rough* part: the residual less its
local quadratic trend over ``TREND_WINDOW_S`` (a Savitzky-Golay smoother), so that a
missing effect's signature, smooth on that scale, is not taken for noise and whitened
away (on the residual itself an AR model predicts a smooth signature almost exactly);
the trend removal's own effect on the noise's autocovariance is undone
(:func:`estimate_noise`). White sensor noise gives order 0. The price: noise correlated
beyond the trend window keeps part of its power where the rough part cannot see it, and
is whitened only in part (AR(1) noise of phi = 0.8: standard errors 0.5-0.6 of the true
scatter, the white-noise fit's 0.33; at phi = 0.5 within 10 %; tests/unit/calibrate/
test_likelihood.py). A base model's own error, smooth and correlated far longer, is not
noise: it is carried as a discrepancy of known covariance (:mod:`ccedi.calibrate.discrepancy`),
and the innovations are then L^-1 r, L L^T the covariance of the noise plus the discrepancy
on the training samples.
The whitened residual (the innovations e_t, on the training samples whose p predecessors
are training samples too) is what the fits minimise (generalised least squares) and what
the likelihood is of, with s^2 profiled out::

    ln L = -(m / 2) (ln(2 pi RSS_e / m) + 1),   m innovations, RSS_e their sum of squares

The evidence of a model with k parameters z (the optimiser's variables, uniform priors
over their bounds of widths w_i) by Laplace's method around the fit z*::

    ln Z = ln L(z*) - sum_i ln w_i + (k / 2) ln(2 pi) - (1 / 2) ln det(J_e^T J_e / s^2)

with J_e the Jacobian of the innovations in z: the fit's likelihood times the Occam
factor, the posterior's volume over the prior's. Models compared on one record share the
noise model, so the terms of the noise's own parameters cancel.
"""
from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import cholesky, solve_triangular, toeplitz
from scipy.signal import lfilter, savgol_coeffs, savgol_filter

TREND_WINDOW_S = 0.021
"""Width of the local quadratic trend removed before the noise is estimated [s]: the
noise model sees what varies faster than ~50 Hz."""
MAX_AR_ORDER = 8
"""Highest autoregressive order tried."""
AUTOCOVARIANCE_LAGS = 2 * MAX_AR_ORDER
"""Lags of the rough part's autocovariance the noise's is deconvolved from."""
CHI2_Z = 3.0
"""The lowest order whose autocovariance fits the rough part's within this many standard
deviations of the chi-square (sample autocorrelations' standard error 1 / sqrt(m)) is kept."""
AR_MEMORY = 200
"""Lags of the AR noise's autocovariance kept in its covariance matrix (the impulse response
of a stationary AR model of these orders has decayed long before)."""
NOISE_SAME = 0.02
"""Largest change of an AR coefficient (absolute) or of the innovation std (relative) for
which two noise models are the same."""


@dataclass(frozen=True, eq=False)
class NoiseModel:
    """Autoregressive noise: e_t = r_t - sum_k ar[k-1] r_{t-k} is white (module docstring),
    plus, optionally, a model discrepancy of known covariance.

    Parameters
    ----------
    ar : numpy.ndarray
        Coefficients phi_1 .. phi_p [-]; empty for white noise.
    innovation_std : float
        Standard deviation of e_t on the rough part it was estimated from, in the
        residual's unit.
    discrepancy : numpy.ndarray or None, optional
        Covariance of the base model's own error at every sample, shape (n, n), in the
        residual's unit squared (:mod:`ccedi.calibrate.discrepancy`). With it, the
        innovations are L^-1 r, L L^T the training samples' covariance (the AR noise's
        and the discrepancy's). Default None.
    _factors : dict, optional
        Cache of the covariance's Cholesky factors by scored-sample mask (filled on use).
    """

    ar: np.ndarray
    innovation_std: float = float("nan")
    discrepancy: np.ndarray | None = None
    _factors: dict = field(default_factory=dict, repr=False)

    @property
    def order(self):
        """The autoregressive order p."""
        return len(self.ar)

    def innovations(self, residual, mask):
        """The whitened residual on the scored samples, standardised: unit variance when the
        noise model is right.

        Without a discrepancy, e_t / innovation_std on the samples of ``mask`` whose p
        predecessors are in it (e_t itself when the std is not known, :data:`WHITE`); with
        one, L^-1 r on the samples of ``mask``.

        Parameters
        ----------
        residual : numpy.ndarray
            Residual at every sample, shape (n,).
        mask : numpy.ndarray
            Boolean, shape (n,): the samples scored (the training samples).

        Returns
        -------
        numpy.ndarray
            The innovations, in sample order.
        """
        r = np.asarray(residual, dtype=float)
        if self.discrepancy is not None:
            return solve_triangular(self._cholesky(mask), r[mask], lower=True, check_finite=False)
        valid = _with_predecessors(mask, self.order)
        e = r[valid].copy()
        idx = np.flatnonzero(valid)
        for k, phi in enumerate(self.ar, start=1):
            e -= phi * r[idx - k]
        return e / self.innovation_std if np.isfinite(self.innovation_std) and self.innovation_std > 0.0 else e

    def covariance(self, n):
        """The AR noise's covariance over n consecutive samples (the residual's unit squared).

        Parameters
        ----------
        n : int
            Number of samples.

        Returns
        -------
        numpy.ndarray
            Toeplitz covariance, shape (n, n).
        """
        psi = lfilter([1.0], np.r_[1.0, -self.ar], np.r_[1.0, np.zeros(AR_MEMORY - 1)])
        gamma = self.innovation_std**2 * np.array([psi[:AR_MEMORY - k] @ psi[k:] for k in range(min(n, AR_MEMORY))])
        return toeplitz(np.r_[gamma, np.zeros(max(n - AR_MEMORY, 0))])

    def process_variance(self):
        """The AR noise's variance gamma(0) (the residual's unit squared): innovation_std^2
        times sum psi_k^2, psi its impulse response.

        Returns
        -------
        float
            gamma(0).
        """
        return float(self.covariance(1)[0, 0])

    def effective_samples(self, n):
        """How many independent samples n correlated ones are worth for a mean square:
        n / sum_k rho_k^2 over all lags, rho the autocorrelation of the AR noise plus the
        discrepancy's diagonal (taken as white), so that the mean square of n samples of
        the noise has the relative standard deviation sqrt(2 / n_eff).

        Parameters
        ----------
        n : int
            Number of samples.

        Returns
        -------
        float
            n_eff, at most n; n for white noise or a noise of unknown scale.
        """
        if not (np.isfinite(self.innovation_std) and self.order):
            return float(n)
        gamma = self.covariance(AR_MEMORY)[0]
        if self.discrepancy is not None:
            gamma[0] += float(np.mean(np.diag(self.discrepancy)))
        rho = gamma / gamma[0]
        return float(n / (1.0 + 2.0 * np.sum(rho[1:] ** 2)))

    def _cholesky(self, mask):
        key = np.asarray(mask, dtype=bool).tobytes()
        if key not in self._factors:
            mask = np.asarray(mask, dtype=bool)
            cov = (self.covariance(len(mask)) + self.discrepancy)[np.ix_(mask, mask)]
            self._factors[key] = cholesky(cov, lower=True)
        return self._factors[key]

    def with_discrepancy(self, covariance):
        """This noise plus a model discrepancy of the given covariance.

        Parameters
        ----------
        covariance : numpy.ndarray or None
            The discrepancy's covariance, shape (n, n); None: none.

        Returns
        -------
        NoiseModel
            The combined noise model.
        """
        return NoiseModel(self.ar, self.innovation_std, covariance)

    def same_as(self, other):
        """Whether two noise models are the same to within NOISE_SAME in every AR
        coefficient and innovation std (relative), with the same discrepancy.

        Parameters
        ----------
        other : NoiseModel
            The other.

        Returns
        -------
        bool
            True when the same.
        """
        if self.order != other.order or not np.allclose(self.ar, other.ar, atol=NOISE_SAME):
            return False
        if (self.discrepancy is None) != (other.discrepancy is None):
            return False
        if self.discrepancy is None:
            return True
        return (np.isclose(self.innovation_std, other.innovation_std, rtol=NOISE_SAME)
                and np.allclose(self.discrepancy, other.discrepancy, rtol=0.0,
                                atol=NOISE_SAME * float(np.max(np.abs(self.discrepancy)) or 1.0)))

    def summary(self):
        """The noise model, JSON-ready.

        Returns
        -------
        dict
            ``order``, ``ar``, ``innovation_std`` (the residual's unit) and
            ``discrepancy_rms`` (the discrepancy's RMS std over the record, or None).
        """
        return {"order": self.order, "ar": [float(a) for a in self.ar], "innovation_std": self.innovation_std,
                "discrepancy_rms": None if self.discrepancy is None
                else float(np.sqrt(np.mean(np.diag(self.discrepancy))))}


WHITE = NoiseModel(np.zeros(0))
"""White noise: the innovations are the residual."""


def _with_predecessors(mask, p):
    """Samples of ``mask`` whose p predecessors are in ``mask`` too."""
    mask = np.asarray(mask, dtype=bool)
    valid = mask.copy()
    for k in range(1, p + 1):
        valid[k:] &= mask[:-k]
        valid[:k] = False
    return valid


def rough_part(residual, dt):
    """The residual less its local quadratic trend over TREND_WINDOW_S (module docstring).

    Parameters
    ----------
    residual : numpy.ndarray
        Residual at uniformly spaced samples, shape (n,).
    dt : float
        Sample interval [s].

    Returns
    -------
    numpy.ndarray
        The rough part, shape (n,).
    """
    r = np.asarray(residual, dtype=float)
    return r - savgol_filter(r, _trend_window(dt, len(r)), 2)


def estimate_noise(residual, mask, dt, *, max_order=MAX_AR_ORDER):
    """The autoregressive noise model of a residual (module docstring).

    The rough part x = h * r (h = delta - g, g the trend's Savitzky-Golay kernel) of
    stationary noise of autocovariance gamma has the autocovariance gamma_x = rho_h * gamma,
    rho_h the autocorrelation of h. The noise's gamma(0 .. q), zero beyond, is fitted by
    least squares to the sample autocovariance of x over the training pairs at lags
    0 .. AUTOCOVARIANCE_LAGS, for q = 0, 1, ... up to the first whose fit is within the
    sampling error (chi-square at ``CHI2_Z``; m training samples, standard error of a
    sample autocorrelation 1 / sqrt(m)): white noise gives q = 0. The lowest such q, because
    the noise's power at low frequencies is not observable on x (the trend removal took
    it with the trend): parsimony takes it as white there. The AR(q) coefficients follow
    from gamma(0 .. q) by the Yule-Walker equations (Levinson-Durbin). Estimating on x
    as if it were the noise would take the trend removal's own dip at low frequencies for
    the noise's. A model with more power at high frequencies than at low ones (sum of the
    coefficients below 0) is not a sensor's noise but what is left of a large smooth
    residual near the trend's reach (sensor_offset_drift_high's baseline: order 5, every
    coefficient -0.25 to -0.30, which weighted the smooth rest 2.35 x): white noise is
    taken instead.

    Parameters
    ----------
    residual : numpy.ndarray
        The residual at every sample, shape (n,), in the record's unit.
    mask : numpy.ndarray
        Boolean, shape (n,): the samples it is estimated on (the training samples).
    dt : float
        Sample interval [s].
    max_order : int, optional
        Highest order tried (0: white noise of the rough part's std, corrected for the
        trend removal). Default MAX_AR_ORDER.

    Returns
    -------
    NoiseModel
        The estimated noise.
    """
    mask = np.asarray(mask, dtype=bool)
    window = _trend_window(dt, len(mask))
    rough = rough_part(residual, dt)
    h = -savgol_coeffs(window, 2)
    h[window // 2] += 1.0
    rho = np.correlate(h, h, "full")                 # rho_h(m), m = -(window - 1) .. window - 1
    centre = window - 1

    def rho_h(m):
        m = np.abs(m)
        return np.where(m <= centre, rho[centre + np.minimum(m, centre)], 0.0)

    lags = np.arange(AUTOCOVARIANCE_LAGS + 1)
    gamma_x = np.array([_mean_product(rough, mask, k) for k in lags])
    m = max(int(mask.sum()), 1)
    columns = np.column_stack([rho_h(lags)] + [rho_h(lags - j) + rho_h(lags + j)
                                                for j in range(1, MAX_AR_ORDER + 1)])
    chi2_limit = AUTOCOVARIANCE_LAGS + CHI2_Z * np.sqrt(2.0 * AUTOCOVARIANCE_LAGS)
    for order in range(max_order + 1):
        gamma = np.linalg.lstsq(columns[:, :order + 1], gamma_x, rcond=None)[0]
        misfit = gamma_x - columns[:, :order + 1] @ gamma
        if gamma[0] > 0.0 and m * np.sum(misfit[1:] ** 2) / gamma_x[0] ** 2 <= chi2_limit:
            break
    if gamma[0] <= 0.0:                              # no order fits: the rough part taken as white
        return NoiseModel(np.zeros(0), float(np.sqrt(max(gamma_x[0], 0.0) / max(columns[0, 0], 1e-300))))
    if order == 0:
        return NoiseModel(np.zeros(0), float(np.sqrt(gamma[0])))
    phi, variance = _yule_walker(gamma)
    if phi.sum() < 0.0:                              # more power at high frequencies than white: not a sensor's
        return NoiseModel(np.zeros(0), float(np.sqrt(gamma[0])))
    return NoiseModel(phi, float(np.sqrt(variance)))


def _trend_window(dt, n):
    """The trend's Savitzky-Golay window in samples (odd, at least 5, at most n)."""
    window = int(round(TREND_WINDOW_S / dt)) | 1
    return max(5, min(window, n - 1 + n % 2))


def _mean_product(x, mask, k):
    """Mean of x_t x_{t-k} over the t with both samples in ``mask``."""
    both = mask[k:] & mask[:len(mask) - k]
    return float(np.mean(x[k:][both] * x[:len(x) - k][both])) if both.any() else 0.0


def _yule_walker(gamma):
    """AR(p) coefficients and innovation variance from autocovariances gamma(0 .. p),
    by the Levinson-Durbin recursion, stopped at the last stable order (|partial
    autocorrelation| < 1)."""
    a, v = np.zeros(0), float(gamma[0])
    for q in range(1, len(gamma)):
        k = (gamma[q] - a @ gamma[q - 1:0:-1]) / v
        if abs(k) >= 1.0:
            break
        a = np.r_[a - k * a[::-1], k]
        v *= 1.0 - k * k
    return a, v


def log_likelihood(innovations):
    """Gaussian log-likelihood of white innovations with their variance profiled out.

    Parameters
    ----------
    innovations : numpy.ndarray
        The whitened residual.

    Returns
    -------
    float
        ln L (module docstring) [-].
    """
    m = len(innovations)
    rss = float(np.sum(np.square(innovations)))
    return -0.5 * m * (np.log(2.0 * np.pi * max(rss, 1e-300) / m) + 1.0)


def laplace_log_evidence(innovations, jacobian, prior_widths):
    """Log evidence of a fitted model by Laplace's method, uniform priors (module docstring).

    Parameters
    ----------
    innovations : numpy.ndarray
        The fit's whitened residual, shape (m,).
    jacobian : numpy.ndarray
        Its Jacobian in the optimiser's variables z, shape (m, k).
    prior_widths : numpy.ndarray
        Widths of the uniform priors on z (the fit's bounds), shape (k,).

    Returns
    -------
    float
        ln Z [-]; the posterior's volume is capped at the prior's (a parameter the record
        does not inform costs nothing and gains nothing).
    """
    m = len(innovations)
    s2 = max(float(np.sum(np.square(innovations))) / m, 1e-300)
    J = np.asarray(jacobian, dtype=float)
    k = J.shape[1]
    if k == 0:
        return log_likelihood(innovations)
    sign, logdet = np.linalg.slogdet(J.T @ J / s2)
    half_widths = 0.5 * k * np.log(2.0 * np.pi) - 0.5 * logdet if sign > 0 else 0.0
    occam = min(half_widths - float(np.sum(np.log(prior_widths))), 0.0)
    return log_likelihood(innovations) + occam
