"""Calibration of the impulse records with model-form error (data/measured_solid/, made by
:mod:`ccedi.calibrate.synthetic_solid` from SM-C's tetrahedra with the effects built into the
FE) against their manifest of truths.

Per record: its role (effect, control, declaration), the injected effects, the adequacy
verdict (failed checks, the record's own first frequency [Hz], its first-mode effective
tip mass [kg] and the declared finger's), the effects found (or the ambiguity), the final
E factor against the true one (true E over the declared) and its relative error, whether
the outcome is right, and the wall time [s]. An effect record is right when exactly its
effect is found; a control when nothing is found, the declaration is accepted and E is
within 2 %; the declaration ``declared_E_x1.5`` when it is refused with the record's own
first frequency in the message; ``viscoelastic_root_declared`` when it is not refused.

Totals: the right effect x/N with its Wilson 95 % interval (and counting an ambiguity
between the right effect and another; the misses with the loop's stop reason), the
controls with nothing found, E within 2 % on the records whose effect leaves the stiffness alone (controls
included), and the two declaration cases.

Run: ``.venv/bin/python validation/calibrate_impulse_solid.py [NAME ...]`` (every record by
default, ~1-3 min each on the shared two cores); writes
validation/calibrate_impulse_solid.json (records named on the command line replace their
rows in it, the totals are recomputed).
"""
import json
import sys
import time
from pathlib import Path

from ccedi.calibrate.experiment import load_experiment
from ccedi.calibrate.loop import calibrate, summary
from ccedi.outputs import report_figures
from ccedi.statistics import wilson_interval

DATA = Path(__file__).parents[1] / "data" / "measured_solid"
OUT = Path(__file__).with_suffix(".json")
E_WITHIN = 0.02
"""E counts as recovered within this relative error [-]."""
STIFFNESS_EFFECTS = {"tip_mass", "root_compliance", "viscoelastic"}
"""Effects that change the finger's stiffness or inertia (E_factor absorbs part of them)."""
def row(name, truth, result, wall_s):
    """The per-record outcome (module docstring)."""
    a = result["adequacy"]
    found = [e["name"] for e in result["effects_found"]]
    E_error = result["final_params"]["E_factor"] / truth["E_factor"] - 1.0
    injected = set(truth["effects"])
    if truth["role"] == "effect":
        right = set(found) == injected and result["model_adequate"]
    elif truth["role"] == "control":
        right = not found and result["ambiguous"] is None and result["model_adequate"] and abs(E_error) <= E_WITHIN
    elif truth["declaration_right"]:
        right = result["model_adequate"]
    else:
        own = a["record_first_frequency_hz"]
        right = not result["model_adequate"] and own is not None and f"{own:.4g} Hz" in a["message"]
    return {"role": truth["role"], "injected": sorted(injected), "found": found,
            "ambiguous": result["ambiguous"]["effects"] if result["ambiguous"] else None,
            "unexplained_residual": result["unexplained_residual"],
            "model_adequate": result["model_adequate"], "failed_checks": a["failed_checks"],
            "adequacy_message": a["message"], "record_first_frequency_hz": a["record_first_frequency_hz"],
            "declared_first_frequency_hz": a["declared_first_frequency_hz"],
            "record_effective_tip_mass_kg": a["record_effective_tip_mass_kg"],
            "declared_effective_tip_mass_kg": a["declared_effective_tip_mass_kg"],
            "baseline_E_factor": a["E_factor"], "E_factor": result["final_params"]["E_factor"],
            "true_E_factor": truth["E_factor"], "E_relative_error": E_error,
            "baseline_nrmse": result["baseline"]["nrmse"], "final_nrmse": result["final_nrmse"],
            "noise_floor_nrmse": result["noise_floor_nrmse"], "stop_reason": result["stop_reason"],
            "right": bool(right), "right_or_ambiguous": bool(right or (truth["role"] == "effect" and result["ambiguous"]
                                                                     and injected <= set(result["ambiguous"]["effects"]))),
            "wall_s": wall_s}


def main(names):
    manifest = json.loads((DATA / "manifest.json").read_text())["records"]
    rows = json.loads(OUT.read_text())["records_detail"] if names and OUT.is_file() else {}
    for name in names or list(manifest):
        start = time.perf_counter()
        result = summary(calibrate(load_experiment(DATA / f"{name}.csv")))
        rows[name] = row(name, manifest[name], result, time.perf_counter() - start)
        r = rows[name]
        print(f"{name}: adequate {r['model_adequate']} {r['failed_checks']}, found {r['found']}, ambiguous "
              f"{r['ambiguous']}, E {r['E_factor']:.4f} (true {r['true_E_factor']:.4f}), right {r['right']}, "
              f"{r['wall_s']:.0f} s", flush=True)
    effects = [r for r in rows.values() if r["role"] == "effect"]
    controls = [r for r in rows.values() if r["role"] == "control"]
    stiffness_free = [r for r in effects + controls if not set(r["injected"]) & STIFFNESS_EFFECTS]
    right = sum(r["right"] for r in effects)
    figures = {"records": len(rows), "effect_records": len(effects)}
    if effects:
        low, high = wilson_interval(right, len(effects))
        either = sum(r["right_or_ambiguous"] for r in effects)
        figures |= {"right_effect": right, "right_effect_fraction": right / len(effects),
                    "right_effect_wilson95_low": low, "right_effect_wilson95_high": high,
                    "right_effect_or_ambiguous_with_it": either,
                    "effect_misses": {k: r["stop_reason"] for k, r in rows.items()
                                      if r["role"] == "effect" and not r["right"]}}
    figures |= {"controls": len(controls), "controls_nothing_found": sum(not r["found"] and r["ambiguous"] is None
                                                                         for r in controls),
                "controls_right": sum(r["right"] for r in controls),
                "E_within_2pct": sum(abs(r["E_relative_error"]) <= E_WITHIN for r in stiffness_free),
                "E_records_stiffness_unchanged": len(stiffness_free),
                "E_largest_relative_error_stiffness_unchanged": max((abs(r["E_relative_error"]) for r in stiffness_free),
                                                                    default=None)}
    for name in ("declared_E_x1.5", "viscoelastic_root_declared"):
        if name in rows:
            figures[f"{name}_model_adequate"] = rows[name]["model_adequate"]
            figures[f"{name}_right"] = rows[name]["right"]
    figures["wall_s_largest"] = max(r["wall_s"] for r in rows.values())
    figures["records_detail"] = rows
    report_figures(figures, OUT)


if __name__ == "__main__":
    main(sys.argv[1:])
