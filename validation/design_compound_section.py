"""The section's semi-thickness b as a compound design variable: the catalogue surrogate over
(alpha, L, E', b) on the bundled catalogue (``data/compounds.csv``), the paper's drum,
relative damping, b 4-12 mm (the default, up to the semi-width a), L 3-8 in.

What it measures:

* the first mode omega_1(L, b) fitted through FE eigen solves (5 lengths x 4 semi-thicknesses)
  against fresh eigen solves off its points, at the reference material and at another;
* the surrogate's cost (ROM runs, model builds, wall time) on the default grid
  :data:`ccedi.design.catalogue_design.CATALOGUE_SECTION_GRID` and its off-grid error
  against 20 ROM runs (:func:`ccedi.design.surrogate.validation_errors`);
* the ranking of the catalogue with b designed, under the ``parts`` requirements (the
  defaults without the ringing limit; no model-error margin: it was measured on the
  paper's section), each optimum verified by the ROM at its own E, rho and b, every
  feasible compound's fastest drum; and the same with a firmer push, contact impulse
  >= 3 N s, which a stiffer finger gives: the chosen b of the compounds the impulse binds
  should thicken (``b_change_mm``: b under the firm push minus b under ``parts``). (The
  object force is minimised, so a tighter force limit does not bind where the force is
  already least: the thinnest section the other requirements allow.) Each set's winner
  is re-checked by the full FEA at its own E, rho, alpha, L and b (``winner_fea_check``:
  the surrogate's error on every output, the requirements on the FEA's outputs).

Run: ``OPENBLAS_NUM_THREADS=1 .venv/bin/python validation/design_compound_section.py``; writes
validation/design_compound_section.json (the ROM grid cached in
validation/cache/design_compound_section/).
"""
import time
from pathlib import Path

import numpy as np

from ccedi.design.catalogue_design import (
    CATALOGUE_SECTION_GRID,
    COMPOUND_THICKNESS_MM,
    catalogue_surrogate,
    compound_setup,
    design_compounds,
)
from ccedi.design.compounds import load_compounds
from ccedi.design.drum_speed import with_drum_speeds
from ccedi.design.recheck import fea_check
from ccedi.design.requirements import Requirements
from ccedi.design.surrogate import run_rom, validation_errors, validation_points
from ccedi.fea.material import NeoHookean
from ccedi.outputs import report_figures
from ccedi.rom.finger_identification import finger_omega1
from ccedi.study.commands.fea import contact_setup
from ccedi.study.config import validate

OUT = Path(__file__).with_suffix(".json")
CACHE = Path(__file__).parent / "cache" / "design_compound_section"
LENGTHS_IN = (3.0, 8.0)
THICKNESS_MM = COMPOUND_THICKNESS_MM
SETS = {"parts": {"max_ringing_amplitude_m": None},
        "parts_firm_push": {"max_ringing_amplitude_m": None, "min_contact_impulse_N_s": 3.0}}


def first_mode_check(first_mode, setup):
    """The fit against fresh FE eigen solves off its points, at the set-up's rubber and at
    E 2 MPa, rho 1250 kg/m^3."""
    a = setup.finger_semi_axes_m[0]
    rows = []
    for material in (setup.finger_material, NeoHookean(E=2.0e6, nu=setup.finger_material.nu, rho=1250.0)):
        for x, b_mm in ((3.6, 4.9), (5.3, 8.45), (7.4, 11.2), (4.4, 10.6), (6.6, 5.6)):
            fe = finger_omega1(x, material=material, semi_axes_m=(a, 1e-3 * b_mm))
            fit = float(first_mode(x, E_Pa=material.E, rho_kg_m3=material.rho, semi_thickness_m=1e-3 * b_mm))
            rows.append({"length_in": x, "semi_thickness_mm": b_mm, "E_Pa": material.E, "rho_kg_m3": material.rho,
                         "fe_rad_s": fe, "fit_rad_s": fit, "relative_error": fit / fe - 1.0})
    return {"node_fit_error": first_mode.fit_error, "off_node": rows,
            "largest_off_node_error": max(abs(r["relative_error"]) for r in rows)}


def ranking_figures(ranking):
    """Per compound: feasible, alpha, L, b, objective, binding, fastest drum."""
    return [{k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in row.items()
             if not k.startswith("margin: ")} for row in ranking.table.to_dict(orient="records")]


def winner_fea_check(ranking, setup, requirements):
    """The winner re-checked by the full FEA at its compound's E, rho and alpha, its L and
    b, as ``ccedi design --compounds`` does (None without a winner)."""
    w = ranking.winner
    if w is None:
        return None
    row = fea_check(compound_setup(setup, w.compound, w.semi_thickness_m), [w.design], limits=requirements.limits(),
                    variables=w.problem.surrogate.variables)[0]
    return {k: row[k] for k in ("surrogate", "fea", "relative_error", "requirements", "meets_requirements", "failed",
                                "wall_time_s")}


def main():
    setup = contact_setup(validate({}))
    compounds = load_compounds()
    CACHE.mkdir(parents=True, exist_ok=True)
    figures = {"grid": list(CATALOGUE_SECTION_GRID), "length_bounds_in": list(LENGTHS_IN),
               "semi_thickness_bounds_mm": list(THICKNESS_MM)}
    t0 = time.perf_counter()
    surrogate, first_mode, runs, cached = catalogue_surrogate(
        setup, compounds.values(), length_bounds_in=LENGTHS_IN, semi_thickness_bounds_mm=THICKNESS_MM,
        path=CACHE / "rom_catalogue_section_grid.csv",
        progress=lambda k, n: print(f"ROM runs {k}/{n}", flush=True) if k % 50 == 0 or k == n else None)
    figures["surrogate"] = {
        "grid_runs": len(runs), "grid_from_cache": cached, "build_wall_time_s": time.perf_counter() - t0,
        "model_builds": int(np.prod(CATALOGUE_SECTION_GRID[1:])),
        "rom_run_wall_time_s_mean": float(runs["wall_time_s"].mean()),
        "rom_runs_wall_time_s_total": float(runs["wall_time_s"].sum()),
        "space": [{"name": v.name, "lo": float(v.shown(v.lo)), "hi": float(v.shown(v.hi)), "unit": v.unit}
                  for v in surrogate.variables]}
    print(figures["surrogate"], flush=True)
    figures["first_mode"] = first_mode_check(first_mode, setup)
    print(figures["first_mode"]["largest_off_node_error"], flush=True)
    t0 = time.perf_counter()
    check = run_rom(setup, validation_points(surrogate.variables, 20), variables=surrogate.variables)
    off_grid = validation_errors(surrogate, check)
    figures["off_grid"] = {"runs": len(check), "wall_time_s": time.perf_counter() - t0,
                           "error": {k: off_grid[k] for k in ("sensor_peak_force_N", "max_finger_stress_Pa",
                                                              "recovery_deviation_m", "ringing_amplitude_m",
                                                              "contact_impulse_N_s", "contact_patch_from_root_m")}}
    print(figures["off_grid"], flush=True)
    figures["sets"] = {}
    for name, spec in SETS.items():
        t0 = time.perf_counter()
        ranking = design_compounds(surrogate, compounds.values(), setup=setup, first_mode=first_mode,
                                   requirements=Requirements(**spec))
        ranked_s = time.perf_counter() - t0
        ranking = with_drum_speeds(ranking, setup)
        figures["sets"][name] = {"requirements": [lim.describe() for lim in Requirements(**spec).limits()],
                                 "ranking_wall_time_s": ranked_s, "with_drum_wall_time_s": time.perf_counter() - t0,
                                 "winner": None if ranking.winner is None else ranking.winner.compound.name,
                                 "table": ranking_figures(ranking),
                                 "winner_fea_check": winner_fea_check(ranking, setup, Requirements(**spec))}
        print(name, figures["sets"][name]["winner"], ranked_s, flush=True)
    b = {name: {r["compound"]: r["semi_thickness_mm"] for r in st["table"] if r["feasible"]}
         for name, st in figures["sets"].items()}
    figures["b_change_mm"] = {c: b["parts_firm_push"][c] - b["parts"][c] for c in b["parts_firm_push"] if c in b["parts"]}
    report_figures(figures, OUT)


if __name__ == "__main__":
    main()
