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

Relative damping, the model-error margins of ``data/design/rom_check.json`` (measured on
the paper's rubber over alpha and L, carried as they are), each compound's optimum
verified by the ROM at its own E and rho. The ROM grid (15 x 11 x 6 runs, ~5 min on the
2-core AMD VM beside other runs) is cached under ``validation/cache/design_compounds/``;
two FE runs of ~2-3 min.

Run: ``OPENBLAS_NUM_THREADS=1 .venv/bin/python validation/design_compounds.py [--no-fea]``;
writes validation/design_compounds.json.
"""
import argparse
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from ccedi.design.catalogue_design import (
    CATALOGUE_GRID,
    CompoundSurrogate,
    catalogue_surrogate,
    design_compounds,
)
from ccedi.design.compounds import load_compounds
from ccedi.design.model_error import model_errors, read_cases
from ccedi.design.outputs import DENSITY_SCALED
from ccedi.design.recheck import fea_check
from ccedi.design.requirements import Requirements
from ccedi.design.surrogate import run_rom, validation_errors, validation_points
from ccedi.fea.contact.drum import DrumSetup
from ccedi.fea.material import NeoHookean
from ccedi.outputs import report_figures
from ccedi.rom.finger_identification import finger_omega1
from ccedi.study.commands.design import MODEL_ERROR_FILE
from ccedi.units import INCH

OUT = Path(__file__).with_suffix(".json")
CACHE = Path(__file__).parent / "cache" / "design_compounds"
LENGTHS_IN = (3.0, 8.0)
OMEGA_RAD_S = 2.095
"""The paper's drum speed (20 rpm)."""
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


def catalogue(compounds):
    """The catalogue surrogate at the paper's drum, timed."""
    setup = DrumSetup(omega_rad_s=OMEGA_RAD_S)
    t0 = time.perf_counter()
    surrogate, first_mode, runs, cached = catalogue_surrogate(setup, compounds.values(), length_bounds_in=LENGTHS_IN,
                                                              path=CACHE / "grid.csv")
    build = {"grid": list(CATALOGUE_GRID), "grid_runs": len(runs), "grid_from_cache": cached,
             "rom_run_wall_time_s_mean": float(runs["wall_time_s"].mean()),
             "rom_runs_wall_time_s_total": float(runs["wall_time_s"].sum()),
             "build_wall_time_s": time.perf_counter() - t0,
             "space": [{"name": v.name, "lo": float(v.shown(v.lo)), "hi": float(v.shown(v.hi)), "unit": v.unit}
                       for v in surrogate.variables]}
    check = run_rom(setup, validation_points(surrogate.variables, 20), variables=surrogate.variables)
    off_grid = validation_errors(surrogate, check)
    build["off_grid_error"] = {k: off_grid[k] for k in ("sensor_peak_force_N", "max_finger_stress_Pa",
                                                        "recovery_deviation_m", "ringing_amplitude_m",
                                                        "contact_impulse_N_s")}
    return setup, surrogate, first_mode, build


def run_set(requirements, *, setup, surrogate, first_mode, compounds, errors, fea):
    t1 = time.perf_counter()
    cat = design_compounds(surrogate, compounds.values(), setup=setup, first_mode=first_mode,
                           requirements=requirements, model_error=errors)
    out = {"requirements": [lim.describe() for lim in requirements.limits()],
           "rank_wall_time_s": time.perf_counter() - t1, "ranking": cat.as_dict()}
    win = cat.winner
    if fea and win is not None:
        own = replace(setup, finger_material=NeoHookean(E=win.compound.E_nominal_Pa, nu=setup.finger_material.nu,
                                                        rho=win.compound.rho_kg_m3))
        sliced = CompoundSurrogate(surrogate, E_Pa=win.compound.E_nominal_Pa, rho_kg_m3=win.compound.rho_kg_m3,
                                   reference_rho_kg_m3=first_mode.rho_kg_m3)
        row = fea_check(own, [win.design], limits=requirements.limits(), variables=sliced.variables)[0]
        out["winner_fea_check"] = {k: row[k] for k in ("alpha_per_s", "length_in", "requirements",
                                                       "meets_requirements", "relative_error", "wall_time_s")}
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--no-fea", action="store_true", help="skip the FEA re-check of the winners")
    args = parser.parse_args()
    compounds = load_compounds()
    errors = model_errors(read_cases(MODEL_ERROR_FILE), damping="relative", alpha_bounds_per_s=(1.0, 600.0),
                          length_bounds_in=LENGTHS_IN, tolerance=0.0)
    setup, surrogate, first_mode, build = catalogue(compounds)
    figures = {"surrogate": build, "sets": {}}
    for name, spec in SETS.items():
        figures["sets"][name] = run_set(Requirements(**spec), setup=setup, surrogate=surrogate,
                                        first_mode=first_mode, compounds=compounds, errors=errors,
                                        fea=name in FEA_CHECKED and not args.no_fea)
    figures["winners"] = {name: s["ranking"]["winner"] for name, s in figures["sets"].items()}
    figures["similarity"] = similarity(setup)
    figures["first_mode"] = first_mode_check(first_mode, setup)
    report_figures(figures, OUT)


if __name__ == "__main__":
    main()
