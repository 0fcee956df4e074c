"""The ``ccedi`` command line.

Sub-commands:
  table1   the paper's Table 1 for SM-A and SM-B (nodes, elements, time step, stiffness)
  impulse  impulse response of the SM-A finger for several alpha (paper Fig. 7), CSV + plot
and the sub-commands of :mod:`rom.cli` (identify, damping-fits).
"""
import argparse
import sys
from pathlib import Path

from .errors import InputError, SolverError


def _fmt(value):
    return f"{value:d}" if isinstance(value, int) else f"{value:.4g}"


def _cmd_table1(args):
    from .outputs import write_json
    from .studies import PAPER_TABLE1, table1

    result = table1(length_in=args.length_in, stiffness=not args.no_stiffness)
    for name, row in result.items():
        paper = PAPER_TABLE1[name] if args.length_in == 4.5 else {}
        print(f"{name}: " + ", ".join(
            f"{k} = {_fmt(v)}" + (f" (paper {_fmt(paper[k])})" if k in paper else "") for k, v in row.items()))
    if args.json:
        write_json(args.json, result)
        print(f"wrote {args.json}")


def _cmd_impulse(args):
    import numpy as np

    from .outputs import write_csv, write_figure, write_json
    from .studies import impulse_study, plot_impulse_study

    out = Path(args.out)
    history, summaries = impulse_study(alphas=args.alpha, length_in=args.length_in, force_N=args.force_N,
                                       duration_s=args.duration_s, t_end_s=args.t_end_s)
    write_csv(out / "impulse_response.csv", history)
    write_figure(out / "impulse_response.png", plot_impulse_study(history))
    peaks = {}
    for a, h in history.groupby("alpha_per_s"):
        i = int(np.argmax(h.tip_uy_m.values))
        peaks[f"{a:g}"] = {"peak_tip_uy_m": float(h.tip_uy_m.values[i]),
                           "time_of_peak_s": float(h.time_s.values[i]),
                           "min_tip_uy_after_peak_m": float(h.tip_uy_m.values[i:].min()),
                           "peak_von_mises_Pa": float(h.max_von_mises_Pa.max())}
    write_json(out / "impulse_summary.json", {
        "length_in": args.length_in, "force_N": args.force_N, "duration_s": args.duration_s,
        "runs": summaries, "peaks": peaks})
    for s in summaries:
        print(f"alpha = {s['alpha_per_s']:g} 1/s: {s['steps']} steps, dt0 = {s['dt_initial_s'] * 1e6:.3f} us, "
              f"wall {s['wall_time_s']:.2f} s ({s['ns_per_element_cycle']:.0f} ns/element-cycle)")
    print(f"wrote {out}/impulse_response.csv, .png, impulse_summary.json")


def build_parser():
    p = argparse.ArgumentParser(prog="ccedi", description="Compliant finger design: explicit FEA, "
                                "damping identification, reduced models, design optimisation.")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    t = sub.add_parser("table1", help="paper Table 1: nodes, elements, stable time step and tip stiffness "
                       "of SM-A and SM-B")
    t.add_argument("--length-in", type=float, default=4.5, help="finger length [in] (default 4.5)")
    t.add_argument("--json", help="write the table as JSON to this path")
    t.add_argument("--no-stiffness", action="store_true", help="skip the static stiffness solves")
    t.set_defaults(func=_cmd_table1)
    i = sub.add_parser("impulse", help="tip impulse response of the SM-A finger for several alpha "
                       "(paper Fig. 7): CSV, plot, JSON")
    i.add_argument("--alpha", type=float, nargs="+", default=[70.0, 120.0, 160.0, 180.0, 200.0],
                   help="mass-proportional damping values [1/s]")
    i.add_argument("--length-in", type=float, default=4.5, help="finger length [in]")
    i.add_argument("--force-N", type=float, default=1.0, help="tip force [N] (soft direction)")
    i.add_argument("--duration-s", type=float, default=0.01, help="pulse duration [s]")
    i.add_argument("--t-end-s", type=float, default=0.2, help="simulated time [s]")
    i.add_argument("--out", default="reports/impulse", help="output directory")
    i.set_defaults(func=_cmd_impulse)
    from rom.cli import add_parsers as add_rom_parsers
    add_rom_parsers(sub)
    return p


def main(argv=None):
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        args.func(args)
    except (InputError, SolverError) as err:
        print(f"ccedi {args.command}: error: {err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"ccedi {args.command}: interrupted; no partial outputs were written", file=sys.stderr)
        return 130
    return 0


if __name__ == "__main__":
    sys.exit(main())
