"""The fastest drum a compound's finger allows: the ROM of the finger at its own material,
length and alpha run over drum speeds; the speed where a recovery requirement starts to
fail, checked by ROM runs either side of it; bad bounds refused in one line."""
import math

import numpy as np
import pandas as pd
import pytest

from ccedi.design.catalogue_design import FirstMode, catalogue_space, design_compounds
from ccedi.design.compounds import Compound
from ccedi.design.drum_speed import fastest_drum_speed
from ccedi.design.outputs import setup_for_length
from ccedi.design.requirements import Limit, Requirements
from ccedi.design.surrogate import Surrogate, grid_points, run_rom, speed_space
from ccedi.errors import InputError
from ccedi.fea.contact.drum import DrumSetup
from ccedi.units import RPM

FIRST_MODE = FirstMode((0.0, -2.0, math.log(89.41 * 4.5**2)), 6.1e6, 1000.0, (3.0, 8.0), 0.0)
"""omega_1 = 1810 / L^2 rad/s (L in inches) at the paper's rubber."""
RECOVERY = Requirements.from_limits([Limit("recovery_deviation_m", 0.001, label="recovery", unit="mm")])


@pytest.fixture(scope="module")
def paper_rubber_design():
    """The paper's over-damped rubber (tan delta 2) designed on a flat surrogate (every
    length alike, the shortest chosen): only the compound, its tie and the requirement
    matter to the drum speed."""
    c = Compound(name="paper_like", E_min_Pa=6.1e6, E_max_Pa=6.1e6, rho_kg_m3=1000.0, tan_delta_min=2.0,
                 tan_delta_max=2.0, band_min_hz=1.0, band_max_hz=100.0, source="test compound")
    space = catalogue_space([c], FIRST_MODE, (4.0, 5.0))
    X = np.array(grid_points(space, (5, 5, 4)))
    frame = pd.DataFrame({"alpha_per_s": X[:, 0], "length_m": X[:, 1], "youngs_modulus_Pa": X[:, 2],
                          "sensor_peak_force_N": 10.0 + X[:, 1], "recovery_deviation_m": np.zeros(len(X))})
    return design_compounds(Surrogate.fit(space, frame), [c], setup=DrumSetup(), first_mode=FIRST_MODE,
                            requirements=RECOVERY, verify=False).designs[0]


def test_the_fastest_drum_is_where_the_finger_no_longer_recovers_in_time(paper_rubber_design):
    """At 10 rpm the 4-in finger is back in shape long before the next object; a faster drum
    leaves it less time (cycle 2 pi / (2 omega)). The speed found sits where the ROM's
    recovery deviation crosses 1 mm: a run 5 % slower recovers within it, 5 % faster not."""
    setup = DrumSetup()
    check = fastest_drum_speed(paper_rubber_design, setup, speed_bounds_rpm=(10.0, 120.0), n=12)
    assert check.fastest_rpm is not None and 10.0 < check.fastest_rpm < 120.0, check
    assert check.binding == "recovery <= 1 mm" and check.worst_margin[0] > 0 > check.worst_margin[-1]
    assert check.cycle_time_s == pytest.approx(2 * np.pi / (check.fastest_rpm * RPM * 2.0))
    own = setup_for_length(setup, check.length_m)
    runs = run_rom(own, [(check.alpha_per_s, f * check.fastest_rpm * RPM) for f in (0.95, 1.05)],
                   variables=speed_space((1.0, 1e3), (1.0, 200.0)))
    slower, faster = runs["recovery_deviation_m"]
    assert slower < 0.001 < faster


def test_bad_drum_speed_settings_are_refused(paper_rubber_design):
    for kwargs, said in (({"speed_bounds_rpm": (40.0, 10.0)}, "drum speed bounds 40.0-10.0 rpm"),
                         ({"speed_bounds_rpm": (10.0, 500.0)}, "<= 120"), ({"n": 2}, "at least 3")):
        with pytest.raises(InputError, match=said):
            fastest_drum_speed(paper_rubber_design, DrumSetup(), **kwargs)
