"""Report of a calibration: figures of the fit and of the residual before and after, the
residual time series as CSV, and a markdown summary of the evidence.

Files: ``fit.png`` (record, baseline and final model [mm] against time [s]),
``residual.png`` (residual [mm] against time [s], and its amplitude spectrum [mm] against
frequency [Hz], before and after), ``residuals.csv`` (time_s, tip_displacement_m,
baseline_m, final_m) and ``report.md`` (first the result: the calibrated finger, the effects
found with their values or why none was, the error before and after, and the contact
prediction when there is one; then the evidence: the model's adequacy, the damping kind,
and every round's candidates with their scores, posterior probabilities and why each was
or was not selected). A contact record's figures and columns are its reaction force [N]
instead (``reaction_force_N``, ``baseline_N``, ``final_N``). With a contact prediction
(``ccedi calibrate --predict-contact``), ``report.md`` gets the table "Prediction of the
contact record" and ``prediction.png`` shows the predicted filtered reading [N] against
time [s], with the record's when there is one.
"""
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the file-only backend)
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from ccedi.calibrate.loop import Calibration  # noqa: E402
from ccedi.calibrate.prediction import FEATURE_NAMES, FEATURES, filtered_reading  # noqa: E402
from ccedi.outputs import write_csv, write_figure, write_text  # noqa: E402

SIGNALS = {"impulse": ("tip displacement", "tip_displacement_m", "m", 1e3, "mm"),
           "contact": ("reaction force", "reaction_force_N", "N", 1.0, "N")}
"""Per record kind: signal name, CSV column, SI unit, plot scale and plot unit."""


def _figures(cal: Calibration):
    name_, _, _, k, unit = SIGNALS[cal.experiment.kind]
    t = cal.experiment.time_s
    y = cal.experiment.signal
    base, final = cal.baseline.prediction, cal.final.prediction
    label = "+".join(cal.final.effects) or "baseline"
    fit_fig, ax = plt.subplots(figsize=(7.5, 4.0))
    ax.plot(t, k * y, ".", ms=2, color="0.6", label="record")
    ax.plot(t, k * base, "-", lw=1.0, label=f"baseline (NRMSE {cal.baseline.nrmse:.2%})")
    ax.plot(t, k * final, "--", lw=1.0, label=f"{label} (NRMSE {cal.final.nrmse:.2%})")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"{name_} [{unit}]")
    ax.legend(fontsize=8)
    fit_fig.tight_layout()
    res_fig, (a1, a2) = plt.subplots(2, 1, figsize=(7.5, 6.0))
    dt = float(np.median(np.diff(t)))
    f = np.fft.rfftfreq(len(t), d=dt)
    for pred, name in ((base, "baseline"), (final, label)):
        r = y - pred
        a1.plot(t, k * r, lw=0.6, label=f"{name}: RMS {k * np.sqrt(np.mean(r**2)):.3g} {unit}")
        a2.semilogy(f, k * 2.0 * np.abs(np.fft.rfft(r)) / len(r), lw=0.6, label=name)
    a1.axhline(k * cal.noise_std_m, color="k", lw=0.5, ls=":", label="noise std")
    a1.axhline(-k * cal.noise_std_m, color="k", lw=0.5, ls=":")
    a1.set_xlabel("time [s]")
    a1.set_ylabel(f"residual [{unit}]")
    a1.legend(fontsize=8)
    a2.set_xlabel("frequency [Hz]")
    a2.set_ylabel(f"residual amplitude [{unit}]")
    a2.set_xlim(0.0, min(f[-1], 100.0))
    a2.legend(fontsize=8)
    res_fig.tight_layout()
    return fit_fig, res_fig


def _adequacy_rows(a):
    """The adequacy evidence table rows of an impulse or a contact record."""
    rows = [f"| baseline E factor [-] (bounds) | {a['E_factor']:.4g} ({a['E_factor_bounds'][0]:g}.."
            f"{a['E_factor_bounds'][1]:g}) |"]
    if "peak_over_noise" in a:
        return rows + [f"| record peak over the noise std [-] | {a['peak_over_noise']:.4g} |"]
    own = a["record_first_frequency_hz"]
    return [f"| record's first-mode frequency [Hz] | {'not measurable' if own is None else f'{own:.4g}'} |",
            f"| declared finger's first frequency [Hz] | {a['declared_first_frequency_hz']:.4g} |",
            f"| allowed band [Hz] | {a['allowed_band_hz'][0]:.4g}..{a['allowed_band_hz'][1]:.4g} |",
            *rows,
            f"| declared first periods covered [-] | {a['periods_covered']:.3g} (at least {a['min_periods']:g}) |"]


def _candidate_lines(rounds, unit):
    """Every round's candidates, accepted or not: fitted parameters, scores, why each was or
    was not selected, and how much of each added parameter's signature the others cannot mimic."""
    lines = []
    for k, r in enumerate(rounds, start=1):
        before = " + ".join(["baseline"] + r["effects_before"])
        start = r.get("posterior_of_start")
        lines += [f"## Candidates of round {k} (on {before}; added: {r['added'] or 'none'})", "",
                  f"Posterior probability of {before} itself: {start:.3g}." if start is not None else "", "",
                  f"| candidate | fitted | posterior [-] | delta ln Z [-] | held-out RMS [{unit}] | NRMSE [-] "
                  "| excess explained [-] | verdict | share not mimicked [-] | mimicked by (correlation) |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for name, c in r["candidates"].items():
            fitted = ", ".join(f"{p} = {v:.4g} +- {c['stderr'][p]:.2g}" for p, v in c["params"].items())
            shares = ", ".join(f"{c['unique_share'][p]:.2f}" for p in c["params"])
            mimics = "; ".join(f"{q} ({corr:+.2f})" for p in c["params"] for q, corr in c["mimicked_by"][p]) or "-"
            lines.append(f"| {name} | {fitted} | {c['posterior']:.3g} | {c['delta_log_evidence']:+.1f} | "
                         f"{c['holdout_rms_m']:.4g} | {c['nrmse']:.4%} | {c['explained']:.0%} | {c['verdict']} | "
                         f"{shares} | {mimics} |")
        lines.append("")
    return lines


def _result_lines(summary, unit):
    """What the calibration concluded, first: the calibrated finger, the effects found with
    their values, or why none was, and the error against the noise floor."""
    fin = summary["final_params"]
    cal = summary["calibrated"]
    lines = ["## Result", "",
             f"Calibrated finger: alpha = {cal['alpha_per_s']:.5g} 1/s +- {summary['final_stderr']['alpha_per_s']:.2g}, "
             f"E = {cal['E_Pa']:.5g} Pa (declared x {fin['E_factor']:.4f} +- {summary['final_stderr']['E_factor']:.2g})."]
    if summary["effects_found"]:
        for e in summary["effects_found"]:
            lines.append(f"- {e['name']}: " + ", ".join(f"{k} = {v:.5g} +- {e['stderr_final'][k]:.2g}"
                                                          for k, v in e["params_final"].items())
                         + f" (selected: {e['why']})")
    elif summary.get("ambiguous"):
        a = summary["ambiguous"]
        lines.append(f"- ambiguous, neither added: {' or '.join(a['effects'])} ({a['why']}); separate them by "
                     f"{a['separating_measurement']['measurement']}.")
    else:
        lines.append(f"- no effect added: {summary['stop_reason']}.")
    if summary.get("rejected_effects"):
        r = summary["rejected_effects"]
        lines.append(f"- not accepted: {'+'.join(r['effects'])} leave the residual at {r['rms_over_noise']:.3f} sigma "
                     "(the nearest catalogued stand-ins, not the missing physics).")
    lines += ["", f"Error: NRMSE {summary['baseline']['nrmse']:.4%} (baseline) -> {summary['final_nrmse']:.4%} "
              f"(final), noise floor {summary['noise_floor_nrmse']:.4%}; final max error "
              f"{summary['final_max_error_m']:.4g} {unit}.", ""]
    return lines


def _prediction_lines(p):
    """The table "Prediction of the contact record" of a prediction's summary."""
    lines = ["## Prediction of the contact record", "",
             f"{p['contact_source']} predicted from this record's E x {p['E_factor']:.4f} (of the contact sidecar's E, "
             f"+- {p['stderr_E_factor']:.2g}) and alpha {p['alpha_per_s']:.4g} +- {p['stderr_alpha_per_s']:.2g} 1/s "
             f"(correlation {p['correlation']:+.2f}); intervals {p['interval_probability']:.0%}, from the parameters' "
             f"covariance, the chain's error against the full FEA and the record's noise "
             f"({p['noise_std_N']:.3g} N std).", "",
             *([f"The standard errors include the shift of E and alpha from the baseline fit to the final one "
                f"(E x {p['selection_shift_E_factor']:+.4f}, alpha {p['selection_shift_alpha_per_s']:+.4g} 1/s): the "
                f"effects selected ({', '.join(p['impulse_effects_not_carried'])}) are not in the contact chain.", ""]
               if p["impulse_effects_not_carried"] else []),
             "Features: " + "; ".join(f"{k}: {v}" for k, v in p["definitions"].items()) + ".", "",
             "| feature | predicted | interval | measured | inside |", "|---|---|---|---|---|"]
    for name, f in p["features"].items():
        u = FEATURES[name]
        lo, hi = f[f"interval_{u}"]
        measured = "-" if f[f"measured_{u}"] is None else f"{f[f'measured_{u}']:.4g}"
        inside = "-" if f["inside"] is None else ("yes" if f["inside"] else "**no**")
        lines.append(f"| {FEATURE_NAMES[name]} [{u}] | {f[f'predicted_{u}']:.4g} | {lo:.4g}..{hi:.4g} | {measured} | "
                     f"{inside} |")
    return lines + [""]


def _prediction_figure(prediction):
    """Predicted filtered reading against the record's (when there is one)."""
    t = prediction.contact.time_s
    fig, ax = plt.subplots(figsize=(7.5, 4.0))
    if prediction.recorded:
        y = prediction.contact.signal
        ax.plot(t, y, ".", ms=2, color="0.7", label="record")
        ax.plot(t, filtered_reading(t, y), "-", lw=1.0, color="k", label="record, filtered")
    f = prediction.features
    ax.plot(t, filtered_reading(t, prediction.reading_N), "--", lw=1.2, color="C3", label="predicted, filtered")
    for name in ("contact_start_s", "contact_end_s"):
        ax.axvspan(*f[name].interval, color="C3", alpha=0.2, lw=0)
    lo, hi = f["filtered_peak_force_N"].interval
    ax.axhspan(lo, hi, color="C3", alpha=0.2, lw=0, label="predicted intervals")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("reaction force [N]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def _markdown(summary):
    b = summary["baseline"]
    a = summary["adequacy"]
    unit = SIGNALS[summary.get("kind", "impulse")][2]
    lines = [f"# Calibration of {summary['source']}", "", *_result_lines(summary, unit),
             *(_prediction_lines(summary["prediction"]) if summary.get("prediction") else []),
             "## Evidence", "",
             f"Model adequacy: {a['message']}.", "",
             "| evidence | value |", "|---|---|", *_adequacy_rows(a),
             "", f"Noise floor NRMSE {summary['noise_floor_nrmse']:.4%}.", "",
             f"| model | NRMSE [-] | max error [{unit}] |", "|---|---|---|"]
    if summary.get("chain_baseline"):
        lines.append(f"| baseline, chain alone | {summary['chain_baseline']['nrmse']:.4%} | |")
    lines.append(f"| baseline | {b['nrmse']:.4%} | {b['max_error_m']:.4g} |")
    for e in summary["effects_found"]:
        lines.append(f"| + {e['name']} | {e['nrmse_after']:.4%} | {e['max_error_after_m']:.4g} |")
    lines += ["", "Baseline parameters: " + ", ".join(f"{k} = {v:.5g} +- {b['stderr'][k]:.2g}"
                                                     for k, v in b["params"].items()), ""]
    kind = summary.get("damping_kind")
    if kind:
        other = "relative" if kind["declared"] == "global" else "global"
        lines += [f"Damping kind: the record supports **{kind['supported']}** damping (declared {kind['declared']}; "
                  f"baseline NRMSE {kind[kind['declared']]['nrmse']:.4%} at alpha "
                  f"{kind[kind['declared']]['alpha_per_s']:.4g} 1/s, posterior probability "
                  f"{kind[kind['declared']]['posterior']:.3g}; with {other} damping "
                  f"{kind[other]['nrmse']:.4%} at {kind[other]['alpha_per_s']:.4g} 1/s, "
                  f"{kind[other]['posterior']:.3g}); calibrated with **{kind['used']}** damping.", ""]
    lines += [f"Stop: {summary['stop_reason']}.", ""]
    lines += _candidate_lines(summary.get("rounds", []), unit)
    f = summary.get("fea_check")
    if f:
        lines += [f"The chain carried the smooth part of its discrepancy from one full FEA run at the baseline "
                  f"(RMS {f['correction_rms_N']:.4g} N); the rest, {f['rough_error_N']:.4g} N RMS, was its model error. "
                  f"The full FEA run of the last correction (of {f['fea_runs']}), at "
                  f"{', '.join(f'{k} = {v:.5g}' for k, v in f['run_at'].items())}: NRMSE {f['nrmse']:.4%}, "
                  f"{f['rms_over_noise']:.3f} x the noise std, peak {f['peak_error']:+.2%}.", ""]
    return "\n".join(lines)


def write_report(out_dir, cal: Calibration, summary, *, prediction=None):
    """Write the calibration report files (module docstring) into ``out_dir``.

    Parameters
    ----------
    out_dir : str or pathlib.Path
        Output directory (created if missing).
    cal : Calibration
        The calibration result (figures and residual series).
    summary : dict
        Its JSON summary (:func:`ccedi.calibrate.loop.summary`), for ``report.md``, with
        the ``prediction`` block when there is one.
    prediction : ccedi.calibrate.prediction.ContactPrediction, optional
        A contact prediction from this calibration: ``prediction.png``. Default None.

    Returns
    -------
    list of pathlib.Path
        The paths of ``fit.png``, ``residual.png``, ``residuals.csv``, ``report.md`` and,
        with a prediction, ``prediction.png``.
    """
    out = Path(out_dir)
    fit_fig, res_fig = _figures(cal)
    md = _markdown(summary)
    _, column, unit, _, _ = SIGNALS[cal.experiment.kind]
    frame = pd.DataFrame({"time_s": cal.experiment.time_s, column: cal.experiment.signal,
                          f"baseline_{unit}": cal.baseline.prediction, f"final_{unit}": cal.final.prediction})
    paths = [write_figure(out / "fit.png", fit_fig), write_figure(out / "residual.png", res_fig),
             write_csv(out / "residuals.csv", frame), write_text(out / "report.md", md)]
    if prediction is not None:
        paths.append(write_figure(out / "prediction.png", _prediction_figure(prediction)))
    return paths
