"""Log-decrement on analytic single-degree-of-freedom responses."""
import numpy as np
import pytest

from ccedi.errors import InputError
from ccedi.rom.damping import log_decrement


def sdof_free_response(zeta, omega_n=90.0, t_end=0.5, n=2000, x0=1e-3):
    """Exact free response of m x'' + 2 zeta omega_n m x' + omega_n^2 m x = 0, x(0) = x0, x'(0) = 0."""
    t = np.linspace(0.0, t_end, n)
    wd = omega_n * np.sqrt(1.0 - zeta**2)
    x = x0 * np.exp(-zeta * omega_n * t) * (np.cos(wd * t) + zeta * omega_n / wd * np.sin(wd * t))
    return t, x


@pytest.mark.parametrize("zeta", [0.005, 0.05, 0.2])
def test_recovers_sdof_damping_ratio_and_frequency(zeta):
    t, x = sdof_free_response(zeta, t_end=min(3.0, 4.0 / (zeta * 90.0)), n=20000)
    ld = log_decrement(t, x, y_final=0.0)
    assert ld.zeta == pytest.approx(zeta, rel=0.01)
    assert ld.omega_d_rad_s == pytest.approx(90.0 * np.sqrt(1 - zeta**2), rel=0.005)
    assert ld.n_cycles >= 2


def test_confidence_interval_covers_truth_with_noise():
    rng = np.random.default_rng(5)
    t, x = sdof_free_response(0.03, t_end=1.0, n=4000)
    ld = log_decrement(t, x + 2e-6 * rng.standard_normal(len(t)), y_final=0.0, noise_band=0.05)
    lo, hi = ld.zeta_ci95
    assert lo < 0.03 < hi and hi - lo < 0.01


def test_overdamped_response_is_refused():
    t = np.linspace(0.0, 0.5, 500)
    x = 1e-3 * (1 + 200 * t) * np.exp(-200 * t)          # critically damped: no oscillation
    with pytest.raises(InputError, match="does not oscillate"):
        log_decrement(t, x, y_final=0.0)


@pytest.mark.parametrize("t, y, match", [
    (np.linspace(0, 1, 50), np.full(50, np.nan), "finite"),
    (np.linspace(0, 1, 50), np.zeros(40), "equal length"),
    (np.linspace(1, 0, 50), np.sin(np.linspace(0, 20, 50)), "increasing")])
def test_bad_signals_are_named(t, y, match):
    with pytest.raises(InputError, match=match):
        log_decrement(t, y)


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from ccedi.rom.damping import envelope_fit, half_power, oscillates  # noqa: E402


def sdof_impulse_response(zeta, omega_n, noise, seed, periods_min=30):
    """h(t) = exp(-zeta wn t) sin(wd t) / wd, sampled 40 times per period over at least
    ``periods_min`` periods and 8 decay times 1/(zeta wn), plus white noise of
    ``noise`` x the peak."""
    wd = omega_n * np.sqrt(1 - zeta**2)
    t_end = max(periods_min * 2 * np.pi / wd, 8.0 / (zeta * omega_n))
    t = np.arange(0.0, t_end, 2 * np.pi / wd / 40)
    h = np.exp(-zeta * omega_n * t) * np.sin(wd * t) / wd
    rng = np.random.default_rng(seed)
    return t, h + noise * np.abs(h).max() * rng.standard_normal(len(t))


zetas = st.floats(0.001, 0.3)


@settings(max_examples=25, deadline=None)
@given(zetas, st.floats(10.0, 500.0), st.integers(0, 2**16))
def test_log_decrement_recovers_zeta_with_noise(zeta, omega_n, seed):
    t, y = sdof_impulse_response(zeta, omega_n, noise=1e-3, seed=seed)
    ld = log_decrement(t, y, y_final=0.0, noise_band=0.02)
    assert ld.zeta == pytest.approx(zeta, rel=0.05)


@settings(max_examples=25, deadline=None)
@given(zetas, st.floats(10.0, 500.0), st.integers(0, 2**16))
def test_half_power_recovers_zeta_with_noise(zeta, omega_n, seed):
    t, y = sdof_impulse_response(zeta, omega_n, noise=1e-3, seed=seed)
    hp = half_power(t, y)
    assert hp.zeta == pytest.approx(zeta, rel=0.05)
    assert hp.omega_n_rad_s == pytest.approx(omega_n, rel=0.01)


@settings(max_examples=25, deadline=None)
@given(st.floats(0.005, 0.3), st.floats(10.0, 500.0), st.integers(0, 2**16))
def test_envelope_fit_recovers_zeta_with_noise(zeta, omega_n, seed):
    t, y = sdof_impulse_response(zeta, omega_n, noise=1e-3, seed=seed)
    assert envelope_fit(t, y, y_final=0.0).zeta == pytest.approx(zeta, rel=0.05)


def test_half_power_with_force_signal():
    """A forced record: response to a 5-sample rectangular pulse, FRF = Y / F."""
    zeta, wn = 0.05, 60.0
    t, h = sdof_impulse_response(zeta, wn, noise=0.0, seed=0)
    f = np.zeros_like(t)
    f[:5] = 1.0
    y = np.convolve(f, h)[:len(t)]
    assert half_power(t, y, force=f).zeta == pytest.approx(zeta, rel=0.03)


@pytest.mark.parametrize("method", [half_power, envelope_fit])
def test_overdamped_response_is_refused_by_every_method(method):
    t = np.linspace(0.0, 2.0, 2000)
    y = np.exp(-30 * t) - np.exp(-60 * t)                 # over-damped impulse response
    with pytest.raises(InputError, match="over-damped|does not oscillate"):
        method(t, y)


def test_oscillation_criterion_separates_under_from_critical_damping():
    t = np.linspace(0.0, 1.0, 4000)
    wn = 50.0
    critical = t * np.exp(-wn * t)
    assert not oscillates(t, critical)
    for zeta in (0.9, 0.95):
        wd = wn * np.sqrt(1 - zeta**2)
        under = np.exp(-zeta * wn * t) * np.sin(wd * t)
        assert oscillates(t, under)


def test_noise_level_of_a_noisy_decay():
    t, y = sdof_impulse_response(0.05, 60.0, noise=0.0, seed=0)
    rng = np.random.default_rng(9)
    sigma = 0.01 * np.abs(y).max()
    from ccedi.rom.damping import noise_level
    assert noise_level(y + sigma * rng.standard_normal(len(y))) == pytest.approx(sigma, rel=0.1)
    assert noise_level(y) < 0.05 * sigma               # a clean, finely sampled signal has ~none
