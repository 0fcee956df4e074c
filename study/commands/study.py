"""``ccedi`` sub-commands of the end-to-end study (:mod:`ccedi.study`).

  study   the design study of the configured finger (--paper: and the paper's reproduction) -> OUT/index.html
  init    write a commented example study TOML
  export  a model as an LS-DYNA keyword deck, or a run's results as VTU, CSV or Parquet
"""
# Imports inside functions: building the parser imports no library, so that `ccedi --help`
# answers at once (tests/conventions/test_layout.py); each command loads what it runs.
from pathlib import Path

from ccedi.errors import InputError
from ccedi.study.commands.arguments import (
    CONTACT_KEYS,
    IMPULSE_FINGER_KEYS,
    add_command,
    add_config_argument,
    add_output_argument,
    add_scheduler_argument,
    check_flag,
    load_config,
    output_dir,
    output_file,
)


def add_parsers(sub):
    """Register study, init and export on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-command registry of the ``ccedi`` parser.
    """
    s = add_command(sub, "study", help="the design study of the configured finger (the bundled one by default): its "
                       "stiffness and first frequency, impulse and contact runs, design with FEA re-check, "
                       "calibration -> OUT/index.html; with --paper, the paper's reproduction too")
    s.add_argument("--config", help="study TOML (default: built-in defaults; see ccedi init)")
    add_output_argument(s, "--out", "dir", default="reports", help="output directory (default reports)")
    add_scheduler_argument(s, default=None)
    s.add_argument("--quick", action="store_true", help="a few-minute smoke run of every step (short runs, "
                   "one length, one contact alpha, no FEA re-check)")
    s.add_argument("--paper", action="store_true", help="also reproduce the paper on its own finger: Table 1, the "
                   "steel rod, Figs. 6 and 8, the contact sweep with its global damping ([study] paper = true)")
    s.add_argument("--only", nargs="+", metavar="STEP", help="run only these steps (finger impulse contact design "
                   "calibrate; the paper's: table1 steel_rod mesh damping_fits), then rewrite index.html")
    s.set_defaults(func=cmd_study)
    i = add_command(sub, "init", help="write a commented example study TOML (every key, its unit, range and default)")
    add_output_argument(i, "path", "file", nargs="?", default="study.toml", help="file to write (default study.toml)")
    i.add_argument("--force", action="store_true", help="overwrite an existing file")
    i.set_defaults(func=cmd_init)
    e = add_command(sub, "export", help="a model as an LS-DYNA keyword deck, or its run as VTU (ParaView), "
                       "CSV or Parquet time series")
    e.add_argument("--case", choices=("impulse", "contact"), default="impulse",
                   help="impulse: clamped finger (SM-A, or [finger] mesh of --config), tip pulse; contact: the "
                   "finger on the drum ([finger] mesh, else contact_length_in of --config, default 8 in)")
    e.add_argument("--format", choices=("lsdyna", "vtu", "csv", "parquet"), default="lsdyna",
                   help="lsdyna: a keyword deck of the model; vtu, csv, parquet: run the case and write its "
                        "animation (ParaView) or time history")
    e.add_argument("--alpha", type=float, default=180.0, help="mass-proportional damping [1/s]")
    e.add_argument("--length-in", type=float, default=None,
                   help="SM-A finger length of the impulse case [in] (4.5 when not given; not with a [finger] mesh)")
    e.add_argument("--t-end-s", type=float, help="simulated time [s] (default 0.2 impulse, 1.5 contact)")
    e.add_argument("--out", required=True, help="file (lsdyna: .k; csv/parquet) or directory (vtu)")
    add_config_argument(e, lambda args: IMPULSE_FINGER_KEYS if args.case == "impulse" else CONTACT_KEYS)
    e.set_defaults(func=cmd_export)


def cmd_study(args):
    """``ccedi study``: :func:`ccedi.study.run.run_study` of the parsed arguments."""
    from ccedi.study.run import STEP_NAMES, run_study

    cfg = load_config(args)
    if args.paper:
        cfg["study"]["paper"] = True
    unknown = sorted(set(args.only or ()) - set(STEP_NAMES))
    if unknown:
        raise InputError(f"--only: unknown step {unknown[0]!r} (steps: {' '.join(STEP_NAMES)})")
    index = run_study(cfg, args.out, scheduler=args.scheduler, quick=args.quick, only=args.only)
    print(f"wrote {index}")


def cmd_init(args):
    """``ccedi init``: write a commented example study TOML."""
    from ccedi.outputs import write_text
    from ccedi.study.config import example

    path = Path(args.path)
    if path.exists() and not args.force:
        raise InputError(f"{path} exists (use --force to overwrite)")
    write_text(path, example())
    print(f"wrote {path}; run: ccedi study --config {path}")


def _case(args, t_end_s):
    """(model, simulate) of the export case; simulate(snapshot_every) -> RunResult."""
    from ccedi.fea.cases.studies import impulse_model
    from ccedi.fea.contact.drum import contact_run, finger_on_drum
    from ccedi.fea.solvers.explicit import run
    from ccedi.study.commands.fea import contact_setup, finger_of
    from ccedi.study.config import finger_inputs

    cfg = load_config(args)
    if args.case == "impulse":
        material, semi_axes = finger_inputs(cfg)
        mesh, length_in, _ = finger_of(cfg, args.length_in)
        model = impulse_model(length_in=length_in, alpha=args.alpha, material=material, semi_axes_m=semi_axes,
                              mesh=mesh)
        return model, lambda every: run(model, t_end_s, snapshot_every=every, progress=True)
    setup = contact_setup(cfg)
    model = finger_on_drum(setup, args.alpha)[0]
    return model, lambda every: contact_run(setup, args.alpha, t_end_s=t_end_s, snapshot_every=every,
                                            progress=True)[0]


def cmd_export(args):
    """``ccedi export``: the impulse or contact case as an LS-DYNA deck, or its run as VTU, CSV or Parquet."""
    from ccedi.fea.io.lsdyna import write_keyword
    from ccedi.fea.io.vtu import write_series
    from ccedi.outputs import require_parquet, write_table

    if args.format == "parquet":
        require_parquet()
    if args.format == "vtu":
        output_dir(args.out, "--out")
    else:
        output_file(args.out if args.format == "lsdyna" else Path(args.out).with_suffix(f".{args.format}"), "--out")
    check_flag("--alpha", [args.alpha], section="study", key="contact_alphas_per_s")
    if args.length_in is not None:
        check_flag("--length-in", args.length_in, section="finger", key="impulse_length_in")
    t_end_s = args.t_end_s if args.t_end_s is not None else {"impulse": 0.2, "contact": 1.5}[args.case]
    check_flag("--t-end-s", t_end_s, section="study", key=f"{args.case}_t_end_s")
    model, simulate = _case(args, t_end_s)
    if args.format != "lsdyna":
        print(f"export: running the {args.case} case, alpha = {args.alpha:g} 1/s, {t_end_s:g} s simulated", flush=True)
    if args.format == "lsdyna":
        path = write_keyword(model, args.out, t_end_s, title=f"ccedi {args.case}, alpha = {args.alpha:g} 1/s")
    elif args.format == "vtu":
        path = write_series(args.out, model, simulate(10), stem=args.case)
    else:
        path = write_table(Path(args.out).with_suffix(f".{args.format}"), simulate(0).history)
    print(f"wrote {path}")
