"""The contact chain's discrepancy as a Gaussian process: its covariance is a proper one
(symmetric, positive semi-definite, zero off contact), its kernel's variance is what
its amplitudes say, and a kernel fitted by maximum likelihood to draws of a known one
finds it again."""
import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from ccedi.calibrate.discrepancy import (
    CONTACT_LEVEL,
    ENVELOPE_WIDENING_S,
    NUGGET,
    DiscrepancyKernel,
    contact_envelope,
    log_likelihood,
    matern32,
)

T = np.arange(1, 1501) * 1e-3
READING = 15.0 * np.clip(np.sin(np.pi * (T - 0.4) / 0.8), 0.0, None) * (T > 0.4) * (T < 1.2)
KERNEL = DiscrepancyKernel(amplitudes=(0.02, 0.015), length_scales_s=(0.005, 0.1))


def test_matern32_is_one_at_zero_and_decays():
    x = np.linspace(0.0, 5.0, 51)
    k = matern32(x)
    assert k[0] == 1.0
    assert np.all(np.diff(k) < 0.0)
    assert matern32(np.array([1.0]))[0] == pytest.approx((1 + np.sqrt(3)) * np.exp(-np.sqrt(3)))


def test_the_envelope_covers_the_contact_and_its_widening():
    env = contact_envelope(T, READING)
    inside = READING > CONTACT_LEVEL * READING.max()
    first, last = np.flatnonzero(inside)[[0, -1]]
    widen = int(round(ENVELOPE_WIDENING_S / 1e-3))
    assert np.all(env[first - widen:last + widen + 1] == 1.0)
    assert np.all(env[:first - widen] == 0.0) and np.all(env[last + widen + 1:] == 0.0)


def test_the_covariance_is_proper_and_its_variance_is_the_amplitudes():
    C = KERNEL.covariance(T, READING)
    env = contact_envelope(T, READING)
    assert np.allclose(C, C.T)
    assert np.min(np.linalg.eigvalsh(C)) > -1e-9 * np.max(C)
    assert np.all(C[env == 0.0] == 0.0)
    expected = READING.max() ** 2 * sum(a**2 for a in KERNEL.amplitudes)
    assert np.allclose(np.diag(C)[env == 1.0], expected)
    assert np.allclose(KERNEL.scaled(0.5).covariance(T, READING), 0.25 * C)


def test_a_fitted_amplitude_recovers_the_drawn_one():
    """Ten draws of a one-component kernel (amplitude 0.03 of the peak, 20 ms) with the
    nugget: the maximum-likelihood amplitude, the length scale held, is within 10 % of
    0.03, and the chi-square per sample at it is about 1."""
    true = DiscrepancyKernel(amplitudes=(0.03,), length_scales_s=(0.02,))
    keep = contact_envelope(T, READING) > 0
    C = true.covariance(T[keep], READING[keep])
    L = np.linalg.cholesky(C + NUGGET * READING.max() ** 2 * np.eye(len(C)))
    rng = np.random.default_rng(1)
    draws = [L @ rng.standard_normal(len(C)) for _ in range(10)]

    def cost(log_a):
        k = DiscrepancyKernel(amplitudes=(np.exp(log_a),), length_scales_s=(0.02,))
        return -sum(log_likelihood(k, time_s=T[keep], reading=READING[keep], discrepancy=d)[0] for d in draws)

    a = float(np.exp(minimize_scalar(cost, bounds=(np.log(0.003), np.log(0.3)), method="bounded").x))
    assert a == pytest.approx(0.03, rel=0.1)
    chi2 = np.mean([log_likelihood(true, time_s=T[keep], reading=READING[keep], discrepancy=d)[1] for d in draws])
    assert chi2 == pytest.approx(1.0, abs=0.1)
