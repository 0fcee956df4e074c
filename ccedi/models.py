"""One interface for full and reduced models: what a model takes and what it answers.

As in pyMOR, a reductor takes a full model and returns a reduced one with the same
interface, so a study (the CCEDI search, the design surrogate, the FEA re-check,
``rom-check``) swaps one for the other with one argument. Two kinds of model:

* an **impulse model** (:class:`ImpulseModel`): a clamped structure under a tip force
  pulse of ``force_N`` [N] held for ``duration_s`` [s], with mass-proportional
  (Rayleigh) damping ``alpha``; ``run(alpha, t_end_s, n_outputs)`` answers an
  :class:`ImpulseResponse`. Full: :class:`ccedi.fea.cases.studies.FullImpulseModel` (the explicit
  FE finger, :func:`ccedi.fea.cases.studies.finger_impulse_model`, and the steel rod,
  :func:`ccedi.fea.cases.steel_rod.steel_rod_impulse_model`). Reduced:
  :class:`ccedi.rom.modal.ModalImpulseModel` (from :func:`ccedi.rom.modal.reduce_impulse_model`).
* a **contact model** (:class:`ContactModel`): the finger on the rotating drum sweeping
  over the object (:class:`ccedi.fea.contact.drum.DrumSetup`); ``run(alpha, *, damping, t_end_s,
  n_outputs, progress)`` answers a :class:`ContactResponse`. Full:
  :class:`ccedi.fea.contact.drum.FullContactModel`; reduced:
  :class:`ccedi.rom.contact_rom.ReducedContactModel` ('stations' and 'face' contact).

Each response holds a history (one row per output time) whose **core columns**
(:data:`IMPULSE_CORE_COLUMNS`, :data:`CONTACT_CORE_COLUMNS`) and a summary whose **core
keys** (:data:`IMPULSE_CORE_SUMMARY`, :data:`CONTACT_CORE_SUMMARY`) mean the same in
every model of the kind; a model may add extras on top, declared per model
(:data:`FE_CONTACT_EXTRA_COLUMNS`, :data:`ROM_CONTACT_EXTRA_SUMMARY`, ...). Code that
must work with either model reads the core only.

The run arguments are checked in one place, :func:`validate_run_args`, by every model.
"""
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
import pandas as pd

from ccedi.errors import InputError, require_finite_positive

DAMPING_KINDS = ("global", "relative")
"""Mass-damping kinds of a run: "global" acts on the absolute velocity, "relative" on the
velocity in the rotating drum frame (the same for a structure that does not rotate)."""


@dataclass(frozen=True)
class Column:
    """One declared history column (or summary key).

    Parameters
    ----------
    name : str
        Column name as it appears in the history DataFrame (and the CSV files).
    unit : str
        SI unit ("-" for a dimensionless number or a count).
    meaning : str
        What the value is, the same in every model that declares the column.
    """

    name: str
    unit: str
    meaning: str


def _names(columns):
    return tuple(c.name for c in columns)


IMPULSE_CORE_COLUMNS = (
    Column("time_s", "s", "output time, n_outputs equal steps after 0 (0 excluded)"),
    Column("tip_uy_m", "m", "tip displacement along the load (+y): the face-weighted mean of the tip nodes "
                            "(FE finger), the tip node (rod), the modal output (modal ROM)"),
)
"""History columns every impulse model answers."""

IMPULSE_CORE_SUMMARY = (
    Column("model", "-", "name of the model (e.g. 'fea', 'modal-6')"),
    Column("alpha_per_s", "1/s", "mass-proportional damping coefficient of the run"),
    Column("wall_time_s", "s", "wall time of the run"),
    Column("warnings", "-", "list of the run's validity warnings (str; empty for a healthy run), see "
                            "ccedi.fea.solvers.validity"),
)
"""Summary keys every impulse model answers."""

FE_IMPULSE_EXTRA_COLUMNS = (
    Column("tip_ux_m", "m", "tip displacement along x"),
    Column("tip_uz_m", "m", "tip displacement along z"),
    Column("max_von_mises_Pa", "Pa", "largest element von Mises stress"),
    Column("max_log_strain", "-", "largest principal logarithmic strain of the solid elements (NaN without them)"),
    Column("reaction_y_N", "N", "clamp reaction along y (and the other solver columns: energies, "
                                "reaction_x/z_N, ... of ccedi.fea.solvers.explicit.run)"),
)
"""Extra history columns of the full FE impulse model (the explicit solver's history)."""

CONTACT_CORE_COLUMNS = (
    Column("time_s", "s", "output time, n_outputs equal steps after 0 (0 excluded)"),
    Column("reaction_force_N", "N", "magnitude of the contact force on the object"),
    Column("contact_force_x_N", "N", "contact force on the object along x (drum plane)"),
    Column("contact_force_y_N", "N", "contact force on the object along y (drum plane)"),
    Column("contact_nodes", "-", "number of active contact points (those carrying a contact force): "
                                 "finger surface nodes in the full FE model, contact points "
                                 "(stations or face points) in the reduced model"),
    Column("contact_point_x_m", "m", "force-weighted contact point, x (NaN without contact)"),
    Column("contact_point_y_m", "m", "force-weighted contact point, y (NaN without contact)"),
    Column("max_penetration_m", "m", "deepest penetration of a contact point into the object"),
    Column("max_von_mises_Pa", "Pa", "largest von Mises stress in the finger"),
    Column("tip_ux_m", "m", "tip displacement from its initial position, x (drum frame at rest)"),
    Column("tip_uy_m", "m", "tip displacement from its initial position, y"),
)
"""History columns every contact model answers (names as in the CSV files)."""

FE_CONTACT_EXTRA_COLUMNS = (
    Column("contact_force_z_N", "N", "contact force on the object along z (drum axis)"),
    Column("max_object_von_mises_Pa", "Pa", "largest object von Mises stress (linear static solve; NaN "
                                            "when the model runs without it)"),
    Column("contact_patch_start_m", "m", "contact patch along the finger, nearest the root"),
    Column("contact_patch_end_m", "m", "contact patch along the finger, nearest the tip"),
    Column("penalty_energy_J", "J", "stored contact penalty energy (and the solver's other energies: "
                                    "kinetic, internal, hourglass, damping, external work, friction work)"),
)
"""Extra history columns of the full FE contact model."""

CONTACT_CORE_SUMMARY = (
    Column("model", "-", "name of the model ('fea', 'rom-corotational', 'rom-linear')"),
    Column("alpha_per_s", "1/s", "mass-proportional damping coefficient of the run"),
    Column("damping", "-", "damping kind, 'global' or 'relative'"),
    Column("wall_time_s", "s", "wall time of the run"),
    Column("steps", "-", "time steps taken"),
    Column("max_finger_stress_Pa", "Pa", "largest finger von Mises stress over the run"),
    Column("contact_start_s", "s", "first output with contact (None without contact)"),
    Column("contact_end_s", "s", "last output with contact (None without contact)"),
    Column("contact_duration_s", "s", "contact_end_s - contact_start_s (None without contact)"),
    Column("contact_ended", "-", "True when the contact ended before the last output"),
    Column("first_contact_point_m", "m", "[x, y] contact point at contact_start_s (None without contact)"),
    Column("last_contact_point_m", "m", "[x, y] contact point at contact_end_s (None without contact)"),
    Column("peak_reaction_force_N", "N", "largest reaction_force_N over the run (0 without contact)"),
    Column("warnings", "-", "list of the run's validity warnings (str; empty for a healthy run), see "
                            "ccedi.fea.solvers.validity"),
)
"""Summary keys every contact model answers (the timing keys from :func:`contact_timing`;
``warnings`` from the model's validity checks, :mod:`ccedi.fea.solvers.validity`)."""

FE_CONTACT_EXTRA_SUMMARY = (
    Column("theta0_rad", "rad", "initial finger angle"),
    Column("first_contact_side", "-", "'front' or 'rear' half of the object at first contact"),
    Column("last_contact_side", "-", "'front' or 'rear' half of the object at last contact"),
    Column("max_object_stress_Pa", "Pa", "largest object stress (None when run without it)"),
    Column("max_penetration_m", "m", "deepest penetration over the run"),
    Column("penetration_to_thickness", "-", "max_penetration_m over the finger's soft thickness"),
    Column("energy_balance_error", "-", "largest |initial energy + external work - kinetic, stored and dissipated "
                                        "energy| over the largest energy (ccedi.fea.solvers.validity.energy_balance_error)"),
    Column("hourglass_energy_fraction", "-", "largest hourglass energy over largest internal energy"),
    Column("max_log_strain", "-", "largest principal logarithmic strain in the finger over the run"),
    Column("friction_work_J", "J", "friction work at the end"),
    Column("max_penalty_energy_J", "J", "largest stored penalty energy"),
)
"""Extra summary keys of the full FE contact model."""

ROM_CONTACT_EXTRA_SUMMARY = (
    Column("dt_s", "s", "fixed time step of the chain"),
    Column("segments", "-", "superelements along the finger"),
    Column("stiffness_scale", "-", "bending stiffness scale of the fit to the FE tip stiffness"),
)
"""Extra summary keys of the reduced contact model."""


def validate_run_args(alpha, t_end_s, n_outputs, *, damping="global"):
    """Check the arguments of a model run (every model calls this).

    Parameters
    ----------
    alpha : float
        Mass-proportional damping coefficient [1/s], finite and >= 0.
    t_end_s : float
        Simulated time [s], finite and > 0.
    n_outputs : int
        Number of output times (>= 1).
    damping : str, optional
        Damping kind, one of :data:`DAMPING_KINDS`.

    Returns
    -------
    tuple
        ``(alpha, t_end_s, n_outputs)`` as (float, float, int).

    Raises
    ------
    InputError
        When an argument is out of range; the message names it.
    """
    alpha = require_finite_positive("alpha (mass-proportional damping, 1/s)", alpha, allow_zero=True)
    if damping not in DAMPING_KINDS:
        raise InputError(f"damping must be 'global' or 'relative', got {damping!r}")
    t_end_s = require_finite_positive("t_end_s (end time, s)", t_end_s)
    try:
        whole = int(n_outputs) == n_outputs
    except (TypeError, ValueError):
        whole = False
    if not whole or n_outputs < 1:
        raise InputError(f"n_outputs must be an integer >= 1, got {n_outputs!r}")
    return alpha, t_end_s, int(n_outputs)


def run_alphas(model, alphas, t_end_s, *, n_outputs=400):
    """Responses of an impulse model at several damping coefficients: in one batched pass
    when the model offers one (``model.run_many``, the full FE model's), else run by run.

    Parameters
    ----------
    model : ImpulseModel
        The model.
    alphas : sequence of float
        Mass-proportional damping coefficients [1/s].
    t_end_s : float
        Simulated time of every run [s].
    n_outputs : int, optional
        Output times of every run.

    Returns
    -------
    list of ImpulseResponse
        In the order of ``alphas``.
    """
    run_many = getattr(model, "run_many", None)
    if run_many is not None and len(alphas) > 1:
        return run_many(alphas, t_end_s, n_outputs)
    return [model.run(alpha, t_end_s, n_outputs) for alpha in alphas]


def _check_core(kind, history, summary, columns, keys):
    if not isinstance(history, pd.DataFrame):
        raise InputError(f"a {kind} history must be a pandas DataFrame, got {type(history).__name__}")
    missing = [c for c in _names(columns) if c not in history.columns]
    missing += [f"summary[{k!r}]" for k in _names(keys) if k not in summary]
    if missing:
        raise InputError(f"{kind} lacks its core columns / keys: {', '.join(missing)}")


@dataclass
class ImpulseResponse:
    """What an impulse model answers.

    Parameters
    ----------
    history : pandas.DataFrame
        One row per output time; holds at least :data:`IMPULSE_CORE_COLUMNS` (model
        extras such as :data:`FE_IMPULSE_EXTRA_COLUMNS` may follow).
    summary : dict
        Holds at least :data:`IMPULSE_CORE_SUMMARY`.

    Raises
    ------
    InputError
        When a core column or key is missing.
    """

    history: pd.DataFrame
    summary: dict

    core_columns = _names(IMPULSE_CORE_COLUMNS)
    core_summary = _names(IMPULSE_CORE_SUMMARY)

    def __post_init__(self):
        _check_core("impulse response", self.history, self.summary, IMPULSE_CORE_COLUMNS, IMPULSE_CORE_SUMMARY)

    def tip_signal(self):
        """The response as two arrays.

        Returns
        -------
        tuple of numpy.ndarray
            ``(time_s [s], tip_uy_m [m])``.
        """
        return self.history.time_s.values, self.history.tip_uy_m.values


@dataclass
class ContactResponse:
    """What a contact model answers.

    Parameters
    ----------
    history : pandas.DataFrame
        One row per output time; holds at least :data:`CONTACT_CORE_COLUMNS` (model
        extras such as :data:`FE_CONTACT_EXTRA_COLUMNS` may follow).
    summary : dict
        Holds at least :data:`CONTACT_CORE_SUMMARY` (model extras:
        :data:`FE_CONTACT_EXTRA_SUMMARY`, :data:`ROM_CONTACT_EXTRA_SUMMARY`).

    Raises
    ------
    InputError
        When a core column or key is missing.
    """

    history: pd.DataFrame
    summary: dict

    core_columns = _names(CONTACT_CORE_COLUMNS)
    core_summary = _names(CONTACT_CORE_SUMMARY)

    def __post_init__(self):
        _check_core("contact response", self.history, self.summary, CONTACT_CORE_COLUMNS, CONTACT_CORE_SUMMARY)

    def core(self):
        """The response restricted to its core columns and keys.

        Returns
        -------
        tuple
            ``(history DataFrame of the core columns, dict of the core summary keys)``.
        """
        return self.history[list(self.core_columns)], {k: self.summary[k] for k in self.core_summary}


@runtime_checkable
class ImpulseModel(Protocol):
    """A clamped structure under a tip force pulse, damped by ``alpha`` M.

    Attributes
    ----------
    name : str
        Name of the model (the ``model`` summary key).
    force_N : float
        Pulse force [N] along the output direction.
    duration_s : float
        How long the force is held [s], from t = 0.
    """

    name: str
    force_N: float
    duration_s: float

    def run(self, alpha, t_end_s, n_outputs=400) -> ImpulseResponse:
        """Response to the pulse.

        Parameters
        ----------
        alpha : float
            Mass-proportional damping coefficient [1/s].
        t_end_s : float
            Simulated time [s].
        n_outputs : int, optional
            Output times, equally spaced after 0.

        Returns
        -------
        ImpulseResponse

        Raises
        ------
        InputError
            Invalid arguments (:func:`validate_run_args`).
        """


@runtime_checkable
class ContactModel(Protocol):
    """The finger on the rotating drum sweeping over the object.

    Attributes
    ----------
    name : str
        Name of the model (the ``model`` summary key).
    setup : ccedi.fea.contact.drum.DrumSetup
        Geometry, speeds and materials.
    """

    name: str
    setup: object

    def run(self, alpha, *, damping="global", t_end_s=1.5, n_outputs=300, progress=False) -> ContactResponse:
        """Sweep over the object from t = 0.

        Parameters
        ----------
        alpha : float
            Mass-proportional damping coefficient [1/s].
        damping : str, optional
            "global" or "relative" (:data:`DAMPING_KINDS`).
        t_end_s : float, optional
            Simulated time [s].
        n_outputs : int, optional
            Output times, equally spaced after 0.
        progress : bool, optional
            Show a progress bar where the model has one (the full FE model).

        Returns
        -------
        ContactResponse

        Raises
        ------
        InputError
            Invalid arguments (:func:`validate_run_args`).
        ccedi.errors.SolverError
            The integration diverged.
        """


def contact_timing(history):
    """Contact timing and peaks from the core columns of a contact history (the same code
    for every :class:`ContactModel`).

    Parameters
    ----------
    history : pandas.DataFrame
        Holds at least ``time_s``, ``contact_nodes``, ``contact_point_x_m`` / ``_y_m``,
        ``reaction_force_N`` and ``max_von_mises_Pa``.

    Returns
    -------
    dict
        ``max_finger_stress_Pa`` [Pa], ``contact_start_s`` / ``contact_end_s`` /
        ``contact_duration_s`` [s] (first and last output with contact; None without
        contact), ``contact_ended``, ``first_contact_point_m`` / ``last_contact_point_m``
        ([x, y] m) and ``peak_reaction_force_N`` [N].
    """
    h = history
    on = h.contact_nodes > 0
    out = {"max_finger_stress_Pa": float(h.max_von_mises_Pa.max())}
    if not on.any():
        out.update({k: None for k in ("contact_start_s", "contact_end_s", "contact_duration_s",
                                      "first_contact_point_m", "last_contact_point_m")})
        out.update({"contact_ended": False, "peak_reaction_force_N": 0.0})
        return out
    first, last = h[on].iloc[0], h[on].iloc[-1]
    start, end = float(first.time_s), float(last.time_s)
    out.update({"contact_start_s": start, "contact_end_s": end, "contact_duration_s": end - start,
                "contact_ended": bool(end < float(h.time_s.iloc[-1])),
                "first_contact_point_m": [float(first.contact_point_x_m), float(first.contact_point_y_m)],
                "last_contact_point_m": [float(last.contact_point_x_m), float(last.contact_point_y_m)],
                "peak_reaction_force_N": float(h.reaction_force_N.max())})
    return out


def pulse_times(t_end_s, n_outputs):
    """The output times of a run: ``n_outputs`` equal steps from 0 (excluded) to ``t_end_s``.

    Parameters
    ----------
    t_end_s : float
        End time [s].
    n_outputs : int
        Number of outputs.

    Returns
    -------
    numpy.ndarray
        Times [s], shape (n_outputs,).
    """
    return np.linspace(0.0, t_end_s, n_outputs + 1)[1:]
