"""Calibration of the contact validation set (data/contact_validation/, made by
:mod:`ccedi.calibrate.contact_validation_set`: another mesh, coloured noise, both damping
kinds, two effect sizes) against its manifest of truths, scored per half.

The calibration's rules and thresholds were set on the bundled set (data/contact/), not on
this one: both halves are unseen; the ``tuning`` half is the one a later retuning may use,
the ``held_out`` half is then the figure to quote.

Per record: the injected effect (catalogue name), the effects found, the ambiguity, right
or not (an effect record: its effect found alone and no ambiguity, or nothing found and
the effect within a reported ambiguous pair; a control: nothing found and no ambiguity), right exactly (found alone), the damping kind
declared (the true one), supported and used, the final E factor and alpha against the
truth, the stop reason, the wall time [s].

Totals per half and over both: the right effect x/N with its Wilson 95 % interval,
exactly, the controls with nothing found, the records whose damping kind the calibration
changed (every change is wrong here: the sidecars declare the true kind), per effect and
size the right fraction.

Run: ``.venv/bin/python validation/calibrate_contact_validation.py [--jobs N] [--bias] [NAME ...]``
(every record by default; about a minute each on one core; ``--jobs`` calibrations at a
time, default 1); writes validation/calibrate_contact_validation.json after every record
(records named on the command line replace their rows), with ``--bias`` (the chain's mean
bias added to its force, :class:`ccedi.calibrate.chain_bias.ChainBias`)
calibrate_contact_validation_bias.json.
"""
import json
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from ccedi.calibrate.chain_bias import ChainBias
from ccedi.calibrate.contact_model import DrumContactModel
from ccedi.calibrate.experiment import load_experiment
from ccedi.calibrate.loop import calibrate, summary
from ccedi.outputs import report_figures
from ccedi.statistics import wilson_interval

DATA = Path(__file__).parents[1] / "data" / "contact_validation"
OUT = Path(__file__).with_suffix(".json")


def calibrated_row(name, truth):
    """Calibrate one record and score it against its truth (module docstring)."""
    t0 = time.perf_counter()
    result = summary(calibrate(load_experiment(DATA / f"{name}.csv")))
    wall = time.perf_counter() - t0
    injected = set(truth["effects"])
    found = [e["name"] for e in result["effects_found"]]
    ambiguous = result["ambiguous"]["effects"] if result["ambiguous"] else None
    if injected:
        exactly = found == sorted(injected) and ambiguous is None
        right = exactly or bool(not found and ambiguous and len(ambiguous) <= 2 and injected <= set(ambiguous))
    else:
        exactly = right = not found and ambiguous is None
    kind = result["damping_kind"]
    return {"half": truth["half"], "injected": sorted(injected) or None, "params_true": truth["effects"],
            "damping": truth["damping"], "found": found, "ambiguous": ambiguous, "right": bool(right),
            "right_exactly": bool(exactly), "rejected": result["rejected_effects"],
            "damping_supported": kind["supported"], "damping_used": kind["used"],
            "E_factor": result["final_params"]["E_factor"], "E_factor_true": truth["E_factor"],
            "alpha_per_s": result["final_params"]["alpha_per_s"], "alpha_true": truth["alpha_per_s"],
            "params": result["final_params"], "stop_reason": result["stop_reason"],
            "noise_ar_true": truth["noise_ar"], "wall_time_s": wall}


def totals(rows):
    """The totals of a set of rows (module docstring)."""
    effects = {k: r for k, r in rows.items() if r["injected"]}
    controls = [r for r in rows.values() if not r["injected"]]
    out = {"records": len(rows)}
    if effects:
        right = sum(r["right"] for r in effects.values())
        low, high = wilson_interval(right, len(effects))
        out |= {"effect_records": len(effects), "right_effect": right, "right_fraction": right / len(effects),
                "right_wilson95": [low, high],
                "right_exactly": sum(r["right_exactly"] for r in effects.values())}
        groups = {}
        for name, r in effects.items():
            size = "small" if "_small_" in name else "large"
            groups.setdefault(f"{r['injected'][0]} {size}", []).append(r["right"])
        out["right_by_effect_and_size"] = {k: f"{sum(v)} of {len(v)}" for k, v in sorted(groups.items())}
    if controls:
        clean = sum(r["right"] for r in controls)
        out |= {"controls": len(controls), "controls_nothing_found": clean,
                "control_false_positive_wilson95": list(wilson_interval(len(controls) - clean, len(controls)))}
    out["damping_kind_changed"] = sum(r["damping_used"] != r["damping"] for r in rows.values())
    return out


def write(rows, extra, out):
    """The JSON of the rows so far (to ``out``): totals per half and over both, then every row."""
    figures = dict(extra)
    for half in ("held_out", "tuning"):
        figures[half] = totals({k: r for k, r in rows.items() if r["half"] == half})
    figures["both_halves"] = totals(rows)
    figures["max_wall_time_s"] = max(r["wall_time_s"] for r in rows.values())
    figures["load_average_1min_now"] = round(os.getloadavg()[0], 1)
    figures["per_record"] = dict(sorted(rows.items()))
    report_figures(figures, out)


def main(args):
    jobs, out = 1, OUT
    if args[:1] == ["--jobs"]:
        jobs, args = int(args[1]), args[2:]
    if args[:1] == ["--bias"]:
        args = args[1:]
        DrumContactModel.bias = ChainBias.read()
        out = OUT.with_name(OUT.stem + "_bias.json")
    manifest = json.loads((DATA / "manifest.json").read_text())
    truths = manifest["records"]
    names = args or list(truths)
    rows = json.loads(out.read_text())["per_record"] if args and out.is_file() else {}
    extra = {"generator": manifest["generator"], "jobs": jobs,
             "bias": None if DrumContactModel.bias is None else DrumContactModel.bias.summary(),
             "rules": "set on the bundled set data/contact/ (not tuned on this set)"}
    with ProcessPoolExecutor(max_workers=jobs) as pool:
        futures = {pool.submit(calibrated_row, name, truths[name]): name for name in names}
        for done, future in enumerate(as_completed(futures), 1):
            name = futures[future]
            rows[name] = r = future.result()
            print(f"[{done}/{len(names)}] {name}: injected {r['injected']}, found {r['found']}, ambiguous "
                  f"{r['ambiguous']}, right {r['right']}, damping {r['damping']} -> {r['damping_used']}, "
                  f"{r['wall_time_s']:.0f} s", flush=True)
            write(rows, extra, out)


if __name__ == "__main__":
    main(sys.argv[1:])
