"""Compare two study output folders number by number: every JSON leaf and every numeric
CSV cell present in both, ignoring wall times (which change from run to run).

Used to check that a change which should not move any published figure (a refactoring, a
package move) did not: run ``ccedi study --paper --out BEFORE`` on the old code and
``--out AFTER`` on the new, then

    python validation/compare_reports.py BEFORE AFTER [--rtol 1e-9] [--json OUT.json]

Prints, per file, the number of values compared, the largest relative difference and the
values beyond ``rtol``; the keys and files only one side has; writes the same as JSON
(relative differences are |a - b| / max(|a|, |b|), 0 for two zeros). Exit status 0 when
nothing differs beyond ``rtol``, 1 otherwise.
"""
import argparse
import json
import math
import re
import sys
from pathlib import Path

import pandas as pd

IGNORED = re.compile(r"wall_time|elapsed|ns_per|per_eval|speedup|build_time|timestamp|generated|from_cache|"
                     r"cached|scheduler|sha256|^config$")
"""Keys (or CSV columns) whose values are not results: timings, cache flags and source
hashes, and the inputs (``study.json``'s ``config``, whose paths name the checkout)."""


def leaves(value, path=""):
    """``{path: number or str}`` of a JSON value's leaves (dict keys and list indices joined by '/')."""
    if isinstance(value, dict):
        out = {}
        for k, v in value.items():
            if not IGNORED.search(str(k)):
                out.update(leaves(v, f"{path}/{k}"))
        return out
    if isinstance(value, list):
        out = {}
        for i, v in enumerate(value):
            out.update(leaves(v, f"{path}[{i}]"))
        return out
    return {path: value}


def relative_difference(a, b):
    """|a - b| / max(|a|, |b|) for numbers (0 for equal values, NaN equal to NaN), 0 or inf
    for other values (equal or not)."""
    if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, (int, float)) or not isinstance(b, (int, float)):
        return 0.0 if a == b else math.inf
    if math.isnan(a) and math.isnan(b):
        return 0.0
    scale = max(abs(a), abs(b))
    return 0.0 if scale == 0 else abs(a - b) / scale


def csv_leaves(path):
    """The numeric cells of a CSV as ``{column[row]: value}`` (timing columns left out)."""
    frame = pd.read_csv(path)
    out = {}
    for column in frame.columns:
        if IGNORED.search(column) or not pd.api.types.is_numeric_dtype(frame[column]):
            continue
        out.update({f"{column}[{i}]": float(v) for i, v in enumerate(frame[column].to_numpy())})
    return out


def compare_file(before, after, rtol):
    """Compare one file's values; returns its record (counts, largest difference, offenders)."""
    read = (lambda p: leaves(json.loads(p.read_text()))) if before.suffix == ".json" else csv_leaves
    a, b = read(before), read(after)
    common = sorted(set(a) & set(b))
    diffs = {k: relative_difference(a[k], b[k]) for k in common}
    worst = max(diffs.values(), default=0.0)
    return {"compared": len(common), "max_relative_difference": worst,
            "beyond_rtol": {k: [a[k], b[k]] for k, d in diffs.items() if d > rtol},
            "only_before": sorted(set(a) - set(b)), "only_after": sorted(set(b) - set(a))}


def compare(before, after, rtol):
    """Compare every JSON and CSV file of two study folders."""
    files = lambda root: {p.relative_to(root) for p in root.rglob("*") if p.suffix in (".json", ".csv")}  # noqa: E731
    a, b = files(before), files(after)
    result = {"rtol": rtol, "files": {}, "only_before": sorted(map(str, a - b)), "only_after": sorted(map(str, b - a))}
    for rel in sorted(a & b):
        result["files"][str(rel)] = compare_file(before / rel, after / rel, rtol)
    return result


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--rtol", type=float, default=1e-9, help="relative tolerance (default 1e-9)")
    parser.add_argument("--json", type=Path, help="also write the comparison here")
    args = parser.parse_args(argv)
    for folder in (args.before, args.after):
        if not folder.is_dir():
            parser.error(f"{folder}: not a folder")
    result = compare(args.before, args.after, args.rtol)
    failed = False
    for name, r in result["files"].items():
        mark = "DIFFERS" if r["beyond_rtol"] else "same"
        failed |= bool(r["beyond_rtol"])
        print(f"{mark:8s} {name}: {r['compared']} values, largest relative difference {r['max_relative_difference']:.3g}"
              + (f"; only before: {len(r['only_before'])} keys" if r["only_before"] else "")
              + (f"; only after: {len(r['only_after'])} keys" if r["only_after"] else ""))
        for key, (x, y) in list(r["beyond_rtol"].items())[:10]:
            print(f"         {key}: {x!r} -> {y!r}")
    for side in ("only_before", "only_after"):
        if result[side]:
            print(f"files {side.replace('_', ' ')}: {', '.join(result[side])}")
    if args.json:
        args.json.write_text(json.dumps(result, indent=1, default=str) + "\n")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
