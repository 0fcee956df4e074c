"""``ccedi design``: pick finger damping and length (registered by :mod:`fea.cli`)."""
import time
from pathlib import Path

from fea.distributed import add_scheduler_argument
from fea.errors import InputError
from study.config import add_config_argument, drum_setup, from_args


def add_parsers(sub):
    d = sub.add_parser("design", help="design optimiser: alpha and finger length trading contact stress, duration "
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
    d.add_argument("--alpha-bounds", type=float, nargs=2, default=(1.0, 600.0), metavar=("LO", "HI"),
                   help="damping bounds [1/s]")
    d.add_argument("--length-bounds-in", type=float, nargs=2, default=(3.0, 8.0), metavar=("LO", "HI"),
                   help="finger length bounds [in]")
    d.add_argument("--grid", type=int, nargs=2, default=(15, 11), metavar=("N_ALPHA", "N_LENGTH"),
                   help="ROM runs of the surrogate grid (cached in OUT)")
    d.add_argument("--validation-runs", type=int, default=20, help="off-grid ROM runs measuring the surrogate error")
    d.add_argument("--pareto-points", type=int, default=24, help="epsilon-constraint points of the front")
    d.add_argument("--starts", type=int, default=8, help="IPOPT starts")
    add_scheduler_argument(d, default="local")
    d.add_argument("--no-fea-check", action="store_true", help="skip the full-FEA re-check (minutes per design)")
    d.add_argument("--json", required=True, help="result JSON path")
    d.add_argument("--out", default="reports/design", help="directory for the ROM cache, CSV and the Pareto plot")
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


def cmd_design(args):
    import pandas as pd

    from fea.outputs import write_csv, write_figure, write_json

    from .fea_check import fea_check
    from .optimise import DesignProblem, brute_force, solve
    from .pareto import pareto_front, plot_front, recommended
    from .surrogate import Surrogate, cached_rom_runs, design_space, grid_points, validation_errors, validation_points

    weights = _weights(args.weights)
    for name, value, lo in (("--grid", min(args.grid), 4), ("--validation-runs", args.validation_runs, 1),
                            ("--pareto-points", args.pareto_points, 20), ("--starts", args.starts, 1)):
        _int_at_least(name, value, lo)
    out = Path(args.out)
    setup = drum_setup(from_args(args))
    space = design_space(tuple(args.alpha_bounds), tuple(args.length_bounds_in))

    def tick(k, n):
        if k % 20 == 0 or k == n:
            print(f"ROM runs {k}/{n}", flush=True)

    t0 = time.perf_counter()
    grid, cached = cached_rom_runs(setup, grid_points(space, args.grid), out / "rom_grid.csv", tick)
    check_runs, _ = cached_rom_runs(setup, validation_points(space, args.validation_runs),
                                    out / "rom_validation.csv", tick)
    surrogate = Surrogate.fit(space, grid)
    build_s = time.perf_counter() - t0
    errors = validation_errors(surrogate, check_runs)
    problem = DesignProblem(surrogate, weights=weights, stress_measure=args.objective_stress,
                            alpha_of_length=args.alpha_of_length,
                            allowable_finger_stress_Pa=args.allowable_finger_stress_Pa,
                            contact_start_bounds_s=args.contact_start_bounds_s)
    optimum, info = solve(problem, n_starts=args.starts)
    t1 = time.perf_counter()
    front = pareto_front(problem, n_points=args.pareto_points)
    pareto_s = time.perf_counter() - t1
    grid_best = brute_force(problem)
    picks = recommended(front, optimum)
    checks = [] if args.no_fea_check else fea_check(setup, picks, problem.objective_outputs,
                                                    scheduler=args.scheduler)
    write_figure(out / "pareto.png", plot_front(problem, front, optimum, picks))
    write_csv(out / "pareto.csv", pd.DataFrame([d.as_dict(problem) for d in front]))
    keys = problem.objective_outputs
    result = {
        "optimum": optimum.as_dict(problem),
        "pareto": [d.as_dict(problem) for d in front],
        "fea_check": checks,
        "solver": {**info, "pareto_wall_time_s": pareto_s, "pareto_points": len(front)},
        "grid_check": {"n": problem.n_check, "best": grid_best.as_dict(problem),
                       "relative_difference": {k: (optimum.outputs[k] - grid_best.outputs[k]) / abs(grid_best.outputs[k])
                                               for k in keys}},
        "surrogate": {"kind": "cubic B-spline through ROM runs (casadi interpolant)", "grid": list(args.grid),
                      "grid_from_cache": cached, "build_wall_time_s": build_s, "off_grid_error": errors},
        "problem": {"weights_normalised": list(problem.weights), "objectives": list(keys),
                    "normalisation": {k: {"min": lo, "range": r} for k, (lo, r) in problem.scale.items()},
                    "alpha_of_length": args.alpha_of_length,
                    "allowable_finger_stress_Pa": args.allowable_finger_stress_Pa,
                    "contact_start_bounds_s": args.contact_start_bounds_s,
                    "alpha_bounds_per_s": list(args.alpha_bounds), "length_bounds_in": list(args.length_bounds_in)},
    }
    write_json(args.json, result)
    o = result["optimum"]
    print(f"optimum: alpha = {o['alpha_per_s']:.4g} 1/s, L = {o['length_in']:.3f} in; "
          + ", ".join(f"{k} = {o[k]:.4g}" for k in keys) + f" ({info['status']}, {info['iterations']} iterations)")
    print(f"Pareto front: {len(front)} points in {pareto_s:.2f} s; wrote {args.json}, {out}/pareto.png")
