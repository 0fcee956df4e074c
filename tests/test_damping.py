"""Log-decrement on analytic single-degree-of-freedom responses."""
import numpy as np
import pytest

from fea.errors import InputError
from rom.damping import log_decrement


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
