"""Residual analysis of a fitted model: the signatures that point to a missing effect.

For the record y(t), the model's prediction u(t) and the residual r = y - u [m]:

  rms_over_noise        RMS(r) / sigma (sigma: the sensor noise, given or estimated)
  spectrum_peak_hz      frequency of the largest peak of |FFT(r)| (Hann window) and
  spectrum_peak_mode    the model mode it is nearest to (1-based), with its frequency [Hz]
  frequency_shift       dominant frequency of y over that of u, minus 1 (after the pulse)
  E_factor_at_bound     the fitted E_factor sits on its tolerance bound (stiffness or mass missing)
  decrement_vs_amplitude  slope of the per-cycle log decrement of y against the cycle
                        amplitude, relative to that of u, in decrement per metre (> 0: decay
                        grows with amplitude, drag-like; < 0: friction-like)
  offset_sigma          mean of r over the last quarter in standard errors sigma / sqrt(n)
  drift_t               t-statistic of the slope of a straight line through r(t)
  corr_*                correlation coefficient of r with u, u' , sign(u'), u^2, u^3, |u'| u'

:func:`suggest` turns these into a ranked list of candidate effects with the reason for each.
"""
import numpy as np

from fea.errors import InputError
from rom.damping import log_decrement, noise_level

from .fit import Fit
from .model import FingerModel

SIGNIFICANT_CORRELATION = 0.1
SIGNIFICANT_T = 4.0


def noise_std(exp):
    """Sensor noise std [m]: the sidecar's, or estimated from the record (rom.damping.noise_level)."""
    return exp.noise_std_m if exp.noise_std_m is not None else noise_level(exp.displacement_m)


def _dominant_frequency_hz(t, y):
    spec = np.abs(np.fft.rfft((y - y.mean()) * np.hanning(len(y)), n=16 * len(y)))
    f = np.fft.rfftfreq(16 * len(y), d=float(np.median(np.diff(t))))
    return float(f[1 + np.argmax(spec[1:])])


def _decrement_slope(t, y, y_final, band):
    """Slope [1/m] of the per-cycle log decrement against amplitude (nan if < 4 peaks)."""
    try:
        ld = log_decrement(t, y, y_final=y_final, noise_band=band)
    except InputError:
        return float("nan")
    a = np.asarray(ld.peak_amplitudes)
    if len(a) < 4:
        return float("nan")
    delta = np.log(a[:-1] / a[1:])
    mid = 0.5 * (a[:-1] + a[1:])
    return float(np.polyfit(mid, delta, 1)[0])


def _corr(r, x):
    x = x - x.mean()
    d = np.sqrt(np.sum(x**2) * np.sum((r - r.mean()) ** 2))
    return float(np.sum((r - r.mean()) * x) / d) if d > 0 else 0.0


def analyse(model: FingerModel, fitted: Fit):
    """The residual signatures of ``fitted`` (module docstring) as a flat dict."""
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
    f_data, f_model = _dominant_frequency_hz(t[free], y[free]), _dominant_frequency_hz(t[free], u[free])
    tol = exp.E_tolerance
    E = fitted.values["E_factor"]
    y_final = float(np.mean(u[-len(u) // 10:]))
    band = min(0.5, 5.0 * sigma / max(float(np.max(np.abs(y - y_final))), 1e-300))
    slope = (_decrement_slope(t[free], y[free], y_final, band) - _decrement_slope(t[free], u[free], y_final, band))
    last = r[-len(r) // 4:]
    tc = t - t.mean()
    drift = float(np.sum(tc * r) / np.sum(tc**2))
    drift_se = sigma / np.sqrt(np.sum(tc**2))
    v = np.gradient(u, t)
    return {"rms_over_noise": float(np.sqrt(np.mean(r**2)) / sigma), "noise_std_m": float(sigma),
            "spectrum_peak_hz": peak_hz, "spectrum_peak_mode": nearest + 1, "mode_frequencies_hz": mode_hz[:3].tolist(),
            "frequency_shift": f_data / f_model - 1.0, "E_factor": E,
            "E_factor_at_bound": bool(min(E - (1 - tol), (1 + tol) - E) < 0.01 * max(tol, 1e-3)),
            "decrement_vs_amplitude_per_m": slope,
            "offset_sigma": float(last.mean() / (sigma / np.sqrt(len(last)))), "drift_t": drift / drift_se,
            "corr_u": _corr(r, u), "corr_velocity": _corr(r, v), "corr_sign_velocity": _corr(r, np.sign(v)),
            "corr_u2": _corr(r, u**2), "corr_u3": _corr(r, u**3), "corr_velocity_abs_velocity": _corr(r, np.abs(v) * v)}


def suggest(ev):
    """[(effect name, reason)] suggested by the signatures ``ev`` of :func:`analyse`, strongest first."""
    out = []
    if abs(ev["offset_sigma"]) > SIGNIFICANT_T:
        out.append((abs(ev["offset_sigma"]), "gravity", f"static offset {ev['offset_sigma']:.1f} standard errors"))
    if abs(ev["drift_t"]) > SIGNIFICANT_T:
        out.append((abs(ev["drift_t"]), "sensor_offset_drift", f"slow drift, t = {ev['drift_t']:.1f}"))
    if ev["E_factor_at_bound"]:
        for name in ("tip_mass", "root_compliance"):
            out.append((10.0, name, f"E_factor {ev['E_factor']:.3f} on its tolerance bound; frequency shift "
                                    f"{ev['frequency_shift']:+.2%}"))
    slope = ev["decrement_vs_amplitude_per_m"]
    if np.isfinite(slope) and abs(slope) > 0.0:
        name = "quadratic_damping" if slope > 0 else "coulomb_friction"
        out.append((abs(slope), name, f"log decrement vs amplitude {slope:+.3g} per m against the model"))
    for key, name in (("corr_u2", "sensor_nonlinearity"), ("corr_u3", "geometric_nonlinearity"),
                      ("corr_sign_velocity", "coulomb_friction"), ("corr_velocity_abs_velocity", "quadratic_damping"),
                      ("corr_velocity", "time_delay")):
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
