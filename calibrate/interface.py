"""What the calibration loop asks of a calibration model, typed.

A calibration model is not a run of the finger (that is :mod:`ccedi.models`' interface,
``run(alpha, ...)``): it predicts one measured record, with the sensor, for any values of
named parameters (the baseline alpha and E, plus the parameters of the catalogued
effects the loop adds), and knows what its residual points to. Both calibration models
are made from :mod:`ccedi.rom`'s reductions of the full FE models: the impulse record's
:class:`ccedi.calibrate.model.FingerModel` from the modal reductor's basis
(:func:`ccedi.rom.modal.modal_basis`, with a tip mass and a compliant root as Ritz
terms), the contact record's :class:`ccedi.calibrate.contact_model.DrumContactModel` from
the contact model's reductor (:func:`ccedi.rom.contact_rom.reduce_contact_model` of the
:class:`ccedi.fea.contact.drum.FullContactModel`), corrected by that full model when asked.

The loop (:func:`ccedi.calibrate.loop.calibrate`), the fits (:mod:`ccedi.calibrate.fit`),
the adequacy check and the report see a model only through :class:`CalibrationModel`; a
model whose base is corrected by its full FE model also has :class:`FeaCorrected`'s two
methods, which the loop calls only after :meth:`CalibrationModel.correct_at` answered.
"""
from typing import Protocol, runtime_checkable


@runtime_checkable
class CalibrationModel(Protocol):
    """A model the calibration loop fits to one record.

    Attributes
    ----------
    exp : ccedi.calibrate.experiment.Experiment
        The record and its declaration.
    catalogue : dict
        The effects it can add, by name (:class:`ccedi.calibrate.effects.Effect`).
    model_error : float
        Standard deviation of the model's own error against the finger, in the record's
        unit (0 when the base model is the finger's FE modes).
    scales : ccedi.calibrate.effects.Scales
        The record's scales for bounds and starting values.
    measurements : dict
        The measurements :meth:`observables` can name, with their units.
    """

    exp: object
    catalogue: dict
    model_error: float
    scales: object

    @property
    def measurements(self):
        """The measurements :meth:`observables` can name."""

    def parameters(self, effects):
        """Parameters of the baseline plus ``effects``: list of (Parameter, start)."""

    def baseline_starts(self):
        """Starting points of the baseline fit: list of dict."""

    def candidate_starts(self, name, current, evidence):
        """Starting values for a candidate effect: (start dict, tuple of further starts)."""

    def predict(self, v):
        """The record's signal predicted at parameter values ``v`` (ndarray, the record's unit)."""

    def assess(self, baseline, sigma):
        """Adequacy of the declaration (an object with ``adequate`` and ``message()``)."""

    def analyse(self, fitted, sigma):
        """Residual signatures of a fit (dict)."""

    def suggest(self, evidence):
        """Effects the signatures point to: list of (name, reason)."""

    def observables(self, v):
        """What a further measurement could show at ``v`` (dict, units in the keys)."""

    def unexplained_term(self, fitted):
        """The best sparse term on a fit's residual."""

    def correct_at(self, v):
        """Correct the base model by its full FE model at ``v``; None when it has none."""

    def calibrated(self, v):
        """The calibrated study inputs at ``v`` (dict, SI units in the keys)."""


@runtime_checkable
class FeaCorrected(Protocol):
    """A calibration model whose reduced base is corrected by its full FE model."""

    def corrected_near(self, v):
        """Whether the last correction was made close enough to ``v`` (bool)."""

    def fea_check(self, v, sigma):
        """The full FEA against the record at the final values (dict)."""
