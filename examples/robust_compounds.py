"""A compound choice that survives batch spread: which rubber, how long, how fast a drum.

A designer picks between three catalogued compounds for a finger on the paper's drum
(relative damping). Every compound is designed over the length on its own E, density and
alpha = tan delta x omega_1(L) and ranked by the object force; then each compound's
design is made robust to its batch spread (E +-15 %, tan delta +-30 %: every requirement
met in 95 % of the samples) and the compounds ranked again; last, the chosen finger's
fastest drum.

Run: ``.venv/bin/python examples/robust_compounds.py [--grid N_ALPHA N_LENGTH N_E]``
(the default coarse grid of 4 x 4 x 4 ROM runs takes about a minute; the CLI's
``ccedi design --compounds --robust`` uses 15 x 11 x 6).
"""
import argparse

from ccedi.design import (
    Requirements,
    Spread,
    catalogue_surrogate,
    design_compounds,
    fastest_drum_speed,
    load_compounds,
    robust_catalogue,
)
from ccedi.fea.contact.drum import DrumSetup
from ccedi.units import m_to_inch

COMPOUNDS = ("paper_finger_rubber", "nitrile", "natural_rubber")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--grid", type=int, nargs=3, default=(4, 4, 4), help="ROM runs along alpha, L and E")
    args = parser.parse_args()
    setup = DrumSetup()
    catalogue = load_compounds()
    compounds = [catalogue[name] for name in COMPOUNDS]
    spread = Spread(E_relative=0.15, tan_delta_relative=0.30)
    surrogate, first_mode, _, _ = catalogue_surrogate(setup, compounds, shape=tuple(args.grid), spread=spread)
    requirements = Requirements(max_ringing_amplitude_m=None)         # parts, not live birds: no ringing limit
    nominal = design_compounds(surrogate, compounds, setup=setup, first_mode=first_mode,
                               requirements=requirements, verify=False)
    for rank, d in enumerate(nominal.designs, start=1):
        print(f"nominal {rank}. {d.compound.name}: L = {m_to_inch(d.design.x):.3f} in, "
              f"force {d.objective_value:.2f} N" + ("" if d.feasible else " (misses the requirements)"))
    robust = robust_catalogue(nominal, surrogate, spread=spread, probability=0.95)
    for rank, r in enumerate(robust.designs, start=1):
        print(f"robust {rank}. {r.compound}: L = {m_to_inch(r.length_m):.3f} in, force {r.objective:.2f} N, "
              f"largest violation {r.check.worst:.1%} (nominal design's: {r.nominal.worst:.1%})"
              + ("" if r.feasible else " (no robust length)"))
    if robust.winner is None:
        print("no compound is robust at 95 %")
        return
    chosen = next(d for d in nominal.designs if d.compound.name == robust.winner.compound)
    drum = fastest_drum_speed(chosen, setup, length_m=robust.winner.length_m)
    print(f"chosen: {drum.compound}, L = {m_to_inch(drum.length_m):.3f} in, alpha = {drum.alpha_per_s:.1f} 1/s; "
          + (f"drum up to {drum.fastest_rpm:.1f} rpm" if drum.fastest_rpm is not None else "no drum speed")
          + (f" ({drum.binding} binds)" if drum.binding else " (every speed run meets the requirements)"))


if __name__ == "__main__":
    main()
