"""Speed of the design optimiser (target: the whole Pareto front in < 60 s).

Surrogate build: the default 15 x 11 ROM grid over alpha in [7.5, 600] 1/s and L in
[3, 8] in with relative damping, run afresh (no cache), plus the B-spline fit.
Optimisation: the optimum under the default requirements (8 IPOPT starts), its ROM
verification, the sensitivities and the 24-point epsilon-constraint Pareto front.

Run: ``.venv/bin/python benchmarks/design_speed.py``; writes benchmarks/design_speed.json.
"""
import time
from pathlib import Path

from ccedi.design.optimise import DesignProblem, sensitivities
from ccedi.design.pareto import pareto_front
from ccedi.design.recheck import verified_optimum
from ccedi.design.surrogate import Surrogate, design_space, grid_points, run_rom
from ccedi.fea.contact.drum import DrumSetup
from ccedi.outputs import report_figures

OUT = Path(__file__).with_suffix(".json")


def main():
    space = design_space()
    t0 = time.perf_counter()
    grid = run_rom(DrumSetup(), grid_points(space, (15, 11)), damping="relative")
    t1 = time.perf_counter()
    surrogate = Surrogate.fit(space, grid)
    t2 = time.perf_counter()
    optimum, problem, _ = verified_optimum(DesignProblem(surrogate), DrumSetup(), damping="relative")
    sensitivities(problem, optimum)
    front = pareto_front(problem, n_points=24)
    t3 = time.perf_counter()
    report_figures({"rom_grid_runs": len(grid), "rom_grid_wall_time_s": round(t1 - t0, 2),
            "surrogate_fit_wall_time_s": round(t2 - t1, 3),
            "optimum_and_pareto_wall_time_s": round(t3 - t2, 3), "pareto_points": len(front),
            "whole_front_incl_grid_s": round(t3 - t0, 2), "target_s": 60.0}, OUT)


if __name__ == "__main__":
    main()
