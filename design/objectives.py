"""What a finger design is judged on, from one contact run (ROM or full FEA).

A design is (alpha, L): mass-proportional damping alpha [1/s] and finger length L [m]
(SM-A cross-section, the drum set-up of :class:`ccedi.fea.drum.DrumSetup`). From the run's
history (:class:`ccedi.models.ContactResponse`) :func:`design_outputs` computes

* ``peak_reaction_force_N`` [N]: max_t of the force on the object averaged over a
  sliding 25 ms window, max_t |(1/w) int_{t-w/2}^{t+w/2} F dt'|, w = 25 ms: the load
  a force sensor reports. Under-damped fingers chatter on the object (impacts of
  ~10 ms, up to 60 N in the ROM against a 15-20 N sustained force; the full FEA
  chatters differently), which makes the instantaneous peak a rough, model-dependent
  function of the design; it is kept as ``peak_instantaneous_force_N`` for reference;
* ``max_object_stress_Pa`` [Pa]: max von Mises stress of the object, from a linear
  static solve of the object (:class:`ccedi.fea.drum.ObjectStress`) under the 25 ms-averaged
  contact force at the force-weighted contact point, at the outputs where the averaged
  force is at least half its peak;
* ``contact_duration_s`` [s]: t_end - t_start, last minus first output with contact;
* ``contact_start_s`` [s]: first output with contact;
* ``residual_oscillation_m_s`` [m/s]: RMS over the 0.5 s after breakaway of the tip's
  velocity relative to the rigidly turning finger,
  sqrt( (1/T) int_{t_b}^{t_b+T} (d lag/dt)^2 dt ), T = 0.5 s, where lag(t) is
  :func:`ccedi.fea.contact_study.tip_lag_series_m`. A velocity, not a displacement, so that an
  over-damped finger creeping back to its rest lag counts as quiet and a ringing one
  as loud (ring amplitude A at omega_1 gives ~A omega_1 / sqrt(2));
* ``max_finger_stress_Pa`` [Pa]: max von Mises stress in the finger over the run.

Lengths enter the CLI/JSON in inches (``length_in``); everything here is SI.
"""
from dataclasses import replace

import casadi as ca
import numpy as np

from ccedi.errors import InputError
from ccedi.fea.contact_study import tip_lag_series_m, window_mean
from ccedi.fea.drum import DrumSetup, ObjectStress
from ccedi.fea.mesh import sm_a_elements_along
from ccedi.models import contact_timing
from ccedi.rom.ccedi import piecewise_alpha_fit

RESIDUAL_WINDOW_S = 0.5
"""Length of the after-breakaway window of the residual oscillation [s]."""

OUTPUT_STEP_S = 0.0025
"""Output interval of the design runs [s] (>= 12 samples per period of the 3-in
finger's first mode, ~31 ms)."""

SEGMENT_LENGTH_M = 0.012
"""Superelement length of the design ROM [m]: three SM-A element layers, as the 8-in
finger's validated 17-segment chain."""

FORCE_WINDOW_S = 0.025
"""Averaging window of the peak reaction force [s]."""

OUTPUTS = ("peak_reaction_force_N", "max_object_stress_Pa", "contact_duration_s", "contact_start_s",
           "residual_oscillation_m_s", "max_finger_stress_Pa")
"""The design outputs of one run, in the order of the surrogate."""

PAPER_MATCHED_ALPHA = {3.0: 600.0, 4.5: 180.0}
"""The paper's alpha [1/s] matched to its measured over-damped 3 and 4.5-in fingers."""

PAPER_ZETA = {6.0: 0.17, 8.0: 0.15}
"""The paper's measured damping ratios of the 6 and 8-in fingers (log-decrement)."""

FIT_ALPHA_CR = (3525.0, -1.997)
"""Our alpha_cr(x) = c x^p [1/s], x in inches (README, "Damping identification")."""


def rom_segments(length_m):
    """Superelements of the design ROM for a finger of ``length_m`` [m]: round(L / 12 mm),
    at least 1, at most the SM-A element layers.

    Parameters
    ----------
    length_m : float
        Finger length [m].

    Returns
    -------
    int
    """
    return int(min(sm_a_elements_along(length_m), max(1, round(length_m / SEGMENT_LENGTH_M))))


def setup_for_length(base: DrumSetup, length_m):
    """``base`` with the finger length set to ``length_m`` [m]. A finger given as a mesh
    (``base.finger``) has its own length: it is kept, and another length is refused.

    Parameters
    ----------
    base : DrumSetup
    length_m : float
        Finger length [m].

    Returns
    -------
    DrumSetup

    Raises
    ------
    InputError
        ``base.finger`` is a mesh and ``length_m`` is not its length (to 1e-6).
    """
    if base.finger is not None:
        if not np.isclose(length_m, base.finger_length_m, rtol=1e-6, atol=0.0):
            raise InputError(f"design length {length_m:.6g} m: the finger is a given {base.finger.element_type} mesh "
                             f"{base.finger_length_m:.6g} m long; only the generated finger takes another length")
        return base
    return replace(base, finger_length_m=float(length_m))


def run_time_s(contact_end_s):
    """Simulated time [s] that covers breakaway at ``contact_end_s`` plus the residual window.

    Parameters
    ----------
    contact_end_s : float
        Predicted breakaway [s].

    Returns
    -------
    float
        Simulated time [s].
    """
    return float(contact_end_s) + RESIDUAL_WINDOW_S + 4 * OUTPUT_STEP_S


def residual_oscillation_m_s(setup: DrumSetup, history, contact_end_s):
    """RMS tip velocity relative to the rigidly turning finger [m/s] over
    (t_b, t_b + 0.5 s], t_b = ``contact_end_s`` (central differences of the tip lag).
    None when the history ends before the window does.

    Parameters
    ----------
    setup : DrumSetup
    history : pandas.DataFrame
        Contact history (core columns of :class:`ccedi.models.ContactResponse`).
    contact_end_s : float or None
        Breakaway [s].

    Returns
    -------
    float or None
        RMS velocity [m/s].
    """
    t = history.time_s.to_numpy()
    if contact_end_s is None or t[-1] < contact_end_s + RESIDUAL_WINDOW_S - 1e-9:
        return None
    v = np.gradient(tip_lag_series_m(setup, history), t)
    window = (t > contact_end_s) & (t <= contact_end_s + RESIDUAL_WINDOW_S + 1e-9)
    return float(np.sqrt(np.mean(v[window] ** 2)))


def averaged_contact_force(history):
    """25 ms-averaged contact force (fx, fy) [N] per output.

    Parameters
    ----------
    history : pandas.DataFrame
        Contact history (core columns).

    Returns
    -------
    tuple of numpy.ndarray
        (fx, fy) [N].
    """
    t = history.time_s.to_numpy()
    return (window_mean(t, history.contact_force_x_N.to_numpy(), FORCE_WINDOW_S),
            window_mean(t, history.contact_force_y_N.to_numpy(), FORCE_WINDOW_S))


OBJECT_STRESS_SAMPLES = 12
"""Outputs at which :func:`max_object_stress_Pa` solves the object (each is a static FE solve)."""


def max_object_stress_Pa(object_stress: ObjectStress, history, fx, fy):
    """Largest object von Mises stress [Pa] under the averaged contact force (fx, fy) [N]
    at the force-weighted contact point (x, y, 0), over the outputs with contact where the
    force is at least half its peak: the peak-force output and up to
    ``OBJECT_STRESS_SAMPLES`` outputs evenly spread over the others.

    Parameters
    ----------
    object_stress : ObjectStress
        The object's static solver.
    history : pandas.DataFrame
        Contact history (core columns).
    fx, fy : numpy.ndarray
        Averaged contact force [N] per output.

    Returns
    -------
    float
        Stress [Pa] (0 without contact).
    """
    f = np.hypot(fx, fy)
    px, py = history.contact_point_x_m.to_numpy(), history.contact_point_y_m.to_numpy()
    on = history.contact_nodes.to_numpy() > 0
    rows = np.flatnonzero((f >= 0.5 * f.max()) & on & np.isfinite(px) & np.isfinite(py) & (f > 0))
    if len(rows) > OBJECT_STRESS_SAMPLES:
        rows = np.union1d(rows[np.linspace(0, len(rows) - 1, OBJECT_STRESS_SAMPLES).astype(int)],
                          [int(np.argmax(np.where(on, f, 0.0)))])
    return max((object_stress.max_von_mises(np.array([[px[k], py[k], 0.0]]), np.array([[fx[k], fy[k], 0.0]]))
                for k in rows), default=0.0)


def design_outputs(setup: DrumSetup, history, object_stress: ObjectStress):
    """The :data:`OUTPUTS` of one contact run (dict, SI units; None where undefined,
    e.g. no contact), plus ``peak_instantaneous_force_N``.

    Reads only the core columns of :class:`ccedi.models.ContactResponse`, so any
    contact model's history serves.

    Parameters
    ----------
    setup : DrumSetup
        The set-up at the design's length.
    history : pandas.DataFrame
        Contact history.
    object_stress : ObjectStress
        The object's static solver.

    Returns
    -------
    dict
        :data:`OUTPUTS` and ``peak_instantaneous_force_N``.
    """
    timing = contact_timing(history)
    fx, fy = averaged_contact_force(history)
    out = {"peak_reaction_force_N": float(np.hypot(fx, fy).max()),
           "max_object_stress_Pa": max_object_stress_Pa(object_stress, history, fx, fy),
           "contact_duration_s": timing["contact_duration_s"] or 0.0,
           "contact_start_s": timing["contact_start_s"],
           "residual_oscillation_m_s": residual_oscillation_m_s(setup, history, timing["contact_end_s"]),
           "max_finger_stress_Pa": timing["max_finger_stress_Pa"],
           "peak_instantaneous_force_N": timing["peak_reaction_force_N"]}
    return out


def _piecewise(x, quad, line):
    """quad(x) for x <= 6 in, line(x) above (the form of the paper's Eq. 7); numpy or casadi."""
    q = quad[0] * x**2 + quad[1] * x + quad[2]
    l_ = line[0] * x + line[1]
    if isinstance(x, (ca.SX, ca.MX)):
        return ca.if_else(x <= 6.0, q, l_)
    return np.where(np.asarray(x) <= 6.0, q, l_)


ALPHA_OF_LENGTH = {
    "paper": ((56.667, -705.0, 2205.0), (-3.75, 37.5)),
    "fit": piecewise_alpha_fit([3.0, 4.5, 6.0, 8.0], [
        PAPER_MATCHED_ALPHA[3.0], PAPER_MATCHED_ALPHA[4.5],
        PAPER_ZETA[6.0] * FIT_ALPHA_CR[0] * 6.0 ** FIT_ALPHA_CR[1],
        PAPER_ZETA[8.0] * FIT_ALPHA_CR[0] * 8.0 ** FIT_ALPHA_CR[1]]),
}
"""Coefficients (quadratic 3-6 in, line 6-8 in) of alpha(x) [1/s], x in inches: "paper"
is Eq. (7); "fit" the same form through the paper's matched alpha at 3 and 4.5 in and
its measured zeta times our alpha_cr at 6 and 8 in (as ``ccedi damping-fits``)."""


def alpha_of_length(mode, length_in):
    """alpha(x) [1/s] of "this rubber" at finger length ``length_in`` [in] (numpy or
    casadi expression); ``mode`` is "paper" or "fit" (see :data:`ALPHA_OF_LENGTH`).

    Parameters
    ----------
    mode : str
        "paper" or "fit".
    length_in : float or casadi expression
        Finger length [in].

    Returns
    -------
    float or casadi expression
        alpha [1/s].

    Raises
    ------
    InputError
        Unknown ``mode``.
    """
    if mode not in ALPHA_OF_LENGTH:
        raise InputError(f"alpha-of-length must be one of {sorted(ALPHA_OF_LENGTH)} or 'free', got {mode!r}")
    return _piecewise(length_in, *ALPHA_OF_LENGTH[mode])

