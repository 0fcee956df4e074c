"""The force transducer (second-order low-pass) against its analytic responses."""
import numpy as np
import pytest

from ccedi.errors import InputError
from ccedi.rom.sensor import Transducer, peak


def analytic_step(t, wn, zeta):
    """Unit step response of omega_n^2 / (s^2 + 2 zeta omega_n s + omega_n^2), zeta < 1."""
    wd = wn * np.sqrt(1.0 - zeta**2)
    phi = np.arccos(zeta)
    return 1.0 - np.exp(-zeta * wn * t) * np.sin(wd * t + phi) / np.sqrt(1.0 - zeta**2)


@pytest.mark.parametrize("f_n, zeta", [(100.0, 1.0 / np.sqrt(2.0)), (400.0, 0.05)])
def test_step_response_is_the_analytic_one(f_n, zeta):
    sensor = Transducer(f_n, zeta)
    t = np.linspace(0.0, 0.05, 2001)
    force = np.where(t > 0.0, 3.0, 0.0)
    force[0] = 0.0                                    # at rest, reading zero; the step ramps over one sample
    y = sensor.measured(t, force)
    dt = t[1] - t[0]
    # a ramp over the first step: the exact response is the step response averaged over it
    ref = 3.0 * np.array([np.mean(analytic_step(np.clip(ti - np.linspace(0.0, dt, 41), 0.0, None),
                                                sensor.omega_n_rad_s, zeta)) for ti in t])
    assert np.max(np.abs(y - ref)) < 1e-3 * 3.0
    overshoot = y.max() / 3.0 - 1.0
    assert overshoot == pytest.approx(np.exp(-np.pi * zeta / np.sqrt(1.0 - zeta**2)), rel=0.02)


@pytest.mark.parametrize("f", [20.0, 100.0, 400.0])
def test_steady_sine_has_the_gain_and_phase_of_h(f):
    sensor = Transducer()
    t = np.arange(0.0, 0.5, 1.0 / (60.0 * f))
    y = sensor.measured(t, np.sin(2.0 * np.pi * f * t))
    late = t > 0.3                                    # transients decayed (time constant 1/(zeta w_n) = 2.3 ms)
    h = sensor.frequency_response(f)
    expected = np.abs(h) * np.sin(2.0 * np.pi * f * t[late] + np.angle(h))
    assert np.max(np.abs(y[late] - expected)) < 2e-3 * max(np.abs(h), 0.05)
    if f == 100.0:
        assert np.abs(h) == pytest.approx(1.0 / np.sqrt(2.0), rel=1e-12)      # Butterworth: -3 dB at f_n


def test_static_gain_and_start_at_rest():
    sensor = Transducer(50.0, 0.3)
    t = np.linspace(0.0, 0.2, 801)
    y = sensor.measured(t, np.full_like(t, 7.5))
    assert np.allclose(y, 7.5, rtol=1e-9)


def test_non_uniform_sampling_matches_the_uniform_reading():
    sensor = Transducer()
    t = np.linspace(0.0, 0.3, 3001)
    f = np.sin(2.0 * np.pi * 15.0 * t) ** 2 * 10.0
    y = sensor.measured(t, f)
    rng = np.random.default_rng(0)
    ts = np.sort(np.concatenate([[0.0, 0.3], rng.uniform(0.0, 0.3, 2998)]))
    ys = sensor.measured(ts, np.sin(2.0 * np.pi * 15.0 * ts) ** 2 * 10.0)
    assert np.max(np.abs(ys - np.interp(ts, t, y))) < 0.01
    assert peak(t, f, sensor) == pytest.approx(y.max())


def test_lower_bandwidth_lowers_a_chatter_peak():
    t = np.linspace(0.0, 0.5, 5001)
    f = 15.0 + 10.0 * np.sin(2.0 * np.pi * 400.0 * t)
    late = t > 0.2                                    # after the start-up transient
    peaks = [Transducer(fn).measured(t, f)[late].max() for fn in (2000.0, 200.0, 50.0)]
    assert peaks[0] > peaks[1] > peaks[2] > 15.0
    for fn, p in zip((2000.0, 200.0, 50.0), peaks):  # steady swing: the gain at 400 Hz (crest sampled: 2 %)
        assert p - 15.0 == pytest.approx(10.0 * abs(Transducer(fn).frequency_response(400.0)), rel=0.02)


@pytest.mark.parametrize("kwargs", [{"natural_frequency_hz": 0.0}, {"damping_ratio": -0.1},
                                    {"natural_frequency_hz": np.nan}])
def test_bad_parameters_are_refused(kwargs):
    with pytest.raises(InputError):
        Transducer(**kwargs)


def test_bad_samples_are_refused():
    with pytest.raises(InputError, match="strictly increasing"):
        Transducer().measured([0.0, 0.1, 0.1], [1.0, 2.0, 3.0])
    with pytest.raises(InputError, match="same length"):
        Transducer().measured([0.0, 0.1], [1.0])


@pytest.mark.parametrize("f_n, zeta, step", [(100.0, 1 / np.sqrt(2), 5e-4), (20.0, 0.3, 1e-3), (400.0, 1.0, 2e-4)])
def test_the_digital_filter_is_lsim_with_a_first_order_hold(f_n, zeta, step):
    """The reference path: scipy's lsim (first-order hold, started at rest at the first
    sample) gives the same reading to round-off."""
    from scipy import signal

    tr = Transducer(f_n, zeta)
    t = np.arange(1, 3001) * step
    rng = np.random.default_rng(7)
    f = np.cumsum(rng.normal(size=len(t))) + 5.0 * np.sin(2 * np.pi * 0.4 / step * t)
    sys = tr.system()
    x0 = -np.linalg.solve(sys.A, sys.B[:, 0]) * f[0]
    _, ref, _ = signal.lsim(sys, f, t - t[0], X0=x0, interp=True)
    np.testing.assert_allclose(tr.measured(t, f), ref, rtol=0, atol=1e-12 * np.abs(ref).max())
