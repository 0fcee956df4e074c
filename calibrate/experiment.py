"""A measured experiment: the CSV record (:mod:`ccedi.rom.measurement`) and its JSON sidecar,
both validated; every error names the offending field and its allowed range.

Sidecar (``DATA.json`` beside ``DATA.csv``; format in data/README.md)::

    kind          "impulse" or "contact"
    finger        length_in or length_m; section_semi_axes_m [a, b] (b along the bending
                  direction); E_Pa; nu; rho_kg_m3
    load          impulse: force_N, duration_s, at ("tip"), start_s (optional, default 0)
    drum          contact: drum_radius_m, omega_rad_s, theta0_rad, object_center_m [x, y],
                  object_semi_axes_m [a, b], friction, optionally contact_damping_ratio (the keys
                  of the study TOML's [drum])
    damping       (optional, contact) "global" (default) or "relative"
    alpha_per_s   (optional) mass-proportional damping, the fit's starting value [1/s]
    sensor        (optional) impulse: noise_std_m [m]; contact: noise_std_N [N]
    tolerances    (optional) E_Pa: relative tolerance of E (default 0.2)

A contact record's CSV holds ``time_s`` and ``reaction_force_N`` (the magnitude of the
in-plane force on the object as the transducer reads it), optionally
``contact_force_x_N``, ``contact_force_y_N`` (lab frame); an impulse record's
``time_s`` and ``tip_displacement_m`` (:mod:`ccedi.rom.measurement`).

Every number is checked against its entry of :data:`ccedi.quantities.QUANTITIES` (the
ranges of the study TOML and the command line), with the one message format
``SIDECAR: sidecar field 'load.force_N' = 500: must be in 0.0001..100 (N)``.

Plausibility ("units that cannot be right"): the tip displacement must stay below half
the finger length, the sample interval must resolve the declared finger's first mode
(below a quarter of its period at E x (1 + tolerance)), the pulse must end before the
record does, and a force_N column must peak within 20 % of load.force_N. Whether the
record is long enough to test the declared finger, and whether that finger can explain
it, is the calibration's adequacy check (:mod:`ccedi.calibrate.adequacy`).
"""
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ccedi.errors import InputError, brief_repr, one_line
from ccedi.fea.cases.beam_theory import cantilever_frequencies, ellipse_section_properties
from ccedi.quantities import QUANTITIES
from ccedi.rom.measurement import (
    CONTACT_COLUMNS,
    REQUIRED_COLUMNS,
    MeasuredResponse,
    check_sampling,
    force_pulse,
    load_response,
)
from ccedi.units import inch_to_m

KINDS = ("impulse", "contact")
DAMPINGS = ("global", "relative")
DEFAULT_E_TOLERANCE = 0.2
MAX_DISPLACEMENT_FRACTION = 0.5
FORCE_PEAK_TOLERANCE = 0.2


@dataclass(frozen=True)
class Finger:
    """The finger declared in the sidecar.

    Parameters
    ----------
    length_m : float
        Finger length L [m].
    semi_axes_m : tuple of float
        Elliptical section semi-axes (a, b) [m], b along the bending direction.
    E_Pa : float
        Declared Young's modulus [Pa].
    nu : float
        Poisson's ratio [-].
    rho_kg_m3 : float
        Density [kg/m^3].
    """

    length_m: float
    semi_axes_m: tuple
    E_Pa: float
    nu: float
    rho_kg_m3: float

    @property
    def area_m2(self):
        """Section area pi a b [m^2]."""
        return ellipse_section_properties(*self.semi_axes_m)[0]

    @property
    def second_moment_m4(self):
        """Second moment of area pi a b^3 / 4 about the bending axis [m^4]."""
        return ellipse_section_properties(*self.semi_axes_m)[1]

    def omega1_rad_s(self, E_factor=1.0):
        """Euler-Bernoulli first clamped-free frequency at E x ``E_factor``.

        Parameters
        ----------
        E_factor : float, optional
            Multiplier of the declared E [-]. Default 1.

        Returns
        -------
        float
            omega_1 = 1.8751^2 sqrt(E I / (rho A L^4)) [rad/s].
        """
        return float(cantilever_frequencies(self.E_Pa * E_factor, self.rho_kg_m3, self.length_m,
                                            area=self.area_m2, second_moment=self.second_moment_m4)[0])


@dataclass(frozen=True)
class Experiment:
    """A validated measured record with its sidecar.

    Parameters
    ----------
    kind : str
        ``"impulse"`` or ``"contact"``.
    finger : Finger
        The declared finger.
    force_N : float
        Tip pulse force [N] (0 for a contact record).
    duration_s : float
        Tip pulse duration [s] (0 for a contact record).
    start_s : float
        Tip pulse start [s].
    alpha_per_s : float or None
        Declared mass-proportional damping, the fit's starting value [1/s], or None.
    noise_std_m : float or None
        Declared sensor noise standard deviation [m], or None.
    E_tolerance : float
        Relative tolerance of the declared E [-]: E lies in E_Pa (1 +- E_tolerance).
    record : MeasuredResponse
        The CSV record (:class:`ccedi.rom.measurement.MeasuredResponse`).
    drum : dict or None, optional
        Contact: the declared drum set-up (the sidecar's ``drum`` keys, validated).
    damping : str, optional
        Contact: "global" or "relative" mass damping. Default "global".
    noise_std_N : float or None, optional
        Contact: declared transducer noise standard deviation [N], or None.
    """

    kind: str
    finger: Finger
    force_N: float
    duration_s: float
    start_s: float
    alpha_per_s: float | None
    noise_std_m: float | None
    E_tolerance: float
    record: MeasuredResponse
    drum: dict | None = None
    damping: str = "global"
    noise_std_N: float | None = None

    @property
    def time_s(self):
        """Sample times of the record [s]."""
        return self.record.time_s

    @property
    def displacement_m(self):
        """Measured tip displacement of the record [m]."""
        return self.record.tip_displacement_m

    @property
    def signal(self):
        """The measured signal the calibration fits: the tip displacement [m] of an
        impulse record, the reaction force [N] of a contact record."""
        return self.record.reaction_force_N if self.kind == "contact" else self.record.tip_displacement_m

    @property
    def signal_unit(self):
        """Unit of :attr:`signal`: "N" for a contact record, "m" for an impulse record."""
        return "N" if self.kind == "contact" else "m"

    @property
    def declared_noise(self):
        """Declared noise std of :attr:`signal` (its unit), or None."""
        return self.noise_std_N if self.kind == "contact" else self.noise_std_m


FIELDS = {"": ("kind", "finger", "load", "drum", "damping", "alpha_per_s", "sensor", "tolerances"),
          "finger": ("length_in", "length_m", "section_semi_axes_m", "E_Pa", "nu", "rho_kg_m3"),
          "load": ("force_N", "duration_s", "start_s", "at"), "sensor": ("noise_std_m", "noise_std_N"),
          "tolerances": ("E_Pa",),
          "drum": ("drum_radius_m", "omega_rad_s", "theta0_rad", "object_center_m", "object_semi_axes_m", "friction",
                   "contact_damping_ratio")}
"""The sidecar's fields, by object ("" the top level). Any other is refused: a misspelt
optional field (``tolerances.E``) would otherwise be ignored and its default used."""


def _known_fields(mapping, where, source):
    """Raise :class:`ccedi.errors.InputError` for the first key of ``mapping`` that
    :data:`FIELDS` ``[where]`` does not list."""
    for key in mapping:
        if key not in FIELDS[where]:
            name = f"{where}.{key}" if where else key
            raise InputError(f"{source}: sidecar field {brief_repr(name)} is unknown (allowed"
                             f"{' in ' + repr(where) if where else ''}: {', '.join(FIELDS[where])})")


def _section(sidecar, key, source, optional=False):
    """The object ``sidecar[key]`` ({} when ``optional`` and absent)."""
    if optional and key not in sidecar:
        return {}
    value = sidecar.get(key)
    if not isinstance(value, dict):
        raise InputError(f"{source}: sidecar field '{key}' " + ("must be an object" if optional
                                                                 else "is missing or not an object"))
    _known_fields(value, key, source)
    return value


def _quantity(section, name, quantity, source, required=True, default=None):
    """The sidecar field ``name`` (``"load.force_N"``: key ``force_N`` of ``section``) checked
    against ``QUANTITIES[quantity]`` (:mod:`ccedi.quantities`); when absent (or null), an
    error if ``required``, else ``default``."""
    key = name.rsplit(".", 1)[-1]
    if section.get(key) is None:
        if required:
            raise InputError(f"{source}: sidecar field '{name}' is missing")
        return default
    return QUANTITIES[quantity].check(section[key], f"{source}: sidecar field '{name}'")


def parse_finger(finger, source):
    """:class:`Finger` from the sidecar's ``finger`` object.

    Parameters
    ----------
    finger : dict
        With exactly one of ``length_in`` [in] and ``length_m`` [m];
        ``section_semi_axes_m`` [a, b] [m], both smaller than the length; ``E_Pa``
        [Pa]; ``nu``; ``rho_kg_m3`` [kg/m^3]; each within the range of
        :data:`ccedi.quantities.QUANTITIES` (the study TOML's ranges).
    source : str
        Name of the sidecar in error messages (its path).

    Returns
    -------
    Finger
        The validated finger (length in metres).

    Raises
    ------
    InputError
        Naming the sidecar field that is missing or out of range.
    """
    has_in, has_m = "length_in" in finger, "length_m" in finger
    if has_in == has_m:
        raise InputError(f"{source}: sidecar field 'finger.length_in' or 'finger.length_m' is needed (exactly one)")
    length = (inch_to_m(_quantity(finger, "finger.length_in", "length_in", source)) if has_in
              else QUANTITIES["length_m"].check(finger["length_m"], f"{source}: sidecar field 'finger.length_m'"))
    axes = finger.get("section_semi_axes_m")
    if not isinstance(axes, (list, tuple)) or len(axes) != 2:
        raise InputError(f"{source}: sidecar field 'finger.section_semi_axes_m' must be a list [a, b] of two "
                         f"semi-axes in metres, got {brief_repr(axes)}")
    a, b = (QUANTITIES["section_semi_axis_m"].check(x, f"{source}: sidecar field 'finger.section_semi_axes_m'")
            for x in axes)
    if max(a, b) >= length:
        raise InputError(f"{source}: sidecar field 'finger.section_semi_axes_m' ({a}, {b} m) must be smaller than "
                         f"the finger length {length} m (units?)")
    return Finger(length_m=length, semi_axes_m=(a, b), E_Pa=_quantity(finger, "finger.E_Pa", "E_Pa", source),
                  nu=_quantity(finger, "finger.nu", "nu", source),
                  rho_kg_m3=_quantity(finger, "finger.rho_kg_m3", "rho_kg_m3", source))


def load_experiment(csv_path, meta_path=None):
    """Read and validate a measured record and its JSON sidecar.

    Parameters
    ----------
    csv_path : str or pathlib.Path
        The record CSV (see :mod:`ccedi.rom.measurement`).
    meta_path : str or pathlib.Path, optional
        The sidecar. Default: ``csv_path`` with the suffix ``.json``.

    Returns
    -------
    Experiment
        The validated experiment.

    Raises
    ------
    InputError
        If the record or its sidecar is missing, the sidecar is not valid JSON or not an
        object, or the record or sidecar fails validation (see :func:`experiment_from`).
    """
    csv_path = Path(csv_path)
    meta_path = Path(meta_path) if meta_path else csv_path.with_suffix(".json")
    if not csv_path.is_file():
        raise InputError(f"measured record not found: {csv_path}")
    sidecar = read_sidecar(meta_path)
    required = CONTACT_COLUMNS if sidecar.get("kind") == "contact" else REQUIRED_COLUMNS
    return experiment_from(load_response(csv_path, required=required), sidecar, source=str(meta_path))


def read_sidecar(meta_path):
    """Read a JSON sidecar (not yet validated: :func:`experiment_from` does that).

    Parameters
    ----------
    meta_path : str or pathlib.Path
        The sidecar.

    Returns
    -------
    dict
        The parsed JSON object.

    Raises
    ------
    InputError
        If the file is missing, not valid JSON or not a JSON object.
    """
    meta_path = Path(meta_path)
    if not meta_path.is_file():
        raise InputError(f"sidecar not found: {meta_path} (give --meta, or put DATA.json beside DATA.csv)")
    try:
        sidecar = json.loads(meta_path.read_text(encoding="utf-8-sig"))
    except RecursionError:
        raise InputError(f"{meta_path}: not valid JSON (arrays or objects nested too deeply)") from None
    except ValueError as err:   # JSONDecodeError, UnicodeDecodeError, or an integer of too many digits
        raise InputError(f"{meta_path}: not valid JSON ({one_line(err)})") from None
    if not isinstance(sidecar, dict):
        raise InputError(f"{meta_path}: the sidecar must be a JSON object")
    return sidecar


DRUM_QUANTITIES = {"drum_radius_m": "drum_radius_m", "omega_rad_s": "omega_rad_s", "theta0_rad": "angle_rad",
                   "object_center_m": "object_position_m", "object_semi_axes_m": "object_semi_axis_m",
                   "friction": "friction", "contact_damping_ratio": "contact_damping_ratio"}
"""The contact sidecar's ``drum`` keys and their :data:`ccedi.quantities.QUANTITIES` entries
(``contact_damping_ratio`` optional, default 0)."""


def parse_drum(drum, source):
    """The sidecar's ``drum`` object, every key but contact_damping_ratio required, all checked.

    Parameters
    ----------
    drum : dict
        ``drum_radius_m`` [m], ``omega_rad_s`` [rad/s], ``theta0_rad`` [rad],
        ``object_center_m`` [x, y] [m], ``object_semi_axes_m`` [a, b] [m], ``friction`` [-],
        optionally ``contact_damping_ratio`` [-] (default 0).
    source : str
        Name of the sidecar in error messages.

    Returns
    -------
    dict
        The validated values (pairs as tuples).

    Raises
    ------
    InputError
        Naming the missing or out-of-range field.
    """
    out = {}
    for key, quantity in DRUM_QUANTITIES.items():
        name = f"drum.{key}"
        if key in ("object_center_m", "object_semi_axes_m"):
            pair = drum.get(key)
            if not isinstance(pair, (list, tuple)) or len(pair) != 2:
                raise InputError(f"{source}: sidecar field '{name}' must be a list of two numbers in metres, "
                                 f"got {brief_repr(pair)}")
            out[key] = tuple(QUANTITIES[quantity].check(x, f"{source}: sidecar field '{name}'") for x in pair)
        else:
            optional = key == "contact_damping_ratio"
            out[key] = _quantity(drum, name, quantity, source, required=not optional, default=0.0 if optional else None)
    return out


def experiment_from(record: MeasuredResponse, sidecar, source="<sidecar>", *, check_record=True):
    """Validate a sidecar and a record together (module docstring) into an :class:`Experiment`.

    Parameters
    ----------
    record : MeasuredResponse
        The measured record.
    sidecar : dict
        The parsed sidecar JSON.
    source : str, optional
        Name of the sidecar in error messages. Default ``"<sidecar>"``.
    check_record : bool, optional
        Check the record's plausibility (:func:`check_plausible`); False for a set-up
        with no record yet (``record`` then only carries the times a prediction is made
        at). Default True.

    Returns
    -------
    Experiment
        The validated experiment.

    Raises
    ------
    InputError
        Naming the sidecar field that is missing or out of range (kind, finger,
        load, alpha_per_s, sensor, tolerances), or if the record is implausible for
        the declared finger (see :func:`check_plausible`).
    """
    kind = sidecar.get("kind")
    if kind not in KINDS:
        raise InputError(f"{source}: sidecar field 'kind' must be one of {', '.join(KINDS)}, got {brief_repr(kind)}")
    _known_fields(sidecar, "", source)
    finger = parse_finger(_section(sidecar, "finger", source), source)
    load = _section(sidecar, "load", source, optional=kind != "impulse")
    drum, damping, noise_N = None, "global", None
    if kind == "contact":
        drum = parse_drum(_section(sidecar, "drum", source), source)
        damping = sidecar.get("damping", "global")
        if damping not in DAMPINGS:
            raise InputError(f"{source}: sidecar field 'damping' must be one of {', '.join(DAMPINGS)}, "
                             f"got {brief_repr(damping)}")
        noise_N = _quantity(_section(sidecar, "sensor", source, optional=True), "sensor.noise_std_N", "noise_std_N",
                            source, required=False)
    elif "drum" in sidecar or "damping" in sidecar:
        raise InputError(f"{source}: sidecar fields 'drum' and 'damping' belong to a contact record, not kind {kind!r}")
    force = duration = start = 0.0
    if kind == "impulse":
        if load.get("at") != "tip":
            raise InputError(f"{source}: sidecar field 'load.at' must be \"tip\" for an impulse, "
                             f"got {brief_repr(load.get('at'))}")
        force = _quantity(load, "load.force_N", "force_N", source)
        duration = _quantity(load, "load.duration_s", "pulse_duration_s", source)
        start = _quantity(load, "load.start_s", "pulse_start_s", source, required=False, default=0.0)
    alpha = _quantity(sidecar, "alpha_per_s", "alpha_per_s", source, required=False)
    noise = _quantity(_section(sidecar, "sensor", source, optional=True), "sensor.noise_std_m", "noise_std_m", source,
                      required=False)
    tol = _quantity(_section(sidecar, "tolerances", source, optional=True), "tolerances.E_Pa", "E_tolerance", source,
                    required=False, default=DEFAULT_E_TOLERANCE)
    exp = Experiment(kind=kind, finger=finger, force_N=force, duration_s=duration, start_s=start, alpha_per_s=alpha,
                     noise_std_m=noise, E_tolerance=tol, record=record, drum=drum, damping=damping, noise_std_N=noise_N)
    if check_record:
        check_plausible(exp)
    return exp


def check_plausible(exp: Experiment):
    """Reject records whose units cannot be right for the declared finger.

    Checks: |tip displacement| below half the finger length; the largest sample interval
    below a quarter of the first period at E x (1 + tolerance); for an impulse, the record
    starts by the pulse, the pulse ends before the last sample, and a ``force_N`` column
    pulses where the sidecar says and peaks within 20 % of its ``load.force_N``. A contact
    record: :func:`_check_contact`.

    Parameters
    ----------
    exp : Experiment
        The experiment to check.

    Raises
    ------
    InputError
        Naming the failed check, the values found and the limit.
    """
    src = exp.record.source
    if exp.kind == "contact":
        _check_contact(exp)
        return
    y = exp.displacement_m
    limit = MAX_DISPLACEMENT_FRACTION * exp.finger.length_m
    if np.max(np.abs(y)) > limit:
        raise InputError(f"{src}: tip_displacement_m reaches {np.max(np.abs(y)):.4g} m, more than half the "
                         f"{exp.finger.length_m:.4g} m finger ({limit:.4g} m): not metres, or not this finger")
    check_sampling(exp.time_s, exp.finger.omega1_rad_s(1.0 + exp.E_tolerance), src)
    end = exp.start_s + exp.duration_s
    if exp.kind == "impulse" and end >= exp.time_s[-1]:
        raise InputError(f"{src}: the pulse (load.start_s + load.duration_s) ends at {end:.4g} s but the record ends "
                         f"at {exp.time_s[-1]:.4g} s: the record must hold the response after the pulse")
    _check_pulse_timing(exp)
    f = exp.record.force_N
    if exp.kind == "impulse" and f is not None:
        peak = float(np.max(np.abs(f)))
        if abs(peak - exp.force_N) > FORCE_PEAK_TOLERANCE * exp.force_N:
            raise InputError(f"{src}: force_N column peaks at {peak:.4g} N but sidecar field 'load.force_N' is "
                             f"{exp.force_N:.4g} N (allowed: within {FORCE_PEAK_TOLERANCE:.0%})")


def _check_pulse_timing(exp: Experiment):
    """The record starts by the declared pulse (``load.start_s``), and a ``force_N`` column's
    pulse (where |F| is at least half its peak) lies where the sidecar puts it, within a
    sample and the pulse's length."""
    src, t = exp.record.source, exp.time_s
    slack = max(float(np.max(np.diff(t))), exp.duration_s)
    if t[0] > exp.start_s + 0.5 * float(t[1] - t[0]):
        raise InputError(f"{src}: time_s starts at {t[0]:.4g} s, after the pulse starts (load.start_s = "
                         f"{exp.start_s:.4g} s): the record must hold the pulse; shift time_s or set load.start_s")
    f = exp.record.force_N
    if f is None or not np.any(f):
        return
    start = force_pulse(t, f)[1]
    if abs(start - exp.start_s) > slack:
        raise InputError(f"{src}: the force_N column's pulse starts at {start:.4g} s but the sidecar's at "
                         f"{exp.start_s:.4g} s (load.start_s; allowed: within {slack:.3g} s): shift time_s or set "
                         "load.start_s")


CONTACT_FORCE_LIMIT_N = 1e4
"""Largest plausible reaction force of a finger on the object [N]."""


def _check_contact(exp: Experiment):
    """Contact-record plausibility: the sampling resolves the declared finger's first mode,
    the reaction force stays below :data:`CONTACT_FORCE_LIMIT_N` and shows a contact (its
    peak above the declared noise, when given, by 10 sigma)."""
    src = exp.record.source
    check_sampling(exp.time_s, exp.finger.omega1_rad_s(1.0 + exp.E_tolerance), src)
    span = float(exp.time_s[-1] - exp.time_s[0])
    if exp.time_s[0] > span:
        raise InputError(f"{src}: time_s starts at {exp.time_s[0]:.4g} s, later than the record lasts ({span:.4g} s): "
                         "a contact record's time counts from the drum's start (t = 0 at [drum] theta0_rad); "
                         "shift time_s")
    f = exp.signal
    peak = float(np.max(np.abs(f)))
    if peak > CONTACT_FORCE_LIMIT_N:
        raise InputError(f"{src}: reaction_force_N reaches {peak:.4g} N, more than {CONTACT_FORCE_LIMIT_N:g} N: "
                         f"not newtons, or not this finger")
    if exp.noise_std_N is not None and peak < 10.0 * exp.noise_std_N:
        raise InputError(f"{src}: reaction_force_N peaks at {peak:.4g} N, below 10 x the declared noise "
                         f"(sensor.noise_std_N = {exp.noise_std_N:.4g} N): the record shows no contact")
