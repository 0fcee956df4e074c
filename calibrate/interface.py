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
        """Parameters of the baseline plus ``effects``.

        Parameters
        ----------
        effects : tuple of str
            Effect names in :attr:`catalogue`.

        Returns
        -------
        list of (ccedi.calibrate.effects.Parameter, float)
            Each parameter with its starting value, the baseline's first.
        """

    def discrepancy_covariance(self, reading):
        """Covariance of the base model's own error at the record's samples, or None.

        Parameters
        ----------
        reading : numpy.ndarray
            The model's reading at the record's samples (the error's envelope).

        Returns
        -------
        numpy.ndarray or None
            Shape (n, n), in the record's unit squared; None when the base model is the
            finger's own FE modes.
        """

    def baseline_starts(self):
        """Starting points of the baseline fit: list of dict."""

    def candidate_starts(self, name, current, evidence):
        """Starting values for a candidate effect.

        Parameters
        ----------
        name : str
            The candidate effect.
        current : ccedi.calibrate.fit.Fit
            The model it is added to.
        evidence : dict
            Its residual signatures (:meth:`analyse`).

        Returns
        -------
        tuple
            (dict of starting values, tuple of further starting points).
        """

    def predict(self, v):
        """The record's signal predicted at parameter values ``v``.

        Parameters
        ----------
        v : dict
            Parameter values by name (SI units as named).

        Returns
        -------
        numpy.ndarray
            At the record's sample times, in the record's unit.
        """

    def assess(self, baseline, sigma):
        """Adequacy of the declaration against the record.

        Parameters
        ----------
        baseline : ccedi.calibrate.fit.Fit
            The baseline fit.
        sigma : float
            The residual std the loop expects (noise and model error), record's unit.

        Returns
        -------
        object
            With ``adequate`` (bool) and ``message()``.
        """

    def analyse(self, fitted, sigma):
        """Residual signatures of a fit.

        Parameters
        ----------
        fitted : ccedi.calibrate.fit.Fit
            The fit.
        sigma : float
            The residual std the loop expects, record's unit.

        Returns
        -------
        dict
            The signatures, by name.
        """

    def suggest(self, evidence):
        """Effects the signatures point to.

        Parameters
        ----------
        evidence : dict
            :meth:`analyse`'s signatures.

        Returns
        -------
        list of (str, str)
            (effect, reason).
        """

    def observables(self, v):
        """What a further measurement could show at ``v``.

        Parameters
        ----------
        v : dict
            Parameter values.

        Returns
        -------
        dict
            Values by measurement name, units in the names.
        """

    def unexplained_term(self, fitted):
        """The best sparse term on a fit's residual.

        Parameters
        ----------
        fitted : ccedi.calibrate.fit.Fit
            The final fit.

        Returns
        -------
        ccedi.calibrate.sparse.SparseTerm
        """

    def correct_at(self, v):
        """Correct the base model by its full FE model at ``v``.

        Parameters
        ----------
        v : dict
            Parameter values.

        Returns
        -------
        object or None
            The correction, or None for a model without one.
        """

    def calibrated(self, v):
        """The calibrated study inputs at ``v``.

        Parameters
        ----------
        v : dict
            Final parameter values.

        Returns
        -------
        dict
            Inputs by name, SI units in the names.
        """


@runtime_checkable
class FeaCorrected(Protocol):
    """A calibration model whose reduced base is corrected by its full FE model."""

    def corrected_near(self, v):
        """Whether the last correction was made close enough to ``v``.

        Parameters
        ----------
        v : dict
            Parameter values.

        Returns
        -------
        bool
        """

    def fea_check(self, v, sigma):
        """The full FEA against the record at the final values.

        Parameters
        ----------
        v : dict
            Final parameter values.
        sigma : float
            The calibration's residual std, record's unit.

        Returns
        -------
        dict
            Its errors against the record.
        """
