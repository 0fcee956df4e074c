"""A design script: the finger damping and length that meet a gripper designer's
requirements, with a requirement of their own on an output of their own.

The designer handles soft fruit: the object takes at most 20 N, the finger must be back
in shape (within 3 mm) when the next fruit comes, and, their own requirement, the
finger's tip must never trail the turning drum by more than 20 mm before it reaches the
fruit (a user-defined output computed from the run's history). Relative damping (a
finger turned in air).

Run: ``.venv/bin/python examples/design_script.py [--grid N_ALPHA N_LENGTH] [--fea]``
(``--fea`` re-checks the optimum with the full explicit FEA, a few minutes; without it
the re-check runs the contact ROM itself, in seconds).
"""
import argparse

import numpy as np

from ccedi.design import (
    DesignProblem,
    Limit,
    Requirements,
    Surrogate,
    binding,
    design_space,
    fea_check,
    grid_points,
    pareto_front,
    run_rom,
)
from ccedi.design.recheck import full_fea_factory, verified_optimum
from ccedi.design.surrogate import rom_factory
from ccedi.fea.cases.contact_study import tip_lag_series_m
from ccedi.fea.contact.drum import DrumSetup
from ccedi.models import contact_timing
from ccedi.units import m_to_inch


def lag_before_contact_m(setup, history):
    """The designer's own output: the largest tip lag behind the turning drum before the
    first contact [m]."""
    start = contact_timing(history)["contact_start_s"] or np.inf
    before = history.time_s.to_numpy() < start
    return float(np.abs(tip_lag_series_m(setup, history)[before]).max(initial=0.0))


def main(grid=(8, 6), fea=False):
    setup = DrumSetup()                                    # the paper's drum and object, 20 rpm
    space = design_space(alpha_bounds_per_s=(7.5, 600.0), length_bounds_in=(3.0, 8.0))
    extra = {"lag_before_contact_m": lag_before_contact_m}
    runs = run_rom(setup, grid_points(space, grid), damping="relative", extra_outputs=extra)
    surrogate = Surrogate.fit(space, runs)
    requirements = Requirements(max_object_force_N=20.0, max_recovery_deviation_m=0.003,
                                extra=(Limit("lag_before_contact_m", 0.020, label="tip lag before contact",
                                             unit="mm"),))
    problem = DesignProblem(surrogate, requirements=requirements, objective="object_force")
    optimum, problem, steps = verified_optimum(problem, setup, damping="relative", extra_outputs=extra)
    print(f"optimum: alpha = {optimum.alpha_per_s:.4g} 1/s, L = {m_to_inch(optimum.x):.3f} in, "
          f"object force {optimum.outputs['sensor_peak_force_N']:.3f} N ({len(steps)} ROM verification runs)")
    print("binding:", ", ".join(binding(problem, optimum)) or "none")
    front = pareto_front(problem, second="ringing_amplitude_m", n_points=8)
    print(f"Pareto front, force against ringing: {len(front)} designs")
    factory = full_fea_factory if fea else rom_factory
    check = fea_check(setup, [optimum], damping="relative", limits=problem.limits, model_factory=factory,
                      progress=None, extra_outputs=extra)[0]
    missed = [f"{name} ({q['value']:.4g})" for name, q in check["requirements"].items() if not q["met"]]
    print(f"re-check ({'full FEA' if fea else 'contact ROM'}): "
          + ("meets every requirement" if not missed else "misses " + "; ".join(missed)))
    return optimum, check


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", type=int, nargs=2, default=(8, 6), metavar=("N_ALPHA", "N_LENGTH"))
    parser.add_argument("--fea", action="store_true", help="re-check with the full explicit FEA")
    args = parser.parse_args()
    main(tuple(args.grid), args.fea)
