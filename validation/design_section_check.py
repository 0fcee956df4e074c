"""The section as a design variable: a surrogate over (alpha, the section's semi-thickness
b) of the 5-in finger (the semi-width a at the paper's 12 mm) checked against the full FEA
at two sections far from the paper's b = 8.45 mm: b = 4.5 mm (a finger half as thick,
one sixth as stiff in bending) and b = 13 mm (half as thick again, 3.6 times as stiff),
at alpha = 60 1/s. The contact ROM's own error there is measured beside the surrogate's
(the ROM run at the same points), so that the interpolation and the reduction are told
apart; and the design over (alpha, b) at the default requirements is solved.

Relative damping; ROM grid 10 x 7 (cached under ``validation/cache/design_section/``, ~1 min),
10 off-grid ROM runs; two FE runs of ~2-6 min on the 2-core AMD VM.

Run: ``OPENBLAS_NUM_THREADS=1 .venv/bin/python validation/design_section_check.py``;
writes validation/design_section_check.json.
"""
import time
from pathlib import Path

from ccedi.design.model_error import output_error
from ccedi.design.optimise import Design, DesignProblem, binding, solve
from ccedi.design.recheck import fea_check, model_run
from ccedi.design.requirements import Requirements
from ccedi.design.surrogate import (
    Surrogate,
    cached_rom_runs,
    grid_points,
    rom_factory,
    run_rom,
    section_space,
    validation_errors,
    validation_points,
)
from ccedi.fea.contact.drum import DrumSetup
from ccedi.outputs import report_figures
from ccedi.units import INCH

OUT = Path(__file__).with_suffix(".json")
CACHE = Path(__file__).parent / "cache" / "design_section"
ALPHA_PER_S = 60.0
CHECKED_B_MM = (4.5, 13.0)
SHOWN = ("sensor_peak_force_N", "max_finger_stress_Pa", "contact_impulse_N_s", "contact_patch_from_root_m",
         "recovery_deviation_m", "ringing_amplitude_m", "contact_duration_s")


def main():
    setup = DrumSetup(finger_length_m=5.0 * INCH)
    space = section_space((7.5, 600.0), "semi_thickness_m", (4.0, 14.0))
    t0 = time.perf_counter()
    grid, cached = cached_rom_runs(setup, grid_points(space, (10, 7)), CACHE / "grid.csv", variables=space)
    surrogate = Surrogate.fit(space, grid)
    build_s = time.perf_counter() - t0
    off_grid = validation_errors(surrogate, run_rom(setup, validation_points(space, 10), variables=space,
                                                    damping="relative"))
    requirements = Requirements()
    problem = DesignProblem(surrogate, requirements=requirements)
    optimum, info = solve(problem)
    designs = []
    for b_mm in CHECKED_B_MM:
        x = (ALPHA_PER_S, b_mm * 1e-3)
        outputs = {k: float(v[0]) for k, v in surrogate.evaluate([x]).items()}
        designs.append(Design(*x, outputs, float(problem.J(outputs))))
    fea = fea_check(setup, designs, limits=requirements.limits(), variables=space)
    checks = []
    for d, row in zip(designs, fea):
        rom = model_run(d, setup, damping="relative", model_factory=rom_factory, variables=space)["outputs"]
        checks.append({"semi_thickness_mm": d.x * 1e3, "alpha_per_s": d.alpha_per_s,
                       "fea": {k: row["fea"][k] for k in SHOWN},
                       "surrogate_error": {k: row["relative_error"][k] for k in SHOWN},
                       "rom_error": {k: output_error(k, rom[k], row["fea"][k]) for k in SHOWN},
                       "fea_wall_time_s": row["wall_time_s"]})
    report_figures({"length_in": 5.0, "semi_width_mm": setup.finger_semi_axes_m[0] * 1e3,
                    "grid": [10, 7], "grid_from_cache": cached, "build_wall_time_s": build_s,
                    "off_grid_error": {k: off_grid[k] for k in SHOWN},
                    "design": {**optimum.as_dict(problem), "binding": binding(problem, optimum),
                               "status": info["status"]},
                    "fea_checks": checks}, OUT)


if __name__ == "__main__":
    main()
