"""Calibration of the bundled full-FEA contact records (data/contact/): outcome against
the manifest of truths, and the time to calibrate each record (target: under 5 minutes):
wall time and the process's CPU time (on this machine other jobs' measurements pause
helper processes, which the wall time then includes).

Per record: the effect selected (or the ambiguity, or nothing), whether it is the injected
one, the final NRMSE over the noise floor (target: within 10 %; and the chain's own
baseline before its FEA correction), the model error std the stopping test allowed (over
the noise std), the full FEA at the final parameters against the record (``fea_check``),
the calibrated E factor and alpha against the truth, the wall time [s]. Totals: right effects among the effect
records, false positives among the clean controls, the largest time. The chain ROM is
built and compiled before the timing; the 1-minute load average is recorded (the times
scale with it on the shared 2-core machine).

Run: ``.venv/bin/python validation/calibrate_contact.py [--chain] [--discrepancy] [--bias] [--contact face] [NAME ...]``
(every record of the manifest by default; ~2-4 min each with the FEA correction, under a
minute with the chain alone); writes validation/calibrate_contact.json, with ``--chain``
(the chain alone, no FEA correction: ``ccedi calibrate``'s default)
calibrate_contact_chain.json, with ``--discrepancy`` (the chain's measured discrepancy from
the FEA, :data:`ccedi.calibrate.discrepancy.CHAIN_DISCREPANCY`, carried in the likelihood
instead of the white model error) ..._discrepancy.json, with ``--bias`` (the chain's mean
bias over the FE design, :class:`ccedi.calibrate.chain_bias.ChainBias`, added to its
force) ..._bias.json, or calibrate_contact_face.json with
the chain's face contact
(``ccedi.rom.contact_rom.DEFAULT_CONTACT`` set to "face" for the run).
"""
import json
import os
import sys
import time
from pathlib import Path

from ccedi.calibrate.chain_bias import ChainBias
from ccedi.calibrate.contact_model import DrumContactModel
from ccedi.calibrate.discrepancy import CHAIN_DISCREPANCY
from ccedi.calibrate.experiment import load_experiment
from ccedi.calibrate.loop import calibrate, calibration_model, summary
from ccedi.outputs import report_figures

DATA = Path(__file__).parents[1] / "data" / "contact"
OUT = Path(__file__).with_suffix(".json")


def outcome(result, truth):
    """(selected, right) of a calibration against its truth: the selected effect, or
    'ambiguous: a/b', or None; right when it names the injected effect (alone or in the
    ambiguity) or, for a control, nothing."""
    injected = set(truth["effects"])
    if result["ambiguous"]:
        names = result["ambiguous"]["effects"]
        return "ambiguous: " + "/".join(names), bool(injected & set(names))
    chosen = [e["name"] for e in result["effects_found"]]
    return "+".join(chosen) or None, set(chosen) == injected


def main(args):
    import ccedi.rom.contact_rom as contact_rom

    out, names = OUT, list(args)
    fea_correction = "--chain" not in names
    if not fea_correction:
        names.remove("--chain")
        out = OUT.with_name("calibrate_contact_chain.json")
    if "--discrepancy" in names:
        names.remove("--discrepancy")
        DrumContactModel.discrepancy = CHAIN_DISCREPANCY
        out = out.with_name(out.stem + "_discrepancy.json")
    if "--bias" in names:
        names.remove("--bias")
        DrumContactModel.bias = ChainBias.read()
        out = out.with_name(out.stem + "_bias.json")
    if names[:1] == ["--contact"]:
        contact_rom.DEFAULT_CONTACT, names = names[1], names[2:]
        out = OUT.with_name(f"calibrate_contact_{contact_rom.DEFAULT_CONTACT}.json")
    manifest = json.loads((DATA / "manifest.json").read_text())["records"]
    names = names or list(manifest)
    figures = {"contact_model": contact_rom.DEFAULT_CONTACT, "fea_correction": fea_correction,
               "discrepancy": None if DrumContactModel.discrepancy is None else DrumContactModel.discrepancy.summary(),
               "bias": None if DrumContactModel.bias is None else DrumContactModel.bias.summary(),
               "load_average_1min_before": round(os.getloadavg()[0], 1)}
    first = load_experiment(DATA / f"{names[0]}.csv")
    model = calibration_model(first)
    model.predict({"alpha_per_s": 100.0, "E_factor": 1.0})              # build and compile
    rows = {}
    for name in names:
        exp = load_experiment(DATA / f"{name}.csv")
        t0, c0 = time.perf_counter(), time.process_time()
        result = summary(calibrate(exp, fea_correction=fea_correction))
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        truth = manifest[name]
        selected, right = outcome(result, truth)
        rows[name] = {"injected": list(truth["effects"]) or None, "selected": selected, "right": right,
                      "final_nrmse_over_noise_floor": result["final_nrmse"] / result["noise_floor_nrmse"],
                      "E_factor": result["final_params"]["E_factor"], "E_factor_true": truth["E_factor"],
                      "alpha_per_s": result["final_params"]["alpha_per_s"], "alpha_true": truth["alpha_per_s"],
                      "params": result["final_params"], "unexplained_residual": result["unexplained_residual"],
                      "chain_baseline_nrmse_over_noise_floor": (None if result["chain_baseline"] is None else
                                                                result["chain_baseline"]["nrmse"]
                                                                / result["noise_floor_nrmse"]),
                      "model_error_over_noise": result["model_error_std"] / exp.noise_std_N,
                      "fea_check": result["fea_check"], "stop_reason": result["stop_reason"],
                      "wall_time_s": wall, "cpu_time_s": cpu}
        print(name, json.dumps(rows[name]), flush=True)
    effects = [r for r in rows.values() if r["injected"]]
    controls = [r for r in rows.values() if not r["injected"]]
    figures.update({"records": len(rows), "right_effect": f"{sum(r['right'] for r in effects)} of {len(effects)}",
                    "selected_exactly": f"{sum(r['right'] and not str(r['selected']).startswith('ambiguous') for r in effects)}"
                                        f" of {len(effects)}",
                    "control_false_positives": f"{sum(not r['right'] for r in controls)} of {len(controls)}",
                    "max_final_nrmse_over_noise_floor": max(r["final_nrmse_over_noise_floor"] for r in rows.values()),
                    "max_wall_time_s": max(r["wall_time_s"] for r in rows.values()),
                    "max_cpu_time_s": max(r["cpu_time_s"] for r in rows.values()),
                    "load_average_1min_after": round(os.getloadavg()[0], 1), "per_record": rows})
    report_figures(figures, out)


if __name__ == "__main__":
    main(sys.argv[1:])
