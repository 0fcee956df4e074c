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

from fea.errors import InputError


@dataclass(frozen=True)
class LogDecrement:
    """Result of :func:`log_decrement`.

    zeta : damping ratio [-]; delta : logarithmic decrement per cycle [-];
    zeta_ci95 : (low, high) 95 % confidence interval of zeta (nan when only 2 peaks);
    n_cycles : number of cycles used (peaks - 1); period_s : mean damped period [s];
    omega_d_rad_s : damped angular frequency 2 pi / period [rad/s];
    peak_times_s, peak_amplitudes : the peaks used (amplitudes in the units of y).
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


def log_decrement(t, y, y_final=None, noise_band=0.01, max_cycles=None):
    """Damping ratio of the dominant mode of a decaying oscillation by log-decrement.

    t : sample times [s]; y : response (any unit), e.g. tip displacement [m].
    y_final : equilibrium value the response decays to (default: mean of the last 10 %).
    noise_band : peaks smaller than ``noise_band`` x the largest excursion are ignored [-].
    max_cycles : use at most this many cycles after the first peak (default: all).

    Raises InputError when fewer than two peaks rise above the noise band: the response
    does not oscillate (over-damped) and a log-decrement would be meaningless.
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
    # one peak per lobe (stretch between zero crossings of r) on the side of the largest
    # excursion, so higher-mode ripples cannot add spurious peaks
    sign = 1.0 if r[np.argmax(np.abs(r))] > 0 else -1.0
    lobes = _lobe_peaks(sign * r, noise_band * scale)
    if lobes:                                                     # start at the largest peak
        lobes = lobes[int(np.argmax([np.max(sign * r[lobe]) for lobe in lobes])):]
    if max_cycles is not None:
        lobes = lobes[:int(max_cycles) + 1]
    if len(lobes) < 2:
        raise InputError("response does not oscillate: fewer than two peaks above the noise band "
                         f"({noise_band:g} x max excursion); log-decrement needs an under-damped response")
    tp, ap = _refine_peaks(t, sign * r, lobes)
    k = np.arange(len(ap))
    slope, intercept = np.polyfit(k, np.log(ap), 1)
    delta = -slope
    if delta <= 0.0:
        raise InputError("peak amplitudes do not decay: the response is not a damped free vibration")
    ci = (np.nan, np.nan)
    if len(ap) > 2:
        resid = np.log(ap) - (intercept + slope * k)
        se = np.sqrt(np.sum(resid**2) / (len(k) - 2) / np.sum((k - k.mean())**2))
        half = stats.t.ppf(0.975, len(k) - 2) * se
        ci = (float(_zeta(max(delta - half, 0.0))), float(_zeta(delta + half)))
    period = float(np.mean(np.diff(tp)))
    return LogDecrement(zeta=float(_zeta(delta)), delta=float(delta), zeta_ci95=ci, n_cycles=len(ap) - 1,
                        period_s=period, omega_d_rad_s=2.0 * np.pi / period,
                        peak_times_s=tp, peak_amplitudes=ap)


def _lobe_peaks(r, height):
    """Lobes of r (stretches between sign changes) whose maximum exceeds ``height``:
    a list of index arrays, one per positive lobe."""
    crossings = np.flatnonzero(np.signbit(r[1:]) != np.signbit(r[:-1])) + 1
    bounds = np.concatenate([[0], crossings, [len(r)]])
    return [np.arange(lo, hi) for lo, hi in zip(bounds[:-1], bounds[1:])
            if r[lo] > 0.0 and r[lo:hi].max() > height]


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
