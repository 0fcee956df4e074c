"""Prediction of a finger's contact record from its impulse calibration: the next experiment.

Young's modulus and the mass-proportional alpha calibrated on an impulse record of a finger
(:func:`ccedi.calibrate.loop.calibrate`, the final fit's values and covariance) are put into
the contact chain of the same finger on the declared drum, read through the declared
transducer (:class:`ccedi.calibrate.contact_model.DrumContactModel`), and the contact
record's features are predicted, each with a 95 % interval.

The features (:func:`contact_features`), measured the same way on the prediction and on a
record: the reading is low-passed (:func:`filtered_reading`, zero-phase 2nd-order
Butterworth at :data:`FEATURE_BAND_HZ`, which removes the sensor noise and leaves the
contact load); its peak is the *filtered peak force* [N]; contact starts and ends where the
filtered reading first and last reaches :data:`CONTACT_FRACTION` of that peak (linear
interpolation between samples) [s]; the duration is end minus start [s].

The predicted feature is the chain's, corrected by the chain's measured bias against the
full FEA at the calibrated alpha (:func:`chain_error`); its interval is f +- z sigma_f (z for
:data:`INTERVAL_PROBABILITY`, two-sided normal), with three independent terms in quadrature::

    sigma_f^2 = sigma_parameters^2 + sigma_chain^2 + sigma_noise^2

  sigma_parameters  the impulse fit's covariance of (E_factor, alpha) (Gauss-Newton,
                    :mod:`ccedi.calibrate.fit`), plus, when the calibration added effects,
                    d d^T with d the shift of (E_factor, alpha) from its baseline fit to
                    its final one (how far the values depend on the effects selected, none
                    of which the chain carries: on an impulse record at alpha = 600 1/s the
                    loop added quadratic damping and moved E by 7.6 %, 4.7 of its final
                    standard errors, validation/predict_contact.json ``pair_600``), taken
                    through the chain by the unscented transform: the chain at the four
                    symmetric sigma points mean +- sqrt(2) L_k (L L^T the covariance),
                    weights 1/4
  sigma_chain       the chain's own error against the full explicit FEA on the drum, per
                    feature: chain minus FEA (both read noise-free through the transducer,
                    at the true E, alpha and set-up) on the ten bundled full-FEA contact
                    runs, fitted by a straight line in ln alpha (validation/predict_contact.py,
                    :data:`CHAIN_ERROR`); the line is the bias removed, sigma_chain the std
                    of a new run about it (the residual std with the line's own
                    uncertainty, growing away from the runs' alphas, 80-600 1/s)
  sigma_noise       the record's noise on its measured feature: the features of the
                    predicted reading with :data:`NOISE_DRAWS` draws of white noise of the
                    record's noise std (the sidecar's ``sensor.noise_std_N``, else estimated
                    from the record, :func:`ccedi.calibrate.residual.noise_std`); none when
                    a set-up without record declares no noise

Not in the interval: the impulse model's own error (its fit's covariance assumes the modal
model exact and the noise white), the effects the impulse calibration found (a tip mass, a
compliant root...: the chain has none of them; the prediction names them), and any effect
the contact record has that its sidecar does not declare (friction, drum speed, object
position and transducer are taken as declared).
"""
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.stats import norm

from ccedi.errors import InputError
from ccedi.rom.measurement import MeasuredResponse

from .contact_model import DrumContactModel, zero_phase_lowpass
from .experiment import Experiment, experiment_from, load_experiment, read_sidecar
from .residual import noise_std

FEATURE_BAND_HZ = 20.0
"""Corner frequency [Hz] of the zero-phase low-pass of :func:`filtered_reading`: the
contact load rises over ~0.1 s (content below ~20 Hz, :mod:`ccedi.rom.sensor`); the 2 %
white noise of a 1 kHz record drops to ~0.2 of its std."""
CONTACT_FRACTION = 0.1
"""Fraction of the filtered peak that marks contact start and end [-]: on the drum the
finger's force jumps to about a third of its peak at touch-down and drops from about a
quarter at lift-off, so 10 % lies on those edges, ~25 noise std of the filtered reading
above zero."""
INTERVAL_PROBABILITY = 0.95
"""Probability of the stated intervals (two-sided, normal) [-]."""
NOISE_DRAWS = 200
"""Noise realisations of sigma_noise (module docstring); seeded, so a prediction is
deterministic."""
NOISE_SEED = 2012
SET_UP_SPAN_S = 1.5
"""Span [s] of the times a set-up without record is predicted at (the bundled contact
records' span, :data:`ccedi.calibrate.contact_synthetic.RECORD_S`)."""
SET_UP_RATE_HZ = 1000.0
"""Sample rate [Hz] of those times (the bundled records')."""
CHAIN_RUNS = {"runs": 10, "alpha_geometric_mean_per_s": 188.282, "sxx_ln_alpha": 4.09484}
"""The full-FEA runs the chain's error was measured on (:data:`CHAIN_ERROR`): their number,
the geometric mean of their alphas [1/s] and the sum of squares of ln alpha about its mean."""
CHAIN_ERROR = {"contact_start_s": {"at_mean": 1.3459e-3, "per_ln_alpha": 0.9056e-3, "residual_std": 0.2665e-3},
               "contact_end_s": {"at_mean": 1.1584e-3, "per_ln_alpha": 0.2146e-3, "residual_std": 0.1238e-3},
               "contact_duration_s": {"at_mean": -0.1875e-3, "per_ln_alpha": -0.6910e-3, "residual_std": 0.2347e-3},
               "filtered_peak_force_fraction": {"at_mean": -0.026483, "per_ln_alpha": -0.0010701,
                                                "residual_std": 0.011643}}
"""The chain's feature minus the full FEA's on the ten bundled full-FEA contact runs (alpha
80-600 1/s; friction, drum speed, object position and drum angle varied), a straight line
in ln alpha: the error at the runs' geometric-mean alpha, its slope per unit ln alpha and
the residual std (8 dof); contact start, end and duration in s, the filtered peak force as
chain / FEA - 1. From validation/predict_contact.json ``chain_error.regression``: the chain
touches the object 1.3 ms late at alpha 188 1/s, 0.9 ms more per unit ln alpha, lifts off
1.2 ms late, and reads the peak 2.6 % low, each within 0.27 ms and 1.2 % about the line.
All ten runs are of the declared 8-in finger with global damping: another finger, or
relative damping, is predicted with the same line, not measured there."""
FEATURES = {"contact_start_s": "s", "contact_end_s": "s", "contact_duration_s": "s", "filtered_peak_force_N": "N"}
"""The predicted features and their units."""
FEATURE_NAMES = {"contact_start_s": "contact start", "contact_end_s": "contact end",
                 "contact_duration_s": "contact duration", "filtered_peak_force_N": "filtered peak force"}
"""The predicted features in words."""


def chain_error(name, alpha_per_s):
    """The chain's bias against the full FEA in a feature, and the std of a prediction about
    it (:data:`CHAIN_ERROR`): the line b_0 + b_1 x, x = ln(alpha / alpha_g) with alpha_g the
    runs' geometric-mean alpha, and s sqrt(1 + 1/n + x^2 / S_xx) (a new run's prediction
    std of a least-squares line; s the residual std, n runs, S_xx their sum of squares of x).

    Parameters
    ----------
    name : str
        ``contact_start_s``, ``contact_end_s``, ``contact_duration_s`` (in s) or
        ``filtered_peak_force_fraction`` (chain / FEA - 1).
    alpha_per_s : float
        Mass-proportional damping [1/s].

    Returns
    -------
    bias : float
        Chain minus FEA (s, or the fraction).
    std : float
        Its std for one prediction (same unit).
    """
    c, x = CHAIN_ERROR[name], float(np.log(alpha_per_s / CHAIN_RUNS["alpha_geometric_mean_per_s"]))
    std = c["residual_std"] * np.sqrt(1.0 + 1.0 / CHAIN_RUNS["runs"] + x**2 / CHAIN_RUNS["sxx_ln_alpha"])
    return c["at_mean"] + c["per_ln_alpha"] * x, float(std)


def fea_equivalent(features, alpha_per_s):
    """The chain's features with its bias against the full FEA removed (:func:`chain_error`).

    Parameters
    ----------
    features : dict
        The chain's :func:`contact_features`.
    alpha_per_s : float
        The alpha it ran at [1/s].

    Returns
    -------
    corrected : dict
        The features the full FEA is expected to show (times in s, peak in N).
    std : dict
        sigma_chain of each (same units).
    """
    corrected, std = {}, {}
    for name, value in features.items():
        if name == "filtered_peak_force_N":
            bias, s = chain_error("filtered_peak_force_fraction", alpha_per_s)
            corrected[name] = value / (1.0 + bias)
            std[name] = s * corrected[name]
        else:
            bias, std[name] = chain_error(name, alpha_per_s)
            corrected[name] = value - bias
    return corrected, std


def filtered_reading(time_s, reading_N):
    """The reading low-passed for its features (module docstring).

    Parameters
    ----------
    time_s : numpy.ndarray
        Uniform sample times [s].
    reading_N : numpy.ndarray
        Transducer reading [N].

    Returns
    -------
    numpy.ndarray
        The zero-phase low-passed reading at ``time_s`` [N].
    """
    return zero_phase_lowpass(time_s, reading_N, FEATURE_BAND_HZ)


def _level_time(t, y, k, level):
    """Time the straight line through samples k and k + 1 reaches ``level``."""
    return float(t[k] + (level - y[k]) / (y[k + 1] - y[k]) * (t[k + 1] - t[k]))


def contact_features(time_s, reading_N):
    """Contact start, end, duration and filtered peak force of a reading (module docstring).

    Parameters
    ----------
    time_s : numpy.ndarray
        Uniform sample times [s].
    reading_N : numpy.ndarray
        Transducer reading (a record, or a model's prediction) [N].

    Returns
    -------
    dict
        ``contact_start_s``, ``contact_end_s``, ``contact_duration_s`` [s],
        ``filtered_peak_force_N`` [N].

    Raises
    ------
    InputError
        The filtered reading has no positive peak, or is above the contact level at the
        first or last sample (the record does not hold the whole contact).
    """
    t = np.asarray(time_s, dtype=float)
    y = filtered_reading(t, np.asarray(reading_N, dtype=float))
    peak = float(np.max(y))
    if peak <= 0.0:
        raise InputError(f"the reading shows no contact (its filtered peak is {peak:.4g} N)")
    level = CONTACT_FRACTION * peak
    on = np.flatnonzero(y >= level)
    if on[0] == 0 or on[-1] == len(y) - 1:
        raise InputError(f"the filtered reading is above {CONTACT_FRACTION:.0%} of its peak at the record's "
                         f"{'first' if on[0] == 0 else 'last'} sample ({t[0] if on[0] == 0 else t[-1]:.4g} s): "
                         "the record does not hold the whole contact")
    start, end = _level_time(t, y, on[0] - 1, level), _level_time(t, y, on[-1], level)
    return {"contact_start_s": start, "contact_end_s": end, "contact_duration_s": end - start,
            "filtered_peak_force_N": peak}


def load_contact_setup(path):
    """A contact experiment to predict: a record (CSV with its sidecar beside it) or a set-up
    without record (its sidecar JSON alone, predicted at :data:`SET_UP_SPAN_S` sampled at
    :data:`SET_UP_RATE_HZ`).

    Parameters
    ----------
    path : str or pathlib.Path
        ``CONTACT.csv`` (sidecar ``CONTACT.json`` beside it) or ``CONTACT.json``.

    Returns
    -------
    experiment : Experiment
        The validated contact experiment (without record: zero reading at the prediction
        times).
    recorded : bool
        Whether it holds a measured record.

    Raises
    ------
    InputError
        Not a .csv or .json path, a file missing or invalid, or not a contact record.
    """
    path = Path(path)
    if path.suffix.lower() not in (".csv", ".json"):
        raise InputError(f"contact set-up {path}: give a contact record CSV (its sidecar JSON beside it) or a "
                         "contact sidecar JSON alone")
    recorded = path.suffix.lower() == ".csv"
    sidecar = path.with_suffix(".json")
    if not path.is_file() or not sidecar.is_file():
        raise InputError(f"contact set-up {path}: {'not found' if not path.is_file() else f'no sidecar {sidecar} beside it'}")
    if recorded:
        exp = load_experiment(path)
    else:
        t = np.arange(1, int(round(SET_UP_SPAN_S * SET_UP_RATE_HZ)) + 1) / SET_UP_RATE_HZ
        quiet = MeasuredResponse(time_s=t, tip_displacement_m=None, force_N=None, source=f"{path} (set-up, no record)",
                                 reaction_force_N=np.zeros_like(t))
        exp = experiment_from(quiet, read_sidecar(sidecar), source=str(path), check_record=False)
    if exp.kind != "contact":
        raise InputError(f"contact set-up {path}: sidecar kind is {exp.kind!r}, a contact record or set-up "
                         "(kind \"contact\") is needed")
    return exp, recorded


FINGER_FIELDS = {"length_m": "length", "semi_axes_m": "section semi-axes", "rho_kg_m3": "density", "nu": "Poisson's ratio"}
"""The declared finger's fields an impulse record and a contact record must share to be of
the same finger (E may be declared differently: it is converted)."""


def check_same_finger(impulse: Experiment, contact: Experiment):
    """Refuse a contact set-up whose declared finger is not the impulse record's.

    Parameters
    ----------
    impulse : Experiment
        The calibrated impulse experiment.
    contact : Experiment
        The contact experiment to predict.

    Raises
    ------
    InputError
        One line naming the fields that differ, with both values.
    """
    a, b = impulse.finger, contact.finger
    differ = [f"{name} {getattr(a, key)} vs {getattr(b, key)}" for key, name in FINGER_FIELDS.items()
              if not np.allclose(getattr(a, key), getattr(b, key), rtol=1e-6, atol=0.0)]
    if differ:
        raise InputError(f"{contact.record.source}: its finger is not the impulse record's "
                         f"({impulse.record.source}): {'; '.join(differ)}")


@dataclass(frozen=True)
class FeaturePrediction:
    """One predicted feature with its interval (module docstring).

    Parameters
    ----------
    name : str
        The feature (:data:`FEATURES`).
    predicted : float
        The chain's feature at the calibrated values with its bias removed (unit of the
        feature).
    std_parameters, std_chain, std_noise : float
        The three terms of its standard deviation.
    measured : float or None
        The record's feature, or None without record.
    """

    name: str
    predicted: float
    std_parameters: float
    std_chain: float
    std_noise: float
    measured: float | None = None

    @property
    def std(self):
        """Standard deviation of the feature: the three terms in quadrature."""
        return float(np.sqrt(self.std_parameters**2 + self.std_chain**2 + self.std_noise**2))

    @property
    def interval(self):
        """(lower, upper) of the :data:`INTERVAL_PROBABILITY` interval."""
        half = norm.ppf(0.5 + INTERVAL_PROBABILITY / 2.0) * self.std
        return self.predicted - half, self.predicted + half

    @property
    def inside(self):
        """Whether the measured feature lies in the interval (None without record)."""
        if self.measured is None:
            return None
        lo, hi = self.interval
        return bool(lo <= self.measured <= hi)

    def summary(self):
        """The JSON-ready figures, every key with the feature's unit.

        Returns
        -------
        dict
            ``predicted_U``, ``interval_U`` [lower, upper], ``std_U`` and its terms
            ``std_parameters_U``, ``std_chain_U``, ``std_noise_U``, ``measured_U``,
            ``error_U`` (measured minus predicted, or None) and ``inside`` (U the unit).
        """
        u = FEATURES[self.name]
        return {f"predicted_{u}": self.predicted, f"interval_{u}": list(self.interval), f"std_{u}": self.std,
                f"std_parameters_{u}": self.std_parameters, f"std_chain_{u}": self.std_chain,
                f"std_noise_{u}": self.std_noise, f"measured_{u}": self.measured,
                f"error_{u}": None if self.measured is None else self.measured - self.predicted, "inside": self.inside}


@dataclass(frozen=True)
class ContactPrediction:
    """The predicted contact record of :func:`predict_contact`.

    Parameters
    ----------
    contact : Experiment
        The contact experiment predicted.
    recorded : bool
        Whether it holds a measured record.
    values : dict
        ``E_factor`` (over the contact sidecar's declared E) and ``alpha_per_s`` [1/s] the
        chain ran at.
    covariance : numpy.ndarray
        Their covariance (2, 2), in that order, with the selection shift's d d^T.
    selection_shift : numpy.ndarray
        d: the final fit's (E_factor, alpha) minus the baseline's (zero when no effect
        was added).
    reading_N : numpy.ndarray
        The predicted transducer reading at the contact experiment's times [N].
    features : dict
        {name: FeaturePrediction} of :data:`FEATURES`.
    noise_std_N : float
        The noise std of sigma_noise [N] (0: not included).
    effects_not_carried : tuple of str
        Effects of the impulse calibration's final model the chain does not have.
    """

    contact: Experiment
    recorded: bool
    values: dict
    covariance: np.ndarray
    selection_shift: np.ndarray
    reading_N: np.ndarray
    features: dict
    noise_std_N: float
    effects_not_carried: tuple = ()

    def summary(self):
        """The JSON-ready prediction.

        Returns
        -------
        dict
            ``contact_source``, ``recorded``, ``E_factor`` (over the contact sidecar's E),
            ``E_Pa``, ``alpha_per_s``, their ``stderr_E_factor``, ``stderr_alpha_per_s``,
            ``correlation`` (with the selection shift), ``selection_shift_E_factor``,
            ``selection_shift_alpha_per_s``, ``interval_probability``, ``noise_std_N``, ``definitions`` (of
            the features, in words), ``features`` ({name: :meth:`FeaturePrediction.summary`}),
            ``all_inside`` (None without record) and ``impulse_effects_not_carried``.
        """
        s = np.sqrt(np.diag(self.covariance))
        corr = float(self.covariance[0, 1] / (s[0] * s[1])) if s[0] * s[1] > 0 else 0.0
        inside = [f.inside for f in self.features.values()]
        return {"contact_source": self.contact.record.source, "recorded": self.recorded,
                "E_factor": self.values["E_factor"], "E_Pa": self.values["E_factor"] * self.contact.finger.E_Pa,
                "alpha_per_s": self.values["alpha_per_s"], "stderr_E_factor": float(s[0]),
                "stderr_alpha_per_s": float(s[1]), "correlation": corr,
                "selection_shift_E_factor": float(self.selection_shift[0]),
                "selection_shift_alpha_per_s": float(self.selection_shift[1]),
                "interval_probability": INTERVAL_PROBABILITY, "noise_std_N": self.noise_std_N,
                "definitions": {"filtered_reading": f"the reading low-passed at {FEATURE_BAND_HZ:g} Hz (zero-phase "
                                                    "2nd-order Butterworth)",
                                "filtered_peak_force_N": "peak of the filtered reading",
                                "contact_start_s": f"first time the filtered reading reaches {CONTACT_FRACTION:.0%} "
                                                   "of its peak",
                                "contact_end_s": f"last time it is at {CONTACT_FRACTION:.0%} of its peak",
                                "contact_duration_s": "end minus start"},
                "features": {k: f.summary() for k, f in self.features.items()},
                "all_inside": None if not self.recorded else all(inside),
                "impulse_effects_not_carried": list(self.effects_not_carried)}


def impulse_parameters(fit):
    """E_factor and alpha of an impulse fit with their covariance.

    Parameters
    ----------
    fit : ccedi.calibrate.fit.Fit
        The final fit of an impulse calibration.

    Returns
    -------
    mean : numpy.ndarray
        (E_factor [-], alpha [1/s]).
    covariance : numpy.ndarray
        (2, 2), from the fit's standard errors and correlation.
    """
    names = ("E_factor", "alpha_per_s")
    s = np.array([fit.stderr[k] for k in names])
    r = fit.correlation.get(names, fit.correlation.get(names[::-1], 0.0))
    return np.array([fit.values[k] for k in names]), np.array([[1.0, r], [r, 1.0]]) * np.outer(s, s)


def sigma_points(mean, covariance):
    """The symmetric sigma points of the unscented transform (weights 1 / (2 n) each).

    Parameters
    ----------
    mean : numpy.ndarray
        Mean (n,).
    covariance : numpy.ndarray
        Covariance (n, n), symmetric positive semi-definite.

    Returns
    -------
    numpy.ndarray
        (2 n, n): mean + sqrt(n) L_k, then mean - sqrt(n) L_k, L_k the columns of a
        square root L L^T = covariance (from its eigen-decomposition).
    """
    w, v = np.linalg.eigh(covariance)
    root = v * np.sqrt(np.clip(w, 0.0, None)) * np.sqrt(len(mean))
    return np.vstack([mean + root.T, mean - root.T])


def predict_contact(calibration, contact: Experiment, *, recorded=True):
    """Predict a contact record's features from an impulse calibration (module docstring).

    Parameters
    ----------
    calibration : ccedi.calibrate.loop.Calibration
        The calibration of an impulse record of the finger.
    contact : Experiment
        The contact experiment (:func:`load_contact_setup`).
    recorded : bool, optional
        Whether ``contact`` holds a measured record (its features are then measured and
        compared). Default True.

    Returns
    -------
    ContactPrediction
        The predicted reading and features, with intervals.

    Raises
    ------
    InputError
        The calibration is not of an impulse record, the experiment not a contact one,
        their fingers differ (:func:`check_same_finger`), or a reading does not hold the
        whole contact (:func:`contact_features`).
    ccedi.errors.SolverError
        The chain diverged.
    """
    impulse = calibration.experiment
    if impulse.kind != "impulse" or contact.kind != "contact":
        raise InputError(f"a contact record is predicted from an impulse record's calibration, got a {impulse.kind} "
                         f"calibration ({impulse.record.source}) and a {contact.kind} record ({contact.record.source})")
    check_same_finger(impulse, contact)
    mean, cov = impulse_parameters(calibration.final)
    shift = mean - impulse_parameters(calibration.baseline)[0]
    to_contact = np.array([impulse.finger.E_Pa / contact.finger.E_Pa, 1.0])   # E_factor over the contact's E
    mean, shift = mean * to_contact, shift * to_contact
    cov = cov * np.outer(to_contact, to_contact) + np.outer(shift, shift)
    model = DrumContactModel(contact)
    t = contact.time_s

    def reading(p):
        return model.predict({"E_factor": float(p[0]), "alpha_per_s": float(p[1])})

    centre = reading(mean)
    predicted, chain_std = fea_equivalent(contact_features(t, centre), mean[1])
    spread = [fea_equivalent(contact_features(t, reading(p)), p[1])[0] for p in sigma_points(mean, cov)]
    sigma = noise_std(contact) if recorded else (contact.noise_std_N or 0.0)
    rng = np.random.default_rng(NOISE_SEED)
    noisy = [contact_features(t, centre + sigma * rng.standard_normal(len(t))) for _ in range(NOISE_DRAWS if sigma else 0)]
    measured = contact_features(t, contact.signal) if recorded else {}
    features = {}
    for k in FEATURES:
        features[k] = FeaturePrediction(name=k, predicted=predicted[k], std_parameters=float(np.std([s[k] for s in spread])),
                                        std_chain=chain_std[k], std_noise=float(np.std([s[k] for s in noisy])) if noisy else 0.0,
                                        measured=measured.get(k))
    return ContactPrediction(contact=contact, recorded=recorded,
                             values={"E_factor": float(mean[0]), "alpha_per_s": float(mean[1])}, covariance=cov,
                             selection_shift=shift,
                             reading_N=centre, features=features, noise_std_N=float(sigma),
                             effects_not_carried=tuple(calibration.final.effects))
