"""What a finger design is judged on, from one contact run (ROM or full FEA).

A run (:class:`ccedi.models.ContactResponse`, any contact model: only the core columns
are read) starts with the finger turning rigidly with the drum, its steady running shape
under relative damping (the drum frame's centrifugal stretch aside, radial and small), and
lasts until the next object arrives, one cycle (:attr:`ccedi.fea.contact.drum.DrumSetup.cycle_s`)
after the first contact. :func:`design_outputs` reads from its history (SI units):

* ``sensor_peak_force_N`` [N]: the largest force on the object as the force transducer
  reads it (:class:`ccedi.rom.sensor.Transducer`, 100 Hz Butterworth by default), the
  load the object feels once the finger's ~400 Hz friction chatter is filtered;
* ``max_object_stress_Pa`` [Pa]: largest object von Mises stress, a linear static solve
  of the object (:class:`ccedi.fea.contact.drum.ObjectStress`) under the transducer-filtered
  contact force at the force-weighted contact point, at up to
  :data:`OBJECT_STRESS_SAMPLES` outputs where the force is at least half its peak;
* ``root_stress_before_contact_Pa`` [Pa]: largest finger von Mises stress before the
  first contact (the paper's "before contact" rise of a highly damped finger: under
  global damping the drag bends it; under relative damping it stays near zero);
* ``max_finger_stress_Pa`` [Pa]: largest finger von Mises stress over the whole cycle
  (before, during and after contact); the largest of a bent cantilever is at its root;
* ``recovery_deviation_m`` [m]: the tip's largest distance from its running position
  over the :data:`RECOVERY_WINDOW_S` before the next object arrives (at first contact +
  one cycle). The running position is the tip's place in the drum frame at the last
  output before first contact: the rigidly turning tip under relative damping, the
  drag-bent one under global damping. A window of one period of the slowest finger's
  first mode makes a ringing finger count by its amplitude, not its phase;
* ``ringing_amplitude_m`` [m]: the tip's largest overshoot past its running position
  between breakaway and the next arrival, along the drum's motion (the bending
  direction), on the side opposite to its deflection at breakaway: the first swing of a
  ringing finger, e^(-zeta pi / sqrt(1 - zeta^2)) of its deflection for one mode, and 0
  for a finger that creeps back without crossing (slow recovery is
  ``recovery_deviation_m``'s business). Continuous in the damping, and blind to the
  full FE finger's small high-frequency jitter, unlike a count of extrema;
* ``first_contact_front_m`` [m]: signed distance of the first contact point from the
  object's minor axis, positive on the front half that the sweep reaches first
  (:func:`ccedi.fea.contact.drum.front_distance_m`); a drag-bent finger first touches the rear;
* ``contact_patch_from_root_m`` [m]: closest approach of the force-weighted contact
  point to the finger's root, its distance from the drum axis minus the drum radius;
* ``contact_impulse_N_s`` [N s]: integral of the contact force magnitude over the run;
* ``contact_start_s``, ``contact_duration_s`` [s]: first output with contact, and the
  last minus the first;
* ``cycle_time_s`` [s]: time between two objects (:attr:`ccedi.fea.contact.drum.DrumSetup.cycle_s`),
  whose inverse is the throughput; it moves with the drum speed when that is a design
  variable;
* ``settling_time_s`` [s] (not in :data:`OUTPUTS`; None when it does not settle within
  the run): time from breakaway until the tip stays within ``settle_tolerance_m`` of its
  running position.

The design variables (:data:`VARIABLES`) are set on a :class:`ccedi.fea.contact.drum.DrumSetup` by
:func:`setup_at`. Lengths enter the CLI/JSON in inches (``length_in``), drum speeds in rpm
(``drum_speed_rpm``); everything here is SI.
"""
from dataclasses import replace

import numpy as np

from ccedi.errors import InputError
from ccedi.fea.cases.contact_study import tip_drum_frame_displacement_m
from ccedi.fea.contact.drum import DrumSetup, ObjectStress, first_contact_angle, front_distance_m
from ccedi.fea.mesh import sm_a_elements_along
from ccedi.models import contact_timing
from ccedi.rom.sensor import Transducer
from ccedi.units import INCH, RPM

OUTPUT_STEP_S = 0.0005
"""Output interval of the design runs [s]: resolves the full FE finger's ~400 Hz friction
chatter before the transducer filters it, in the ROM and the FEA alike."""

RECOVERY_WINDOW_S = 0.15
"""Window before the next arrival over which the recovery deviation is the largest [s]:
one period of the first mode of the slowest finger in the design space (8 in, ~7 Hz)."""

ARRIVAL_MARGIN_S = 0.35
"""Simulated time beyond the rigid finger's first contact plus one cycle [s]: a drag-bent
finger (global damping) first touches up to 0.27 s later than the rigid one (8 in, alpha
600 1/s), and its next arrival with it."""

SEGMENT_LENGTH_M = 0.012
"""Superelement length of the design ROM [m]: three SM-A element layers, as the 8-in
finger's validated 17-segment chain."""

OUTPUTS = ("sensor_peak_force_N", "max_object_stress_Pa", "root_stress_before_contact_Pa", "max_finger_stress_Pa",
           "recovery_deviation_m", "ringing_amplitude_m", "first_contact_front_m", "contact_patch_from_root_m",
           "contact_impulse_N_s", "contact_start_s", "contact_duration_s", "cycle_time_s")
"""The design outputs of one run, in the order of the surrogate."""

UNITS = {"sensor_peak_force_N": "N", "max_object_stress_Pa": "Pa", "root_stress_before_contact_Pa": "Pa",
         "max_finger_stress_Pa": "Pa", "recovery_deviation_m": "m", "ringing_amplitude_m": "m",
         "first_contact_front_m": "m", "contact_patch_from_root_m": "m", "contact_impulse_N_s": "N s",
         "contact_start_s": "s", "contact_duration_s": "s", "cycle_time_s": "s", "settling_time_s": "s"}
"""SI unit of every output."""

DENSITY_SCALED = tuple(k for k in OUTPUTS if UNITS[k] in ("N", "N s", "Pa"))
"""The outputs in force units (forces, the impulse, stresses), which scale with the finger's
density at a fixed E / rho. Scaling the finger's E and rho by one factor k scales its
mass, stiffness and contact springs by k and leaves its motion unchanged (every force of
the run, drum-frame inertia, damping alpha M, friction, is k times its own): these outputs
are k times theirs, the others (lengths, times) unchanged. :mod:`ccedi.design.catalogue_design`
designs every compound on one surrogate over E at one density by this similarity, which
the contact ROM keeps to round-off (``tests/unit/design/test_catalogue_design.py``)."""


def density_scaled(outputs, factor):
    """Outputs of the finger whose E and rho are both ``factor`` times the one they were
    computed for (:data:`DENSITY_SCALED`): those in force units times ``factor``, the
    others unchanged.

    Parameters
    ----------
    outputs : dict
        {output: value} (numbers, arrays or casadi expressions).
    factor : float
        The common factor k of E and rho [-].

    Returns
    -------
    dict
        The scaled outputs.
    """
    return {k: v * factor if k in DENSITY_SCALED else v for k, v in outputs.items()}

OBJECT_STRESS_SAMPLES = 12
"""Outputs at which the object's stress is solved (each is a static FE solve)."""


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


VARIABLES = {"alpha_per_s": ("alpha", "1/s", "alpha_per_s", 1.0),
             "length_m": ("L", "in", "length_in", INCH),
             "drum_speed_rad_s": ("drum speed", "rpm", "drum_speed_rpm", RPM),
             "youngs_modulus_Pa": ("E", "MPa", "E_MPa", 1e6),
             "semi_width_m": ("a", "mm", "semi_width_mm", 1e-3),
             "semi_thickness_m": ("b", "mm", "semi_thickness_mm", 1e-3),
             "taper_ratio": ("taper ratio", "-", "taper_ratio", 1.0)}
"""Design variables: SI name -> (label, unit shown, JSON key of the shown value, one shown
unit in SI). alpha is not a set-up quantity (it is the run's damping); the finger's Young's
modulus is set on its material at the set-up's density; the section's semi-axes are the
generated finger's at its root: a across the finger (the width 2a), b along the bending
direction (the thickness 2b); the taper ratio is its tip's semi-axes over its root's (both
scale linearly along the length)."""


def setup_at(base: DrumSetup, names, point):
    """``base`` with the design variables ``names`` set to the values ``point`` (SI); alpha
    is skipped (it is the run's argument, not the set-up's).

    Parameters
    ----------
    base : DrumSetup
    names : sequence of str
        Variable names (keys of :data:`VARIABLES`).
    point : sequence of float
        Their values [SI].

    Returns
    -------
    DrumSetup

    Raises
    ------
    InputError
        An unknown variable, a length other than a finger mesh's own
        (:func:`setup_for_length`), or a section or a taper on a finger mesh
        (:func:`setup_for_section`, :func:`setup_for_taper`).
    """
    setup = base
    for name, x in zip(names, point):
        if name == "length_m":
            setup = setup_for_length(setup, x)
        elif name == "drum_speed_rad_s":
            setup = replace(setup, omega_rad_s=float(x))
        elif name == "youngs_modulus_Pa":
            setup = replace(setup, finger_material=replace(setup.finger_material, E=float(x)))
        elif name in ("semi_width_m", "semi_thickness_m"):
            setup = setup_for_section(setup, **{name: x})
        elif name == "taper_ratio":
            setup = setup_for_taper(setup, x)
        elif name != "alpha_per_s":
            raise InputError(f"design variable {name!r}: must be one of {', '.join(VARIABLES)}")
    return setup


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


def setup_for_section(base: DrumSetup, *, semi_width_m=None, semi_thickness_m=None):
    """``base`` with the generated finger's section semi-axes set: a (across, the width 2a)
    and b (along the bending direction, the thickness 2b) [m]; None keeps one.

    Parameters
    ----------
    base : DrumSetup
    semi_width_m : float, optional
        Semi-axis a [m].
    semi_thickness_m : float, optional
        Semi-axis b [m].

    Returns
    -------
    DrumSetup
        A copy with the new section (the finger is generated from it at each run).

    Raises
    ------
    InputError
        ``base.finger`` is a mesh (its section is its own), or a semi-axis out of range.
    """
    if base.finger is not None:
        raise InputError(f"design section: the finger is a given {base.finger.element_type} mesh, whose section is "
                         "its own; only the generated finger takes other semi-axes")
    a, b = base.finger_semi_axes_m
    return replace(base, finger_semi_axes_m=(float(a if semi_width_m is None else semi_width_m),
                                             float(b if semi_thickness_m is None else semi_thickness_m)))


def setup_for_taper(base: DrumSetup, taper_ratio):
    """``base`` with the generated finger tapered: its tip's semi-axes ``taper_ratio`` times
    its root's, the root section kept.

    Parameters
    ----------
    base : DrumSetup
    taper_ratio : float
        Tip over root semi-axes [-] (1: the prism).

    Returns
    -------
    DrumSetup
        A copy with the new taper (the finger is generated from it at each run).

    Raises
    ------
    InputError
        ``base.finger`` is a mesh (its shape is its own), or the ratio is out of range.
    """
    if base.finger is not None:
        raise InputError(f"design taper: the finger is a given {base.finger.element_type} mesh, whose shape is "
                         "its own; only the generated finger takes a taper")
    return replace(base, finger_taper_ratio=float(taper_ratio))


def run_time_s(setup: DrumSetup):
    """Simulated time [s] of a design run: the rigid finger's first contact, one cycle
    and :data:`ARRIVAL_MARGIN_S`.

    Parameters
    ----------
    setup : DrumSetup
        The set-up at the design's length.

    Returns
    -------
    float
        Simulated time [s].

    Raises
    ------
    InputError
        The finger never reaches the object.
    """
    return first_contact_angle(setup) / setup.omega_rad_s + setup.cycle_s + ARRIVAL_MARGIN_S


def output_count(t_end_s):
    """Outputs of a run of ``t_end_s`` [s] at :data:`OUTPUT_STEP_S`.

    Parameters
    ----------
    t_end_s : float
        Simulated time [s].

    Returns
    -------
    int
    """
    return max(1, int(round(t_end_s / OUTPUT_STEP_S)))


def _running_deviation(setup, history, t_start):
    """Tip deviation (n, 2) [m] (radial, tangential) from its running position, the drum
    frame position at the last output before ``t_start`` (the first output when None or
    at the first output)."""
    d = tip_drum_frame_displacement_m(setup, history)
    t = history.time_s.to_numpy()
    before = np.flatnonzero(t < t_start) if t_start is not None else np.array([], dtype=int)
    ref = d[before[-1]] if len(before) else np.zeros(2)
    return d - ref


def overshoot(x):
    """The largest excursion of ``x`` past zero on the side opposite to ``x[0]`` (0 when
    it never crosses).

    Parameters
    ----------
    x : numpy.ndarray
        A signal that starts away from zero.

    Returns
    -------
    float
    """
    if len(x) == 0 or x[0] == 0.0:
        return 0.0
    return float(max(0.0, (-np.sign(x[0]) * x).max()))


def settling_time_s(t, deviation, *, t_from, tolerance_m):
    """Time [s] from ``t_from`` until |deviation| stays within ``tolerance_m`` to the
    end of the record; None when it is outside at the last output.

    Parameters
    ----------
    t : numpy.ndarray
        Output times [s].
    deviation : numpy.ndarray
        (n, 2) tip deviation [m].
    t_from : float
        Start of the count (breakaway) [s].
    tolerance_m : float
        Band [m].

    Returns
    -------
    float or None
    """
    outside = np.flatnonzero((np.hypot(*deviation.T) > tolerance_m) & (t >= t_from))
    if len(outside) == 0:
        return 0.0
    if outside[-1] == len(t) - 1:
        return None
    return float(t[outside[-1] + 1] - t_from)


def sensor_force(history, transducer):
    """Transducer readings (x, y, magnitude) [N] of the contact force per output.

    Parameters
    ----------
    history : pandas.DataFrame
        Contact history (core columns).
    transducer : ccedi.rom.sensor.Transducer

    Returns
    -------
    tuple of numpy.ndarray
        (fx, fy, |f|) [N].
    """
    t = history.time_s.to_numpy()
    return (transducer.measured(t, history.contact_force_x_N.to_numpy()),
            transducer.measured(t, history.contact_force_y_N.to_numpy()),
            transducer.measured(t, history.reaction_force_N.to_numpy()))


def max_object_stress_Pa(object_stress: ObjectStress, history, *, fx, fy):
    """Largest object von Mises stress [Pa] under the filtered contact force (fx, fy) [N]
    at the force-weighted contact point (x, y, 0), over the outputs with contact where the
    force is at least half its peak: the peak-force output and up to
    :data:`OBJECT_STRESS_SAMPLES` outputs evenly spread over the others.

    Parameters
    ----------
    object_stress : ObjectStress
        The object's static solver.
    history : pandas.DataFrame
        Contact history (core columns).
    fx, fy : numpy.ndarray
        Filtered contact force [N] per output.

    Returns
    -------
    float
        Stress [Pa] (0 without contact).
    """
    f = np.hypot(fx, fy)
    px, py = history.contact_point_x_m.to_numpy(), history.contact_point_y_m.to_numpy()
    on = (history.contact_nodes.to_numpy() > 0) & np.isfinite(px) & np.isfinite(py)
    if not on.any():
        return 0.0
    rows = np.flatnonzero((f >= 0.5 * f[on].max()) & on & (f > 0))
    if len(rows) > OBJECT_STRESS_SAMPLES:
        rows = np.union1d(rows[np.linspace(0, len(rows) - 1, OBJECT_STRESS_SAMPLES).astype(int)],
                          [int(np.argmax(np.where(on, f, 0.0)))])
    return max((object_stress.max_von_mises(np.array([[px[k], py[k], 0.0]]), np.array([[fx[k], fy[k], 0.0]]))
                for k in rows), default=0.0)


def design_outputs(setup: DrumSetup, history, object_stress: ObjectStress, *, transducer=None,
                   settle_tolerance_m=0.005, extra=None):
    """The :data:`OUTPUTS` of one contact run (dict, SI units), plus ``settling_time_s``,
    ``contact_end_s``, ``next_arrival_s`` and user-defined outputs.

    Reads only the core columns of :class:`ccedi.models.ContactResponse`, so any
    contact model's history serves. A run without contact has zero force, stress and
    impulse, and its contact outputs (start, front, patch) None.

    Parameters
    ----------
    setup : DrumSetup
        The set-up at the design's length (its cycle sets the next arrival).
    history : pandas.DataFrame
        Contact history, to the next arrival or beyond.
    object_stress : ObjectStress
        The object's static solver.
    transducer : ccedi.rom.sensor.Transducer, optional
        The force transducer (default ``Transducer()``).
    settle_tolerance_m : float, optional
        Band of the settling time [m].
    extra : dict, optional
        User-defined outputs, ``{name: function(setup, history) -> float}`` (SI units).

    Returns
    -------
    dict
        Outputs by name.

    Raises
    ------
    InputError
        The history ends before the next arrival.
    """
    t = history.time_s.to_numpy()
    timing = contact_timing(history)
    start, end = timing["contact_start_s"], timing["contact_end_s"]
    arrival = (start if start is not None else 0.0) + setup.cycle_s
    if t[-1] < arrival - 1e-9:
        raise InputError(f"the run ends at {t[-1]:.4g} s, before the next object arrives at {arrival:.4g} s "
                         "(first contact + one cycle): run longer")
    fx, fy, f = sensor_force(history, transducer or Transducer())
    dev = _running_deviation(setup, history, start)
    cycle = t <= arrival + 1e-9
    window = cycle & (t >= arrival - RECOVERY_WINDOW_S)
    after = cycle & (t > end) if end is not None else np.zeros(len(t), dtype=bool)
    on = history.contact_nodes.to_numpy() > 0
    stress = history.max_von_mises_Pa.to_numpy()
    force = history.reaction_force_N.to_numpy()
    radius = np.hypot(history.contact_point_x_m.to_numpy(), history.contact_point_y_m.to_numpy())
    out = {"sensor_peak_force_N": float(f[cycle].max()),
           "max_object_stress_Pa": max_object_stress_Pa(object_stress, history[cycle], fx=fx[cycle], fy=fy[cycle]),
           "root_stress_before_contact_Pa": float(stress[t < start].max(initial=0.0)) if start is not None
           else float(stress[cycle].max()),
           "max_finger_stress_Pa": float(stress[cycle].max()),
           "recovery_deviation_m": float(np.hypot(*dev[window].T).max()),
           "ringing_amplitude_m": overshoot(dev[after, 1]) if after.any() else 0.0,
           "first_contact_front_m": (None if start is None
                                     else front_distance_m(setup, timing["first_contact_point_m"])),
           "contact_patch_from_root_m": (None if start is None
                                         else float(np.nanmin(radius[on & cycle]) - setup.drum_radius_m)),
           "contact_impulse_N_s": float(np.trapezoid(force[cycle], t[cycle])),
           "contact_start_s": start,
           "contact_duration_s": timing["contact_duration_s"] or 0.0,
           "cycle_time_s": setup.cycle_s,
           "contact_end_s": end,
           "next_arrival_s": arrival,
           "settling_time_s": None if end is None else settling_time_s(t[cycle], dev[cycle], t_from=end,
                                                                       tolerance_m=settle_tolerance_m)}
    for name, function in (extra or {}).items():
        if name in out:
            raise InputError(f"user-defined output {name!r} has the name of a built-in output")
        out[name] = float(function(setup, history))
    return out
