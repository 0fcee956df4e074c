"""The design surrogate against the full FEA below alpha = 7.5 1/s, and what the face
contact model would change there.

The design's surrogate (:mod:`ccedi.design.surrogate`: the stations contact ROM on the
default 15 x 11 grid over alpha 1-600 1/s and L 3-8 in) is evaluated at designs with
alpha below the paper's lowest studied 7.5 1/s, and re-checked as ``ccedi design`` does
(:func:`ccedi.design.fea_check.fea_check`) with the full FEA, and with the ROM itself with
each contact model (stations, the surrogate's own; face) at the same points. Reported per
design and model: the design outputs and their relative errors (model - FEA) / FEA.

Run: ``.venv/bin/python benchmarks/design_low_alpha.py [CACHE_DIR]`` (165 ROM runs for the
grid, cached in CACHE_DIR, default reports/design; one full FE run, ~3 min of
CPU); writes benchmarks/design_low_alpha.json.
"""
import sys
from pathlib import Path

from _output import report  # benchmarks/ is on sys.path when run as a script

from ccedi.design.fea_check import fea_check
from ccedi.design.objectives import rom_segments
from ccedi.design.optimise import Design
from ccedi.design.surrogate import Surrogate, cached_rom_runs, design_space, grid_points
from ccedi.fea.drum import DrumSetup
from ccedi.fea.units import inch_to_m
from ccedi.rom.contact_rom import ReducedContactModel

OUT = Path(__file__).with_suffix(".json")
DESIGNS = ((3.0, 8.0),)
"""(alpha [1/s], L [in]) checked."""
GRID = (15, 11)
"""The design command's default surrogate grid (alpha, length)."""
OUTPUTS = ("peak_reaction_force_N", "contact_duration_s", "residual_oscillation_m_s")


def rom_factory(contact):
    """A design-ROM factory with the given contact model."""
    def factory(setup):
        return ReducedContactModel(setup, n_segments=rom_segments(setup.finger_length_m), contact=contact)
    return factory


def main(cache_dir):
    setup = DrumSetup()
    space = design_space()
    grid, _ = cached_rom_runs(setup, grid_points(space, GRID), Path(cache_dir) / "rom_grid.csv")
    surrogate = Surrogate.fit(space, grid)
    designs = []
    for alpha, length_in in DESIGNS:
        out = surrogate.evaluate([[alpha, inch_to_m(length_in)]])
        designs.append(Design(alpha, inch_to_m(length_in), {k: float(v[0]) for k, v in out.items()}, 0.0))
    figures = {}
    checks = {"fea": fea_check(setup, designs, OUTPUTS)}
    for contact in ("stations", "face"):
        checks[f"rom_{contact}"] = fea_check(setup, designs, OUTPUTS, model_factory=rom_factory(contact))
    for i, (alpha, length_in) in enumerate(DESIGNS):
        key = f"alpha {alpha:g}, L {length_in:g} in"
        fea = checks["fea"][i]
        figures[f"{key}: fea"] = fea["fea"]
        figures[f"{key}: surrogate vs fea"] = fea["relative_error"]
        for contact in ("stations", "face"):
            rom = checks[f"rom_{contact}"][i]["fea"]
            figures[f"{key}: rom {contact}"] = rom
            figures[f"{key}: rom {contact} vs fea"] = {k: None if fea["fea"][k] in (None, 0.0) or rom[k] is None
                                                       else (rom[k] - fea["fea"][k]) / abs(fea["fea"][k])
                                                       for k in rom}
    report(figures, OUT)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).parents[1] / "reports" / "design")
