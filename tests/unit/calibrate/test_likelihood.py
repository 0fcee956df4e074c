"""The calibration's likelihood: the autoregressive noise model estimated on a residual's
rough part, its whitening, and Laplace's evidence, against processes and integrals whose
answer is known."""
import numpy as np
import pytest
from scipy.integrate import quad
from scipy.signal import lfilter

from ccedi.calibrate.discrepancy import DiscrepancyKernel
from ccedi.calibrate.effects import Parameter
from ccedi.calibrate.fit import Fit, fit, holdout_mask
from ccedi.calibrate.likelihood import WHITE, NoiseModel, estimate_noise, laplace_log_evidence, log_likelihood

DT = 1e-3
N = 1500
MASK = ~holdout_mask(N)
T = np.arange(N) * DT


def _white(seed=0):
    return np.random.default_rng(seed).standard_normal(N)


def _lag1(x):
    x = x - x.mean()
    return float(x[1:] @ x[:-1] / (x @ x))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_white_noise_is_estimated_white_with_its_std(seed):
    noise = estimate_noise(0.3 * _white(seed), MASK, DT)
    assert noise.order == 0
    assert noise.innovation_std == pytest.approx(0.3, rel=0.06)


def test_a_smooth_signature_is_not_taken_for_noise():
    """A decaying 8 Hz oscillation 20 x the noise, on white noise: still white noise
    (the signature is the model's to explain, not the noise's); the same residual's raw
    lag-1 autocorrelation is 0.99, which an AR model on the residual itself would whiten."""
    residual = _white() + 20.0 * np.exp(-T) * np.sin(2 * np.pi * 8.0 * T)
    assert _lag1(residual) > 0.95
    noise = estimate_noise(residual, MASK, DT)
    assert noise.order == 0
    assert noise.innovation_std == pytest.approx(1.0, rel=0.06)


@pytest.mark.parametrize("ar", [(0.5,), (0.9, -0.3)])
def test_autoregressive_noise_is_whitened(ar):
    """AR noise (lag-1 autocorrelation 0.5-0.7) correlated over a few samples: the model's
    low-frequency gain 1 - sum(phi) is the process's within 0.1, and its innovations have
    a lag-1 autocorrelation below 0.1, on a residual with a smooth signature too."""
    x = lfilter([1.0], np.r_[1.0, -np.array(ar)], _white(3))
    residual = x + 10.0 * np.exp(-T) * np.sin(2 * np.pi * 8.0 * T)
    noise = estimate_noise(residual, MASK, DT)
    assert noise.order >= 1
    assert 1.0 - noise.ar.sum() == pytest.approx(1.0 - sum(ar), abs=0.1)
    assert abs(_lag1(noise.innovations(x, MASK))) < 0.1
    assert abs(_lag1(x)) > 0.45


def test_innovations_use_only_samples_whose_predecessors_are_scored():
    """Order 2 on a mask with gaps: each scored run of samples loses its first two, and
    e_t = r_t - phi_1 r_{t-1} - phi_2 r_{t-2} exactly."""
    noise = NoiseModel(np.array([0.5, -0.2]))
    r = _white(4)
    e = noise.innovations(r, MASK)
    runs = np.diff(np.r_[0, MASK.astype(int), 0])
    n_runs = int(np.sum(runs == 1))
    assert len(e) == int(MASK.sum()) - 2 * n_runs
    t = np.flatnonzero(MASK)[2]                         # third sample of the first scored run
    assert e[0] == pytest.approx(r[t] - 0.5 * r[t - 1] + 0.2 * r[t - 2])
    assert np.array_equal(WHITE.innovations(r, MASK), r[MASK])


def test_laplace_evidence_of_a_linear_model_is_the_integral():
    """For a linear model y = a x the likelihood is Gaussian in a, so Laplace's evidence
    (uniform prior of width w, the innovation variance held at its profiled value) is
    the integral of the likelihood over the prior, divided by w, within quadrature's error."""
    rng = np.random.default_rng(5)
    x = np.linspace(0.0, 1.0, 200)
    y = 2.0 * x + 0.1 * rng.standard_normal(x.size)
    a_hat = float(x @ y / (x @ x))
    s2 = float(np.mean((y - a_hat * x) ** 2))
    width = 10.0

    def likelihood(a):
        r = y - a * x
        return np.exp(-0.5 * np.sum(r**2) / s2 - 0.5 * x.size * np.log(2 * np.pi * s2) - log_likelihood(y - a_hat * x))

    integral = quad(likelihood, a_hat - 1.0, a_hat + 1.0, points=[a_hat], epsabs=0.0, epsrel=1e-10)[0]
    expected = log_likelihood(y - a_hat * x) + np.log(integral / width)
    assert laplace_log_evidence(y - a_hat * x, -x[:, None], np.array([width])) == pytest.approx(expected, abs=1e-6)


def test_evidence_penalises_a_parameter_the_record_does_not_need():
    """The same residual with a second, useless parameter (a column the first cannot
    mimic, so it is resolved): ln Z drops by the Occam factor, ln(prior width / posterior
    width) - ln sqrt(2 pi) > 0; a parameter that removes misfit gains."""
    rng = np.random.default_rng(6)
    e = rng.standard_normal(500)
    one = rng.standard_normal((500, 1))
    two = np.column_stack([one, rng.standard_normal(500)])
    assert laplace_log_evidence(e, two, np.array([1.0, 1.0])) < laplace_log_evidence(e, one, np.array([1.0])) - 1.0
    better = e * 0.8                                     # the second parameter's fit removes 36 % of the RSS
    assert laplace_log_evidence(better, two, np.array([1.0, 1.0])) > laplace_log_evidence(e, one, np.array([1.0]))


class _Experiment:
    def __init__(self, time_s, signal):
        self.time_s, self.signal = time_s, signal


class _DecayModel:
    """A toy calibration model: amplitude x exp(-t / 0.3 s) on a record with AR(1) noise."""

    def __init__(self, phi, seed=7):
        noise = 0.05 * lfilter([1.0], [1.0, -phi], np.random.default_rng(seed).standard_normal(N))
        self.exp = _Experiment(T, np.exp(-T / 0.3) + noise)

    def parameters(self, effects):
        return [(Parameter("amplitude_m", 0.1, 10.0), 0.5)]

    def predict(self, values):
        return values["amplitude_m"] * np.exp(-T / 0.3)


def test_noise_correlated_beyond_the_trend_window_is_whitened_only_in_part():
    """The limit stated in the module: AR(1) noise of phi = 0.8 keeps much of its power
    below the trend's ~50 Hz, where the rough part cannot see it; its estimated
    low-frequency gain is 0.4 against the process's 0.2, and the innovations keep a lag-1
    autocorrelation of 0.2 (the raw noise's is 0.8)."""
    x = lfilter([1.0], [1.0, -0.8], _white(3))
    noise = estimate_noise(x, MASK, DT)
    assert 0.3 < 1.0 - noise.ar.sum() < 0.5
    assert 0.1 < _lag1(noise.innovations(x, MASK)) < 0.3


@pytest.mark.parametrize("phi, claimed_over_scatter", [(0.5, (0.8, 1.2)), (0.8, (0.45, 0.7))])
def test_correlated_noise_widens_the_standard_error_honestly(phi, claimed_over_scatter):
    """Over 40 records with AR(1) noise the fitted amplitude scatters by about
    sqrt((1 + phi) / (1 - phi)) (1.7 x at phi = 0.5, 3 x at 0.8) what the white-noise fit
    claims; under the estimated noise model its claimed standard error is within 20 % of
    the scatter at phi = 0.5 and, past the trend window's reach, 0.45-0.7 of it at 0.8
    (the white fit's: 0.33)."""
    fits_white, fits_ar = [], []
    for seed in range(40):
        model = _DecayModel(phi, seed)
        white: Fit = fit(model, ())
        noise = estimate_noise(white.prediction - model.exp.signal, MASK, DT)
        fits_white.append(white)
        fits_ar.append(fit(model, (), start=white.values, noise=noise))
    scatter = np.std([f.values["amplitude_m"] for f in fits_ar])
    assert np.median([f.stderr["amplitude_m"] for f in fits_white]) < 0.65 * scatter
    low, high = claimed_over_scatter
    assert low * scatter < np.median([f.stderr["amplitude_m"] for f in fits_ar]) < high * scatter


def test_ar_covariance_is_the_processes():
    """AR(1) of innovation std s: gamma(k) = s^2 phi^k / (1 - phi^2)."""
    cov = NoiseModel(np.array([0.6]), 0.5).covariance(30)
    k = np.arange(30)
    assert np.allclose(cov[0], 0.25 * 0.6**k / (1 - 0.36), rtol=1e-12)
    assert np.allclose(cov, cov.T)


def test_a_discrepancy_is_whitened_with_the_noise():
    """Residuals drawn from white noise plus a smooth discrepancy of known covariance: the
    innovations L^-1 r are white with unit variance (chi-square per sample within 0.1 of 1,
    lag-1 autocorrelation below 0.1), and without the discrepancy they are not."""
    rng = np.random.default_rng(8)
    reading = 10.0 * np.exp(-(((T - 0.75) / 0.2) ** 2))
    disc = DiscrepancyKernel(amplitudes=(0.03,), length_scales_s=(0.05,)).covariance(T, reading)
    noise = NoiseModel(np.zeros(0), 0.1)
    combined = noise.with_discrepancy(disc)
    L = np.linalg.cholesky(disc + 1e-10 * np.eye(N))
    chi2, lag1, chi2_white = [], [], []
    for _ in range(5):
        r = 0.1 * rng.standard_normal(N) + L @ rng.standard_normal(N)
        e = combined.innovations(r, MASK)
        chi2.append(np.mean(e**2))
        lag1.append(_lag1(e))
        chi2_white.append(np.mean((r[MASK] / 0.1) ** 2))
    assert np.mean(chi2) == pytest.approx(1.0, abs=0.1)
    assert abs(np.mean(lag1)) < 0.1
    assert np.mean(chi2_white) > 3.0
    assert not combined.same_as(noise) and combined.same_as(noise.with_discrepancy(disc))


@pytest.mark.parametrize("phi", [0.3, 0.6, 0.85])
def test_effective_samples_of_ar1_noise(phi):
    """AR(1): the mean square of n samples has variance 2 sigma^4 (1 + phi^2) / ((1 - phi^2) n),
    so n_eff = n (1 - phi^2) / (1 + phi^2); and a Monte Carlo of the mean square agrees."""
    noise = NoiseModel(np.array([phi]), innovation_std=1.0)
    n = 1500
    assert noise.effective_samples(n) == pytest.approx(n * (1 - phi**2) / (1 + phi**2), rel=1e-3)
    rng = np.random.default_rng(5)
    w = rng.standard_normal((4000, n + 200))
    x = lfilter([1.0], [1.0, -phi], w, axis=1)[:, 200:]
    ms = np.mean(x**2, axis=1) / np.var(x)
    assert np.var(ms) == pytest.approx(2.0 / noise.effective_samples(n), rel=0.15)
    assert WHITE.effective_samples(n) == n
