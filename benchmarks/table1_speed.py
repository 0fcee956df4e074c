"""Wall time of ``ccedi table1`` (SM-A, SM-B, SM-C with their nonlinear tip stiffness and
first frequency, the DM's mesh and step), here and in a baseline checkout, side by side.

Each run is ``ccedi table1 --json`` in a process of its own (imports, meshing and solves
included, as a user waits for it); with ``--baseline DIR`` (another checkout of ccedi with
its own ``.venv``, e.g. ``git worktree add /tmp/base <commit> && make -C /tmp/base
.venv/.installed``) the two alternate, ``--repeats`` times each, and the best of each is
compared. Every numeric figure of the two tables must agree within 1e-6 relative.

Prints and writes benchmarks/table1_speed.json: each run's wall time [s], the best of
each, the speed-up and the largest relative difference of the figures.

Run: ``.venv/bin/python benchmarks/table1_speed.py [--baseline DIR] [--repeats N]``.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from ccedi.outputs import report_figures

OUT = Path(__file__).with_suffix(".json")
HERE = Path(__file__).resolve().parents[1]


def timed_table1(checkout, json_path):
    """Wall time [s] of ``ccedi table1 --json json_path`` run in ``checkout``."""
    ccedi = Path(checkout) / ".venv" / "bin" / "ccedi"
    if not ccedi.exists():
        raise SystemExit(f"--baseline {checkout}: no {ccedi} (make .venv/.installed there first)")
    t0 = time.perf_counter()
    subprocess.run([str(ccedi), "table1", "--json", str(json_path)], cwd=checkout, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t0


def numbers(table, prefix=""):
    """Every numeric leaf of a Table 1 JSON, by its path."""
    if isinstance(table, dict):
        return {k: v for key, value in table.items() for k, v in numbers(value, f"{prefix}/{key}").items()}
    if isinstance(table, (int, float)) and not isinstance(table, bool):
        return {prefix: float(table)}
    return {}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", help="another ccedi checkout with its own .venv to compare with")
    parser.add_argument("--repeats", type=int, default=2, help="runs of each (default 2)")
    args = parser.parse_args()
    checkouts = {"this": HERE} | ({"baseline": Path(args.baseline).resolve()} if args.baseline else {})
    times = {name: [] for name in checkouts}
    with tempfile.TemporaryDirectory() as tmp:
        for repeat in range(args.repeats):
            for name, checkout in checkouts.items():
                seconds = timed_table1(checkout, Path(tmp) / f"{name}.json")
                times[name].append(round(seconds, 2))
                print(f"run {repeat + 1}: {name} {seconds:.1f} s", flush=True)
        tables = {name: numbers(json.loads((Path(tmp) / f"{name}.json").read_text())) for name in checkouts}
    figures = {f"{name}_runs_s": runs for name, runs in times.items()}
    figures |= {f"{name}_best_s": min(runs) for name, runs in times.items()}
    if args.baseline:
        this, base = tables["this"], tables["baseline"]
        shared = [key for key in base if key in this]
        figures["speedup_best_over_best"] = round(min(times["baseline"]) / min(times["this"]), 2)
        figures["figures_compared"] = len(shared)
        figures["largest_relative_difference"] = max(abs(this[k] - base[k]) / max(abs(base[k]), 1e-300)
                                                     for k in shared)
    figures["load_average_after"] = round(os.getloadavg()[0], 2)
    figures["cores"] = os.cpu_count()
    figures["python"] = sys.version.split()[0]
    report_figures(figures, OUT)


if __name__ == "__main__":
    main()
