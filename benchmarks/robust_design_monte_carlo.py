"""Robust against nominal design, checked by a full-FEA Monte Carlo: the bundled catalogue
designed under a requirement set (:data:`SETS`, default ``parts``), ranked by nominal
designs and by robust designs (:func:`ccedi.design.robust.robust_catalogue`, E +-15 %,
tan delta +-30 %, 95 %); then ``N_FEA`` samples of each checked compound's E and loss
factor run through the full explicit FEA at the robust winner's length and at the nominal
optimum of every compound the nominal ranking puts above it (compounds of the same E/rho
and loss factor run once; the winner's own nominal optimum when it is not robust): each requirement's violation fraction with its Wilson 95 %
interval, beside the surrogate's violation probability at the same length.

The catalogue surrogate is built wide enough for the spread (15 x 11 x 6 ROM runs, cached
under benchmarks/cache/robust_design/); each FE run is one drum run of the finger at the
sample's E and alpha (~0.5-1 minute here), ``--jobs`` at a time.

Run: ``OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/robust_design_monte_carlo.py [--n N] [--jobs J] [--set SET]``;
writes benchmarks/robust_design_monte_carlo.json (``--set live_birds``: ..._live_birds.json).
"""
import argparse
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, replace
from pathlib import Path

from ccedi.design.catalogue_design import catalogue_surrogate, compound_setup, design_compounds
from ccedi.design.compounds import alpha_from_loss_factor, load_compounds
from ccedi.design.optimise import Design
from ccedi.design.recheck import fea_check
from ccedi.design.requirements import Requirements
from ccedi.design.robust import Spread, robust_catalogue, violation_probabilities
from ccedi.outputs import report_figures
from ccedi.statistics import wilson_interval
from ccedi.study.commands.fea import contact_setup
from ccedi.study.config import validate
from ccedi.units import m_to_inch

OUT = Path(__file__).with_suffix(".json")
CACHE = Path(__file__).parent / "cache" / "robust_design"
SETS = {"parts": {"max_ringing_amplitude_m": None}, "live_birds": {}}
"""Requirement sets (as validation/design_compounds.py): ``parts`` the default requirements
without the ringing limit, ``live_birds`` the defaults."""
N_FEA = 20
SEED = 2032


def one_run(setup, E_Pa, alpha_per_s, length_m, limits):
    """The full FEA's requirement check of one sample (fea_check of one design)."""
    own = replace(setup, finger_material=replace(setup.finger_material, E=float(E_Pa)))
    d = Design(alpha_per_s=float(alpha_per_s), x=float(length_m), outputs={}, J=float("nan"))
    row = fea_check(own, [d], limits=limits, progress=None)[0]
    return {k: {"value": q["value"], "met": q["met"]} for k, q in row["requirements"].items()}, row["wall_time_s"]


def checked_designs(robust):
    """[(label, RobustDesign, length [m])]: the robust winner at its robust length, then the
    nominal optimum of every compound ranked above it by the nominal ranking (and the winner's
    own nominal optimum when it is not robust itself), one per (E/rho, tan delta, length)."""
    win = robust.winner or robust.designs[0]
    by_name = {d.compound: d for d in robust.designs}
    compounds = [n.compound for n in robust.nominal.designs]          # in the nominal ranking's order
    ahead = compounds[:[c.name for c in compounds].index(win.compound) + 1]
    chosen, seen = [("robust: " + win.compound, win, win.length_m)], set()
    for c in ahead:
        name, d = c.name, by_name[c.name]
        key = (round(c.E_nominal_Pa / c.rho_kg_m3, 3), round(c.tan_delta_nominal, 6), round(d.nominal.length_m, 6))
        if key in seen or (name == win.compound and d.nominal.worst <= d.allowed):
            continue
        seen.add(key)
        chosen.append(("nominal: " + name, d, d.nominal.length_m))
    return chosen


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=N_FEA, help="FE samples per design")
    parser.add_argument("--jobs", type=int, default=2, help="FE runs at a time")
    parser.add_argument("--set", choices=sorted(SETS), default="parts", help="requirement set")
    args = parser.parse_args()
    out = OUT if args.set == "parts" else OUT.with_name(f"{OUT.stem}_{args.set}.json")
    t0 = time.perf_counter()
    cfg = validate({})
    setup = contact_setup(cfg)
    requirements = Requirements(**SETS[args.set])
    compounds = list(load_compounds().values())
    spread = Spread()
    CACHE.mkdir(parents=True, exist_ok=True)
    surrogate, first_mode, runs, cached = catalogue_surrogate(setup, compounds, spread=spread,
                                                              path=CACHE / "rom_catalogue_grid.csv",
                                                              progress=lambda done, total: None)
    built_s = time.perf_counter() - t0
    ranking = design_compounds(surrogate, compounds, setup=setup, first_mode=first_mode, requirements=requirements,
                               verify=False)
    robust = robust_catalogue(ranking, surrogate, spread=spread)
    nominal_of = {d.compound.name: d for d in ranking.designs}
    limits = ranking.designs[0].problem.limits
    figures = {"requirement_set": args.set, "requirements": SETS[args.set], "spread": asdict(spread),
               "probability": robust.probability, "surrogate_runs": len(runs), "surrogate_from_cache": cached,
               "surrogate_build_s": built_s, "fea_samples": args.n,
               "nominal_ranking": [(d.compound.name, d.feasible, m_to_inch(d.design.x), d.objective_value)
                                   for d in ranking.designs],
               "robust_ranking": [(d.compound, d.feasible, m_to_inch(d.length_m), d.objective, d.check.worst)
                                  for d in robust.designs], "designs": {}}
    for label, r, length_m in checked_designs(robust):
        nominal = nominal_of[r.compound]
        c = nominal.compound
        E, tan_delta = spread.samples(c, args.n, seed=SEED)
        own = compound_setup(setup, c)
        omega = first_mode(m_to_inch(length_m), E_Pa=E, rho_kg_m3=c.rho_kg_m3)
        alphas = alpha_from_loss_factor(tan_delta, omega)
        with ProcessPoolExecutor(max_workers=args.jobs) as pool:
            results = list(pool.map(one_run, [own] * args.n, E, alphas, [length_m] * args.n, [limits] * args.n))
        per_req = {}
        for name in results[0][0]:
            bad = sum(not q[0][name]["met"] for q in results)
            per_req[name] = {"fea_violations": bad, "fea_fraction": bad / args.n,
                             "fea_wilson95": list(wilson_interval(bad, args.n))}
        surrogate_p = violation_probabilities(nominal, surrogate, length_m=length_m,
                                              samples=spread.samples(c, 2000, seed=SEED + 1))
        for name, p in surrogate_p.items():
            per_req.setdefault(name, {})["surrogate_probability"] = p
        figures["designs"][label] = {"compound": c.name, "length_in": m_to_inch(length_m),
                                     "alpha_nominal_per_s": float(nominal.tie(m_to_inch(length_m))),
                                     "objective_nominal": r.objective if label.startswith("robust") else
                                     r.nominal_objective, "requirements": per_req,
                                     "fea_wall_s": [q[1] for q in results]}
        print(label, f"L {m_to_inch(length_m):.3f} in:", {k: (v.get("fea_violations"), v.get("surrogate_probability"))
                                                        for k, v in per_req.items()}, flush=True)
    figures["robust_feasible_on_surrogate"] = robust.winner is not None
    figures["wall_time_s"] = time.perf_counter() - t0
    report_figures(figures, out)


if __name__ == "__main__":
    main()
