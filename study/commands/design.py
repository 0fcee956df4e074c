"""``ccedi design``: pick the finger's damping and its length (or, for a finger given as a
mesh, the drum speed) that meet the designer's requirements (:mod:`ccedi.design`), checked
by the full FEA, with a report that explains the decision."""
# Imports inside functions: building the parser imports no library, so that `ccedi --help`
# answers at once (tests/conventions/test_layout.py); each command loads what it runs.
import time
import warnings
from dataclasses import dataclass, fields, replace
from pathlib import Path

from ccedi.errors import InputError, RequirementsUnmet, ValidityWarning
from ccedi.study.commands.arguments import (
    CONTACT_KEYS,
    add_command,
    add_config_argument,
    add_output_argument,
    add_scheduler_argument,
    load_config,
)
from ccedi.units import inch_to_m, m_to_inch

MODEL_ERROR_FILE = Path(__file__).resolve().parents[2] / "data" / "design" / "rom_check.json"
"""The ROM-against-FEA check the design takes its model-error margins from
(``validation/design_rom_check.py`` writes it)."""

VARIED = ("length", "drum_speed", "semi_thickness", "semi_width", "taper")
"""What ``--vary`` takes: the second design variable beside alpha (the section's semi-axes
b, along the bending direction, and a, across; the taper ratio, the tip's semi-axes over
the root's)."""

CORRECTED_INSTEAD = "none: the surrogate is corrected by the full FEA (--fea-correction)"
"""The result's ``model_error_source`` when ``--fea-correction`` replaces the model-error margins."""

REQUIREMENT_FLAGS = (("--max-object-force-N", "max_object_force_N", 1.0),
                     ("--max-object-stress-Pa", "max_object_stress_Pa", 1.0),
                     ("--allowable-root-stress-Pa", "allowable_root_stress_Pa", 1.0),
                     ("--max-recovery-deviation-mm", "max_recovery_deviation_m", 1e-3),
                     ("--max-ringing-amplitude-mm", "max_ringing_amplitude_m", 1e-3),
                     ("--min-patch-from-root-mm", "min_patch_from_root_m", 1e-3),
                     ("--min-contact-impulse-N-s", "min_contact_impulse_N_s", 1.0))
"""Command-line overrides of ``[requirements]``: flag, Requirements field, flag unit in SI."""


def add_parsers(sub):
    """Register design on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-command registry of the ``ccedi`` parser.
    """
    d = add_command(sub, "design", help="design optimiser: the alpha and finger length (a [finger] mesh: alpha and "
                       "drum speed) that meet the requirements ([requirements] of --config) at the least object force "
                       "(ROM surrogate, casadi/IPOPT, feasible region, Pareto front, sensitivities, full-FEA re-check, "
                       "report)")
    d.add_argument("--damping", choices=("relative", "global"), default=None,
                   help="mass damping kind (default: [damping] kind of --config, relative)")
    d.add_argument("--objective", choices=("object_force", "object_stress", "root_stress", "recovery", "ringing",
                                           "throughput", "weighted"), default=None,
                   help="what is minimised (default: [requirements] objective of --config, object_force)")
    d.add_argument("--weights", default=None, metavar="OUTPUT=W,...",
                   help="weights of --objective weighted, e.g. sensor_peak_force_N=1,ringing_amplitude_m=1")
    for flag, name, _ in REQUIREMENT_FLAGS:
        d.add_argument(flag, type=float, default=None, dest=name,
                       help=f"requirement {name} in the flag's unit, 0 for none (default: [requirements])")
    d.add_argument("--allowable-finger-stress-Pa", type=float, default=None, dest="allowable_finger_stress_Pa",
                   help="the same as --allowable-root-stress-Pa")
    d.add_argument("--alpha-of-length", choices=("paper", "fit", "free"), default="free",
                   help="alpha tied to length for this rubber (paper Eq. 7, or our fit) or free")
    d.add_argument("--alpha-bounds", type=float, nargs=2, default=DesignOptions.alpha_bounds, metavar=("LO", "HI"),
                   help="damping bounds [1/s]")
    d.add_argument("--length-bounds-in", type=float, nargs=2, default=(3.0, 8.0), metavar=("LO", "HI"),
                   help="finger length bounds [in]")
    d.add_argument("--vary", choices=VARIED, default=None,
                   help="the second design variable beside alpha (default: length; drum_speed for a [finger] mesh, "
                        "whose length is fixed)")
    d.add_argument("--drum-speed-bounds-rpm", type=float, nargs=2, default=DesignOptions.drum_speed_bounds_rpm,
                   metavar=("LO", "HI"), help="drum speed bounds [rpm] (--vary drum_speed)")
    d.add_argument("--section-bounds-mm", type=float, nargs=2, default=None, metavar=("LO", "HI"),
                   help="bounds of the varied section semi-axis [mm] (--vary semi_thickness: b, along the bending "
                        "direction, default 4 14, with --compounds 4 12, at most the semi-width a; --vary semi_width: "
                        "a, across, default 6 18) at the set-up's length (with --compounds: the length varied too)")
    d.add_argument("--taper-bounds", type=float, nargs=2, default=DesignOptions.taper_bounds, metavar=("LO", "HI"),
                   help="bounds of the taper ratio, the tip's semi-axes over the root's [-] (--vary taper; default "
                        "0.6 1: down to a tip 0.6 times the root section, up to the prism; below 0.6 the full FE "
                        "tip is crushed by the contact) at the set-up's length")
    d.add_argument("--grid", type=int, nargs=2, default=None, metavar=("N_ALPHA", "N_SECOND"),
                   help="ROM runs of the surrogate grid along alpha and the second variable (cached in OUT; default "
                        "15 11, with --compounds --vary semi_thickness 9 7: along L, with 4 along E and 4 along b)")
    d.add_argument("--validation-runs", type=int, default=20, help="off-grid ROM runs measuring the surrogate error")
    d.add_argument("--pareto-points", type=int, default=24, help="epsilon-constraint points of the front")
    d.add_argument("--pareto-output", default="ringing_amplitude_m",
                   help="the output traded against the objective on the Pareto front")
    d.add_argument("--starts", type=int, default=8, help="IPOPT starts")
    d.add_argument("--fea-correction", type=int, nargs=2, default=None, metavar=("N_ALPHA", "N_SECOND"),
                   help="correct the ROM surrogate by full FEA runs at an N_ALPHA x N_SECOND grid of the design "
                        "variables, bounds included (2-5 each; minutes per run; cached in OUT); replaces the "
                        "model-error margins (with --compounds: over alpha and L, and b at its bounds with --vary "
                        "semi_thickness, on the set-up's own rubber)")
    d.add_argument("--no-model-error", action="store_true",
                   help="do not tighten the requirements by the ROM's measured error against the FEA")
    d.add_argument("--compounds", nargs="?", const="", default=None, metavar="CATALOGUE",
                   help="design every compound of a catalogue CSV (no PATH: the bundled data/compounds.csv) with its "
                        "own E, density and alpha = tan delta x omega_1(L), the length optimised, and rank them "
                        "(report table, drawing of the winner)")
    d.add_argument("--no-drum-speed", action="store_true",
                   help="with --compounds: do not search each feasible compound's fastest drum (9 ROM runs each, over "
                        "--drum-speed-bounds-rpm)")
    d.add_argument("--rank-by", choices=("objective", "fastest_drum"), default="objective",
                   help="with --compounds: order the compounds that meet the requirements by the objective (default) "
                        "or by their fastest drum, fastest first")
    d.add_argument("--robust", nargs="?", type=float, const=0.95, default=None, metavar="PROBABILITY",
                   help="with --compounds: design each compound to meet every requirement with this probability "
                        "(default 0.95) over its spread of E and tan delta, rank the robust designs and show them "
                        "beside the nominal ones")
    d.add_argument("--spread", type=float, nargs=2, default=None, metavar=("E_FRACTION", "TAN_DELTA_FRACTION"),
                   help="with --robust: half-widths of the uniform spread of E and tan delta about the nominal "
                        "values, fractions (default 0.15 0.30)")
    d.add_argument("--spread-from", default=None, metavar="CALIBRATION_JSON",
                   help="with --robust: E and alpha normal with the standard errors and correlation of a ccedi "
                        "calibrate result JSON instead of --spread")
    add_scheduler_argument(d, default="local")
    d.add_argument("--no-fea-check", action="store_true", help="skip the full-FEA re-check (minutes per design)")
    d.add_argument("--fea-check-designs", type=int, default=3, choices=(1, 2, 3),
                   help="designs the full FEA re-checks: the optimum, then the front points")
    add_output_argument(d, "--json", "file", required=True, help="result JSON path")
    add_output_argument(d, "--out", "dir", default="reports/design",
                        help="directory for the ROM cache, CSV, figures and the report")
    add_config_argument(d, CONTACT_KEYS + ("material.alpha_per_s", "damping", "requirements"))
    d.set_defaults(func=cmd_design)


def parse_weights(text):
    """``"out=w,out=w"`` as a dict of floats.

    Parameters
    ----------
    text : str

    Returns
    -------
    dict

    Raises
    ------
    InputError
        Not OUTPUT=NUMBER pairs.
    """
    try:
        pairs = [item.split("=") for item in text.split(",")]
        return {k.strip(): float(v) for k, v in pairs}
    except ValueError:
        raise InputError(f"--weights must be OUTPUT=NUMBER pairs separated by commas, got {text!r}") from None


def _int_at_least(name, value, lo):
    if value < lo:
        raise InputError(f"{name} must be an integer >= {lo}, got {value}")


@dataclass(frozen=True)
class DesignOptions:
    """What ``ccedi design`` is asked (the defaults are the command line's).

    Parameters
    ----------
    requirements : ccedi.design.requirements.Requirements or None
        The designer's requirements (None: their documented defaults).
    objective : str
        One of :data:`ccedi.design.optimise.OBJECTIVES` or "weighted".
    weights : dict or None
        ``{output: weight}`` of the weighted objective.
    damping : {"relative", "global"}
        Mass damping kind of every run.
    alpha_of_length : {"free", "paper", "fit"}
        alpha free, or tied to the length by the paper's Eq. (7) or our fit.
    alpha_bounds : tuple of float
        Damping bounds [1/s] (default :data:`ccedi.design.surrogate.CHECKED_ALPHA_PER_S`).
    length_bounds_in : tuple of float
        Finger length bounds [in].
    vary : {"length", "drum_speed", "semi_thickness", "semi_width", "taper"} or None
        The second design variable beside alpha (None: the length for the generated
        finger, the drum speed for a finger mesh).
    section_bounds_mm : tuple of float or None
        Bounds of the varied section semi-axis [mm] (None: the default of
        :data:`ccedi.design.surrogate.SECTION_BOUNDS_MM`).
    taper_bounds : tuple of float
        Bounds of the taper ratio [-] (default :data:`ccedi.design.surrogate.TAPER_BOUNDS`;
        a lower bound below it is warned of).
    drum_speed_bounds_rpm : tuple of float
        Drum speed bounds [rpm] (default :data:`ccedi.design.surrogate.DRUM_SPEED_BOUNDS_RPM`).
    grid : tuple of int
        ROM runs of the surrogate grid along alpha and the second variable.
    validation_runs : int
        Off-grid ROM runs that measure the surrogate error.
    pareto_points : int
        Epsilon-constraint points of the front.
    pareto_output : str
        The output traded against the objective on the front.
    starts : int
        IPOPT starts.
    model_error : bool
        Tighten the requirements by the ROM's measured error (:data:`MODEL_ERROR_FILE`,
        measured on the generated finger over alpha and length). Where it does not
        apply (a finger mesh, the drum speed varied), the optimum is verified by the full
        FEA instead (:func:`ccedi.design.recheck.verified_optimum` with the FEA).
    fea_check : bool
        Re-check the optimum and two front points with the full FEA (False: no FEA at
        all).
    fea_check_designs : int
        How many of the recommended designs (:func:`ccedi.design.pareto.recommended`, the
        optimum first) the FEA re-checks, 1 to 3.
    fea_correction : tuple of int or None
        Training grid of the surrogate's correction by the full FEA
        (:func:`ccedi.design.recheck.fea_correction`) along alpha and the second variable
        (None: no correction).
    robust_probability : float or None
        With the compound design: the probability every requirement is met with over the
        compounds' spread (None: nominal designs only).
    spread : ccedi.design.robust.Spread, ccedi.design.robust.CalibratedSpread or None
        The spread of the robust design (None: the default Spread).
    drum_speed : bool
        With the compound design: search every feasible compound's fastest drum
        (:func:`ccedi.design.drum_speed.with_drum_speeds`).
    rank_by : {"objective", "fastest_drum"}
        With the compound design: what orders the compounds that meet the requirements.
    """

    requirements: object = None
    objective: str = "object_force"
    weights: dict | None = None
    damping: str = "relative"
    alpha_of_length: str = "free"
    alpha_bounds: tuple = (7.5, 600.0)
    length_bounds_in: tuple = (3.0, 8.0)
    vary: str | None = None
    section_bounds_mm: tuple | None = None
    taper_bounds: tuple = (0.6, 1.0)
    drum_speed_bounds_rpm: tuple = (10.0, 40.0)
    grid: tuple = (15, 11)
    validation_runs: int = 20
    pareto_points: int = 24
    pareto_output: str = "ringing_amplitude_m"
    starts: int = 8
    model_error: bool = True
    fea_check: bool = True
    fea_check_designs: int = 3
    fea_correction: tuple | None = None
    robust_probability: float | None = None
    spread: object = None
    drum_speed: bool = True
    rank_by: str = "objective"


def options_from(cfg, **overrides):
    """:class:`DesignOptions` of the validated inputs ``cfg`` ([damping], [requirements]),
    with ``overrides``.

    Parameters
    ----------
    cfg : dict
        Validated inputs (:func:`ccedi.study.config.load`).
    **overrides
        DesignOptions fields.

    Returns
    -------
    DesignOptions
    """
    from ccedi.study.config import requirements

    base = DesignOptions(requirements=requirements(cfg), objective=cfg["requirements"]["objective"],
                         damping=cfg["damping"]["kind"])
    return replace(base, **overrides)


def cmd_design(args):
    """``ccedi design``: :func:`write_design` of the parsed arguments and ``--config``."""
    from ccedi.study.commands.fea import contact_setup

    cfg = load_config(args)
    req = options_from(cfg).requirements
    said = {name: getattr(args, name) * factor for _, name, factor in REQUIREMENT_FLAGS
            if getattr(args, name) is not None}
    if args.allowable_finger_stress_Pa is not None:
        said["allowable_root_stress_Pa"] = args.allowable_finger_stress_Pa
    for flag, name, _ in REQUIREMENT_FLAGS:
        if name in said and said[name] < 0:
            raise InputError(f"{flag} = {getattr(args, name)!r}: must be >= 0 (0: no limit)")
    req = replace(req, **{k: (v if v > 0 else None) for k, v in said.items()})
    options = options_from(
        cfg, requirements=req, objective=args.objective or cfg["requirements"]["objective"],
        weights=None if args.weights is None else parse_weights(args.weights),
        damping=args.damping or cfg["damping"]["kind"], alpha_of_length=args.alpha_of_length,
        alpha_bounds=tuple(args.alpha_bounds), length_bounds_in=tuple(args.length_bounds_in), vary=args.vary,
        section_bounds_mm=None if args.section_bounds_mm is None else tuple(args.section_bounds_mm),
        taper_bounds=tuple(args.taper_bounds),
        drum_speed_bounds_rpm=tuple(args.drum_speed_bounds_rpm), grid=_grid(args),
        validation_runs=args.validation_runs, pareto_points=args.pareto_points, pareto_output=args.pareto_output,
        starts=args.starts, model_error=not args.no_model_error, fea_check=not args.no_fea_check,
        fea_check_designs=args.fea_check_designs,
        fea_correction=None if args.fea_correction is None else tuple(args.fea_correction),
        drum_speed=not args.no_drum_speed, rank_by=args.rank_by, **robust_options(args))
    if args.compounds is None and (args.no_drum_speed or args.rank_by != "objective"):
        raise InputError(f"{'--no-drum-speed' if args.no_drum_speed else '--rank-by ' + args.rank_by}: the fastest "
                         "drum per compound belongs to the compound design: give --compounds too")
    if args.compounds is not None:
        write_catalogue_design(contact_setup(cfg), options, catalogue=args.compounds or None, json_path=args.json,
                               out=args.out, scheduler=args.scheduler)
        return
    write_design(contact_setup(cfg), options, json_path=args.json, out=args.out, scheduler=args.scheduler,
                 measured_alpha=cfg["material"]["alpha_per_s"], mesh_path=cfg["finger"]["mesh"] or None)


def _grid(args):
    """``--grid``, or its default: along alpha and L of the catalogue grid over the section
    for ``--compounds --vary semi_thickness``, else :attr:`DesignOptions.grid`."""
    from ccedi.design.catalogue_design import CATALOGUE_SECTION_GRID

    if args.grid is not None:
        return tuple(args.grid)
    section = args.compounds is not None and args.vary == "semi_thickness"
    return tuple(CATALOGUE_SECTION_GRID[:2]) if section else DesignOptions.grid


def robust_options(args):
    """The robust design's DesignOptions fields from ``--robust``, ``--spread`` and
    ``--spread-from``, checked before anything runs.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed ``ccedi design`` arguments.

    Returns
    -------
    dict
        ``robust_probability`` and ``spread``.

    Raises
    ------
    InputError
        A probability outside (0.5, 1), a spread outside [0, 0.9), both spreads, a
        spread without ``--robust``, ``--robust`` without ``--compounds``, or a
        calibration result that does not read.
    """
    from ccedi.design.robust import CalibratedSpread, Spread

    if args.robust is None:
        for flag, value in (("--spread", args.spread), ("--spread-from", args.spread_from)):
            if value is not None:
                raise InputError(f"{flag} is the robust design's spread: give --robust too")
        return {}
    if args.compounds is None:
        raise InputError("--robust designs over a compound's spread: give --compounds too")
    if not 0.5 < args.robust < 1.0:
        raise InputError(f"--robust {args.robust!r}: the probability must be in (0.5, 1), e.g. 0.95")
    if args.spread is not None and args.spread_from is not None:
        raise InputError("--spread and --spread-from: give one spread")
    if args.spread_from is not None:
        spread = CalibratedSpread.from_calibration(args.spread_from)
    elif args.spread is not None:
        try:
            spread = Spread(*args.spread)
        except InputError:
            raise InputError(f"--spread {args.spread[0]!r} {args.spread[1]!r}: each half-width must be a fraction "
                             "in [0, 0.9), e.g. 0.15 0.30") from None
    else:
        spread = Spread()
    return {"robust_probability": float(args.robust), "spread": spread}


def second_variable(setup, o):
    """The design's second variable beside alpha: ``o.vary``, by default the length for the
    generated finger and the drum speed for a finger mesh.

    Parameters
    ----------
    setup : ccedi.fea.contact.drum.DrumSetup
    o : DesignOptions

    Returns
    -------
    str
        One of :data:`VARIED`.

    Raises
    ------
    InputError
        The length or the section asked of a finger mesh (its geometry is its own).
    """
    vary = o.vary or ("length" if setup.finger is None else "drum_speed")
    if vary not in VARIED:
        raise InputError(f"--vary {vary!r}: must be one of {', '.join(VARIED)}")
    if (vary.startswith("semi_") or vary == "taper") and setup.finger is not None:
        raise InputError(f"--vary {vary}: the finger is a given {setup.finger.element_type} mesh, whose section is "
                         "its own; its design varies alpha and the drum speed (--vary drum_speed)")
    if vary == "length" and setup.finger is not None:
        raise InputError(f"--vary length: the finger is a given {setup.finger.element_type} mesh "
                         f"{setup.finger_length_m * 1e3:.4g} mm long, whose length is fixed; its design varies alpha "
                         "and the drum speed (--vary drum_speed)")
    return vary


def _check_options(setup, o):
    """Everything about the request that can be checked before the first ROM run."""
    from ccedi.design.outputs import OUTPUTS
    from ccedi.quantities import QUANTITIES
    from ccedi.units import RPM

    vary = second_variable(setup, o)
    if vary != "length" and o.alpha_of_length != "free":
        raise InputError(f"--alpha-of-length {o.alpha_of_length}: alpha tied to the length needs --vary length")
    if o.objective == "throughput" and vary != "drum_speed":
        raise InputError("--objective throughput maximises the drum speed: it needs --vary drum_speed")
    if o.objective == "throughput" and setup.cycle_time_s is not None:
        raise InputError(f"--objective throughput: [drum] cycle_time_s = {setup.cycle_time_s:g} s fixes the time "
                         "between objects whatever the drum speed; set objects_per_revolution instead")
    bounds = [("--alpha-bounds", o.alpha_bounds, QUANTITIES["alpha_per_s"]),
              ("--length-bounds-in", o.length_bounds_in, QUANTITIES["length_in"]),
              ("--drum-speed-bounds-rpm", o.drum_speed_bounds_rpm, QUANTITIES["omega_rad_s"].in_unit(1.0 / RPM, "rpm"))]
    if o.section_bounds_mm is not None:
        bounds.append(("--section-bounds-mm", o.section_bounds_mm, QUANTITIES["section_semi_axis_m"].in_unit(1e3, "mm")))
    if vary == "taper":
        bounds.append(("--taper-bounds", o.taper_bounds, QUANTITIES["taper_ratio"]))
    for flag, (lo, hi), quantity in bounds:
        for value in (lo, hi):
            quantity.check(value, flag)
        if not 0.0 < lo < hi:
            raise InputError(f"{flag} {lo:g} {hi:g}: must satisfy 0 < LO < HI ({quantity.unit})")
    if vary == "length" and max(setup.finger_semi_axes_m) >= inch_to_m(o.length_bounds_in[0]):
        raise InputError(f"--length-bounds-in {o.length_bounds_in[0]:g} {o.length_bounds_in[1]:g}: a "
                         f"{1e3 * inch_to_m(o.length_bounds_in[0]):.4g} mm finger is no longer than its section's "
                         f"semi-axis {1e3 * max(setup.finger_semi_axes_m):.4g} mm ([finger] section_semi_axes_m); "
                         "raise the lower bound")
    if o.fea_check_designs not in (1, 2, 3):
        raise InputError(f"fea_check_designs must be 1, 2 or 3, got {o.fea_check_designs}")
    if o.fea_correction is not None and not all(2 <= n <= 5 for n in o.fea_correction):
        raise InputError(f"--fea-correction {' '.join(map(str, o.fea_correction))}: training values along alpha and "
                         "the second variable, each 2 to 5 (full FE runs: their product)")
    for name, value, lo in (("--grid", min(o.grid), 4), ("--validation-runs", o.validation_runs, 1),
                            ("--pareto-points", o.pareto_points, 4), ("--starts", o.starts, 1)):
        _int_at_least(name, value, lo)
    if o.pareto_output not in OUTPUTS:
        raise InputError(f"--pareto-output {o.pareto_output!r}: must be one of {', '.join(OUTPUTS)}")
    if o.objective == "weighted" and not o.weights:
        raise InputError("--objective weighted needs --weights OUTPUT=W,...")
    for name in (o.weights or {}):
        if name not in OUTPUTS:
            raise InputError(f"--weights: {name!r} is no output; outputs: {', '.join(OUTPUTS)}")


def _model_error(o, vary):
    """The model-error margins of the request and where they come from: the ROM's
    measured error against the FEA on every output (also those within 10 %), carried
    where the design lands; none when the design varies the drum speed (the check is
    over alpha and length of the generated finger)."""
    from ccedi.design.model_error import model_errors, read_cases

    if not o.model_error or vary != "length":
        return {}, None
    if not MODEL_ERROR_FILE.exists():
        warnings.warn(ValidityWarning(f"no ROM check at {MODEL_ERROR_FILE}: the design carries no model-error "
                                      "margin (run validation/design_rom_check.py)"), stacklevel=2)
        return {}, None
    errors = model_errors(read_cases(MODEL_ERROR_FILE), damping=o.damping, alpha_bounds_per_s=o.alpha_bounds,
                          length_bounds_in=o.length_bounds_in, tolerance=0.0)
    return errors, str(MODEL_ERROR_FILE.relative_to(MODEL_ERROR_FILE.parents[2]))


def _without_runs(steps):
    """The verification steps for the JSON (their runs' outputs are the steps' ``model``)."""
    return [{k: v for k, v in s.items() if k != "run"} for s in steps]


def write_design(setup, options, *, json_path, out, scheduler="local", measured_alpha=None, mesh_path=None):
    """Build the ROM surrogate, find the design that meets the requirements at the best
    objective, draw the feasible region and the Pareto front, measure what relaxing each
    requirement buys, re-check the optimum and two front points with the full FEA, and
    write the result JSON, ``design_report.md``, ``feasible_region.png``, ``pareto.png``,
    ``pareto.csv`` and the ROM caches.

    Parameters
    ----------
    setup : ccedi.fea.contact.drum.DrumSetup
        The drum test (its finger length is replaced by each design's).
    options : DesignOptions
        What is asked.
    json_path : str or Path
        Result JSON.
    out : str or Path
        Directory for the ROM caches, CSV, figures and report.
    scheduler : str
        ``serial``, ``local`` or a Dask scheduler address (the FEA re-checks).
    measured_alpha : float, optional
        The finger's measured alpha [1/s] (``[material] alpha_per_s``): the result's
        ``measured_finger`` is the surrogate at it and the set-up's length (or drum speed).
    mesh_path : str, optional
        Where the finger mesh came from (named in the report).

    Returns
    -------
    dict
        The result written to ``json_path``.

    Raises
    ------
    ccedi.errors.InputError
        An option is out of range or contradicts another, or the length is asked of a
        finger mesh.
    ccedi.errors.RequirementsUnmet
        No design meets the requirements; raised after the result (``feasible: false``,
        the closest design and its misses) and the report are written.
    """
    import numpy as np
    import pandas as pd

    from ccedi.design.optimise import (
        DesignProblem,
        binding,
        brute_force,
        closest_design,
        on_bounds,
        sensitivities,
        solve,
    )
    from ccedi.design.pareto import pareto_front, recommended
    from ccedi.design.recheck import fea_check as recheck
    from ccedi.design.recheck import fea_correction, full_fea_factory, verified_optimum
    from ccedi.design.requirements import Requirements
    from ccedi.design.surrogate import (
        CHECKED_ALPHA_PER_S,
        TAPER_BOUNDS,
        Surrogate,
        cached_rom_runs,
        design_space,
        grid_points,
        section_space,
        speed_space,
        taper_space,
        validation_errors,
        validation_points,
    )
    from ccedi.outputs import write_csv, write_figure, write_json, write_text
    from ccedi.study.design_report import feasible_region_figure, pareto_figure, report_markdown

    o = options
    req = o.requirements if o.requirements is not None else Requirements()
    _check_options(setup, o)
    vary = second_variable(setup, o)
    out = Path(out)
    space = (design_space(tuple(o.alpha_bounds), tuple(o.length_bounds_in)) if vary == "length"
             else speed_space(tuple(o.alpha_bounds), tuple(o.drum_speed_bounds_rpm)) if vary == "drum_speed"
             else taper_space(tuple(o.alpha_bounds), tuple(o.taper_bounds)) if vary == "taper"
             else section_space(tuple(o.alpha_bounds), f"{vary}_m", o.section_bounds_mm))
    if vary == "taper" and o.taper_bounds[0] < TAPER_BOUNDS[0]:
        warnings.warn(ValidityWarning(
            f"--taper-bounds reach {o.taper_bounds[0]:g}, below {TAPER_BOUNDS[0]:g}: the full FE finger's thin tip is "
            "crushed by the contact there (an element inverted at 0.4 on the 5-in finger); its FEA re-check may "
            "fail"), stacklevel=2)
    if o.alpha_bounds[0] < CHECKED_ALPHA_PER_S[0]:
        warnings.warn(ValidityWarning(
            f"alpha bounds reach {o.alpha_bounds[0]:g} 1/s, below {CHECKED_ALPHA_PER_S[0]:g} 1/s: the contact ROM's "
            "peak force is 24-28 % below the FEA's at 3 1/s (the model-error margin carries it)"), stacklevel=2)
    errors, error_source = _model_error(o, vary)
    if o.fea_correction is not None:
        errors, error_source = {}, CORRECTED_INSTEAD
    fea_verifies = o.fea_check and not errors

    def tick(k, n):
        if k % 20 == 0 or k == n:
            print(f"ROM runs {k}/{n} ({o.damping} damping)", flush=True)

    t0 = time.perf_counter()
    grid, cached = cached_rom_runs(setup, grid_points(space, o.grid), out / "rom_grid.csv", damping=o.damping,
                                   progress=tick, variables=space)
    check_runs, _ = cached_rom_runs(setup, validation_points(space, o.validation_runs), out / "rom_validation.csv",
                                    damping=o.damping, progress=tick, variables=space)
    correction = None
    if o.fea_correction is not None:
        def fe_tick(k, n):
            print(f"full FE training runs {k}/{n} (the surrogate's correction)", flush=True)

        correction, _, correction_cached = fea_correction(setup, space, levels=o.fea_correction, damping=o.damping,
                                                          directory=out, progress=fe_tick,
                                                          model_factory=full_fea_factory)
        grid, check_runs = correction.apply(grid), correction.apply(check_runs)
    surrogate = Surrogate.fit(space, grid)
    build_s = time.perf_counter() - t0
    problem = DesignProblem(surrogate, requirements=req, objective=o.objective, weights=o.weights,
                            alpha_of_length=o.alpha_of_length, model_error=errors)
    m = setup.finger_material
    result = {
        "feasible": True,
        "finger_material": {"E_Pa": m.E, "nu": m.nu, "rho_kg_m3": m.rho},
        "drum": {"omega_rad_s": setup.omega_rad_s, "theta0_rad": setup.theta0_rad, "friction": setup.friction,
                 "object_center_m": list(setup.object_center_m), "object_semi_axes_m": list(setup.object_semi_axes_m),
                 "cycle_s": setup.cycle_s},
        "problem": {"damping": o.damping, "objective": o.objective,
                    "objective_output": None if o.objective == "weighted" else next(iter(problem.weights)),
                    "weights": problem.weights, "alpha_of_length": o.alpha_of_length,
                    "alpha_bounds_per_s": list(o.alpha_bounds),
                    "variables": [{"name": v.name, "label": v.label, "unit": v.unit, "key": v.key,
                                   "lo": float(v.shown(v.lo)), "hi": float(v.shown(v.hi))} for v in space],
                    "verified_by": "full FEA" if fea_verifies else "ROM",
                    "requirements": [lim.describe() for lim in problem.limits]},
        "finger_mesh": None if setup.finger is None else {
            "path": mesh_path or "(given mesh)", "element_type": setup.finger.element_type,
            "nodes": setup.finger.n_nodes, "elements": setup.finger.n_elements, "length_m": setup.finger_length_m},
        "requirement_outputs": {lim.describe(): lim.output for lim in problem.limits},
        "requirements_stated": {f.name: getattr(req, f.name) for f in fields(req) if f.name != "extra"},
        "model_error": {k: {"largest_under": e.largest()[0], "largest_over": e.largest()[1], "relative": e.relative,
                            "at_optimum": None} for k, e in errors.items()},
        "model_error_source": error_source,
        "surrogate": {"kind": "cubic B-spline through ROM runs (casadi interpolant)", "grid": list(o.grid),
                      "grid_from_cache": cached, "build_wall_time_s": build_s,
                      "off_grid_error": validation_errors(surrogate, check_runs),
                      "fea_correction": None if correction is None else
                      correction.as_dict() | {"training_from_cache": correction_cached}},
    }
    try:
        optimum, info = solve(problem, n_starts=o.starts)
        if fea_verifies:
            print("verifying the optimum with the full FEA (no measured ROM error applies here)", flush=True)
        optimum, problem, verification = verified_optimum(
            problem, setup, damping=o.damping, n_starts=o.starts, start=optimum,
            model_factory=full_fea_factory if fea_verifies else None)
    except RequirementsUnmet as err:
        problem = getattr(err, "problem", problem)        # shifted by the verification runs, when they shifted it
        closest, misses = closest_design(problem)
        for name, miss in misses.items():
            miss["output"] = result["requirement_outputs"][name]
        result.update({"feasible": False, "closest": closest.as_dict(problem), "misses": misses,
                       "rom_verification": _without_runs(getattr(err, "steps", []))})
        write_figure(out / "feasible_region.png", feasible_region_figure(problem, None, checked=[closest]))
        write_text(out / "design_report.md", report_markdown(result))
        write_json(json_path, result)
        print(f"no design meets the requirements; wrote {json_path}, {out}/design_report.md", flush=True)
        raise err from None
    t1 = time.perf_counter()
    front = pareto_front(problem, second=o.pareto_output, n_points=o.pareto_points)
    pareto_s = time.perf_counter() - t1
    picks = recommended(front, optimum, o.pareto_output)[:o.fea_check_designs]
    checks = [] if not o.fea_check else recheck(setup, picks, damping=o.damping, limits=problem.limits,
                                                 scheduler=scheduler, variables=space, model_factory=full_fea_factory,
                                                 done=[s["run"] for s in verification if "run" in s] if fea_verifies
                                                 else ())
    write_figure(out / "feasible_region.png", feasible_region_figure(problem, optimum, front=front, checked=picks))
    limit = next((lim.bound for lim in problem.limits if lim.output == o.pareto_output and lim.upper), None)
    write_figure(out / "pareto.png", pareto_figure(problem, front, o.pareto_output, optimum=optimum, limit=limit))
    write_csv(out / "pareto.csv", pd.DataFrame([{k: v for k, v in d.as_dict(problem).items() if k != "margins"}
                                                for d in front]))
    measured = None
    current = {"length": setup.finger_length_m, "drum_speed": setup.omega_rad_s,
               "semi_width": setup.finger_semi_axes_m[0], "semi_thickness": setup.finger_semi_axes_m[1],
               "taper": setup.finger_taper_ratio}[vary]
    if measured_alpha is not None and all(v.lo <= x <= v.hi for v, x in zip(space, (measured_alpha, current))):
        outputs = {k: float(v[0]) for k, v in surrogate.evaluate(np.array([[measured_alpha, current]])).items()}
        measured = type(optimum)(measured_alpha, current, outputs, float(problem.J(outputs))).as_dict(problem)
    grid_best = brute_force(problem)
    for k, e in errors.items():
        under, over = e.at(optimum.alpha_per_s, optimum.x)
        result["model_error"][k]["at_optimum"] = {"under": float(under), "over": float(over)}
    result.update({
        "optimum": optimum.as_dict(problem),
        "binding": binding(problem, optimum),
        "on_bounds": on_bounds(problem, optimum),
        "sensitivities": sensitivities(problem, optimum),
        "rom_verification": _without_runs(verification),
        "measured_finger": measured,
        "pareto": [d.as_dict(problem) for d in front],
        "pareto_output": o.pareto_output,
        "fea_check": checks,
        "solver": {**info, "pareto_wall_time_s": pareto_s, "pareto_points": len(front)},
        "grid_check": {"n": problem.n_check, "best": grid_best.as_dict(problem),
                       "objective_difference": problem.objective_value(optimum.outputs)
                       - problem.objective_value(grid_best.outputs)},
    })
    write_text(out / "design_report.md", report_markdown(result))
    write_json(json_path, result)
    print(f"optimum: {optimum.describe(space)} ({o.damping} damping); "
          f"objective {problem.objective_value(optimum.outputs):.4g}; binding: {', '.join(result['binding']) or 'none'}"
          + (f"; FLAG: {', '.join(result['on_bounds'])}" if result["on_bounds"] else ""), flush=True)
    print(f"wrote {json_path}, {out}/design_report.md, feasible_region.png, pareto.png ({len(front)} front points)",
          flush=True)
    return result


def write_catalogue_design(setup, options, *, catalogue=None, json_path, out, scheduler="local"):
    """Design every compound of ``catalogue`` over the finger length (with ``options.vary`` =
    "semi_thickness", over the length and the section's semi-thickness b, within
    ``options.section_bounds_mm``, default
    :data:`ccedi.design.catalogue_design.COMPOUND_THICKNESS_MM`, no model-error margin: it
    was measured on the paper's section)
    (:func:`ccedi.design.catalogue_design.design_compounds`: its nominal E, its density, alpha
    = tan delta x omega_1(L[, b])), rank them, re-check the winner with the full FEA at its own
    material, and write the result JSON, ``design_report.md``, ``finger_drawing.png``,
    ``compounds.csv`` (the ranked table) and the ROM cache. With ``options.robust_probability``,
    every compound's robust design over ``options.spread`` as well
    (:func:`ccedi.design.robust.robust_catalogue`), ranked, shown beside the nominal ones,
    the robust winner re-checked by the full FEA at its nominal inputs and drawn. With
    ``options.fea_correction``, the catalogue surrogate is corrected by the full FEA
    (:func:`ccedi.design.recheck.fea_correction` over alpha and the length, and with the
    section varied over its semi-thickness at its two bounds, on the set-up's own rubber;
    the ratio FEA / ROM held across E' (the compounds' forces scale with their E and rho
    as the ROM's do), cached in ``out``): no model-error margin is carried and
    the ROM does not verify the compounds' optima (it would undo the correction); the FEA
    re-check of the winner does. The chosen
    finger's fastest drum (:func:`ccedi.design.drum_speed.fastest_drum_speed`, over
    ``options.drum_speed_bounds_rpm``) is found by its ROM; unless ``options.drum_speed`` is
    False, every feasible compound's is, in the ranking, which ``options.rank_by`` may order
    by it (:func:`ccedi.design.drum_speed.with_drum_speeds`).

    Parameters
    ----------
    setup : ccedi.fea.contact.drum.DrumSetup
        The drum test (its finger's density is the surrogate's; each compound's E and rho
        replace its material).
    options : DesignOptions
        What is asked (requirements, objective, damping, length bounds, grid along alpha
        and L, model error, FEA re-check, IPOPT starts).
    catalogue : str or Path, optional
        The compound catalogue CSV (default: the bundled ``data/compounds.csv``).
    json_path : str or Path
        Result JSON.
    out : str or Path
        Directory for the ROM cache, table, figure and report.
    scheduler : str
        ``serial``, ``local`` or a Dask scheduler address (the FEA re-check).

    Returns
    -------
    dict
        The ranking, the winner's FEA re-check and the surrogate's figures, as written.

    Raises
    ------
    ccedi.errors.InputError
        A catalogue that does not read, an option the compound design does not take (the
        drum speed or the semi-width varied, a semi-thickness above the semi-width, alpha tied to the paper's rubber, a weighted or throughput
        objective: the fastest-drum ranking is ``rank_by``), a finger mesh, ranking by the
        fastest drum without searching it, or an option out of range.
    ccedi.errors.RequirementsUnmet
        No compound meets the requirements (or, robust, none with the probability asked);
        raised after the result and the report are written.
    """
    from ccedi.design.catalogue_design import (
        CATALOGUE_GRID,
        CATALOGUE_SECTION_GRID,
        COMPOUND_THICKNESS_MM,
        catalogue_surrogate,
        compound_setup,
        design_compounds,
    )
    from ccedi.design.compounds import CATALOGUE, load_compounds
    from ccedi.design.drum_speed import fastest_drum_speed, with_drum_speeds
    from ccedi.design.recheck import fea_check, fea_correction
    from ccedi.design.requirements import Requirements
    from ccedi.design.robust import Spread, robust_catalogue
    from ccedi.design.surrogate import Surrogate
    from ccedi.outputs import write_csv, write_figure, write_json, write_text
    from ccedi.study.design_report import catalogue_report_markdown, finger_drawing

    o = options
    for bad, said in ((o.vary in ("drum_speed", "semi_width", "taper"), f"--vary {o.vary}"),
                      (o.alpha_of_length != "free", f"--alpha-of-length {o.alpha_of_length}"),
                      (o.objective in ("weighted", "throughput"), f"--objective {o.objective}")):
        if bad:
            raise InputError(f"--compounds with {said}: the compound design varies the length (and with --vary "
                             "semi_thickness the section's semi-thickness) on each compound's own alpha and ranks an "
                             "objective in a unit (object_force, object_stress, root_stress, recovery, ringing); "
                             "--rank-by fastest_drum ranks by the fastest drum")
    if o.rank_by == "fastest_drum" and not o.drum_speed:
        raise InputError("--rank-by fastest_drum with --no-drum-speed: ranking by the fastest drum needs it searched")
    if setup.finger is not None:
        raise InputError("--compounds: the finger is a given mesh of fixed length; the compound design varies the "
                         "length of the generated finger")
    _check_options(setup, o)
    section = None
    if o.vary == "semi_thickness":
        section = tuple(o.section_bounds_mm or COMPOUND_THICKNESS_MM)
        a_mm = 1e3 * setup.finger_semi_axes_m[0]
        if section[1] > a_mm * (1 + 1e-9):
            raise InputError(f"--section-bounds-mm {section[0]:g} {section[1]:g}: with --compounds the semi-thickness "
                             f"b must stay within the semi-width a = {a_mm:.4g} mm ([finger] section_semi_axes_m; "
                             "a thicker finger's first mode bends across, along a)")
    compounds = load_compounds(catalogue)
    req = o.requirements if o.requirements is not None else Requirements()
    out = Path(out)

    def tick(k, n):
        if k % 100 == 0 or k == n:
            print(f"ROM runs {k}/{n} (catalogue grid, {o.damping} damping)", flush=True)

    t0 = time.perf_counter()
    shape = (o.grid[0], o.grid[1], *(CATALOGUE_GRID[2:] if section is None else CATALOGUE_SECTION_GRID[2:]))
    spread = None if o.robust_probability is None else (o.spread or Spread())
    surrogate, first_mode, runs, cached = catalogue_surrogate(
        setup, compounds.values(), length_bounds_in=tuple(o.length_bounds_in), shape=shape, damping=o.damping,
        path=out / "rom_catalogue_grid.csv", progress=tick, spread=spread, semi_thickness_bounds_mm=section)
    build_s = time.perf_counter() - t0
    va = surrogate.variables[0]
    # the ROM's measured error is of the paper's section: not carried when the section is designed
    errors, error_source = _model_error(replace(o, alpha_bounds=(va.lo, va.hi)), "length" if section is None
                                        else "semi_thickness")
    correction = None
    if o.fea_correction is not None:
        def fe_tick(k, n):
            print(f"full FE training runs {k}/{n} (the catalogue surrogate's correction)", flush=True)

        trained = (*surrogate.variables[:2], *surrogate.variables[3:])      # alpha, L (and b); not E'
        correction, _, correction_cached = fea_correction(
            setup, trained, levels=(*o.fea_correction, *(2,) * (len(trained) - 2)), damping=o.damping, directory=out,
            progress=fe_tick)
        surrogate = Surrogate.fit(surrogate.variables, correction.apply(runs))
        errors, error_source = {}, CORRECTED_INSTEAD
    # the ROM's verification would undo a correction: the corrected ranking is checked by the FEA re-check
    ranking = design_compounds(surrogate, compounds.values(), setup=setup, first_mode=first_mode, requirements=req,
                               objective=o.objective, model_error=errors, damping=o.damping, n_starts=o.starts,
                               verify=correction is None)
    if o.drum_speed:
        def drum_tick(k, n):
            print(f"fastest drum {k}/{n} (the feasible compounds' ROM over drum speeds)", flush=True)

        ranking = with_drum_speeds(ranking, setup, speed_bounds_rpm=tuple(o.drum_speed_bounds_rpm), damping=o.damping,
                                   rank_by=o.rank_by, progress=drum_tick)
    limits = ranking.designs[0].problem.limits
    result = {
        "feasible": ranking.winner is not None,
        "catalogue": str(catalogue or CATALOGUE.relative_to(CATALOGUE.parents[1])),
        "problem": {"damping": o.damping, "objective": o.objective, "length_bounds_in": list(o.length_bounds_in),
                    "semi_thickness_bounds_mm": None if section is None else list(section),
                    "semi_width_mm": 1e3 * setup.finger_semi_axes_m[0],
                    "requirements": [lim.describe() for lim in req.limits()]},
        "requirement_outputs": {lim.describe(): lim.output for lim in req.limits()},
        "surrogate": {"kind": "cubic B-spline through ROM runs over (alpha, L, E at the set-up's density"
                              + (", b)" if section else ")"),
                      "variables": [{"name": v.name, "lo": float(v.shown(v.lo)), "hi": float(v.shown(v.hi)),
                                     "unit": v.unit} for v in surrogate.variables],
                      "grid": list(shape), "grid_from_cache": cached, "build_wall_time_s": build_s,
                      "first_mode_fit_error": first_mode.fit_error,
                      "fea_correction": None if correction is None else
                      correction.as_dict() | {"training_from_cache": correction_cached}},
        "model_error_source": error_source,
        "compounds": ranking.as_dict(),
        "fea_check": None,
        "robust": None,
        "drum_speed": None,
    }
    by_name = {d.compound.name: d for d in ranking.designs}

    def checked(compound_design, design):
        own = compound_setup(setup, compound_design.compound, compound_design.semi_thickness_m)
        return fea_check(own, [design], damping=o.damping, limits=limits, scheduler=scheduler,
                         variables=compound_design.problem.surrogate.variables)[0]

    win = ranking.winner
    if win is not None and o.fea_check:
        result["fea_check"] = checked(win, win.design)
    robust = None
    if spread is not None:
        robust = robust_catalogue(ranking, surrogate, spread=spread, probability=o.robust_probability)
        result["robust"] = robust.as_dict() | {"fea_check": None}
        if robust.winner is not None and o.fea_check:
            result["robust"]["fea_check"] = checked(by_name[robust.winner.compound], robust.winner.design)
    if robust is not None:                       # the finger chosen: the robust winner, else the nominal one
        chosen = None if robust.winner is None else (by_name[robust.winner.compound], robust.winner.length_m)
    else:
        chosen = None if win is None else (win, win.design.x)
    if chosen is not None and chosen[0].drum is not None and chosen[1] == chosen[0].design.x:
        result["drum_speed"] = chosen[0].drum.as_dict()
    elif chosen is not None:
        result["drum_speed"] = fastest_drum_speed(chosen[0], setup, length_m=chosen[1], damping=o.damping,
                                                  speed_bounds_rpm=tuple(o.drum_speed_bounds_rpm)).as_dict()
    if robust is not None:
        r = robust.winner or robust.designs[0]
        name, length_m, alpha, met = r.compound, r.length_m, r.alpha_per_s, robust.winner is not None
        note = f" (robust, {o.robust_probability:.0%})" if met else " (closest; no robust design)"
    else:
        shown = win or ranking.designs[0]
        name, length_m, alpha, met = shown.compound.name, shown.design.x, shown.design.alpha_per_s, win is not None
        note = "" if met else " (closest; misses the requirements)"
    b = by_name[name].semi_thickness_m
    semi_axes = setup.finger_semi_axes_m if b is None else (setup.finger_semi_axes_m[0], b)
    write_figure(out / "finger_drawing.png", finger_drawing(
        length_m, semi_axes, drum_radius_m=setup.drum_radius_m, taper_ratio=setup.finger_taper_ratio,
        title=f"{name}: L = {m_to_inch(length_m):.4g} in" + ("" if b is None else f", b = {1e3 * b:.4g} mm")
        + f", alpha = {alpha:.4g} 1/s{note}"))
    write_csv(out / "compounds.csv", ranking.table)
    write_text(out / "design_report.md", catalogue_report_markdown(result))
    write_json(json_path, result)
    print("compounds ranked: " + ", ".join(f"{r['rank']}. {r['compound']}" + ("" if r["feasible"] else " (misses)")
                                           for r in result["compounds"]["table"]), flush=True)
    if robust is not None:
        print("robust designs ranked: " + ", ".join(
            f"{k}. {d.compound}" + ("" if d.feasible else " (no robust length)")
            for k, d in enumerate(robust.designs, start=1)), flush=True)
    print(f"wrote {json_path}, {out}/design_report.md, finger_drawing.png, compounds.csv", flush=True)
    if win is None:
        closest = ranking.designs[0]
        raise RequirementsUnmet(f"no compound of {result['catalogue']} meets the requirements; the closest, "
                                f"{closest.compound.name}, falls short by {closest.shortfall:.3g} (normalised): "
                                + "; ".join(closest.binding))
    if robust is not None and robust.winner is None:
        r = robust.designs[0]
        raise RequirementsUnmet(f"no compound of {result['catalogue']} meets every requirement with probability "
                                f"{o.robust_probability:g}; the closest, {r.compound} at L = "
                                f"{m_to_inch(r.length_m):.4g} in, misses one in {r.check.worst:.1%} of the samples")
    return result


CALIBRATED = "calibrated"
"""Sub-directory of the design output holding the design with the calibrated inputs."""


def write_designs(cfg, options, record, *, out, scheduler="local"):
    """The study's design step: :func:`write_design` with the declared inputs in ``out``,
    then, when ``record`` is given, :func:`write_calibrated_design` in ``out/calibrated``.

    Parameters
    ----------
    cfg : dict
        Validated study inputs (:func:`ccedi.study.config.load`).
    options : DesignOptions
        What is asked.
    record : str
        Measured record for the calibrated design ("" for none).
    out : Path
        Output directory of the step.
    scheduler : str
        ``serial``, ``local`` or a Dask scheduler address (the FEA re-checks).
    """
    from ccedi.study.commands.fea import contact_setup

    write_design(contact_setup(cfg), options, json_path=out / "design.json", out=out, scheduler=scheduler,
                 mesh_path=cfg["finger"]["mesh"] or None)
    if record:
        write_calibrated_design(cfg, record, options, out=out / CALIBRATED, scheduler=scheduler)


def write_calibrated_design(cfg, record, options, *, out, scheduler="local"):
    """Close the loop on the design: calibrate ``record``, take its calibrated inputs
    (:func:`ccedi.study.config.calibrated_config`: [material] E and alpha, [drum]
    corrections) over ``cfg`` and run :func:`write_design` with them, so that the design
    made with the declared model stands beside the one made with the measured finger.

    Writes ``out/calibration.json`` and its report, ``out/calibrated.toml`` and the design
    files (``out/design.json``, Pareto front, ROM caches, the FEA re-check of its optimum).

    Parameters
    ----------
    cfg : dict
        Validated study inputs (:func:`ccedi.study.config.load`): the declared model.
    record : str or Path
        Measured record (impulse or contact CSV with its JSON sidecar).
    options : DesignOptions
        What is asked (the same as for the declared design).
    out : str or Path
        Output directory.
    scheduler : str
        ``serial``, ``local`` or a Dask scheduler address (the FEA re-checks).

    Returns
    -------
    dict or None
        The design result (:func:`write_design`); None when the declared finger cannot
        explain the record (``out/calibration.json`` says why; no design is made).
    """
    import tomllib

    from ccedi.errors import ModelInadequate
    from ccedi.study.commands.calibrate import write_calibration
    from ccedi.study.commands.fea import contact_setup

    out = Path(out)
    toml_path = out / "calibrated.toml"
    try:
        write_calibration(Path(record), out / "calibration.json", report_dir=out / "calibration",
                          config_path=toml_path, fea_correction=cfg["study"]["calibration_fea_correction"])
    except ModelInadequate as err:
        print(f"calibrated design skipped: {err}", flush=True)
        return None
    fragment = tomllib.loads(toml_path.read_text())
    calibrated = {section: {**keys, **fragment.get(section, {})} for section, keys in cfg.items()}
    return write_design(contact_setup(calibrated), replace(options, fea_check_designs=1), json_path=out / "design.json",
                        out=out, scheduler=scheduler, measured_alpha=calibrated["material"]["alpha_per_s"])
