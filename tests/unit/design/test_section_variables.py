"""The section's semi-axes as design variables: a design point sets them on the generated
finger (its first mode follows the thickness as a bent beam's, omega_1 proportional to b,
and not the width), a finger mesh keeps its own section, and bad requests are refused in
one line."""
import pytest

from ccedi.design.outputs import setup_at, setup_for_section
from ccedi.design.surrogate import section_space
from ccedi.errors import InputError
from ccedi.fea.contact.drum import DrumSetup
from ccedi.fea.mesh import SEMI_AXES
from ccedi.rom.finger_identification import finger_omega1


def test_a_design_point_sets_the_section_and_the_first_mode_follows_the_thickness_as_a_beams():
    space = section_space(semi_axis="semi_thickness_m", bounds_mm=(4.0, 14.0))
    base = DrumSetup()
    thin = setup_at(base, [v.name for v in space], (60.0, 5.0e-3))
    thick = setup_at(base, [v.name for v in space], (60.0, 7.5e-3))
    assert thin.finger_semi_axes_m == (SEMI_AXES[0], 5.0e-3) and thick.finger_semi_axes_m[1] == 7.5e-3
    w = [finger_omega1(6.0, semi_axes_m=s.finger_semi_axes_m) for s in (thin, thick)]
    assert w[1] / w[0] == pytest.approx(1.5, rel=0.03)            # Euler-Bernoulli: omega_1 ~ b / L^2
    wide = setup_at(base, ["alpha_per_s", "semi_width_m"], (60.0, 1.5 * SEMI_AXES[0]))
    assert wide.finger_semi_axes_m == (1.5 * SEMI_AXES[0], SEMI_AXES[1])
    assert finger_omega1(6.0, semi_axes_m=wide.finger_semi_axes_m) == pytest.approx(
        finger_omega1(6.0, semi_axes_m=SEMI_AXES), rel=0.03)    # width: stiffness and mass alike


def test_bad_section_requests_are_refused_in_one_line():
    with pytest.raises(InputError, match="semi_thickness_m, semi_width_m|semi_width_m, semi_thickness_m"):
        section_space(semi_axis="radius_m")
    with pytest.raises(InputError, match="0 < lo < hi"):
        section_space(bounds_mm=(9.0, 3.0))
    with pytest.raises(InputError, match="section_semi_axis_m|semi-axis|semi_axes"):
        setup_for_section(DrumSetup(), semi_thickness_m=-1e-3)
