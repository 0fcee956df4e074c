"""Damping identification from a free (or post-impulse) response.

Logarithmic decrement (paper section 2.2). For successive peaks ``A_0, A_1, ...`` of the
response about its final value, one period apart,

    delta = ln(A_k / A_{k+1})                      [-]
    zeta  = delta / sqrt(4 pi^2 + delta^2)         [-]

ccedi fits ``ln A_k = ln A_0 - delta k`` by least squares over all peaks above the
noise band, which uses every cycle and gives a confidence interval on delta from the
regression's standard error (Student t, n_peaks - 2 degrees of freedom).
"""
from dataclasses import dataclass

import numpy as np
from scipy import stats
from scipy.optimize import least_squares

from ccedi.errors import InputError


@dataclass(frozen=True)
class LogDecrement:
    """Result of :func:`log_decrement`.

    Parameters
    ----------
    zeta : float
        Damping ratio zeta = delta / sqrt(4 pi^2 + delta^2) [-].
    delta : float
        Logarithmic decrement per cycle [-].
    zeta_ci95 : tuple of float
        (low, high) 95 % confidence interval of zeta; (nan, nan) when only 2 peaks.
    n_cycles : int
        Number of cycles used (peaks - 1).
    period_s : float
        Mean damped period [s].
    omega_d_rad_s : float
        Damped angular frequency 2 pi / period [rad/s].
    peak_times_s : numpy.ndarray
        Times of the peaks used [s].
    peak_amplitudes : numpy.ndarray
        Peak excursions from the final value (units of y).
    """
    zeta: float
    delta: float
    zeta_ci95: tuple
    n_cycles: int
    period_s: float
    omega_d_rad_s: float
    peak_times_s: np.ndarray
    peak_amplitudes: np.ndarray


def _zeta(delta):
    return delta / np.sqrt(4.0 * np.pi**2 + delta**2)


def _validate_signal(t, y):
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    if t.ndim != 1 or t.shape != y.shape or len(t) < 8:
        raise InputError(f"time and response must be 1-D arrays of equal length >= 8, "
                         f"got shapes {t.shape} and {y.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(y))):
        raise InputError("time and response must be finite (no NaN or inf samples)")
    if np.any(np.diff(t) <= 0.0):
        raise InputError("time must be strictly increasing")
    return t, y


def log_decrement(t, y, *, y_final=None, noise_band=0.01, max_cycles=None):
    """Damping ratio of the dominant mode of a decaying oscillation by log-decrement.

    One peak per cycle on the side of the largest excursion, from it on; the peak
    heights are refined by a parabola fit and ln A_k = ln A_0 - delta k is fitted by
    least squares (module docstring). Peaks constant within their scatter give zeta = 0.

    Parameters
    ----------
    t : array_like
        Sample times, 1-D, strictly increasing, finite, at least 8 samples [s].
    y : array_like
        Response at ``t`` (any unit), e.g. tip displacement [m].
    y_final : float, optional
        Equilibrium value the response decays to. Default: the mean of the last 10 %
        of the samples.
    noise_band : float, optional
        Peaks smaller than ``noise_band`` x the largest excursion are ignored, in
        [0, 1). Default 0.01.
    max_cycles : int, optional
        Use at most this many cycles after the first peak. Default: all.

    Returns
    -------
    LogDecrement
        zeta, delta, its confidence interval and the peaks used.

    Raises
    ------
    InputError
        If the signal is not 1-D finite with at least 8 samples and strictly increasing times; ``noise_band`` is outside [0, 1); the response is constant; fewer
        than two peaks rise above the noise band (the response does not oscillate); or
        the peaks grow beyond their scatter.
    """
    t, y = _validate_signal(t, y)
    if not 0.0 <= noise_band < 1.0:
        raise InputError(f"noise_band must be in [0, 1), got {noise_band!r}")
    if y_final is None:
        y_final = float(np.mean(y[int(0.9 * len(y)):]))
    r = y - y_final
    scale = np.max(np.abs(r))
    if scale == 0.0:
        raise InputError("response is constant: nothing to identify")
    # one peak per half-cycle on the side of the largest excursion, from it on, so that
    # higher-mode ripples and noise cannot add spurious peaks
    i_max = int(np.argmax(np.abs(r)))
    sign = 1 if r[i_max] > 0 else -1
    cycles = [c for c, sg in half_cycles(r, noise_band * scale) if sg == sign]
    first = next((i for i, c in enumerate(cycles) if c[0] <= i_max <= c[-1]), len(cycles))
    lobes = cycles[first:]
    if max_cycles is not None:
        lobes = lobes[:int(max_cycles) + 1]
    if len(lobes) < 2:
        raise InputError("response does not oscillate: fewer than two peaks above the noise band "
                         f"({noise_band:g} x max excursion); log-decrement needs an under-damped response")
    tp, ap = _refine_peaks(t, sign * r, lobes)
    n = _regular_prefix(tp)
    tp, ap = tp[:n], ap[:n]
    k = np.arange(len(ap))
    slope, intercept = np.polyfit(k, np.log(ap), 1)
    delta = -slope
    half = np.nan
    if len(ap) > 2:
        resid = np.log(ap) - (intercept + slope * k)
        se = np.sqrt(np.sum(resid**2) / (len(k) - 2) / np.sum((k - k.mean())**2))
        half = stats.t.ppf(0.975, len(k) - 2) * se
    if delta + (half if np.isfinite(half) else 0.0) <= 0.0:
        raise InputError("peak amplitudes grow: the response is not a damped free vibration")
    ci = (float(_zeta(max(delta - half, 0.0))), float(_zeta(delta + half))) if np.isfinite(half) else (np.nan, np.nan)
    delta = max(delta, 0.0)             # no decay within the scatter of the peaks: zeta = 0
    period = float(np.mean(np.diff(tp)))
    return LogDecrement(zeta=float(_zeta(delta)), delta=float(delta), zeta_ci95=ci, n_cycles=len(ap) - 1,
                        period_s=period, omega_d_rad_s=2.0 * np.pi / period,
                        peak_times_s=tp, peak_amplitudes=ap)


def _regular_prefix(tp):
    """Length of the leading run of peak times whose spacings stay within 0.5-1.5 times
    their median: where an oscillation fades into the noise band, half-cycles merge or
    split, and the peaks after that point no longer count cycles."""
    if len(tp) < 3:
        return len(tp)
    d = np.diff(tp)
    med = np.median(d)
    bad = np.flatnonzero((d > 1.5 * med) | (d < 0.5 * med))
    return int(bad[0] + 1) if len(bad) else len(tp)


def half_cycles(r, band):
    """Half-cycles of an oscillation about zero, with hysteresis.

    The sign of r only changes when r goes beyond +band or -band, so noise near a zero
    crossing cannot split a half-cycle. A last half-cycle still rising when the record
    ends is dropped (its largest sample is not a peak).

    Parameters
    ----------
    r : numpy.ndarray
        Signal about zero (response minus its final value), 1-D.
    band : float
        Hysteresis half-width (units of r), >= 0.

    Returns
    -------
    list of (numpy.ndarray, int)
        (sample indices, sign +1 or -1) of each half-cycle, signs alternating; samples
        before r first leaves the band belong to none.
    """
    state = np.where(r > band, 1, np.where(r < -band, -1, 0))
    idx = np.where(state != 0, np.arange(len(r)), 0)
    np.maximum.accumulate(idx, out=idx)
    filled = state[idx]                                # forward-filled sign, 0 before the first
    change = np.flatnonzero(np.diff(filled) != 0) + 1
    bounds = np.concatenate([[0], change, [len(r)]])
    cycles = [(np.arange(lo, hi), int(filled[lo])) for lo, hi in zip(bounds[:-1], bounds[1:]) if filled[lo] != 0]
    if cycles:
        last, sgn = cycles[-1]
        if last[-1] == len(r) - 1 and np.argmax(sgn * r[last]) == len(last) - 1:
            cycles.pop()
    return cycles


def _refine_peaks(t, r, lobes):
    """Peak time and height of each lobe: least-squares parabola through the samples of
    the lobe above 70 % of its largest sample (averages noise; exact for a sampled
    parabola), or the largest sample when fewer than three qualify."""
    tp, ap = [], []
    for lobe in lobes:
        top = lobe[r[lobe] >= 0.7 * r[lobe].max()]
        i = lobe[np.argmax(r[lobe])]
        if len(top) >= 3:
            c = np.polyfit(t[top] - t[i], r[top], 2)
            ts = -c[1] / (2.0 * c[0]) if c[0] < 0.0 else np.inf
            if t[top[0]] - t[i] <= ts <= t[top[-1]] - t[i]:
                tp.append(t[i] + ts)
                ap.append(np.polyval(c, ts))
                continue
        tp.append(t[i])
        ap.append(r[i])
    return np.array(tp), np.array(ap)


@dataclass(frozen=True)
class HalfPower:
    """Result of :func:`half_power`.

    Parameters
    ----------
    zeta : float
        Damping ratio [-].
    omega_n_rad_s : float
        Natural frequency omega_n [rad/s].
    half_power_rad_s : tuple of float
        The half-power frequencies (omega_1, omega_2) [rad/s].
    resolution_rad_s : float
        Frequency resolution of the padded spectrum [rad/s].
    """
    zeta: float
    omega_n_rad_s: float
    half_power_rad_s: tuple
    resolution_rad_s: float


def half_power(t, y, *, force=None, pad_factor=16):
    """Damping ratio by the half-power bandwidth of the frequency response.

    ``y`` is an impulse response (e.g. tip displacement after a short force pulse), or,
    with ``force``, any forced response, from which Y(omega)/F(omega) is formed.

    For a single-DOF displacement response |H| = 1 / |omega_n^2 - omega^2 + 2 i zeta
    omega_n omega| the half-power frequencies omega_1 < omega_2 (|H| = |H|_max / sqrt 2)
    satisfy exactly ``(w2^2 - w1^2) / (w1^2 + w2^2) = tan(2 theta)`` with
    ``zeta = sin(theta)``, and ``omega_n^2 = (w1^2 + w2^2) / (2 (1 - 2 zeta^2))``; ccedi
    uses this exact inversion, not the small-damping ``zeta = (w2 - w1) / (2 omega_n)``.
    The record must be long enough for the response to decay (a few times
    1/(zeta omega_n)), otherwise truncation widens the peak.

    Parameters
    ----------
    t : array_like
        Sample times, 1-D, strictly increasing, finite, at least 8 samples [s].
    y : array_like
        Response at ``t`` (any unit), e.g. tip displacement [m].
        Must be uniformly sampled.
    force : array_like, optional
        Applied force at the same samples [N]. Default None (``y`` is an impulse
        response; its last value is subtracted).
    pad_factor : int, optional
        Zero-padding factor of the FFT, an integer >= 1. Default 16.

    Returns
    -------
    HalfPower
        zeta, omega_n, the half-power frequencies and the resolution.

    Raises
    ------
    InputError
        If the signal is not 1-D finite with at least 8 samples and strictly increasing times; the sampling is not uniform; ``pad_factor`` is not an integer
        >= 1; or the spectrum has no resonance peak with both half-power points
        (over-damped, or too short a record).
    """
    t, y = _validate_signal(t, y)
    dt = np.diff(t)
    if np.ptp(dt) > 1e-6 * dt.mean():
        raise InputError("half_power needs uniformly sampled time (constant time_s step)")
    if int(pad_factor) != pad_factor or pad_factor < 1:
        raise InputError(f"pad_factor must be an integer >= 1, got {pad_factor!r}")
    n = int(pad_factor) * len(t)
    omega = 2.0 * np.pi * np.fft.rfftfreq(n, dt.mean())
    H = np.abs(np.fft.rfft(y - y[-1] if force is None else y, n))
    if force is not None:
        _, f = _validate_signal(t, force)
        F = np.abs(np.fft.rfft(f, n))
        keep = F > 1e-6 * F.max()
        H = np.where(keep, H / np.where(keep, F, 1.0), 0.0)
    k = int(np.argmax(H[1:])) + 1
    level = H[k] / np.sqrt(2.0)
    below = np.flatnonzero(H[:k] < level)
    above = np.flatnonzero(H[k:] < level)
    if k < 2 or len(below) == 0 or len(above) == 0:
        raise InputError("no resonance peak with two half-power points: the response is over-damped "
                         "or the record is too short to resolve it")
    i1 = below[-1]
    i2 = k + above[0]
    w1 = np.interp(level, [H[i1], H[i1 + 1]], [omega[i1], omega[i1 + 1]])
    w2 = np.interp(level, [H[i2], H[i2 - 1]], [omega[i2], omega[i2 - 1]])
    u = (w2**2 - w1**2) / (w1**2 + w2**2)
    zeta = float(np.sin(0.5 * np.arctan(u)))
    omega_n = float(np.sqrt((w1**2 + w2**2) / (2.0 * (1.0 - 2.0 * zeta**2))))
    return HalfPower(zeta=zeta, omega_n_rad_s=omega_n, half_power_rad_s=(float(w1), float(w2)),
                     resolution_rad_s=float(omega[1]))


@dataclass(frozen=True)
class EnvelopeFit:
    """Result of :func:`envelope_fit`.

    Parameters
    ----------
    zeta : float
        Damping ratio sigma / sqrt(sigma^2 + omega_d^2) [-].
    decay_rate_per_s : float
        Decay rate sigma = zeta omega_n [1/s].
    omega_d_rad_s : float
        Damped angular frequency omega_d [rad/s].
    amplitude : float
        Fitted amplitude |A| (units of y).
    window_s : tuple of float
        The fitted window (t_start, t_end) [s].
    rms_residual : float
        RMS residual of the fit (units of y).
    """
    zeta: float
    decay_rate_per_s: float
    omega_d_rad_s: float
    amplitude: float
    window_s: tuple
    rms_residual: float


def envelope_fit(t, y, *, y_final=None, noise_band=0.02):
    """Damping ratio from a least-squares fit of an exponentially decaying sinusoid.

    ::

        y(t) = y_final + A exp(-sigma (t - t0)) cos(omega_d (t - t0) + phi)

    is fitted to the record from its largest excursion (time t0) on: envelope and carrier
    together, so every sample counts, not just the peaks. Start values come from the
    half-cycle spacing (omega_d) and the lobe peaks (sigma);
    ``zeta = sigma / sqrt(sigma^2 + omega_d^2)``.

    Parameters
    ----------
    t : array_like
        Sample times, 1-D, strictly increasing, finite, at least 8 samples [s].
    y : array_like
        Response at ``t`` (any unit), e.g. tip displacement [m].
    y_final : float, optional
        Equilibrium value. Default: the mean of the last 10 % of the samples.
    noise_band : float, optional
        Half-cycles not reaching ``noise_band`` x the largest excursion are ignored
        [-]. Default 0.02.

    Returns
    -------
    EnvelopeFit
        zeta, sigma, omega_d, amplitude, window and residual.

    Raises
    ------
    InputError
        If the signal is not 1-D finite with at least 8 samples and strictly increasing times; the response is constant; fewer than three half-cycles reach the
        noise band (it does not oscillate); or the fitted envelope does not decay.
    """
    t, y = _validate_signal(t, y)
    if y_final is None:
        y_final = float(np.mean(y[int(0.9 * len(y)):]))
    r = y - y_final
    i0 = int(np.argmax(np.abs(r)))
    tw, rw = t[i0:] - t[i0], r[i0:]
    scale = abs(rw[0])
    if scale == 0.0:
        raise InputError("response is constant: nothing to identify")
    peaks = [c[np.argmax(np.abs(rw[c]))] for c, _ in half_cycles(rw, noise_band * scale)]
    peaks = peaks[:_regular_prefix(tw[peaks])]
    if len(peaks) < 3:
        raise InputError("response does not oscillate: fewer than three half-cycles above the noise band; "
                         "an envelope fit needs an under-damped response")
    tp, ap = tw[peaks], np.abs(rw[peaks])
    omega_d0 = np.pi / np.mean(np.diff(tp))
    sigma0 = max(-np.polyfit(tp, np.log(ap), 1)[0], 1e-6 * omega_d0)
    keep = tw <= tp[-1] + np.pi / omega_d0            # drop the tail lost in the noise

    def residual(p):
        A, sigma, wd, phi = p
        return A * np.exp(-sigma * tw[keep]) * np.cos(wd * tw[keep] + phi) - rw[keep]

    fit = least_squares(residual, [rw[0], sigma0, omega_d0, 0.0], x_scale=[scale, sigma0, omega_d0, 1.0],
                        bounds=([-np.inf, 0.0, 0.0, -np.pi], [np.inf, np.inf, np.inf, np.pi]))
    A, sigma, wd, _ = fit.x
    if sigma <= 0.0:
        raise InputError("the envelope does not decay: not a damped free vibration")
    return EnvelopeFit(zeta=float(sigma / np.hypot(sigma, wd)), decay_rate_per_s=float(sigma),
                       omega_d_rad_s=float(wd), amplitude=float(abs(A)),
                       window_s=(float(t[i0]), float(t[i0] + tw[keep][-1])),
                       rms_residual=float(np.sqrt(np.mean(fit.fun**2))))


def oscillates(t, y, *, y_final=0.0, noise_band=1e-6):
    """Whether the response overshoots its final value after its largest excursion.

    True when, after its largest excursion from ``y_final``, the response crosses to the
    other side of ``y_final`` by more than ``noise_band`` x that excursion. This is
    ccedi's definition of "the response oscillates" for the CCEDI critical damping
    search: an over-damped (or critically damped) impulse response approaches its final
    value from one side; an under-damped one overshoots it. For noise-free simulations a
    tiny band (1e-6) resolves damping ratios up to about 0.97; for measured data the band
    must exceed the noise.

    Parameters
    ----------
    t : array_like
        Sample times, 1-D, strictly increasing, finite, at least 8 samples [s].
    y : array_like
        Response at ``t`` (any unit), e.g. tip displacement [m].
    y_final : float, optional
        The final (equilibrium) value. Default 0.
    noise_band : float, optional
        Overshoot threshold relative to the largest excursion [-]. Default 1e-6.

    Returns
    -------
    bool
        True if the response overshoots.

    Raises
    ------
    InputError
        If the signal is not 1-D finite with at least 8 samples and strictly increasing times, or the response never leaves ``y_final``.
    """
    t, y = _validate_signal(t, y)
    r = np.asarray(y) - y_final
    i = int(np.argmax(np.abs(r)))
    peak = r[i]
    if peak == 0.0:
        raise InputError("response never leaves its final value: nothing to judge")
    return bool(np.min(np.sign(peak) * r[i:]) < -noise_band * abs(peak))


def noise_level(y):
    """Standard deviation of white measurement noise on a smooth, finely sampled record.

    From the median absolute deviation of the second difference: for noise of std s,
    y[i+1] - 2 y[i] + y[i-1] has std sqrt(6) s; the median makes the estimate robust to
    the signal's own (sparse, large) curvature::

        s = 1.4826 median(|d2 - median(d2)|) / sqrt(6)

    Parameters
    ----------
    y : array_like
        The record, 1-D, at least 5 samples.

    Returns
    -------
    float
        Noise standard deviation s (units of y).

    Raises
    ------
    InputError
        If ``y`` has fewer than 5 samples.
    """
    y = np.asarray(y, dtype=float)
    if len(y) < 5:
        raise InputError("noise_level needs at least 5 samples")
    d2 = y[2:] - 2.0 * y[1:-1] + y[:-2]
    return float(1.4826 * np.median(np.abs(d2 - np.median(d2))) / np.sqrt(6.0))
