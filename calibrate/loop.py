"""Closing the loop: fit the declared model, read its residual, add the missing effects.

1. Baseline: alpha and E (within tolerance) fitted (:func:`ccedi.calibrate.fit.fit_baseline`).
   Adequacy (:mod:`ccedi.calibrate.adequacy`): the record's own first frequency against the
   declared finger's, E_factor against its bounds, the record's length against the declared
   first period. If the declared finger cannot explain the record, the loop stops here:
   no effect is added to cover a wrong declaration.
2. Residual analysis (:mod:`ccedi.calibrate.residual`): signatures and suggested effects.
3. Every catalogued effect not yet in the model is refitted together with it.
4. Selection: the candidate with the lowest training BIC wins if it lowers BIC by more
   than ``BIC_MARGIN`` and lowers the held-out RMS error; it is added, refitted on the
   whole record, and the search repeats. The search stops when the residual is at the
   noise level (chi-square test: RMS(r)^2 / sigma^2 <= 1 + ``NOISE_Z`` sqrt(2 / n)), when no
   candidate wins, or after ``MAX_EFFECTS`` effects.
"""
from dataclasses import dataclass

import numpy as np

from .adequacy import Adequacy, assess
from .effects import CATALOGUE
from .experiment import Experiment
from .fit import Fit, fit, fit_baseline
from .model import FingerModel
from .residual import analyse, noise_std, suggest

BIC_MARGIN = 10.0
"""Minimum BIC decrease to add an effect ("very strong" evidence on Kass & Raftery's scale)."""
NOISE_Z = 3.0
MAX_EFFECTS = 3


@dataclass(frozen=True)
class Round:
    """One selection round of :func:`calibrate`.

    Parameters
    ----------
    start : Fit
        The model the round started from.
    evidence : dict
        Its residual signatures (:func:`ccedi.calibrate.residual.analyse`).
    suggested : list of (str, str)
        (effect, reason) suggested by the residual (none when the declared model is
        inadequate: its residual points at the declaration, not at an effect).
    candidates : dict
        {effect name: Fit} of every candidate tried (empty when the round stopped first).
    added : str or None
        The effect added, or None when the search stopped.
    reason : str
        Why it was added, or why the search stopped.
    """

    start: Fit
    evidence: dict
    suggested: list
    candidates: dict
    added: str | None
    reason: str


@dataclass(frozen=True)
class Calibration:
    """Result of :func:`calibrate`.

    Parameters
    ----------
    experiment : Experiment
        The calibrated experiment.
    model : FingerModel
        Its calibration model.
    baseline : Fit
        The declared model fitted (E_factor, alpha).
    final : Fit
        The final model with the effects added.
    rounds : list of Round
        The selection rounds, the last one the stop.
    noise_std_m : float
        Noise standard deviation used by the stopping test [m].
    adequacy : Adequacy
        Whether the declared finger can explain the record, with the evidence; when it
        cannot, ``final`` is the baseline.
    """

    experiment: Experiment
    model: FingerModel
    baseline: Fit
    final: Fit
    rounds: list
    noise_std_m: float
    adequacy: Adequacy

    @property
    def noise_floor_nrmse(self):
        """Noise std over the record's range: the NRMSE a perfect model would reach [-]."""
        return self.noise_std_m / float(np.ptp(self.experiment.displacement_m))


def at_noise_level(f: Fit, sigma, n):
    """Whether a fit's residual is explained by noise (chi-square test, module docstring).

    RMS(r)^2 / sigma^2 <= 1 + NOISE_Z sqrt(2 / n).

    Parameters
    ----------
    f : Fit
        The fit (its full-record RMS error is used).
    sigma : float
        Noise standard deviation [m].
    n : int
        Number of samples.

    Returns
    -------
    bool
        True at the noise level.
    """
    return (f.rms_m / sigma) ** 2 <= 1.0 + NOISE_Z * np.sqrt(2.0 / n)


def _candidate_starts(name):
    """Extra starting values for effects whose fit has several local minima."""
    if name == "viscoelastic":
        return ({"prony_tau_s": 0.01}, {"prony_tau_s": 0.3})
    return ()


def calibrate(exp: Experiment, candidates=None, progress=None):
    """Run the calibration loop on an experiment (module docstring).

    Parameters
    ----------
    exp : Experiment
        The validated experiment.
    candidates : iterable of str, optional
        Effect names to consider. Default: the whole catalogue.
    progress : callable, optional
        Called with a one-line message before each candidate fit. Default None.

    Returns
    -------
    Calibration
        Baseline and final fits, the rounds, the noise level and the adequacy of the
        declared model (when it is inadequate, one round that adds nothing).
    """
    model = FingerModel(exp)
    names = list(CATALOGUE) if candidates is None else list(candidates)
    sigma = noise_std(exp)
    n = len(exp.time_s)
    current = baseline = fit_baseline(model)
    adequacy = assess(model, baseline, sigma)
    rounds = []
    while True:
        evidence = analyse(model, current)
        if not adequacy.adequate:
            rounds.append(Round(current, evidence, [], {}, None, adequacy.message() + ": no effect added"))
            break
        suggested = suggest(evidence)
        if at_noise_level(current, sigma, n):
            rounds.append(Round(current, evidence, suggested, {}, None,
                                f"residual at the noise level (RMS {evidence['rms_over_noise']:.3f} sigma)"))
            break
        if len(current.effects) >= MAX_EFFECTS:
            rounds.append(Round(current, evidence, suggested, {}, None, f"{MAX_EFFECTS} effects added: stop"))
            break
        tried = {}
        for name in names:
            if name in current.effects:
                continue
            if progress:
                progress(f"round {len(rounds) + 1}: {'+'.join(current.effects + (name,))}")
            tried[name] = fit(model, current.effects + (name,), start=current.values,
                              extra_starts=_candidate_starts(name))
        better = {k: f for k, f in tried.items() if f.holdout_rms_m < current.holdout_rms_m}
        best = min(better, key=lambda k: better[k].bic, default=None)
        if best is None or better[best].bic > current.bic - BIC_MARGIN:
            gain = "" if best is None else f" (best: {best}, BIC {better[best].bic - current.bic:+.1f})"
            rounds.append(Round(current, evidence, suggested, tried, None,
                                f"no candidate lowers BIC by {BIC_MARGIN:g} and the held-out error{gain}"))
            break
        rounds.append(Round(current, evidence, suggested, tried, best,
                            f"BIC {better[best].bic - current.bic:+.1f}, held-out RMS "
                            f"{current.holdout_rms_m:.3g} -> {better[best].holdout_rms_m:.3g} m"))
        current = tried[best]
    return Calibration(experiment=exp, model=model, baseline=baseline, final=current, rounds=rounds,
                       noise_std_m=sigma, adequacy=adequacy)


def summary(cal: Calibration):
    """The JSON-ready result of a calibration.

    Parameters
    ----------
    cal : Calibration
        The calibration.

    Returns
    -------
    dict
        ``source``, ``model_adequate`` (bool) and ``adequacy`` (its evidence,
        :meth:`ccedi.calibrate.adequacy.Adequacy.summary`), ``baseline`` (nrmse, max
        error [m], parameters, standard errors),
        ``effects_found`` (per effect added: parameters and standard errors as fitted in
        its round and in the final model, error after, why, residual evidence and the
        candidates' scores), ``selected_effect``, final NRMSE, max error [m] and
        parameters, ``noise_floor_nrmse``, ``stop_reason``, ``final_evidence`` and
        ``final_suggestions``.
    """
    found = []
    fin = cal.final
    for r in cal.rounds:
        if r.added is None:
            continue
        f = r.candidates[r.added]
        new = [p for p in f.values if p not in r.start.values]
        found.append({"name": r.added, "params": {p: f.values[p] for p in new},
                      "stderr": {p: f.stderr[p] for p in new}, "nrmse_after": f.nrmse,
                      "params_final": {p: fin.values[p] for p in new},
                      "stderr_final": {p: fin.stderr[p] for p in new},
                      "max_error_after_m": f.max_error_m, "why": r.reason,
                      "suggested_by_residual": dict(r.suggested).get(r.added),
                      "evidence": r.evidence,
                      "candidates": {k: {"delta_bic": c.bic - r.start.bic, "holdout_rms_m": c.holdout_rms_m,
                                         "nrmse": c.nrmse} for k, c in sorted(r.candidates.items(),
                                                                              key=lambda kv: kv[1].bic)}})
    last = cal.rounds[-1]
    b = cal.baseline
    return {"source": cal.experiment.record.source,
            "model_adequate": cal.adequacy.adequate, "adequacy": cal.adequacy.summary(),
            "baseline": {"nrmse": b.nrmse, "max_error_m": b.max_error_m, "params": b.values, "stderr": b.stderr},
            "effects_found": found,
            "selected_effect": found[0]["name"] if found else None,
            "final_nrmse": fin.nrmse, "final_max_error_m": fin.max_error_m, "final_params": fin.values,
            "noise_floor_nrmse": cal.noise_floor_nrmse,
            "stop_reason": last.reason, "final_evidence": last.evidence,
            "final_suggestions": [{"effect": k, "reason": why} for k, why in last.suggested]}
