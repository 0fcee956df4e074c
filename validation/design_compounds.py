"""The compound as a design variable: the bundled catalogue (``data/compounds.csv``) ranked
under three requirement sets on the paper's drum (20 rpm), a different compound winning
each of the first two, those winners re-checked by the full FEA at their own E, rho and
alpha.

* ``live_birds``: the default requirements (the object force <= 25 N, ringing after
  breakaway <= 5 mm: a finger that whips after release startles live birds, the paper's
  section 3.4), the object force minimised;
* ``parts``: objects that mind no ringing (its limit off), the rest the default;
* ``parts_firm_push``: as ``parts`` with a firmer push, contact impulse >= 5 N s.

What it measures besides: the similarity the catalogue surrogate rests on (the ROM of a
finger of E k and rho k against the finger of E and rho: forces x k, the motion the
same), the first-mode fit against FE eigen solves off its nodes and at another material,
the surrogate's off-grid error against 20 ROM runs, and the cost (ROM runs and wall time)
of each step.

Each set runs ``ccedi design --compounds``'s
:func:`ccedi.study.commands.design.write_catalogue_design` with the default inputs
(relative damping, the model-error margins of ``data/design/rom_check.json``, measured on
the paper's rubber over alpha and L and carried as they are, each compound's optimum
verified by the ROM at its own E and rho); its reports and drawings are kept as
``validation/cache/design_compounds/<set>_design_report.md`` and ``<set>_finger_drawing.png``.
The ROM grid (15 x 11 x 6 runs, ~6 min on the 2-core AMD VM beside other runs) is cached
there; two FE runs of ~1.5-2.5 min.

Run: ``OPENBLAS_NUM_THREADS=1 .venv/bin/python validation/design_compounds.py [--no-fea]``;
writes validation/design_compounds.json.
"""
import argparse
import shutil
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from ccedi.design.catalogue_design import CATALOGUE_GRID, catalogue_surrogate
from ccedi.design.compounds import load_compounds
from ccedi.design.outputs import DENSITY_SCALED
from ccedi.design.requirements import Requirements
from ccedi.design.surrogate import run_rom, validation_errors, validation_points
from ccedi.fea.material import NeoHookean
from ccedi.outputs import report_figures
from ccedi.rom.finger_identification import finger_omega1
from ccedi.study.commands.design import options_from, write_catalogue_design
from ccedi.study.commands.fea import contact_setup
from ccedi.study.config import validate
from ccedi.units import INCH

OUT = Path(__file__).with_suffix(".json")
CACHE = Path(__file__).parent / "cache" / "design_compounds"
LENGTHS_IN = (3.0, 8.0)
SETS = {
    "live_birds": {},
    "parts": {"max_ringing_amplitude_m": None},
    "parts_firm_push": {"max_ringing_amplitude_m": None, "min_contact_impulse_N_s": 5.0},
}
FEA_CHECKED = ("live_birds", "parts")
"""The sets whose winners the full FEA re-checks."""


def similarity(setup, k=1.35):
    """ROM outputs of E k, rho k against E, rho at two designs: the largest relative
    departure from (force outputs x k, the others equal)."""
    m = setup.finger_material
    points = [(15.0, 4.0 * INCH), (150.0, 6.5 * INCH)]
    a = run_rom(setup, points)
    b = run_rom(replace(setup, finger_material=NeoHookean(E=m.E * k, nu=m.nu, rho=m.rho * k)), points)
    worst = 0.0
    for name in a.columns:
        if name in ("alpha_per_s", "length_m", "wall_time_s"):
            continue
        x, y = a[name].to_numpy() * (k if name in DENSITY_SCALED else 1.0), b[name].to_numpy()
        scale = np.maximum(np.abs(x), 1e-12)
        worst = max(worst, float(np.nanmax(np.abs(y - x) / scale)))
    return {"factor": k, "largest_relative_departure": worst, "points": [list(p) for p in points]}


def first_mode_check(first_mode, setup):
    """The fit against FE eigen solves at lengths between its nodes and another material."""
    other = NeoHookean(E=2.0e6, nu=setup.finger_material.nu, rho=1250.0)
    rows = []
    for x in (3.6, 5.3, 7.4):
        fe = finger_omega1(x, material=other, semi_axes_m=tuple(setup.finger_semi_axes_m))
        fit = float(first_mode(x, E_Pa=other.E, rho_kg_m3=other.rho))
        rows.append({"length_in": x, "fe_rad_s": fe, "fit_rad_s": fit, "relative_error": fit / fe - 1.0})
    return {"node_fit_error": first_mode.fit_error, "off_node": rows}


def surrogate_figures(setup, out):
    """The catalogue surrogate's cost and off-grid error (its runs read from the cache the
    design wrote)."""
    compounds = load_compounds()
    surrogate, first_mode, runs, cached = catalogue_surrogate(setup, compounds.values(), length_bounds_in=LENGTHS_IN,
                                                              path=out / "rom_catalogue_grid.csv")
    check = run_rom(setup, validation_points(surrogate.variables, 20), variables=surrogate.variables)
    off_grid = validation_errors(surrogate, check)
    return first_mode, {
        "grid": list(CATALOGUE_GRID), "grid_runs": len(runs), "grid_from_cache": cached,
        "rom_run_wall_time_s_mean": float(runs["wall_time_s"].mean()),
        "rom_runs_wall_time_s_total": float(runs["wall_time_s"].sum()),
        "space": [{"name": v.name, "lo": float(v.shown(v.lo)), "hi": float(v.shown(v.hi)), "unit": v.unit}
                  for v in surrogate.variables],
        "off_grid_error": {k: off_grid[k] for k in ("sensor_peak_force_N", "max_finger_stress_Pa",
                                                    "recovery_deviation_m", "ringing_amplitude_m",
                                                    "contact_impulse_N_s")}}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--no-fea", action="store_true", help="skip the FEA re-check of the winners")
    args = parser.parse_args()
    cfg = validate({})
    setup = contact_setup(cfg)
    figures = {"sets": {}}
    for name, spec in SETS.items():
        options = replace(options_from(cfg), requirements=Requirements(**spec),
                          fea_check=name in FEA_CHECKED and not args.no_fea)
        t0 = time.perf_counter()
        result = write_catalogue_design(setup, options, json_path=CACHE / f"{name}.json", out=CACHE,
                                        scheduler="serial")
        for made in ("design_report.md", "finger_drawing.png"):          # the next set writes its own
            shutil.copy(CACHE / made, CACHE / f"{name}_{made}")
        fea = result["fea_check"]
        figures["sets"][name] = {
            "requirements": result["problem"]["requirements"], "wall_time_s": time.perf_counter() - t0,
            "grid_from_cache": result["surrogate"]["grid_from_cache"],
            "build_wall_time_s": result["surrogate"]["build_wall_time_s"], "ranking": result["compounds"],
            "winner_fea_check": None if fea is None else {
                k: fea[k] for k in ("alpha_per_s", "length_in", "requirements", "meets_requirements", "fea",
                                    "relative_error", "wall_time_s")}}
    figures["winners"] = {name: s["ranking"]["winner"] for name, s in figures["sets"].items()}
    first_mode, figures["surrogate"] = surrogate_figures(setup, CACHE)
    figures["similarity"] = similarity(setup)
    figures["first_mode"] = first_mode_check(first_mode, setup)
    report_figures(figures, OUT)


if __name__ == "__main__":
    main()
