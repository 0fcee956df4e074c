"""The calibration model: the declared finger's FE-derived Rayleigh-damped modes
(:mod:`ccedi.calibrate.finger_modes`, tip mass and root compliance as Ritz additions) plus
any set of catalogued effects, each a physical extension with named SI parameters.

Baseline parameters: ``alpha_per_s`` (mass-proportional damping, 1/s) and ``E_factor``
(Young's modulus over the declared one, within the sidecar's tolerance; the FE modes are
built once at the declared E and their frequencies scale exactly as sqrt(E_factor)). The
model keeps the y-bending modes the pulse rings: after a pulse F0 of length T, mode i
vibrates freely with tip amplitude F0 b_i^2 |2 sin(omega_i T / 2)| / omega_i^2 <=
F0 b_i^2 min(2, omega_i T) / omega_i^2; the modes whose bound is at least
``MODE_AMPLITUDE`` of the first mode's are kept (at least ``MIN_MODES``). A 10 ms pulse
on the 8-in finger keeps 6 modes (up to 306 Hz), a 1 ms pulse all 10. With modes omega_i, tip
values b_i and weight participations p_i::

    zeta_i = alpha / (2 omega_i) + beta omega_i / 2
    w(t)   = tip displacement of the modal model under the pulse F0 on [t0, t0 + T), plus
             the static sag g_t sum b_i p_i / omega_i^2
    y(t)   = w(t - tau) + s_2 w(t - tau)^2 + y_0 + y_1 t         (what the sensor reports)

The catalogue (:data:`ccedi.calibrate.effects.CATALOGUE`) lists each effect's parameters with units, bounds and
a starting value scaled to the record (mass, stiffness, first frequency, amplitude).
Linear effects keep the exact pulse response of :class:`ccedi.rom.modal.ModalROM`, the
viscoelastic finger alone the exact one of
:func:`ccedi.calibrate.dynamics.viscoelastic_pulse_response`; distributed drag and the
nonlinear tip forces use :func:`ccedi.calibrate.dynamics.integrate_tip`.
"""

from functools import cached_property

import numpy as np
from scipy.optimize import brentq

from ccedi.rom.modal import ModalROM

from .adequacy import assess, declared_effective_mass_kg, effective_tip_mass_kg, record_first_mode
from .dynamics import integrate_tip, viscoelastic_pulse_response
from .effects import CATALOGUE, Parameter, Scales
from .experiment import Experiment
from .finger_modes import finger_basis
from .residual import analyse, suggest
from .sparse import sparse_term

MIN_MODES = 3
"""Fewest y-bending modes kept, whatever the pulse."""
MODE_AMPLITUDE = 1e-3
"""Least bound of a mode's free-vibration tip amplitude after the pulse, relative to the
first mode's, for the mode to be kept (module docstring) [-]."""


def rung_modes(omega_rad_s, tip, duration_s):
    """Number of modes the pulse rings (module docstring).

    Parameters
    ----------
    omega_rad_s : numpy.ndarray
        Angular frequencies omega_i, ascending [rad/s].
    tip : numpy.ndarray
        Tip values b_i [1/sqrt(kg)].
    duration_s : float
        Pulse length T [s].

    Returns
    -------
    int
        One more than the index of the last mode whose amplitude bound
        b_i^2 min(2, omega_i T) / omega_i^2 is at least MODE_AMPLITUDE of the first
        mode's, and at least min(MIN_MODES, number of modes).
    """
    bound = tip**2 * np.minimum(2.0, omega_rad_s * duration_s) / omega_rad_s**2
    rung = np.flatnonzero(bound >= MODE_AMPLITUDE * bound[0])
    return max(min(MIN_MODES, len(omega_rad_s)), int(rung[-1]) + 1)


NONLINEAR = {"drag_N_s2_m3", "friction_N", "cubic_N_m3"}
"""Parameters of the effects that make the model nonlinear (integrated numerically)."""


def baseline_parameters(exp: Experiment, s: Scales):
    """Parameters of the declared model with their starting values.

    Parameters
    ----------
    exp : Experiment
        The experiment (its declared alpha and E tolerance).
    s : Scales
        Record scales (first frequency omega_1).

    Returns
    -------
    list of (Parameter, float)
        ``alpha_per_s`` in [1e-3, 20] omega_1 [1/s], starting at the sidecar's value
        (moved into those bounds) or 0.2 omega_1 (zeta_1 = 0.1); ``E_factor`` within
        1 +- tolerance [-], starting at 1.
    """
    alpha = Parameter("alpha_per_s", 1e-3 * s.omega1, 20.0 * s.omega1)
    alpha0 = 0.2 * s.omega1 if exp.alpha_per_s is None else min(max(exp.alpha_per_s, alpha.lower), alpha.upper)
    tol = exp.E_tolerance
    return [(alpha, alpha0),
            (Parameter("E_factor", 1.0 - tol, 1.0 + tol + 1e-9, log=False, scale=0.01), 1.0)]


MEASUREMENTS = {"mode_1_frequency_hz": "the first mode's frequency",
                "mode_2_frequency_hz": "the second mode's frequency (a shorter pulse or a hammer tap rings it)",
                "mode_3_frequency_hz": "the third mode's frequency (a hammer tap rings it)",
                "static_tip_flexibility_m_N": "the static tip deflection under a known tip load",
                "turned_over_change_m": "the rest reading with the finger turned over (gravity reversed)"}
"""The measurements a fitted impulse model can name (:meth:`FingerModel.observables`,
:func:`ccedi.calibrate.loop.separating_measurement`)."""


N_E_STARTS = 17
"""E_factor values across the tolerance in the baseline's starting grid."""
ZETA_STARTS = (0.01, 0.03, 0.1, 0.3, 1.0, 2.0)
"""First-mode damping ratios in the baseline's starting grid."""


class FingerModel:
    """Predicts the sensor reading of an :class:`Experiment` for parameter values.

    Takes the FE basis of the declared finger (:func:`ccedi.calibrate.finger_modes.finger_basis`,
    cached per finger) and builds the record scales (:class:`ccedi.calibrate.effects.Scales`)
    once.

    Parameters
    ----------
    exp : Experiment
        The validated experiment.

    Attributes
    ----------
    exp : Experiment
        The experiment.
    basis : ccedi.calibrate.finger_modes.FingerBasis
        The finger's FE modes at the declared E.
    n_modes : int
        y-bending modes kept: those below the record's sampling rate, at least MIN_MODES.
    scales : Scales
        Scales of the record for bounds and starting values.
    catalogue : dict
        :data:`ccedi.calibrate.effects.CATALOGUE`.
    """

    catalogue = CATALOGUE
    model_error = 0.0
    """Standard deviation of the model's own error against the finger [m]: none beyond
    the noise (the FE modes are the finger's)."""

    def discrepancy_covariance(self, reading):
        """Covariance of the model's own error: none (the FE modes are the finger's).

        Parameters
        ----------
        reading : numpy.ndarray
            The model's reading at the record's samples [m] (unused).

        Returns
        -------
        None
            No discrepancy.
        """
        return None

    def __init__(self, exp: Experiment):
        f = exp.finger
        self.exp = exp
        self.basis = finger_basis(f.length_m, tuple(f.semi_axes_m), nu=f.nu, rho_kg_m3=f.rho_kg_m3, E_Pa=f.E_Pa)
        full = self.basis.modes(1.0)
        self.n_modes = rung_modes(full.omega_rad_s, full.tip, exp.duration_s)
        modes = self.basis.modes(1.0, n_modes=self.n_modes)
        y = exp.displacement_m
        ei = f.E_Pa * f.second_moment_m4
        self.scales = Scales(mass_kg=self.basis.mass_kg, stiffness_N_m=1.0 / modes.static_flexibility_m_N,
                             ei_over_l=ei / f.length_m, omega1=float(modes.omega_rad_s[0]),
                             omega2=float(modes.omega_rad_s[1]),
                             amplitude_m=0.5 * float(np.ptp(y)), duration_s=float(exp.time_s[-1] - exp.time_s[0]),
                             length_m=f.length_m)

    def parameters(self, effects):
        """Parameters of the baseline plus ``effects``, with starting values.

        Parameters
        ----------
        effects : iterable of str
            Effect names in :data:`ccedi.calibrate.effects.CATALOGUE`.

        Returns
        -------
        list of (Parameter, float)
            Baseline parameters first, then each effect's.
        """
        out = baseline_parameters(self.exp, self.scales)
        for name in effects:
            out += CATALOGUE[name].parameters(self.scales)
        return out

    def baseline_starts(self):
        """Starting points of the baseline fit: ``N_E_STARTS`` values of E across its
        tolerance times the first-mode damping ratios ``ZETA_STARTS``,
        alpha = 2 zeta omega_1 sqrt(E_factor).

        Returns
        -------
        list of dict
            ``{"E_factor", "alpha_per_s"}`` values.
        """
        tol = self.exp.E_tolerance
        return [{"E_factor": float(e), "alpha_per_s": 2.0 * z * self.scales.omega1 * np.sqrt(e)}
                for e in np.linspace(1.0 - tol, 1.0 + tol, N_E_STARTS) for z in ZETA_STARTS]

    def candidate_starts(self, name, current, evidence):
        """Starting values of a candidate effect's fit beyond the catalogue's: the
        viscoelastic relaxation time has several local minima, so two more starts
        (10 ms and 0.3 s) are tried; a tip mass and a compliant root are also started where
        they give the declared finger the record's own first mode (:meth:`first_mode_start`).

        Parameters
        ----------
        name : str
            The candidate effect.
        current : ccedi.calibrate.fit.Fit
            The model it is added to.
        evidence : dict
            Its residual signatures (unused here).

        Returns
        -------
        start : dict
            Values overriding the catalogue's start (none).
        extra : tuple of dict
            Further starts tried.
        """
        if name == "viscoelastic":
            return {}, ({"prony_tau_s": 0.01}, {"prony_tau_s": 0.3})
        own = self.first_mode_start(name)
        return {}, (own,) if own else ()

    @cached_property
    def _own_first_mode(self):
        """The record's own first mode and its effective tip mass over the declared finger's."""
        mode = record_first_mode(self.exp, self.exp.noise_std_m)
        ratio = effective_tip_mass_kg(self.exp, mode) / declared_effective_mass_kg(self) if mode.measurable else None
        return mode, ratio

    def first_mode_start(self, name):
        """E and a tip mass or root stiffness with which the declared finger has the record's
        own first mode: its frequency f_r and its effective tip mass m_r
        (:mod:`ccedi.calibrate.adequacy`). A tip mass adds m_r - m_1 to the declared
        finger's m_1 and E = (f_r / f_1)^2 m_r / m_1; a root of stiffness k gives the mode the
        effective mass m_1 b_1^2 / b(k / E)^2 and the frequency sqrt(E) f(k / E). The fits
        from the catalogue's start and the current E can end in a local minimum far from
        it (a soft root layer: k 1.9 N m/rad at 3.4 noise std, against 1.05 N m/rad at 1.1).

        Parameters
        ----------
        name : str
            The candidate effect.

        Returns
        -------
        dict
            ``E_factor`` and the effect's parameter (clipped into their bounds), or empty:
            another effect, a first mode not measurable, or no such parameter (m_r below
            m_1, or above what the softest root reaches).
        """
        mode, ratio = self._own_first_mode
        if name not in ("tip_mass", "root_compliance") or ratio is None or ratio <= 1.0:
            return {}
        omega_r = 2.0 * np.pi * mode.frequency_hz
        b1 = float(self.basis.tip[0])
        if name == "tip_mass":
            start = {"E_factor": (omega_r / self.scales.omega1) ** 2 * ratio, "tip_mass_kg": (ratio - 1.0) / b1**2}
        else:
            first = lambda log_k: self.basis.modes(1.0, root_stiffness=10.0**log_k, n_modes=1)
            excess = lambda log_k: (b1 / float(first(log_k).tip[0])) ** 2 - ratio
            (root, _), = CATALOGUE[name].parameters(self.scales)
            lo, hi = np.log10(root.lower), np.log10(root.upper)
            if not excess(lo) > 0.0 > excess(hi):
                return {}
            log_k = brentq(excess, lo, hi, xtol=1e-4)
            E = (omega_r / float(first(log_k).omega_rad_s[0])) ** 2
            start = {"E_factor": E, root.name: E * 10.0**log_k}
        bounds = {p.name: (p.lower, p.upper) for p, _ in self.parameters([name])}
        return {k: float(np.clip(v, *bounds[k])) for k, v in start.items()}

    def assess(self, baseline, sigma):
        """Adequacy of the declared finger (:func:`ccedi.calibrate.adequacy.assess`).

        Parameters
        ----------
        baseline : ccedi.calibrate.fit.Fit
            The baseline fit.
        sigma : float
            Noise std [m].

        Returns
        -------
        ccedi.calibrate.adequacy.Adequacy
            The verdict and its evidence.
        """
        return assess(self, baseline, sigma)

    def analyse(self, fitted, sigma):
        """Residual signatures (:func:`ccedi.calibrate.residual.analyse`).

        Parameters
        ----------
        fitted : ccedi.calibrate.fit.Fit
            The fit.
        sigma : float
            Noise std [m] (the analysis uses the experiment's own, :func:`ccedi.calibrate.residual.noise_std`).

        Returns
        -------
        dict
            The signatures.
        """
        return analyse(self, fitted)

    def suggest(self, evidence):
        """Effects the signatures point to (:func:`ccedi.calibrate.residual.suggest`).

        Parameters
        ----------
        evidence : dict
            :meth:`analyse`'s signatures.

        Returns
        -------
        list of (str, str)
            (effect, reason).
        """
        return suggest(evidence)

    def observables(self, v):
        """What a measurement could show of a fitted model: its first three frequencies and
        its static tip flexibility.

        Parameters
        ----------
        v : dict
            Parameter values.

        Returns
        -------
        dict
            ``mode_1_frequency_hz``, ``mode_2_frequency_hz``, ``mode_3_frequency_hz`` [Hz],
            ``static_tip_flexibility_m_N`` [m/N] (a static tip load test) and
            ``turned_over_change_m`` [m] (the change of the rest reading with the finger
            turned over: twice the gravity sag).
        """
        m = self.modes(v)
        out = {f"mode_{i + 1}_frequency_hz": float(m.omega_rad_s[i] / (2.0 * np.pi)) for i in range(3)}
        out["static_tip_flexibility_m_N"] = m.static_flexibility_m_N
        out["turned_over_change_m"] = -2.0 * v.get("gravity_m_s2", 0.0) * m.static_sag_per_g
        return out

    @property
    def measurements(self):
        """The measurements :meth:`observables` can name (:data:`MEASUREMENTS`)."""
        return MEASUREMENTS

    def unexplained_term(self, fitted):
        """The best sparse tip-force term on a fit's residual (:func:`ccedi.calibrate.sparse.sparse_term`).

        Parameters
        ----------
        fitted : ccedi.calibrate.fit.Fit
            The final fit.

        Returns
        -------
        ccedi.calibrate.sparse.SparseTerm
            The term.
        """
        m = self.modes(fitted.values)
        v = fitted.values
        zeta = v["alpha_per_s"] / (2.0 * m.omega_rad_s) + v.get("beta_s", 0.0) * m.omega_rad_s / 2.0
        return sparse_term(self.exp.time_s, self.exp.displacement_m - fitted.prediction, fitted.prediction,
                           modes=m, zeta=zeta)

    def correct_at(self, v):
        """No correction: the base model is the FE model's own modes (the contact model's
        chain is corrected by its FEA, :meth:`ccedi.calibrate.contact_model.DrumContactModel.correct_at`).

        Parameters
        ----------
        v : dict
            Parameter values (unused).

        Returns
        -------
        None
        """
        return None

    def calibrated(self, v):
        """The calibrated study inputs of parameter values ``v``.

        Parameters
        ----------
        v : dict
            Final parameter values.

        Returns
        -------
        dict
            ``E_Pa`` (declared E x E_factor) and ``alpha_per_s``.
        """
        return {"E_Pa": self.exp.finger.E_Pa * v["E_factor"], "alpha_per_s": v["alpha_per_s"]}

    def modes(self, v):
        """Modes of the finger for parameter values ``v``.

        Parameters
        ----------
        v : dict
            Parameter values by name: ``E_factor`` (required), ``tip_mass_kg`` and
            ``root_stiffness_N_m_rad`` (optional; absent means none / rigid clamp).

        Returns
        -------
        Modes
            The ``n_modes`` lowest modes (one more with a compliant root).
        """
        root = v.get("root_stiffness_N_m_rad")
        return self.basis.modes(v["E_factor"], tip_mass_kg=v.get("tip_mass_kg", 0.0), root_stiffness=root,
                                n_modes=self.n_modes + (root is not None))

    def predict(self, v, time_s=None):
        """Sensor reading predicted for parameter values ``v`` (module docstring).

        Parameters
        ----------
        v : dict
            Parameter values by name (SI units as named); ``alpha_per_s`` and ``E_factor``
            are required, absent effects are off.
        time_s : numpy.ndarray, optional
            Times [s]. Default: the record's sample times.

        Returns
        -------
        numpy.ndarray
            Sensor reading y(t) [m].
        """
        exp = self.exp
        t = exp.time_s if time_s is None else time_s
        m = self.modes(v)
        w = m.omega_rad_s
        zeta = v["alpha_per_s"] / (2.0 * w) + v.get("beta_s", 0.0) * w / 2.0
        delay = v.get("delay_s", 0.0)
        if NONLINEAR.intersection(v):
            u = integrate_tip(t, m, zeta, force_N=exp.force_N, duration_s=exp.duration_s, start_s=exp.start_s,
                              prony_g=v.get("prony_g", 0.0), prony_tau_s=v.get("prony_tau_s", 1.0),
                              drag_N_s2_m3=v.get("drag_N_s2_m3", 0.0), friction_N=v.get("friction_N", 0.0),
                              cubic_N_m3=v.get("cubic_N_m3", 0.0))
            if delay:
                u = np.interp(t - delay, t, u, left=0.0)
        elif "prony_g" in v:
            u = viscoelastic_pulse_response(t - exp.start_s - delay, m, zeta, force_N=exp.force_N,
                                            duration_s=exp.duration_s, prony_g=v["prony_g"],
                                            prony_tau_s=v.get("prony_tau_s", 1.0))
        else:
            rom = ModalROM(omega_rad_s=w, gain=m.tip**2, zeta_fitted=zeta)
            u = rom.pulse_response(t - exp.start_s - delay, exp.force_N, exp.duration_s)
        u = u + v.get("gravity_m_s2", 0.0) * m.static_sag_per_g
        return u + v.get("sensor_quadratic_per_m", 0.0) * u**2 + v.get("offset_m", 0.0) + v.get("drift_m_s", 0.0) * t
