"""The section's semi-axes as design variables: a design point sets them on the generated
finger (its first mode follows the thickness as a bent beam's, omega_1 proportional to b,
and not the width), a finger mesh keeps its own section, and bad requests are refused in
one line; the surrogate over the section corrected by full-FEA runs at training designs."""
import numpy as np
import pandas as pd
import pytest

from ccedi.design.model_error import FeaCorrection
from ccedi.design.outputs import setup_at, setup_for_section
from ccedi.design.surrogate import Surrogate, grid_points, section_space
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


def _runs(space, points, ratio=lambda u_alpha, u_b: 1.0):
    """Runs of a made-up model at ``points``: a force growing as b^3 / ln(alpha), a ringing
    length; the force times ``ratio`` of the unit coordinates (the "FEA")."""
    X = np.array(points)
    ua, ub = (v.to_unit(X[:, i]) for i, v in enumerate(space))
    force = (X[:, 1] / 8.45e-3) ** 3 * 20.0 / np.log(X[:, 0])
    return pd.DataFrame({"alpha_per_s": X[:, 0], "semi_thickness_m": X[:, 1],
                         "sensor_peak_force_N": force * ratio(ua, ub), "ringing_amplitude_m": 0.004 + 0.001 * ua})


def test_the_fea_correction_carries_the_ratio_of_the_training_runs_between_and_beyond_them():
    """A model that reads the force low by a factor linear in (ln alpha, b), 12 % at the
    thin, lightly damped corner and 3 % at the thick, heavily damped one; trained at 2 x 3
    designs inside the space, the corrected surrogate gives the FEA's force at designs
    between them (the ratio is bilinear, so its interpolation is exact there) and the
    edge ratio beyond them; the ringing, a length, is left as the model has it."""
    space = section_space((7.5, 600.0), "semi_thickness_m", (4.0, 14.0))
    ratio = lambda ua, ub: 1.0 / (0.925 + 0.025 * ua + 0.02 * ub)          # noqa: E731
    training = [(a, b * 1e-3) for a in (40.0, 250.0) for b in (5.5, 9.0, 12.0)]
    correction = FeaCorrection.fit(space, _runs(space, training), _runs(space, training, ratio),
                                   outputs=("sensor_peak_force_N",))
    grid = _runs(space, grid_points(space, (16, 11)))
    surrogate = Surrogate.fit(space, correction.apply(grid))
    inside = [(60.0, 6e-3), (150.0, 10e-3)]
    fea = _runs(space, inside, ratio)
    got = surrogate.evaluate(inside)
    np.testing.assert_allclose(got["sensor_peak_force_N"], fea["sensor_peak_force_N"], rtol=2e-3)
    np.testing.assert_allclose(got["ringing_amplitude_m"], _runs(space, inside)["ringing_amplitude_m"], rtol=1e-6)
    assert Surrogate.fit(space, grid).evaluate(inside)["sensor_peak_force_N"][0] < 0.93 * fea["sensor_peak_force_N"][0]
    beyond = correction.ratio("sensor_peak_force_N", [(20.0, 4.5e-3), (600.0, 14e-3)])
    edge = correction.ratio("sensor_peak_force_N", [(40.0, 5.5e-3), (250.0, 12e-3)])
    np.testing.assert_allclose(beyond, edge, rtol=1e-12)
    assert correction.as_dict()["semi_thickness_mm"] == pytest.approx([5.5, 9.0, 12.0])


def test_a_length_is_corrected_only_where_both_models_have_it():
    """The recovery of a finger that has recovered (1e-9 m in one model, 1e-7 m in the
    other) keeps ratio 1; where both read millimetres the FEA's ratio is taken."""
    space = section_space((7.5, 600.0), "semi_thickness_m", (4.0, 14.0))
    training = [(a, b * 1e-3) for a in (40.0, 250.0) for b in (5.5, 12.0)]
    model = _runs(space, training).assign(recovery_deviation_m=[1e-9, 1e-9, 5e-3, 1e-9])
    fea = model.assign(recovery_deviation_m=[1e-7, 1e-7, 4.5e-3, 2e-4])
    correction = FeaCorrection.fit(space, model, fea, outputs=("recovery_deviation_m",))
    np.testing.assert_allclose(correction.ratios["recovery_deviation_m"], [[1.0, 1.0], [0.9, 1.0]], rtol=1e-12)


def test_an_fea_correction_needs_a_full_training_grid_of_the_same_points_and_positive_outputs():
    space = section_space((7.5, 600.0), "semi_thickness_m", (4.0, 14.0))
    training = [(a, b * 1e-3) for a in (40.0, 250.0) for b in (5.5, 12.0)]
    runs = _runs(space, training)
    with pytest.raises(InputError, match="same design points"):
        FeaCorrection.fit(space, runs, runs.iloc[::-1].reset_index(drop=True))
    with pytest.raises(InputError, match="full tensor grid"):
        FeaCorrection.fit(space, runs.iloc[:3], runs.iloc[:3])
    with pytest.raises(InputError, match="finite and positive"):
        FeaCorrection.fit(space, runs, runs.assign(sensor_peak_force_N=0.0), outputs=("sensor_peak_force_N",))
    with pytest.raises(InputError, match="missing"):
        FeaCorrection.fit(space, runs, runs)
