"""``ccedi design``: pick finger damping and length (:mod:`ccedi.design`)."""
import time
import warnings
from dataclasses import dataclass, replace
from pathlib import Path

from ccedi.errors import InputError, ValidityWarning
from ccedi.study.commands.arguments import (
    add_command,
    add_config_argument,
    add_output_argument,
    add_scheduler_argument,
    load_config,
)


def add_parsers(sub):
    """Register design on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-command registry of the ``ccedi`` parser.
    """
    d = add_command(sub, "design", help="design optimiser: alpha and finger length trading contact stress, duration "
                       "and residual oscillation (ROM surrogate, casadi/IPOPT, Pareto front, FEA re-check)")
    d.add_argument("--weights", default="1,1,1",
                   help="w_stress,w_duration,w_oscillation (>= 0, not all zero; normalised to sum 1)")
    d.add_argument("--alpha-of-length", choices=("paper", "fit", "free"), default="free",
                   help="alpha tied to length for this rubber (paper Eq. 7, or our fit) or free")
    d.add_argument("--objective-stress", choices=("reaction_force", "object_stress"), default="reaction_force",
                   help="stress objective: peak reaction force [N] or peak object von Mises stress [Pa]")
    d.add_argument("--allowable-finger-stress-Pa", type=float, help="max finger von Mises stress allowed [Pa]")
    d.add_argument("--contact-start-bounds-s", type=float, nargs=2, metavar=("LO", "HI"),
                   help="allowed first-contact time window [s]")
    d.add_argument("--alpha-bounds", type=float, nargs=2, default=DesignOptions.alpha_bounds, metavar=("LO", "HI"),
                   help="damping bounds [1/s] (default: where the contact ROM was checked against the FEA)")
    d.add_argument("--length-bounds-in", type=float, nargs=2, default=(3.0, 8.0), metavar=("LO", "HI"),
                   help="finger length bounds [in]")
    d.add_argument("--grid", type=int, nargs=2, default=(15, 11), metavar=("N_ALPHA", "N_LENGTH"),
                   help="ROM runs of the surrogate grid (cached in OUT)")
    d.add_argument("--validation-runs", type=int, default=20, help="off-grid ROM runs measuring the surrogate error")
    d.add_argument("--pareto-points", type=int, default=24, help="epsilon-constraint points of the front")
    d.add_argument("--starts", type=int, default=8, help="IPOPT starts")
    add_scheduler_argument(d, default="local")
    d.add_argument("--no-fea-check", action="store_true", help="skip the full-FEA re-check (minutes per design)")
    add_output_argument(d, "--json", "file", required=True, help="result JSON path")
    add_output_argument(d, "--out", "dir", default="reports/design", help="directory for the ROM cache, CSV and the Pareto plot")
    add_config_argument(d)
    d.set_defaults(func=cmd_design)


def _weights(text):
    try:
        w = tuple(float(v) for v in text.split(","))
    except ValueError:
        w = ()
    if len(w) != 3:
        raise InputError(f"--weights must be three comma-separated numbers w_stress,w_duration,w_oscillation, "
                         f"got {text!r}")
    return w


def _int_at_least(name, value, lo):
    if value < lo:
        raise InputError(f"{name} must be an integer >= {lo}, got {value}")


@dataclass(frozen=True)
class DesignOptions:
    """What ``ccedi design`` is asked (the defaults are the command line's).

    Parameters
    ----------
    weights : tuple of float
        w_stress, w_duration, w_oscillation (>= 0, not all zero; normalised to sum 1).
    alpha_of_length : {"free", "paper", "fit"}
        alpha free, or tied to the length by the paper's Eq. (7) or our fit.
    objective_stress : {"reaction_force", "object_stress"}
        Stress objective: peak reaction force [N] or peak object von Mises stress [Pa].
    allowable_finger_stress_Pa : float, optional
        Largest finger von Mises stress allowed [Pa].
    contact_start_bounds_s : tuple of float, optional
        Allowed first-contact time window [s].
    alpha_bounds : tuple of float
        Damping bounds [1/s] (default :data:`ccedi.design.surrogate.CHECKED_ALPHA_PER_S`;
        below it the design warns).
    length_bounds_in : tuple of float
        Finger length bounds [in].
    grid : tuple of int
        ROM runs of the surrogate grid along alpha and length.
    validation_runs : int
        Off-grid ROM runs that measure the surrogate error.
    pareto_points : int
        Epsilon-constraint points of the front.
    starts : int
        IPOPT starts.
    fea_check : bool
        Re-check the recommended designs with the full FEA.
    fea_check_designs : int
        How many of the recommended designs (:func:`ccedi.design.pareto.recommended`, the
        optimum first) the FEA re-checks, 1 to 3.
    """

    weights: tuple = (1.0, 1.0, 1.0)
    alpha_of_length: str = "free"
    objective_stress: str = "reaction_force"
    allowable_finger_stress_Pa: float | None = None
    contact_start_bounds_s: tuple | None = None
    alpha_bounds: tuple = (7.5, 600.0)
    length_bounds_in: tuple = (3.0, 8.0)
    grid: tuple = (15, 11)
    validation_runs: int = 20
    pareto_points: int = 24
    starts: int = 8
    fea_check: bool = True
    fea_check_designs: int = 3


def cmd_design(args):
    """``ccedi design``: :func:`write_design` of the parsed arguments."""
    options = DesignOptions(
        weights=_weights(args.weights), alpha_of_length=args.alpha_of_length, objective_stress=args.objective_stress,
        allowable_finger_stress_Pa=args.allowable_finger_stress_Pa,
        contact_start_bounds_s=None if args.contact_start_bounds_s is None else tuple(args.contact_start_bounds_s),
        alpha_bounds=tuple(args.alpha_bounds), length_bounds_in=tuple(args.length_bounds_in), grid=tuple(args.grid),
        validation_runs=args.validation_runs, pareto_points=args.pareto_points, starts=args.starts,
        fea_check=not args.no_fea_check)
    from ccedi.study.config import drum_setup

    cfg = load_config(args)
    write_design(drum_setup(cfg), options, args.json, args.out, scheduler=args.scheduler,
                 measured_alpha=cfg["material"]["alpha_per_s"])


def write_design(setup, options, json_path, out, scheduler="local", measured_alpha=None):
    """Build the ROM surrogate, optimise alpha and length, draw the Pareto front and
    re-check the recommended designs with the full FEA; writes the JSON result, the ROM
    caches, ``pareto.csv`` and ``pareto.png``.

    Parameters
    ----------
    setup : ccedi.fea.drum.DrumSetup
        The drum test (its finger length is replaced by each design's).
    options : DesignOptions
        What is asked.
    json_path : str or Path
        Result JSON.
    out : str or Path
        Directory for the ROM caches, CSV and plot.
    scheduler : str
        ``serial``, ``local`` or a Dask scheduler address (the FEA re-checks).
    measured_alpha : float, optional
        The finger's measured alpha [1/s] (``[material] alpha_per_s``, from ``ccedi
        calibrate --write-config``): the result's ``measured_finger`` is the surrogate at
        it and the set-up's finger length, beside the optimum (None when not given or
        outside the design space).

    Returns
    -------
    dict
        The result written to ``json_path``; ``finger_material`` holds the E_Pa, nu and
        rho_kg_m3 the designs were computed with, ``drum`` the drum set-up (omega_rad_s,
        theta0_rad, friction, object_center_m, object_semi_axes_m).

    Raises
    ------
    ccedi.errors.InputError
        An option is out of range, the problem is infeasible, or the finger is a given mesh
        (the surrogate varies the length on the contact ROM, which needs the generated finger).
    """
    import numpy as np
    import pandas as pd

    from ccedi.design.fea_check import fea_check
    from ccedi.design.optimise import Design, DesignProblem, brute_force, normalised_weights, solve
    from ccedi.design.pareto import pareto_front, plot_front, recommended
    from ccedi.design.surrogate import (
        CHECKED_ALPHA_PER_S,
        Surrogate,
        cached_rom_runs,
        design_space,
        grid_points,
        validation_errors,
        validation_points,
    )
    from ccedi.fea.outputs import write_csv, write_figure, write_json
    from ccedi.rom.contact_rom import require_generated_finger

    require_generated_finger(setup)               # the surrogate is the ROM's, over the length
    o = options
    normalised_weights(o.weights)                 # before the ROM grid, not after it
    if o.fea_check_designs not in (1, 2, 3):
        raise InputError(f"fea_check_designs must be 1, 2 or 3, got {o.fea_check_designs}")
    for name, value, lo in (("--grid", min(o.grid), 4), ("--validation-runs", o.validation_runs, 1),
                            ("--pareto-points", o.pareto_points, 20), ("--starts", o.starts, 1)):
        _int_at_least(name, value, lo)
    out = Path(out)
    space = design_space(tuple(o.alpha_bounds), tuple(o.length_bounds_in))
    if o.alpha_bounds[0] < CHECKED_ALPHA_PER_S[0]:
        warnings.warn(ValidityWarning(
            f"alpha bounds reach {o.alpha_bounds[0]:g} 1/s, below {CHECKED_ALPHA_PER_S[0]:g} 1/s where the contact ROM "
            "was checked against the full FEA: its peak force was 24 % below the FEA's at 3 1/s"), stacklevel=2)

    def tick(k, n):
        if k % 20 == 0 or k == n:
            print(f"ROM runs {k}/{n}", flush=True)

    t0 = time.perf_counter()
    grid, cached = cached_rom_runs(setup, grid_points(space, o.grid), out / "rom_grid.csv", tick)
    check_runs, _ = cached_rom_runs(setup, validation_points(space, o.validation_runs),
                                    out / "rom_validation.csv", tick)
    surrogate = Surrogate.fit(space, grid)
    build_s = time.perf_counter() - t0
    errors = validation_errors(surrogate, check_runs)
    problem = DesignProblem(surrogate, weights=o.weights, stress_measure=o.objective_stress,
                            alpha_of_length=o.alpha_of_length,
                            allowable_finger_stress_Pa=o.allowable_finger_stress_Pa,
                            contact_start_bounds_s=o.contact_start_bounds_s)
    optimum, info = solve(problem, n_starts=o.starts)
    t1 = time.perf_counter()
    front = pareto_front(problem, n_points=o.pareto_points)
    pareto_s = time.perf_counter() - t1
    grid_best = brute_force(problem)
    picks = recommended(front, optimum)[:o.fea_check_designs]
    checks = [] if not o.fea_check else fea_check(setup, picks, problem.objective_outputs,
                                                    scheduler=scheduler)
    write_figure(out / "pareto.png", plot_front(problem, front, optimum, picks))
    write_csv(out / "pareto.csv", pd.DataFrame([d.as_dict(problem) for d in front]))
    keys = problem.objective_outputs
    measured = None
    if measured_alpha is not None and all(v.lo <= x <= v.hi for v, x in zip(space, (measured_alpha,
                                                                                 setup.finger_length_m))):
        X = np.array([[measured_alpha, setup.finger_length_m]])
        outputs = {k: float(v[0]) for k, v in surrogate.evaluate(X).items()}
        measured = Design(measured_alpha, setup.finger_length_m, outputs, float(problem.J(outputs))).as_dict(problem)
    m = setup.finger_material
    result = {
        "optimum": optimum.as_dict(problem),
        "measured_finger": measured,
        "finger_material": {"E_Pa": m.E, "nu": m.nu, "rho_kg_m3": m.rho},
        "drum": {"omega_rad_s": setup.omega_rad_s, "theta0_rad": setup.theta0_rad, "friction": setup.friction,
                 "object_center_m": list(setup.object_center_m), "object_semi_axes_m": list(setup.object_semi_axes_m)},
        "pareto": [d.as_dict(problem) for d in front],
        "fea_check": checks,
        "solver": {**info, "pareto_wall_time_s": pareto_s, "pareto_points": len(front)},
        "grid_check": {"n": problem.n_check, "best": grid_best.as_dict(problem),
                       "relative_difference": {k: (optimum.outputs[k] - grid_best.outputs[k]) / abs(grid_best.outputs[k])
                                               for k in keys}},
        "surrogate": {"kind": "cubic B-spline through ROM runs (casadi interpolant)", "grid": list(o.grid),
                      "grid_from_cache": cached, "build_wall_time_s": build_s, "off_grid_error": errors},
        "problem": {"weights_normalised": list(problem.weights), "objectives": list(keys),
                    "normalisation": {k: {"min": lo, "range": r} for k, (lo, r) in problem.scale.items()},
                    "alpha_of_length": o.alpha_of_length,
                    "allowable_finger_stress_Pa": o.allowable_finger_stress_Pa,
                    "contact_start_bounds_s": o.contact_start_bounds_s,
                    "alpha_bounds_per_s": list(o.alpha_bounds), "length_bounds_in": list(o.length_bounds_in)},
    }
    write_json(json_path, result)
    best = result["optimum"]
    print(f"optimum: alpha = {best['alpha_per_s']:.4g} 1/s, L = {best['length_in']:.3f} in; "
          + ", ".join(f"{k} = {best[k]:.4g}" for k in keys) + f" ({info['status']}, {info['iterations']} iterations)")
    print(f"Pareto front: {len(front)} points in {pareto_s:.2f} s; wrote {json_path}, {out}/pareto.png")
    return result


CALIBRATED = "calibrated"
"""Sub-directory of the design output holding the design with the calibrated inputs."""


def write_designs(cfg, options, record, out, scheduler="local"):
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

    write_design(contact_setup(cfg), options, out / "design.json", out, scheduler=scheduler)
    if record:
        write_calibrated_design(cfg, record, options, out / CALIBRATED, scheduler=scheduler)


def write_calibrated_design(cfg, record, options, out, scheduler="local"):
    """Close the loop on the design: calibrate ``record``, take its calibrated inputs
    (:func:`ccedi.study.config.calibrated_config`: [material] E and alpha, [drum]
    corrections) over ``cfg`` and run :func:`write_design` with them, so that the design
    made with the declared model stands beside the one made with the measured finger.

    Writes ``out/calibration.json`` and its report, ``out/calibrated.toml`` and the design
    files (``out/design.json``, Pareto front, ROM caches, the FEA re-check of its optimum:
    the declared design's other two recommended designs show the surrogate's error off
    the optimum).

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
    return write_design(contact_setup(calibrated), replace(options, fea_check_designs=1), out / "design.json", out,
                        scheduler=scheduler, measured_alpha=calibrated["material"]["alpha_per_s"])
