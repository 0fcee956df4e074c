"""The design's contact ROM against the full FEA on every output a requirement uses.

Cases: finger length {3, 5, 8} in x alpha {3, 7.5, about alpha_cr, 180, 600} 1/s x
damping {relative, global} (the full FE histories of ``validation/design_fea_runs.py``,
run first; 30 runs, ~25 min per damping kind on one core of the 2-core AMD VM). Each case
runs the design's ROM (:func:`ccedi.design.surrogate.rom_factory`) for the same time and
output step, computes :func:`ccedi.design.outputs.design_outputs` from both histories, and
the error of every output (:func:`ccedi.design.model_error.output_error`: relative, or
at the 5 mm scale for lengths).

Writes ``data/design/rom_check.json`` (every case's outputs from both models: the design
reads its model-error margins from it, :mod:`ccedi.design.model_error`) and
``validation/design_rom_check.json`` (per output and damping kind: the largest |error|
over all cases and over the default design space alpha 7.5-600 1/s, whether it is within
10 %, else the margin the design carries).

Run: ``.venv/bin/python validation/design_rom_check.py``.
"""
import json
from pathlib import Path

import pandas as pd
from design_fea_runs import LENGTHS_IN, T_END_S, alphas, case_path  # validation/ is on sys.path when run as a script

from ccedi.design.model_error import TOLERANCE, model_errors, output_error
from ccedi.design.outputs import OUTPUTS, design_outputs
from ccedi.design.surrogate import rom_factory
from ccedi.fea.contact.drum import DrumSetup, ObjectStress
from ccedi.outputs import report_figures
from ccedi.units import inch_to_m

OUT = Path(__file__).with_suffix(".json")
CASES = Path(__file__).resolve().parents[1] / "data" / "design" / "rom_check.json"
KEPT = OUTPUTS + ("settling_time_s",)


def _clean(outputs):
    return {k: outputs[k] for k in KEPT}


def main():
    cases = []
    for kind in ("relative", "global"):
        for length_in in LENGTHS_IN:
            setup = DrumSetup(finger_length_m=inch_to_m(length_in))
            stress = ObjectStress(setup)
            rom = rom_factory(setup)
            for alpha in alphas(length_in):
                path = case_path(length_in, alpha, kind)
                if not path.exists():
                    print(f"missing {path.name}: run validation/design_fea_runs.py first")
                    continue
                fea_h = pd.read_csv(path)
                fea_meta = json.loads(path.with_suffix(".json").read_text())
                res = rom.run(alpha, damping=kind, t_end_s=T_END_S, n_outputs=len(fea_h))
                fea, red = design_outputs(setup, fea_h, stress), design_outputs(setup, res.history, stress)
                cases.append({"length_in": length_in, "alpha_per_s": alpha, "damping": kind,
                              "fea": _clean(fea), "rom": _clean(red),
                              "error": {k: output_error(k, red[k], fea[k]) for k in OUTPUTS},
                              "fea_wall_time_s": fea_meta["wall_time_s"],
                              "rom_wall_time_s": res.summary["wall_time_s"],
                              "fea_warnings": fea_meta["summary"]["warnings"]})
                print(f"{kind} L {length_in:g} alpha {alpha:g}: " + ", ".join(
                    f"{k} {e:+.1%}" for k, e in cases[-1]["error"].items() if e is not None), flush=True)
    CASES.parent.mkdir(parents=True, exist_ok=True)
    CASES.write_text(json.dumps({"about": "design ROM against the full FEA, validation/design_rom_check.py; "
                                          "outputs in SI units (ccedi.design.outputs.UNITS)", "cases": cases},
                                indent=1) + "\n")
    figures = {}
    for kind in ("relative", "global"):
        for space, lo in (("all", 0.0), ("design_space", 7.5)):
            inside = [c for c in cases if c["damping"] == kind and c["alpha_per_s"] >= lo]
            margins = model_errors(cases, damping=kind, alpha_bounds_per_s=(max(lo, 1e-9), 600.0),
                                   length_bounds_in=(3.0, 8.0))
            for k in OUTPUTS:
                errs = [abs(c["error"][k]) for c in inside if c["error"][k] is not None]
                worst = max(errs) if errs else None
                m = margins.get(k)
                figures[f"{kind}/{space}/{k}"] = {
                    "max_abs_error": worst, "within_10_percent": worst is not None and worst <= TOLERANCE,
                    "margin": None if m is None else {"largest_under": m.largest()[0], "largest_over": m.largest()[1],
                                                      "relative": m.relative}}
    report_figures(figures, OUT)


if __name__ == "__main__":
    main()
