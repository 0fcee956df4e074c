"""Residual analysis of a fitted model: the signatures that point to a missing effect.

For the record y(t), the model's prediction u(t) and the residual r = y - u [m]:

  rms_over_noise        RMS(r) / sigma (sigma: the sensor noise, given or estimated)
  spectrum_peak_hz      frequency of the largest peak of |FFT(r)| (Hann window) and
  spectrum_peak_mode    the model mode it is nearest to (1-based)
  frequency_shift       first-mode frequency of y (:func:`ccedi.calibrate.adequacy.record_first_mode`;
                        nan when not measurable) over that of the *declared* model, minus 1
  E_factor_at_bound     the fitted E_factor sits on its tolerance bound (stiffness or mass missing)
  decrement_vs_amplitude  change of the per-cycle log decrement across the amplitude range,
                        data minus model, relative to the model's mean decrement (> 0: decay
                        grows with amplitude, drag-like; < 0: friction-like)
  period_vs_amplitude   the same for the period (< 0: faster at large amplitude, stiffening)
  offset_sigma, drift_t mean and slope of r over the last 40 % of the record (where the
                        response has decayed), in standard errors of white noise sigma
  corr_*                correlation coefficient of r with u, u', sign(u'), u^2, u^3, |u'| u'
                        (sensor-side effects show here directly: s_2 u^2, -tau u')

Cycle quantities come from the peaks (rom.damping.log_decrement) of y and u smoothed alike
by a moving average over SMOOTH_S. :func:`suggest` turns the signatures into a ranked list
of candidate effects with the reason for each; the selection itself refits every candidate.
"""
import numpy as np

from ccedi.errors import InputError
from ccedi.rom.damping import log_decrement, noise_level

from .adequacy import record_first_mode
from .fit import Fit, e_factor_bound

SIGNIFICANT_CORRELATION = 0.2
SIGNIFICANT_T = 5.0
SIGNIFICANT_DECREMENT = 0.5
SIGNIFICANT_PERIOD = 0.05
SMOOTH_S = 0.01
LATE = 0.6


def noise_std(exp):
    """Sensor noise standard deviation of an experiment.

    Parameters
    ----------
    exp : Experiment
        The experiment.

    Returns
    -------
    float
        The sidecar's ``sensor.noise_std_m`` (a contact record's ``sensor.noise_std_N``),
        or else the estimate of :func:`ccedi.rom.damping.noise_level` from the record [m]
        ([N] for a contact record).

    Raises
    ------
    InputError
        When estimating from a record of fewer than 5 samples.
    """
    return exp.declared_noise if exp.declared_noise is not None else noise_level(exp.signal)


def _cycle_slopes(t, y, y_final, band):
    """(d decrement / d amplitude [1/m], d period / d amplitude [s/m], mean decrement,
    mean period [s], largest amplitude [m]) over the peaks of y; nans below 4 peaks."""
    try:
        ld = log_decrement(t, y, y_final=y_final, noise_band=band)
    except InputError:
        return (float("nan"),) * 5
    a, tp = np.asarray(ld.peak_amplitudes), np.asarray(ld.peak_times_s)
    if len(a) < 4:
        return (float("nan"),) * 5
    delta, period, mid = np.log(a[:-1] / a[1:]), np.diff(tp), 0.5 * (a[:-1] + a[1:])
    return (float(np.polyfit(mid, delta, 1)[0]), float(np.polyfit(mid, period, 1)[0]), float(delta.mean()),
            float(period.mean()), float(a[0]))


def _corr(r, x):
    x = x - x.mean()
    d = np.sqrt(np.sum(x**2) * np.sum((r - r.mean()) ** 2))
    return float(np.sum((r - r.mean()) * x) / d) if d > 0 else 0.0


def analyse(model, fitted: Fit):
    """The residual signatures of a fitted model (module docstring), as a flat dict.

    Parameters
    ----------
    model : FingerModel
        The experiment's calibration model.
    fitted : Fit
        The fit whose residual is analysed.

    Returns
    -------
    dict
        ``rms_over_noise`` [-], ``noise_std_m`` [m], ``spectrum_peak_hz`` [Hz],
        ``spectrum_peak_mode`` (1-based), ``mode_frequencies_hz`` (first three) [Hz],
        ``frequency_shift`` [-], ``E_factor`` [-], ``E_factor_at_bound`` (bool),
        ``decrement_vs_amplitude`` and ``period_vs_amplitude`` [-] (nan when too few
        peaks), ``offset_sigma`` and ``drift_t`` [-], and the correlations ``corr_u``,
        ``corr_velocity``, ``corr_sign_velocity``, ``corr_u2``, ``corr_u3``,
        ``corr_velocity_abs_velocity`` [-].
    """
    exp = model.exp
    t, y, u = exp.time_s, exp.displacement_m, fitted.prediction
    r = y - u
    sigma = noise_std(exp)
    free = t >= exp.start_s + exp.duration_s
    spec = np.abs(np.fft.rfft(r * np.hanning(len(r))))
    freqs = np.fft.rfftfreq(len(r), d=float(np.median(np.diff(t))))
    peak_hz = float(freqs[1 + np.argmax(spec[1:])])
    mode_hz = model.modes(fitted.values).omega_rad_s / (2.0 * np.pi)
    nearest = int(np.argmin(np.abs(np.log(max(peak_hz, 1e-9) / mode_hz))))
    declared_hz = model.scales.omega1 / (2.0 * np.pi)
    own = record_first_mode(exp, sigma)
    own_hz = own.frequency_hz if own.measurable else float("nan")
    tol = exp.E_tolerance
    E = fitted.values["E_factor"]
    width = max(1, int(round(SMOOTH_S / float(np.median(np.diff(t))))))
    smooth = lambda x: np.convolve(x, np.ones(width) / width, mode="same")
    y_final = float(np.mean(u[-len(u) // 10:]))
    band = min(0.5, 10.0 * sigma / np.sqrt(width) / max(float(np.max(np.abs(y - y_final))), 1e-300))
    sd = _cycle_slopes(t[free], smooth(y)[free], y_final, band)
    sm = _cycle_slopes(t[free], smooth(u)[free], y_final, band)
    late = t >= t[0] + LATE * (t[-1] - t[0])
    tl, rl = t[late] - t[late].mean(), r[late]
    drift = float(np.sum(tl * rl) / np.sum(tl**2))
    v = np.gradient(u, t)
    return {"rms_over_noise": float(np.sqrt(np.mean(r**2)) / sigma), "noise_std_m": float(sigma),
            "spectrum_peak_hz": peak_hz, "spectrum_peak_mode": nearest + 1, "mode_frequencies_hz": mode_hz[:3].tolist(),
            "frequency_shift": own_hz / declared_hz - 1.0, "E_factor": E,
            "E_factor_at_bound": bool(e_factor_bound(E, tol)),
            "decrement_vs_amplitude": (sd[0] - sm[0]) * sm[4] / sm[2],
            "period_vs_amplitude": (sd[1] - sm[1]) * sm[4] / sm[3],
            "offset_sigma": float(rl.mean() / (sigma / np.sqrt(len(rl)))),
            "drift_t": drift / (sigma / np.sqrt(np.sum(tl**2))),
            "corr_u": _corr(r, u), "corr_velocity": _corr(r, v), "corr_sign_velocity": _corr(r, np.sign(v)),
            "corr_u2": _corr(r, u**2), "corr_u3": _corr(r, u**3), "corr_velocity_abs_velocity": _corr(r, np.abs(v) * v)}


def suggest(ev):
    """Candidate effects suggested by residual signatures, strongest first.

    Parameters
    ----------
    ev : dict
        Signatures from :func:`analyse`.

    Returns
    -------
    list of (str, str)
        (effect name, reason), each effect once, ranked by the strength of its signature.
    """
    out = []
    if abs(ev["offset_sigma"]) > SIGNIFICANT_T:
        out.append((abs(ev["offset_sigma"]), "gravity", f"static offset {ev['offset_sigma']:.1f} standard errors"))
    if abs(ev["drift_t"]) > SIGNIFICANT_T:
        out.append((abs(ev["drift_t"]), "sensor_offset_drift", f"slow drift, t = {ev['drift_t']:.1f}"))
    if ev["E_factor_at_bound"]:
        for name in ("tip_mass", "root_compliance"):
            out.append((20.0, name, f"E_factor {ev['E_factor']:.3f} on its tolerance bound; first-mode frequency "
                                    f"{ev['frequency_shift']:+.1%} from the declared finger"))
    dec, per = ev["decrement_vs_amplitude"], ev["period_vs_amplitude"]
    if np.isfinite(dec) and abs(dec) > SIGNIFICANT_DECREMENT:
        name = "quadratic_damping" if dec > 0 else "coulomb_friction"
        out.append((10.0 * abs(dec), name, f"log decrement changes by {dec:+.0%} across the amplitude range "
                                           f"(against the model)"))
    if np.isfinite(per) and abs(per) > SIGNIFICANT_PERIOD:
        out.append((100.0 * abs(per), "geometric_nonlinearity", f"period changes by {per:+.1%} across the amplitude "
                                                              f"range (against the model)"))
    for key, name in (("corr_u2", "sensor_nonlinearity"), ("corr_velocity", "time_delay")):
        if abs(ev[key]) > SIGNIFICANT_CORRELATION:
            out.append((10.0 * abs(ev[key]), name, f"residual correlation with {key[5:]} = {ev[key]:+.2f}"))
    if ev["spectrum_peak_mode"] >= 2:
        for name in ("stiffness_damping", "viscoelastic"):
            out.append((5.0, name, f"residual spectrum peaks at {ev['spectrum_peak_hz']:.1f} Hz, near mode "
                                   f"{ev['spectrum_peak_mode']}"))
    seen, ranked = set(), []
    for _, name, reason in sorted(out, key=lambda x: -x[0]):
        if name not in seen:
            seen.add(name)
            ranked.append((name, reason))
    return ranked
