"""Closing the loop: fit the declared model, read its residual, add the missing effects.

The model is the declared finger's modal model for an impulse record
(:class:`ccedi.calibrate.model.FingerModel`, catalogue :data:`ccedi.calibrate.effects.CATALOGUE`)
and the declared finger on the declared drum, read through the force transducer, for a
contact record (:class:`ccedi.calibrate.contact_model.DrumContactModel`, catalogue
:data:`ccedi.calibrate.effects.CONTACT_CATALOGUE`); the loop is the same, through the
models' common methods (``parameters``, ``predict``, ``baseline_starts``, ``assess``,
``analyse``, ``suggest``, ``observables``, ``measurements``, ``unexplained_term``,
``calibrated``, ``correct_at``).

1. Baseline: alpha and E (within tolerance) fitted (:func:`ccedi.calibrate.fit.fit_baseline`).
   Adequacy (:mod:`ccedi.calibrate.adequacy`): the record's own first frequency against the
   declared finger's, E_factor against its bounds, the record's length against the declared
   first period. If the declared finger cannot explain the record, the loop stops here:
   no effect is added to cover a wrong declaration. A contact record whose only failed
   check is the force level (E on its bound) is the exception: a faster drum or an object
   moved in changes the force level too, so the catalogue is tried, and the declaration is
   refused only when no accepted effect brings E within its tolerance
   (``ContactAdequacy.resolved_by``). For a contact record the damping
   kind is a structural choice made from the record (:func:`damping_kind_support`): the
   baseline is fitted with global and with relative mass damping, and when the other kind
   than the declared reaches posterior probability ``SELECT_PROBABILITY`` the loop goes on
   with it (the contact start and rise follow the finger's lag, which the kinds set
   differently). A reduced base model is then corrected
   by its full model at the baseline point and refitted (``model.correct_at``: for a contact
   record one full explicit FE run on the drum; the chain carries the smooth part of its
   discrepancy from it, and the rough rest, measured on this record's set-up, becomes the
   model error of the tests below). When the search has added effects that move the model
   away from that point, the full model is run again at the selected model, the chain
   re-corrected there and the selected model refitted before the stopping test of step 6.
   At the end the full model's run of the last correction is compared with the record
   (``model.fea_check``).
2. Residual analysis (:mod:`ccedi.calibrate.residual`): signatures and suggested effects.
3. Every catalogued effect not yet in the model is refitted together with it, from the
   current values and the model's starting values for it (``candidate_starts``: e.g. a
   contact record's timing offset from its contact start and end errors); when those
   starts end worse than the current model, the fit restarts from the current model with
   the effect where it vanishes (``parent`` of :func:`ccedi.calibrate.fit.fit`), so that a
   candidate never scores worse than the model it extends for want of a start. All of a
   round's fits are made and scored under one noise model, the autoregressive noise of
   the current model's residual (:func:`ccedi.calibrate.fit.under_own_noise`,
   :mod:`ccedi.calibrate.likelihood`: the friction chatter of a contact record is
   correlated over a few samples, and a white-noise score lets an effect that follows it
   gain tens of BIC), the current model refitted under it. Every candidate is reported
   with its fitted parameters, scores, posterior probability and how identifiable its
   parameters are (:func:`candidates_summary`), accepted or not.
4. Selection on evidence: the current model and every candidate are compared by their log
   evidence (Laplace's approximation, uniform priors over the parameters' bounds) as
   posterior probabilities with equal priors (:func:`posterior_probabilities`). The most
   probable candidate is added when its probability reaches ``SELECT_PROBABILITY`` and it
   explains at least ``EXPLAINED_FRACTION`` of the excess of the chi-square of the
   current model's standardised innovations over 1 (:func:`excess_explained`; the noise
   model carries the sensor noise and the base model's own error, ``model.model_error``
   or its discrepancy: zero for the impulse model, the contact chain's error against the
   full FEA for a contact record): an effect that leaves most of the misfit is not what
   is missing. The search repeats; it stops when the residual is at the noise level
   (:func:`at_noise_level`: chi^2 <= 1 + ``NOISE_Z`` sqrt(2 / m)), when no candidate is selected, or
   after ``MAX_EFFECTS`` effects.
5. Ambiguity: when the two most probable candidates both explain the excess and reach
   ``SELECT_PROBABILITY`` only together, or the best reaches it alone but the two fitted
   together have parameters correlated beyond ``AMBIGUITY_CORRELATION`` (the data cannot
   split the misfit between them; tried when twice their log-evidence difference is below
   ``AMBIGUITY_JOINT_BIC``), neither is selected: both fits are reported with the
   measurement that would separate them (:func:`separating_measurement`), and the search
   stops. The final model is then the more probable one, provisionally (its E and alpha
   are what the record supports either way), but ``effects_found`` does not list it.
6. No nearest effect: when the search stops (no candidate selected, an ambiguity, or
   ``MAX_EFFECTS`` added) with effects added but the residual not at the noise level, the
   catalogue has not explained the record: each effect may only be the nearest stand-in
   for physics it lacks (on the bundled magnet record, cubic stiffening and
   viscoelasticity share the posterior and leave 1.59 sigma; an earlier search added
   cubic stiffening, then viscoelasticity, then root compliance, each removing 65-83 % of
   what was left, with E drifting 13 %). The effects are then not accepted: the final
   model is the baseline, and the chain is reported as ``rejected``.
7. Beyond the catalogue: when the search stops with the residual's RMS more than
   ``UNEXPLAINED_EXCESS`` above the noise, the result is flagged ``unexplained_residual``,
   with the best sparse force term found on the residual (:mod:`ccedi.calibrate.sparse`).
"""
from dataclasses import dataclass, field, replace

import numpy as np

from ccedi.errors import InputError

from .adequacy import Adequacy
from .experiment import Experiment
from .fit import Fit, fit, fit_baseline, holdout_mask, under_own_noise
from .interface import CalibrationModel
from .model import FingerModel
from .residual import noise_std

SELECT_PROBABILITY = 0.9
"""Posterior probability at which an effect is selected (or, shared by two, an ambiguous pair
reported)."""
NOISE_Z = 3.0
MAX_EFFECTS = 3
EXPLAINED_FRACTION = 0.5
"""Least fraction of the residual's excess mean square over the noise an effect must explain."""
AMBIGUITY_CORRELATION = 0.95
"""|correlation| of two effects' parameters fitted together beyond which they are ambiguous."""
MIMIC_CORRELATION = 0.8
"""|correlation| of a candidate's parameter with another of the same fit beyond which the
report names that one as mimicking it (the candidates' identifiability)."""
AMBIGUITY_JOINT_BIC = 30.0
"""The joint fit of the best two is made when twice the runner-up's log evidence is within
this of the best's (odds above e^-15)."""
UNEXPLAINED_EXCESS = 0.1
"""Relative excess of the final residual RMS over the noise std that is flagged unexplained."""


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
    posterior : dict, optional
        Posterior probability of each candidate and of the start (key None), from their
        log evidence with equal priors (:func:`posterior_probabilities`); empty when no
        candidate was tried.
    explained : dict, optional
        Per candidate, the fraction of the start's excess over the noise it removes
        (:func:`excess_explained`) [-].
    ambiguous : tuple of str, optional
        The two candidates the round could not tell apart (module docstring, step 5), or ().
    """

    start: Fit
    evidence: dict
    suggested: list
    candidates: dict
    added: str | None
    reason: str
    posterior: dict = field(default_factory=dict)
    explained: dict = field(default_factory=dict)
    ambiguous: tuple = ()


@dataclass(frozen=True)
class Calibration:
    """Result of :func:`calibrate`.

    Parameters
    ----------
    experiment : Experiment
        The calibrated experiment.
    model : ccedi.calibrate.interface.CalibrationModel
        Its calibration model.
    baseline : Fit
        The declared model fitted (E_factor, alpha).
    final : Fit
        The final model with the effects added.
    rounds : list of Round
        The selection rounds, the last one the stop.
    noise_std_m : float
        Standard deviation the stopping test compares the residual with [m] ([N] for a
        contact record): the noise's and the model's own error (``model.model_error``:
        0 for an impulse record, the chain's discrepancy from the FEA for a contact
        record) in quadrature.
    adequacy : Adequacy or ccedi.calibrate.contact_model.ContactAdequacy
        Whether the declared finger can explain the record, with the evidence; when it
        cannot, ``final`` is the baseline.
    ambiguous : dict or None
        When the search stopped on two effects it cannot tell apart: ``effects`` (the
        two names), ``fits`` ({name: Fit}), ``delta_bic``, ``correlation`` (of their
        parameters fitted together, or None), ``why`` and ``separating_measurement``.
    unexplained : ccedi.calibrate.sparse.SparseTerm or None
        The sparse term on the final residual when it is flagged unexplained.
    rejected : Fit or None
        The model with the effects the search added that did not bring the residual to
        the noise level (module docstring, step 6), or None.
    chain_baseline : Fit or None
        The baseline of the reduced model before its FEA correction (step 1), or None
        when it was not corrected.
    fea_check : dict or None
        The full FE model's run of the last correction against the record, read as the
        final model reads (``model.fea_check``), or None when the base model was not
        corrected.
    damping_kind : dict or None
        Which mass-damping kind a contact record supports (:func:`damping_kind_support`);
        None for an impulse record.
    """

    experiment: Experiment
    model: CalibrationModel
    baseline: Fit
    final: Fit
    rounds: list
    noise_std_m: float
    adequacy: Adequacy
    ambiguous: dict | None = None
    unexplained: object = None
    rejected: Fit | None = None
    chain_baseline: Fit | None = None
    fea_check: dict | None = None
    damping_kind: dict | None = None

    @property
    def unexplained_residual(self):
        """True when the search stopped with the residual RMS more than UNEXPLAINED_EXCESS
        above the noise on an adequate declared model."""
        return self.unexplained is not None

    @property
    def noise_floor_nrmse(self):
        """Noise std (the sensor's alone) over the record's range: the NRMSE a perfect
        model would reach [-]."""
        return noise_std(self.experiment) / float(np.ptp(self.experiment.signal))


def at_noise_level(f: Fit, sigma, n):
    """Whether a fit's residual is explained by the noise (chi-square tests, module docstring).

    chi^2 <= 1 + NOISE_Z sqrt(2 / m), chi^2 the mean square of the fit's standardised
    innovations (:attr:`ccedi.calibrate.fit.Fit.chi_square`, m of them: the residual
    measured against the noise and the base model's discrepancy together; m the training
    samples), and the residual itself: RMS(r)^2 / sigma^2 <= 1 + NOISE_Z sqrt(2 / n_eff),
    n_eff the samples' worth under the noise model's correlation
    (:meth:`ccedi.calibrate.likelihood.NoiseModel.effective_samples`), or RMS(r) <= (1 +
    ``UNEXPLAINED_EXCESS``) sigma where that is wider (sigma's model-error part is an
    estimate for the contact chain). The second holds the
    first to the noise's declared size: an autoregressive model close to a random walk
    whitens a smooth misfit away (on a contact record made with friction mu 0.35 for the
    declared 0.6, the innovations passed at a residual of 1.73 sigma RMS). Under a noise
    model of unknown scale, the second alone, over the n samples.

    Parameters
    ----------
    f : Fit
        The fit.
    sigma : float
        Noise standard deviation [m], used without a chi-square.
    n : int
        Number of samples of the record.

    Returns
    -------
    bool
        True at the noise level.
    """
    bound = 1.0 + NOISE_Z * np.sqrt(2.0 / f.noise.effective_samples(n))
    if np.isfinite(f.chi_square):
        return ((f.rms_m / sigma) ** 2 <= max(bound, (1.0 + UNEXPLAINED_EXCESS) ** 2)
                and f.chi_square <= 1.0 + NOISE_Z * np.sqrt(2.0 / int(np.sum(~holdout_mask(n)))))
    return (f.rms_m / sigma) ** 2 <= bound


def excess_explained(current: Fit, candidate: Fit, sigma):
    """Fraction of the current residual's excess over the noise a candidate removes.

    (chi^2_current - chi^2_candidate) / (chi^2_current - 1) in the standardised innovations
    of their common noise model; without one, (RMS_current^2 - RMS_candidate^2) /
    (RMS_current^2 - sigma^2).

    Parameters
    ----------
    current, candidate : Fit
        The model before and after adding the candidate.
    sigma : float
        Noise standard deviation [m], used without a chi-square.

    Returns
    -------
    float
        The fraction [-] (1 when the current residual is already at or below the noise).
    """
    if np.isfinite(current.chi_square) and np.isfinite(candidate.chi_square):
        excess = current.chi_square - 1.0
        return 1.0 if excess <= 0.0 else (current.chi_square - candidate.chi_square) / excess
    excess = current.rms_m**2 - sigma**2
    return 1.0 if excess <= 0.0 else (current.rms_m**2 - candidate.rms_m**2) / excess


def separating_measurement(model: CalibrationModel, a: Fit, b: Fit):
    """The measurement that best tells two fitted models apart: the observable
    (:func:`observables`) whose predictions differ most, relatively.

    Parameters
    ----------
    model : ccedi.calibrate.interface.CalibrationModel
        The calibration model (its ``observables`` and ``measurements``).
    a, b : Fit
        The two fits.

    Returns
    -------
    dict
        ``quantity``, ``measurement`` (in words), ``values`` (by effect set),
        ``relative_difference`` [-], and ``all`` (every observable's relative difference).
    """
    oa, ob = model.observables(a.values), model.observables(b.values)
    rel = {k: abs(oa[k] - ob[k]) / max(abs(oa[k]), abs(ob[k]), 1e-300) for k in oa}
    best = max(rel, key=rel.get)
    return {"quantity": best, "measurement": model.measurements[best],
            "values": {"+".join(a.effects): oa[best], "+".join(b.effects): ob[best]},
            "relative_difference": rel[best], "all": rel}


def _correlation(f: Fit, p, q):
    """Correlation of the first parameters p and q of a fit, from its covariance."""
    return f.correlation.get((p, q), f.correlation.get((q, p), 0.0))


def posterior_probabilities(fits):
    """Posterior probabilities of fitted models from their log evidence, equal priors.

    Parameters
    ----------
    fits : dict
        {key: Fit} of the models compared (fitted to one record under one noise model).

    Returns
    -------
    dict
        {key: posterior probability} [-], summing to 1.
    """
    keys = list(fits)
    ln_z = np.array([fits[k].log_evidence for k in keys])
    w = np.exp(ln_z - ln_z.max())
    return dict(zip(keys, (w / w.sum()).tolist()))


def _ambiguity(model, current, best, runner, tried, posterior):
    """The ambiguity record of the two most probable candidates, or None when the
    evidence separates them (module docstring, step 5)."""
    if runner is None:
        return None
    fa, fb = tried[best], tried[runner]
    corr = None
    if posterior[best] < SELECT_PROBABILITY:
        why = (f"posterior probability {posterior[best]:.2f} for {best} and {posterior[runner]:.2f} for {runner}: "
               f"neither reaches {SELECT_PROBABILITY:g}, together {posterior[best] + posterior[runner]:.2f}")
    elif 2.0 * (fa.log_evidence - fb.log_evidence) < AMBIGUITY_JOINT_BIC:
        joint = fit(model, current.effects + (best, runner), start=fa.values | fb.values, parent=fa, noise=fa.noise)
        pa = next(p for p in fa.values if p not in current.values)
        pb = next(p for p in fb.values if p not in current.values)
        corr = _correlation(joint, pa, pb)
        if abs(corr) <= AMBIGUITY_CORRELATION:
            return None
        why = (f"{best} and {runner} fitted together: {pa} and {pb} correlated {corr:+.3f} (beyond "
               f"{AMBIGUITY_CORRELATION:g}); the record cannot split the misfit between them")
    else:
        return None
    return {"effects": [best, runner], "fits": {best: fa, runner: fb}, "delta_bic": fb.bic - fa.bic,
            "delta_log_evidence": fa.log_evidence - fb.log_evidence,
            "posterior": {best: posterior[best], runner: posterior[runner]}, "correlation": corr,
            "why": why, "separating_measurement": separating_measurement(model, fa, fb)}


def damping_kind_fits(exp: Experiment, model, baseline: Fit):
    """The baseline (alpha, E) fitted with both mass-damping kinds: the declared kind's is
    ``baseline``; the other's starts from the best of every other alpha start at the
    baseline's E (E is the finger's, whichever the damping) and is fitted under the
    baseline's noise model.

    Parameters
    ----------
    exp : Experiment
        A contact experiment (its sidecar's ``damping`` is the declared kind).
    model : CalibrationModel
        Its calibration model.
    baseline : Fit
        The baseline fitted with the declared kind.

    Returns
    -------
    dict
        {kind: (calibration model, baseline fit)} for "global" and "relative".
    """
    other = "relative" if exp.damping == "global" else "global"
    alt_model = calibration_model(replace(exp, damping=other))
    e = baseline.values["E_factor"]
    starts = [dict(v, E_factor=e) for v in alt_model.baseline_starts() if v["E_factor"] == 1.0][::2]
    errors = [float(np.sum((alt_model.predict(v) - exp.signal) ** 2)) for v in starts]
    alt = fit(alt_model, (), start=starts[int(np.argmin(errors))], noise=baseline.noise)
    return {exp.damping: (model, baseline), other: (alt_model, alt)}


def damping_kind_support(exp: Experiment, baseline: Fit, fits=None):
    """Which mass-damping kind a contact record supports, a structural choice made from
    the record: under global damping the drag bends the finger back before contact and
    moves the contact start with alpha; under relative damping the finger reaches the
    object undeformed, so the record's contact start and rise tell the two apart. The
    baseline fitted with each kind (:func:`damping_kind_fits`) are compared by their
    posterior probabilities (:func:`posterior_probabilities`): a kind is supported when its
    probability reaches ``SELECT_PROBABILITY``, and :func:`calibrate` then goes on with it.

    Parameters
    ----------
    exp : Experiment
        The experiment (its sidecar's ``damping`` is the declared kind).
    baseline : Fit
        The baseline fitted with the declared kind.
    fits : dict, optional
        :func:`damping_kind_fits` of the record, if made already.

    Returns
    -------
    dict or None
        ``declared``, ``supported`` ("global", "relative" or "either" when neither
        reaches :data:`SELECT_PROBABILITY`), ``used`` (the kind the calibration goes on
        with: the supported one, else the declared), ``delta_log_evidence`` and
        ``delta_bic`` (the other kind's minus the declared one's) and per kind the
        baseline's ``posterior``, ``nrmse``, ``bic`` and ``alpha_per_s``; None for an
        impulse record (a clamped finger that does not turn: the two kinds are the same).
    """
    if exp.kind != "contact":
        return None
    if fits is None:
        fits = damping_kind_fits(exp, calibration_model(exp), baseline)
    other = "relative" if exp.damping == "global" else "global"
    by_kind = {k: f for k, (_, f) in fits.items()}
    posterior = posterior_probabilities(by_kind)
    supported = next((k for k, p in posterior.items() if p >= SELECT_PROBABILITY), "either")
    alt = by_kind[other]
    return {"declared": exp.damping, "supported": supported,
            "used": exp.damping if supported == "either" else supported,
            "delta_log_evidence": alt.log_evidence - baseline.log_evidence, "delta_bic": alt.bic - baseline.bic,
            **{k: {"posterior": posterior[k], "nrmse": f.nrmse, "bic": f.bic, "alpha_per_s": f.values["alpha_per_s"]}
               for k, f in by_kind.items()}}


def calibration_model(exp: Experiment):
    """The calibration model of an experiment: :class:`FingerModel` for an impulse
    record, :class:`ccedi.calibrate.contact_model.DrumContactModel` for a contact record.

    Parameters
    ----------
    exp : Experiment
        The validated experiment.

    Returns
    -------
    CalibrationModel
        The model.
    """
    if exp.kind == "contact":
        # the contact stack (drum FEA, contact ROM) loads only for a contact record
        from .contact_model import DrumContactModel

        return DrumContactModel(exp)
    return FingerModel(exp)


def calibrate(exp: Experiment, *, candidates=None, progress=None, fea_correction=False):
    """Run the calibration loop on an experiment (module docstring).

    Parameters
    ----------
    exp : Experiment
        The validated experiment (impulse or contact).
    candidates : iterable of str, optional
        Effect names to consider. Default: the whole catalogue of the record's kind.
    progress : callable, optional
        Called with a one-line message as each stage starts (the baseline fit, the
        adequacy check, each candidate fit). Default None.
    fea_correction : bool, optional
        Correct a reduced base model by its full FE model at the baseline fit (module
        docstring, step 1; a contact record's chain by one full explicit run on the drum,
        ~2 minutes). No effect on an impulse record, whose base model is
        the FE model's own modes. Default False: on the bundled contact set it found the
        right effect in 7 of 13 records against the chain alone's 8 (validation/calibrate_contact.json).

    Returns
    -------
    Calibration
        Baseline and final fits, the rounds, the noise level, the adequacy of the
        declared model (when it is inadequate, one round that adds nothing), an
        ambiguity when two effects could not be told apart, the effects not accepted
        because they left the residual above the noise (step 6), and the sparse term when
        the residual is left unexplained.

    Raises
    ------
    InputError
        A candidate that is not in the catalogue of the record's kind.
    """
    model = calibration_model(exp)
    names = list(model.catalogue) if candidates is None else list(candidates)
    unknown = [k for k in names if k not in model.catalogue]
    if unknown:
        raise InputError(f"effect(s) {', '.join(unknown)} not in the {exp.kind} catalogue "
                         f"({', '.join(model.catalogue)})")
    n = len(exp.time_s)
    say = progress or (lambda message: None)
    say(f"{n} samples over {exp.time_s[-1] - exp.time_s[0]:.4g} s; fitting the declared finger's alpha and E")
    current = baseline = fit_baseline(model)
    kind = None
    if exp.kind == "contact":
        say("fitting the baseline with the other damping kind")
        kinds = damping_kind_fits(exp, model, baseline)
        kind = damping_kind_support(exp, baseline, kinds)
        if kind["used"] != exp.damping:
            say(f"the record supports {kind['used']} damping (declared {exp.damping}): going on with it")
            exp = replace(exp, damping=kind["used"])
            model, baseline = kinds[kind["used"]]
            current = baseline
    chain_baseline = None
    if fea_correction and model.correct_at(baseline.values) is not None:
        chain_baseline = baseline
        current = baseline = fit(model, (), start=baseline.values, noise=baseline.noise)
    sigma = float(np.hypot(noise_std(exp), model.model_error))
    say("checking the declaration against the record's own first mode")
    adequacy = model.assess(baseline, sigma)
    rounds = []
    ambiguous = None
    provisional = adequacy.effect_may_explain      # the force level may be an effect's: try the catalogue
    while True:
        evidence = model.analyse(current, sigma)
        if not adequacy.adequate and not provisional:
            rounds.append(Round(current, evidence, [], {}, None, adequacy.message() + ": no effect added"))
            break
        suggested = model.suggest(evidence)
        if at_noise_level(current, sigma, n):
            rounds.append(Round(current, evidence, suggested, {}, None,
                                f"residual at the noise level (RMS {evidence['rms_over_noise']:.3f} sigma)"))
            break
        if len(current.effects) >= MAX_EFFECTS:
            rounds.append(Round(current, evidence, suggested, {}, None, f"{MAX_EFFECTS} effects added: stop"))
            break
        if rounds:
            current = under_own_noise(model, current)
        tried = {}
        for name in names:
            if name in current.effects:
                continue
            say(f"round {len(rounds) + 1}: {'+'.join(current.effects + (name,))}")
            start, extra = model.candidate_starts(name, current, evidence)
            tried[name] = fit(model, current.effects + (name,), start=current.values | start, extra_starts=extra,
                              parent=current, noise=current.noise)
        posterior = posterior_probabilities({None: current} | tried)
        ranked = sorted(tried, key=lambda k: -posterior[k])
        explains = {k: excess_explained(current, tried[k], sigma) for k in ranked}
        best = ranked[0] if ranked else None
        runner = ranked[1] if len(ranked) > 1 else None
        pair = best is not None and runner is not None and min(explains[best], explains[runner]) >= EXPLAINED_FRACTION
        if best is None or explains[best] < EXPLAINED_FRACTION or (
                posterior[best] < SELECT_PROBABILITY
                and not (pair and posterior[best] + posterior[runner] >= SELECT_PROBABILITY)):
            gain = "" if best is None else (f" (best: {best}, posterior {posterior[best]:.2f}, ln Z "
                                            f"{tried[best].log_evidence - current.log_evidence:+.1f}, explains "
                                            f"{explains[best]:.0%} of the excess over the noise; "
                                            f"{'+'.join(current.effects) or 'the baseline'} {posterior[None]:.2f})")
            rounds.append(Round(current, evidence, suggested, tried, None,
                                f"no candidate reaches posterior probability {SELECT_PROBABILITY:g} while explaining "
                                f"{EXPLAINED_FRACTION:.0%} of the excess over the noise{gain}", posterior, explains))
            break
        ambiguous = _ambiguity(model, current, best, runner if pair else None, tried, posterior)
        if ambiguous is not None:
            rounds.append(Round(current, evidence, suggested, tried, None, "ambiguous: " + ambiguous["why"],
                                posterior, explains, tuple(ambiguous["effects"])))
            current = tried[best]
            break
        rounds.append(Round(current, evidence, suggested, tried, best,
                            f"posterior probability {posterior[best]:.3f} (ln Z {tried[best].log_evidence - current.log_evidence:+.1f}), "
                            f"held-out RMS {current.holdout_rms_m:.3g} -> {tried[best].holdout_rms_m:.3g} "
                            f"{model.exp.signal_unit}, {explains[best]:.0%} of the excess over the noise", posterior,
                            explains))
        current = tried[best]
    if chain_baseline is not None and current.effects and not model.corrected_near(current.values):
        model.correct_at(current.values)
        current = fit(model, current.effects, start=current.values, noise=current.noise)
        sigma = float(np.hypot(noise_std(exp), model.model_error))
    rejected = None
    if current.effects and not at_noise_level(current, sigma, n):
        stand_ins = "+".join(current.effects) if ambiguous is None else " or ".join(ambiguous["effects"])
        rejected, current, ambiguous = current, baseline, None
        rounds.append(Round(baseline, rounds[0].evidence, [], {}, None,
                            f"{stand_ins} leave the residual at {rejected.rms_m / sigma:.3f} sigma, "
                            f"not the noise level: the catalogue does not explain the record, no effect accepted"))
        if chain_baseline is not None:
            model.correct_at(baseline.values)
            sigma = float(np.hypot(noise_std(exp), model.model_error))
    if provisional:
        adequacy = adequacy.resolved_by(current) if current.effects else adequacy
        if not adequacy.adequate:
            current, ambiguous = baseline, None
            rounds.append(Round(baseline, rounds[0].evidence, [], {}, None,
                                adequacy.message() + ": no catalogued effect brings E within its tolerance, "
                                "none accepted"))
    unexplained = None
    if adequacy.adequate and current.rms_m > (1.0 + UNEXPLAINED_EXCESS) * sigma:
        unexplained = model.unexplained_term(current)
    fea_check = model.fea_check(current.values, sigma) if chain_baseline is not None else None
    return Calibration(experiment=exp, model=model, baseline=baseline, final=current, rounds=rounds,
                       noise_std_m=sigma, adequacy=adequacy, ambiguous=ambiguous, unexplained=unexplained,
                       rejected=rejected, chain_baseline=chain_baseline, fea_check=fea_check, damping_kind=kind)


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
        :meth:`ccedi.calibrate.adequacy.Adequacy.summary`), ``signal_unit`` (the
        record's: "m" for an impulse record, "N" for a contact record; every ``_m``
        error field below is in it), ``baseline`` (nrmse, max error, parameters,
        standard errors),
        ``effects_found`` (per effect added: parameters and standard errors as fitted in
        its round and in the final model, error after, why, residual evidence and the
        candidates' scores), ``selected_effect``, final NRMSE, max error, parameters
        and their standard errors (``final_stderr``) and correlations
        (``final_correlation``, {"p,q": r} for every pair of parameters p before q; what a
        robust design's :class:`ccedi.design.robust.CalibratedSpread` reads), ``kind`` (of the record), ``calibrated`` (E_Pa and alpha_per_s of the
        final model and, for a contact record, ``drum``: the corrected [drum] keys; the
        inputs ``ccedi calibrate --write-config`` writes), ``model_error_std`` (the
        base model's own error std the stopping test allows besides the noise, record
        units), ``noise_floor_nrmse``, ``stop_reason``,
        ``final_evidence``, ``final_suggestions``, ``ambiguous`` (None, or the two effects
        with both fits, their BIC difference, correlation and the separating
        measurement), ``rejected_effects`` (None, or the effects added that left the
        residual above the noise, with their parameters, NRMSE and RMS over the noise
        std), ``unexplained_residual`` (bool) and ``sparse_term`` (None, or the
        best sparse force term on the residual, :meth:`ccedi.calibrate.sparse.SparseTerm.summary`),
        ``damping_kind`` (:func:`damping_kind_support`; None for an impulse record),
        ``rounds`` (every round's candidates with their fitted parameters and scores,
        accepted or not, and their identifiability, :func:`candidates_summary`).
    """
    found = []
    fin = cal.final
    for r in cal.rounds:
        if r.added is None or cal.rejected is not None:
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
                      "candidates": candidates_summary(r)})
    last = cal.rounds[-1]
    b = cal.baseline
    return {"source": cal.experiment.record.source,
            "model_adequate": cal.adequacy.adequate, "adequacy": cal.adequacy.summary(),
            "baseline": {"nrmse": b.nrmse, "max_error_m": b.max_error_m, "params": b.values, "stderr": b.stderr},
            "effects_found": found,
            "selected_effect": found[0]["name"] if found else None,
            "final_nrmse": fin.nrmse, "final_max_error_m": fin.max_error_m, "final_params": fin.values,
            "final_stderr": fin.stderr, "signal_unit": cal.experiment.signal_unit,
            "final_correlation": {f"{p},{q}": r for (p, q), r in fin.correlation.items()},
            "kind": cal.experiment.kind,
            "calibrated": cal.model.calibrated(fin.values),
            "noise_floor_nrmse": cal.noise_floor_nrmse, "model_error_std": cal.model.model_error,
            "stop_reason": last.reason, "final_evidence": last.evidence,
            "final_suggestions": [{"effect": k, "reason": why} for k, why in last.suggested],
            "ambiguous": _ambiguous_summary(cal.ambiguous),
            "rejected_effects": None if cal.rejected is None else {
                "effects": list(cal.rejected.effects), "params": cal.rejected.values, "nrmse": cal.rejected.nrmse,
                "rms_over_noise": cal.rejected.rms_m / cal.noise_std_m},
            "chain_baseline": None if cal.chain_baseline is None else {
                "nrmse": cal.chain_baseline.nrmse, "params": cal.chain_baseline.values},
            "fea_check": cal.fea_check,
            "damping_kind": cal.damping_kind,
            "rounds": [{"effects_before": list(r.start.effects), "added": r.added, "reason": r.reason,
                        "posterior_of_start": r.posterior.get(None), "noise_model": r.start.noise.summary(),
                        "candidates": candidates_summary(r)} for r in cal.rounds if r.candidates],
            "unexplained_residual": cal.unexplained_residual,
            "sparse_term": cal.unexplained.summary() if cal.unexplained is not None else None}


def candidates_summary(round_: Round):
    """Every candidate a round tried, accepted or not: its added parameters as fitted (with
    standard errors), its scores against the round's start and its posterior probability
    (:func:`posterior_probabilities`), and how identifiable each added
    parameter is: the share of its signature the other parameters cannot mimic
    (:attr:`ccedi.calibrate.fit.Fit.unique_share`) and the parameters it is correlated with
    beyond :data:`MIMIC_CORRELATION`.

    Parameters
    ----------
    round_ : Round
        A round of :func:`calibrate`.

    Returns
    -------
    dict
        {effect: {"params", "stderr", "posterior", "delta_log_evidence", "delta_bic",
        "holdout_rms_m", "nrmse", "explained", "verdict", "unique_share", "mimicked_by"}},
        most probable first; ``verdict`` says in words why the candidate was or was not
        selected (:func:`candidate_verdict`).
    """
    out = {}
    for name, f in sorted(round_.candidates.items(), key=lambda kv: -kv[1].log_evidence):
        new = [p for p in f.values if p not in round_.start.values]
        out[name] = {"params": {p: f.values[p] for p in new}, "stderr": {p: f.stderr[p] for p in new},
                     "posterior": round_.posterior.get(name),
                     "delta_log_evidence": f.log_evidence - round_.start.log_evidence,
                     "delta_bic": f.bic - round_.start.bic, "holdout_rms_m": f.holdout_rms_m, "nrmse": f.nrmse,
                     "explained": round_.explained.get(name), "verdict": candidate_verdict(round_, name),
                     "unique_share": {p: f.unique_share.get(p) for p in new},
                     "mimicked_by": {p: sorted(((q, _correlation(f, p, q)) for q in f.values if q != p
                                                and abs(_correlation(f, p, q)) >= MIMIC_CORRELATION),
                                               key=lambda qc: -abs(qc[1])) for p in new}}
    return out


def candidate_verdict(round_: Round, name):
    """Why a round's candidate was or was not selected, in words (module docstring, steps 4-5).

    Parameters
    ----------
    round_ : Round
        A round of :func:`calibrate` that tried candidates.
    name : str
        One of its candidates.

    Returns
    -------
    str
        "selected", or the first selection rule the candidate failed, with its figures.
    """
    if name == round_.added:
        return "selected"
    p, x = round_.posterior.get(name, 0.0), round_.explained.get(name, 0.0)
    if x < EXPLAINED_FRACTION:
        return f"explains {x:.0%} of the excess over the noise (at least {EXPLAINED_FRACTION:.0%} needed)"
    rivals = {k: q for k, q in round_.posterior.items() if k != name}
    rival = max(rivals, key=rivals.get, default=None)
    beaten = "" if rival is None or rivals[rival] <= p else \
        f"; {rival or 'the model without it'} is more probable ({rivals[rival]:.2f})"
    if name in round_.ambiguous:
        return f"not told apart from {next(k for k in round_.ambiguous if k != name)}: {round_.reason}"
    if p < SELECT_PROBABILITY:
        return f"posterior probability {p:.2f} (at least {SELECT_PROBABILITY:g} needed){beaten}"
    return round_.reason


def _ambiguous_summary(amb):
    """The JSON-ready ambiguity record (its fits as parameters and scores)."""
    if amb is None:
        return None
    fits = {k: {"params": f.values, "stderr": f.stderr, "bic": f.bic, "log_evidence": f.log_evidence, "nrmse": f.nrmse,
                "holdout_rms_m": f.holdout_rms_m} for k, f in amb["fits"].items()}
    return {k: v for k, v in amb.items() if k != "fits"} | {"fits": fits}
