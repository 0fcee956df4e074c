"""The fastest drum a compound's finger allows: the ROM of the finger at its own material,
length and alpha run over drum speeds; the speed where a recovery requirement starts to
fail, checked by ROM runs either side of it, for the winner, for every feasible compound of
a ranking (which may rank by it) and on a designed section; bad bounds refused in one line."""
import math

import numpy as np
import pandas as pd
import pytest

from ccedi.design.catalogue_design import FirstMode, catalogue_space, design_compounds
from ccedi.design.compounds import Compound
from ccedi.design.drum_speed import fastest_drum_speed, with_drum_speeds
from ccedi.design.outputs import setup_for_length, setup_for_section
from ccedi.design.requirements import Limit, Requirements
from ccedi.design.surrogate import Surrogate, grid_points, run_rom, speed_space
from ccedi.errors import InputError
from ccedi.fea.contact.drum import DrumSetup
from ccedi.units import RPM

FIRST_MODE = FirstMode((0.0, -2.0, math.log(89.41 * 4.5**2)), 6.1e6, 1000.0, (3.0, 8.0), 0.0)
"""omega_1 = 1810 / L^2 rad/s (L in inches) at the paper's rubber."""
RECOVERY = Requirements.from_limits([Limit("recovery_deviation_m", 0.001, label="recovery", unit="mm")])


def _compound(name, tan_delta):
    return Compound(name=name, E_min_Pa=6.1e6, E_max_Pa=6.1e6, rho_kg_m3=1000.0, tan_delta_min=tan_delta,
                    tan_delta_max=tan_delta, band_min_hz=1.0, band_max_hz=100.0, source="test compound")


def _flat_ranking(compounds, requirements=RECOVERY):
    """The compounds designed on a flat surrogate (a force rising with the length, the
    shortest chosen, and falling with ln alpha: above 100 N below alpha 1.6 1/s): only the compound, its tie and the requirement matter to the drum speed."""
    space = catalogue_space(compounds, FIRST_MODE, (4.0, 5.0))
    X = np.array(grid_points(space, (5, 5, 4)))
    frame = pd.DataFrame({"alpha_per_s": X[:, 0], "length_m": X[:, 1], "youngs_modulus_Pa": X[:, 2],
                          "sensor_peak_force_N": 120.0 + 100.0 * X[:, 1] - 20.0 * np.log(X[:, 0]),
                          "recovery_deviation_m": np.zeros(len(X))})
    return design_compounds(Surrogate.fit(space, frame), compounds, setup=DrumSetup(), first_mode=FIRST_MODE,
                            requirements=requirements, verify=False)


@pytest.fixture(scope="module")
def paper_rubber_design():
    """The paper's over-damped rubber (tan delta 2)."""
    return _flat_ranking([_compound("paper_like", 2.0)]).designs[0]


def _bracketed(check, semi_thickness_m=None):
    """Recovery of ROM runs 5 % slower and 5 % faster than ``check``'s fastest drum (at the
    semi-thickness given, else the set-up's): (slower, faster)."""
    own = setup_for_length(DrumSetup(), check.length_m)
    own = own if semi_thickness_m is None else setup_for_section(own, semi_thickness_m=semi_thickness_m)
    runs = run_rom(own, [(check.alpha_per_s, f * check.fastest_rpm * RPM) for f in (0.95, 1.05)],
                   variables=speed_space((1.0, 1e3), (1.0, 200.0)))
    return tuple(runs["recovery_deviation_m"])


def test_the_fastest_drum_is_where_the_finger_no_longer_recovers_in_time(paper_rubber_design):
    """At 10 rpm the 4-in finger is back in shape long before the next object; a faster drum
    leaves it less time (cycle 2 pi / (2 omega)). The speed found sits where the ROM's
    recovery deviation crosses 1 mm: a run 5 % slower recovers within it, 5 % faster not."""
    setup = DrumSetup()
    check = fastest_drum_speed(paper_rubber_design, setup, speed_bounds_rpm=(10.0, 120.0), n=12)
    assert check.fastest_rpm is not None and 10.0 < check.fastest_rpm < 120.0, check
    assert check.binding == "recovery <= 1 mm" and check.worst_margin[0] > 0 > check.worst_margin[-1]
    assert check.cycle_time_s == pytest.approx(2 * np.pi / (check.fastest_rpm * RPM * 2.0))
    slower, faster = _bracketed(check)
    assert slower < 0.001 < faster


def test_every_feasible_compound_of_a_ranking_carries_its_fastest_drum_and_may_rank_by_it():
    """Two over-damped compounds (tan delta 2 and 3: the more damped creeps back more slowly,
    so its finger allows a slower drum) and one whose alpha leaves it short of the force
    limit. Each feasible compound's fastest drum sits between ROM runs 5 % slower (its
    recovery within 1 mm) and 5 % faster (not); the infeasible one has none; ranked by the
    fastest drum, the faster finger comes first whatever the objective says; the table and
    the JSON carry the speed and the requirement that stops a faster drum."""
    req = Requirements.from_limits([*RECOVERY.limits(), Limit("sensor_peak_force_N", 100.0, label="force",
                                                              unit="N")])
    ranking = _flat_ranking([_compound("damped", 2.0), _compound("more_damped", 3.0), _compound("lively", 0.004)],
                            requirements=req)
    assert [d.compound.name for d in ranking.designs] == ["more_damped", "damped", "lively"]
    assert [d.feasible for d in ranking.designs] == [True, True, False]
    by_objective = with_drum_speeds(ranking, DrumSetup(), speed_bounds_rpm=(10.0, 120.0), n=12)
    by_drum = with_drum_speeds(ranking, DrumSetup(), speed_bounds_rpm=(10.0, 120.0), n=12, rank_by="fastest_drum")
    assert [d.compound.name for d in by_objective.designs] == [d.compound.name for d in ranking.designs]
    fastest = {d.compound.name: d.drum for d in by_objective.designs}
    assert fastest["lively"] is None and by_drum.rank_by == "fastest_drum"
    assert fastest["damped"].fastest_rpm > fastest["more_damped"].fastest_rpm
    assert [d.compound.name for d in by_drum.designs] == ["damped", "more_damped", "lively"]
    for name in ("damped", "more_damped"):
        check = fastest[name]
        assert check.binding == "recovery <= 1 mm", check
        slower, faster = _bracketed(check)
        assert slower < 0.001 < faster, name
    table = by_drum.table.set_index("compound")
    assert table.loc["damped", "fastest_drum_rpm"] == pytest.approx(fastest["damped"].fastest_rpm)
    assert table.loc["damped", "drum_binding"] == "recovery <= 1 mm" and pd.isna(table.loc["lively", "fastest_drum_rpm"])
    assert by_drum.as_dict()["designs"]["more_damped"]["drum_speed"]["fastest_rpm"] == pytest.approx(
        fastest["more_damped"].fastest_rpm)
    assert "fastest_drum_rpm" not in ranking.table and by_drum.as_dict()["rank_by"] == "fastest_drum"
    with pytest.raises(InputError, match="rank_by = 'speed': must be one of objective, fastest_drum"):
        with_drum_speeds(ranking, DrumSetup(), rank_by="speed")


def test_bad_drum_speed_settings_are_refused(paper_rubber_design):
    for kwargs, said in (({"speed_bounds_rpm": (40.0, 10.0)}, "drum speed bounds 40.0-10.0 rpm"),
                         ({"speed_bounds_rpm": (10.0, 500.0)}, "<= 120"), ({"n": 2}, "at least 3")):
        with pytest.raises(InputError, match=said):
            fastest_drum_speed(paper_rubber_design, DrumSetup(), **kwargs)


def test_a_designed_section_is_the_one_the_fastest_drum_is_found_on():
    """A compound designed over (L, b) on a flat surrogate whose force rises with b (the
    thinnest section, 4 mm, chosen): its fastest drum is found on the 4-mm finger, between
    ROM runs of that finger 5 % slower and 5 % faster."""
    mode = FirstMode((0.0, -2.0, math.log(1810.0 / 8.45), 1.0, 0.0, 0.0), 6.1e6, 1000.0, (3.0, 8.0), 0.0,
                     (4.0, 12.0))
    c = _compound("paper_like", 2.0)
    space = catalogue_space([c], mode, (4.0, 5.0))
    X = np.array(grid_points(space, (5, 5, 4, 4)))
    frame = pd.DataFrame({"alpha_per_s": X[:, 0], "length_m": X[:, 1], "youngs_modulus_Pa": X[:, 2],
                          "semi_thickness_m": X[:, 3], "sensor_peak_force_N": 10.0 + X[:, 1] + 1e3 * X[:, 3],
                          "recovery_deviation_m": np.zeros(len(X))})
    design = design_compounds(Surrogate.fit(space, frame), [c], setup=DrumSetup(), first_mode=mode,
                              requirements=RECOVERY, verify=False).designs[0]
    assert design.semi_thickness_m == pytest.approx(0.004)
    check = fastest_drum_speed(design, DrumSetup(), speed_bounds_rpm=(10.0, 120.0), n=12)
    assert check.fastest_rpm is not None and check.binding == "recovery <= 1 mm", check
    assert check.alpha_per_s == pytest.approx(2.0 * mode(4.0, E_Pa=6.1e6, rho_kg_m3=1000.0, semi_thickness_m=0.004))
    slower, faster = _bracketed(check, semi_thickness_m=0.004)
    assert slower < 0.001 < faster
