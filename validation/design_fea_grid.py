"""Brute force with the full FEA around a design optimum: is there a better feasible
design nearby that the surrogate missed?

Reads a ``ccedi design`` result (default ``reports/design/design.json``: its optimum,
damping kind, requirements and drum), runs the full explicit FEA on a 5 x 4 grid around
the optimum (alpha x {0.6, 0.8, 1, 1.25, 1.6}, L + {-0.6, -0.2, +0.2, +0.6} in, inside the
design space) and the optimum itself, computes the design outputs
(:func:`ccedi.design.outputs.design_outputs`) and checks every requirement as stated on
each. Reported: the FEA objective at the optimum, the feasible grid points, and the best
of them relative to the optimum (acceptance: none better by more than 3 %).

Run: ``.venv/bin/python validation/design_fea_grid.py [DESIGN_JSON]`` (21 FE runs on a
2-worker Dask cluster, ~20 min on the 2-core AMD VM); writes
validation/design_fea_grid.json.
"""
import json
import sys
from pathlib import Path

from ccedi.design.optimise import OBJECTIVES, Design
from ccedi.design.recheck import fea_check
from ccedi.design.requirements import Requirements
from ccedi.fea.contact.drum import DrumSetup
from ccedi.outputs import report_figures
from ccedi.units import inch_to_m

OUT = Path(__file__).with_suffix(".json")
ALPHA_FACTORS = (0.6, 0.8, 1.0, 1.25, 1.6)
LENGTH_STEPS_IN = (-0.6, -0.2, 0.2, 0.6)


def requirements_of(result):
    """The stated requirements of a design result (its ``requirements_stated``)."""
    return Requirements(**result["requirements_stated"])


def main(path):
    result = json.loads(Path(path).read_text())
    p, drum, o = result["problem"], result["drum"], result["optimum"]
    setup = DrumSetup(omega_rad_s=drum["omega_rad_s"], theta0_rad=drum["theta0_rad"], friction=drum["friction"],
                      object_center_m=tuple(drum["object_center_m"]),
                      object_semi_axes_m=tuple(drum["object_semi_axes_m"]), cycle_time_s=drum["cycle_s"])
    lo_a, hi_a = p["alpha_bounds_per_s"]
    lo_l, hi_l = p["length_bounds_in"]
    points = [(o["alpha_per_s"], o["length_in"])]
    points += [(o["alpha_per_s"] * f, o["length_in"] + d) for f in ALPHA_FACTORS for d in LENGTH_STEPS_IN
               if lo_a <= o["alpha_per_s"] * f <= hi_a and lo_l <= o["length_in"] + d <= hi_l]
    designs = [Design(a, inch_to_m(L), {}, 0.0) for a, L in points]
    limits = requirements_of(result).limits()
    rows = fea_check(setup, designs, damping=p["damping"], limits=limits, scheduler="local", progress=print)
    key = OBJECTIVES[p["objective"]]
    at_optimum = rows[0]["fea"][key]
    feasible = [r for r in rows[1:] if r["meets_requirements"]]
    best = min(feasible, key=lambda r: r["fea"][key], default=None)
    report_figures({"design": str(path), "objective": key, "damping": p["damping"],
            "optimum": {"alpha_per_s": o["alpha_per_s"], "length_in": o["length_in"],
                        "fea_objective": at_optimum, "fea_meets_requirements": rows[0]["meets_requirements"]},
            "grid_points": len(rows) - 1, "feasible_grid_points": len(feasible),
            "best_feasible": None if best is None else {"alpha_per_s": best["alpha_per_s"],
                                                        "length_in": best["length_in"], "fea_objective": best["fea"][key],
                                                        "better_by": (at_optimum - best["fea"][key]) / at_optimum},
            "grid": [{"alpha_per_s": r["alpha_per_s"], "length_in": r["length_in"], "fea_objective": r["fea"][key],
                      "meets_requirements": r["meets_requirements"],
                      "missed": [k for k, q in r["requirements"].items() if not q["met"]],
                      "wall_time_s": r["wall_time_s"]} for r in rows]}, OUT)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "reports/design/design.json")
