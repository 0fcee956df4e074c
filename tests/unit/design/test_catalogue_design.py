"""The compound as a design variable: the similarity the catalogue surrogate rests on (the
ROM of a finger of E k and rho k moves as the finger of E and rho with k times its
forces), the first mode over length and material against the FE eigen solve, a compound's
view of the surrogate, the ranking (a compound that cannot meet a requirement ranks below
one that can, the feasible ones by the objective, alpha tied to the compound at the
optimum) and the one-line errors on bad input."""
import math
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from ccedi.design.catalogue_design import (
    CompoundSurrogate,
    CompoundTie,
    FirstMode,
    catalogue_space,
    design_compounds,
)
from ccedi.design.compounds import Compound
from ccedi.design.optimise import OBJECTIVES
from ccedi.design.outputs import DENSITY_SCALED
from ccedi.design.requirements import Limit, Requirements
from ccedi.design.robust import (
    CalibratedSpread,
    Spread,
    robust_catalogue,
    robust_design,
    spread_check,
    violation_probabilities,
)
from ccedi.design.surrogate import Surrogate, grid_points, material_space, run_rom
from ccedi.errors import InputError
from ccedi.fea.contact.drum import DrumSetup, finger_mesh
from ccedi.fea.material import NeoHookean
from ccedi.rom.finger_identification import finger_omega1
from ccedi.statistics import wilson_interval
from ccedi.units import INCH, m_to_inch

CANTILEVER = FirstMode((0.0, -2.0, math.log(89.41 * 4.5**2)), 6.1e6, 1000.0, (3.0, 8.0), 0.0)
"""omega_1 = 1810 / L^2 rad/s (L in inches) at the paper's rubber: the Euler-Bernoulli
cantilever through the FE 4.5-in finger's 89.41 rad/s."""


def compound(name, *, E_Pa, tan_delta, rho_kg_m3=1000.0):
    return Compound(name=name, E_min_Pa=E_Pa, E_max_Pa=E_Pa, rho_kg_m3=rho_kg_m3, tan_delta_min=tan_delta,
                    tan_delta_max=tan_delta, band_min_hz=1.0, band_max_hz=100.0, source="test compound")


def synthetic_surrogate(space):
    """A surrogate over (alpha, L, E) of a mass-spring finger at rho 1000: the force of a
    spring of stiffness ~ E / L^3 pushed through a fixed indentation, rising with E and
    falling with L; the first overshoot of a one-mode finger of damping ratio
    zeta = alpha / (2 omega_1), exp(-zeta pi / sqrt(1 - zeta^2)) of a 20 mm deflection."""
    X = np.array(grid_points(space, (12, 8, 5)))
    alpha, L, E = X.T
    omega = CANTILEVER(m_to_inch(L), E_Pa=E, rho_kg_m3=1000.0)
    zeta = np.minimum(alpha / (2.0 * omega), 0.999)
    frame = pd.DataFrame({"alpha_per_s": alpha, "length_m": L, "youngs_modulus_Pa": E,
                          "sensor_peak_force_N": 3.0 * (E / 1e6) * (0.1 / L) ** 1.5,
                          "ringing_amplitude_m": 0.02 * np.exp(-zeta * np.pi / np.sqrt(1.0 - zeta**2))})
    return Surrogate.fit(space, frame)


@pytest.fixture(scope="module")
def synthetic():
    compounds = [compound("damped_soft", E_Pa=3e6, tan_delta=1.6), compound("lively", E_Pa=3e6, tan_delta=0.1),
                 compound("damped_stiff", E_Pa=9e6, tan_delta=1.6, rho_kg_m3=1200.0)]
    space = catalogue_space(compounds, CANTILEVER, (3.0, 8.0))
    return compounds, synthetic_surrogate(space)


REQ = Requirements.from_limits([Limit("sensor_peak_force_N", 60.0, label="object force", unit="N"),
                                Limit("ringing_amplitude_m", 0.004, label="ringing", unit="mm")])


def test_a_finger_of_E_k_and_rho_k_moves_as_that_of_E_and_rho_with_k_times_its_forces():
    setup = DrumSetup()
    m, k = setup.finger_material, 1.4
    point = [(30.0, 5.0 * INCH)]
    a = run_rom(setup, point).iloc[0]
    b = run_rom(replace(setup, finger_material=NeoHookean(E=m.E * k, nu=m.nu, rho=m.rho * k)), point).iloc[0]
    assert a["sensor_peak_force_N"] > 1.0 and a["recovery_deviation_m"] > 0.0
    for name in ("sensor_peak_force_N", "max_finger_stress_Pa", "contact_impulse_N_s", "max_object_stress_Pa",
                 "recovery_deviation_m", "ringing_amplitude_m", "contact_patch_from_root_m", "contact_duration_s"):
        assert b[name] == pytest.approx(a[name] * (k if name in DENSITY_SCALED else 1.0), rel=1e-6, abs=1e-12), name


def test_the_first_mode_follows_length_and_material_as_the_fe_eigen_solve():
    setup = DrumSetup()
    mode = FirstMode.of(setup, (3.0, 8.0))
    assert mode.fit_error < 0.005
    other = NeoHookean(E=2.2e6, nu=0.49, rho=1300.0)
    fe = finger_omega1(5.7, material=other)
    assert mode(5.7, E_Pa=other.E, rho_kg_m3=other.rho) == pytest.approx(fe, rel=0.005)


def test_the_first_mode_of_a_tapered_finger_is_its_own():
    """A tapered set-up's first mode is the tapered finger's (1.2-1.4 times the prism's at
    taper 0.6, the tapered beam's stiffer-for-its-mass tip), not the prism's."""
    setup = DrumSetup(finger_taper_ratio=0.6)
    mode = FirstMode.of(setup, (3.0, 8.0))
    fe = finger_omega1(mesh=finger_mesh(replace(setup, finger_length_m=5.7 * INCH)), material=setup.finger_material)
    assert mode(5.7, E_Pa=setup.finger_material.E, rho_kg_m3=setup.finger_material.rho) == pytest.approx(fe, rel=0.005)
    assert fe > 1.15 * finger_omega1(5.7)


def test_a_compound_sees_the_surrogate_at_its_modulus_over_density_with_its_forces_scaled(synthetic):
    _, surrogate = synthetic
    sliced = CompoundSurrogate(surrogate, E_Pa=6.3e6, rho_kg_m3=1500.0, reference_rho_kg_m3=1000.0)
    x = (40.0, 5.0 * INCH)
    base = {k: float(v[0]) for k, v in surrogate.evaluate([[*x, 4.2e6]]).items()}
    seen = {k: float(v[0]) for k, v in sliced.evaluate([x]).items()}
    assert seen["sensor_peak_force_N"] == pytest.approx(1.5 * base["sensor_peak_force_N"], rel=1e-9)
    assert seen["ringing_amplitude_m"] == pytest.approx(base["ringing_amplitude_m"], rel=1e-9)


def test_a_compound_that_cannot_meet_a_requirement_ranks_below_those_that_can(synthetic):
    compounds, surrogate = synthetic
    cat = design_compounds(surrogate, compounds, setup=DrumSetup(), first_mode=CANTILEVER, requirements=REQ,
                           verify=False)
    names = [d.compound.name for d in cat.designs]
    assert names[-1] == "lively" and not cat.designs[-1].feasible
    assert all(d.feasible for d in cat.designs[:-1])
    lively = cat.designs[-1]
    assert lively.shortfall > 0.0 and any("ringing" in b for b in lively.binding)
    # the lightly damped finger's overshoot: exp(-zeta pi / sqrt(1 - zeta^2)) of 20 mm at its tie
    zeta = lively.design.alpha_per_s / (2.0 * CANTILEVER(m_to_inch(lively.design.x), E_Pa=3e6, rho_kg_m3=1000.0))
    assert lively.design.outputs["ringing_amplitude_m"] == pytest.approx(
        0.02 * math.exp(-zeta * math.pi / math.sqrt(1 - zeta**2)), rel=0.05)
    feasible = [d.objective_value for d in cat.designs if d.feasible]
    assert feasible == sorted(feasible) and cat.winner is cat.designs[0]
    table = cat.table
    assert list(table["compound"]) == names and list(table["rank"]) == [1, 2, 3]
    assert table["objective_unit"].iloc[0] == "N" and "margin: ringing <= 4 mm" in table.columns


def test_alpha_is_the_compounds_at_the_optimum_and_its_robust_margin_is_its_worst_loss_factor(synthetic):
    compounds, surrogate = synthetic
    ranged = replace(compounds[0], name="ranged", tan_delta_min=0.3, tan_delta_max=2.9)
    cat = design_compounds(surrogate, [ranged], setup=DrumSetup(), first_mode=CANTILEVER, requirements=REQ,
                           verify=False)
    d = cat.designs[0]
    tie = CompoundTie(ranged, CANTILEVER)
    assert d.design.alpha_per_s == pytest.approx(tie(m_to_inch(d.design.x)), rel=1e-6)
    assert d.tie.loss_factor == pytest.approx(1.6)
    # met at the nominal loss factor (zeta 0.8), missed at the least damped end of the range (zeta 0.15 rings
    # 0.62 of 20 mm)
    assert d.feasible and min(d.margins.values()) >= 0.0
    assert d.robust_margin < -1.0 and "ringing" in d.robust_limit and "tan delta 0.3" in d.robust_limit


@pytest.mark.parametrize("kwargs, said", [
    ({"objective": "weighted"}, "objective with a unit"),
    ({"compounds": []}, "at least one compound"),
])
def test_bad_requests_are_refused_in_one_line(synthetic, kwargs, said):
    compounds, surrogate = synthetic
    args = {"compounds": compounds, "objective": "object_force", **kwargs}
    with pytest.raises(InputError, match=said) as err:
        design_compounds(surrogate, args["compounds"], setup=DrumSetup(), first_mode=CANTILEVER,
                         objective=args["objective"], requirements=REQ, verify=False)
    assert "\n" not in str(err.value)
    assert "weighted" not in OBJECTIVES


def test_a_compound_outside_the_surrogate_and_a_surrogate_without_E_are_refused(synthetic):
    _, surrogate = synthetic
    with pytest.raises(InputError, match=r"outside its E range"):
        CompoundSurrogate(surrogate, E_Pa=40e6, rho_kg_m3=1000.0, reference_rho_kg_m3=1000.0)
    two = Surrogate(surrogate.variables[:2], surrogate.axes[:2],
                    {"sensor_peak_force_N": np.ones((len(surrogate.axes[0]), len(surrogate.axes[1])))})
    with pytest.raises(InputError, match=r"youngs_modulus_Pa"):
        CompoundSurrogate(two, E_Pa=3e6, rho_kg_m3=1000.0, reference_rho_kg_m3=1000.0)
    with pytest.raises(InputError, match=r"0 < lo < hi"):
        material_space((1.0, 600.0), (3.0, 8.0), (5e6, 2e6))


@pytest.fixture(scope="module")
def spread_wide():
    """One compound and a synthetic surrogate wide enough for its default spread."""
    c = compound("damped_soft", E_Pa=3e6, tan_delta=1.6)
    return c, synthetic_surrogate(catalogue_space([c], CANTILEVER, (3.0, 8.0), spread=Spread()))


def test_the_robust_length_meets_a_force_floor_at_the_modulus_quantile_where_the_nominal_misses_half(spread_wide):
    """Least force above a floor of 6 N: the nominal optimum sits on the floor, so E +-15 %
    (uniform; the force ~ E L^-1.5) misses it about half the time. The robust length
    meets it at E's 5 % quantile, 0.865 E: L_r = L_n 0.865^(2/3), within the length grid,
    and violates it in at most 5 % of the samples and, on fresh samples, within the
    binomial 95 % interval of 5 %."""
    c, surrogate = spread_wide
    floor = Requirements.from_limits([Limit("sensor_peak_force_N", 6.0, upper=False, label="grip", unit="N")])
    nominal = design_compounds(surrogate, [c], setup=DrumSetup(), first_mode=CANTILEVER, requirements=floor,
                               verify=False).designs[0]
    assert nominal.feasible
    samples = Spread().samples(c, 2000, seed=11)
    at_nominal = violation_probabilities(nominal, surrogate, length_m=nominal.design.x, samples=samples)
    assert 0.35 <= max(at_nominal.values()) <= 0.65
    robust = robust_design(nominal, surrogate)
    assert robust.feasible and max(robust.violation.values()) <= 0.05
    step = (surrogate.variables[1].hi - surrogate.variables[1].lo) / 80
    assert robust.length_m == pytest.approx(nominal.design.x * 0.865 ** (2 / 3), abs=2 * step)
    fresh = violation_probabilities(nominal, surrogate, length_m=robust.length_m, samples=samples)
    assert max(fresh.values()) <= wilson_interval(100, 2000)[1]
    assert robust.objective > nominal.objective_value


def test_a_spread_the_surrogate_does_not_cover_and_bad_settings_are_refused(synthetic, spread_wide):
    compounds, narrow = synthetic
    c, wide = spread_wide
    nominal = design_compounds(narrow, compounds[:1], setup=DrumSetup(), first_mode=CANTILEVER, requirements=REQ,
                               verify=False).designs[0]
    with pytest.raises(InputError, match="leaves the surrogate's range"):
        robust_design(nominal, narrow)
    for kwargs, said in (({"probability": 1.0}, "probability"), ({"n_samples": 5}, "samples")):
        with pytest.raises(InputError, match=said):
            robust_design(nominal, wide, **kwargs)
    with pytest.raises(InputError, match="E_relative"):
        Spread(E_relative=1.5)


def test_a_calibrated_spread_draws_E_and_alpha_with_the_reported_errors_and_correlation():
    """E and alpha normal with 4 % and 10 % relative standard errors and correlation -0.6
    (within 3 std): the samples' E std, the implied alpha (tan delta x sqrt(E), the first
    mode ~ sqrt(E)) std and their correlation agree within Monte Carlo error (20 000
    samples: about 1 % of a std, 0.01 of a correlation), nothing beyond the truncation."""
    c = compound("calibrated", E_Pa=4e6, tan_delta=0.5)
    spread = CalibratedSpread(E_relative_std=0.04, alpha_relative_std=0.10, correlation=-0.6)
    E, tan_delta = spread.samples(c, 20_000, seed=3)
    e = E / c.E_nominal_Pa - 1.0
    a = tan_delta / c.tan_delta_nominal * np.sqrt(E / c.E_nominal_Pa) - 1.0
    truncated = 1.0 - 0.0135                                   # variance of a normal cut at 3 std
    assert np.std(e) == pytest.approx(0.04 * np.sqrt(truncated), rel=0.03)
    assert np.std(a) == pytest.approx(0.10 * np.sqrt(truncated), rel=0.03)
    assert np.corrcoef(e, a)[0, 1] == pytest.approx(-0.6, abs=0.03)
    assert np.abs(e).max() <= 3 * 0.04 + 1e-12 and np.abs(a).max() <= 3 * 0.10 + 1e-12
    assert np.abs(tan_delta / c.tan_delta_nominal - 1.0).max() <= spread.tan_delta_relative


def test_a_calibrated_spread_reads_a_calibration_result_and_refuses_what_is_not_one(tmp_path):
    result = {"final_params": {"alpha_per_s": 150.0, "E_factor": 1.02},
              "final_stderr": {"alpha_per_s": 3.0, "E_factor": 0.0102},
              "final_correlation": {"alpha_per_s,E_factor": 0.4}}
    spread = CalibratedSpread.from_calibration(result)
    assert (spread.E_relative_std, spread.alpha_relative_std, spread.correlation) == pytest.approx((0.01, 0.02, 0.4))
    bad = tmp_path / "bad.json"
    bad.write_text('{"final_params": {}}')
    for source in (bad, tmp_path / "missing.json"):
        with pytest.raises(InputError, match=source.name):
            CalibratedSpread.from_calibration(source)
    with pytest.raises(InputError, match="correlation"):
        CalibratedSpread(E_relative_std=0.01, alpha_relative_std=0.01, correlation=1.5)


def test_the_kept_margin_is_the_quantile_and_the_nominal_check_shares_the_robust_samples(spread_wide):
    """At the nominal optimum on a force floor the margin kept with 95 % is the 5 % quantile:
    negative (the floor is missed about half the time) while the nominal margin is about
    zero; the robust design carries that check on its own samples, and its kept margins
    are >= 0 exactly where its violations are <= 5 %."""
    c, surrogate = spread_wide
    floor = Requirements.from_limits([Limit("sensor_peak_force_N", 6.0, upper=False, label="grip", unit="N")])
    nominal = design_compounds(surrogate, [c], setup=DrumSetup(), first_mode=CANTILEVER, requirements=floor,
                               verify=False).designs[0]
    robust = robust_design(nominal, surrogate, n_samples=400, seed=5)
    again = spread_check(nominal, surrogate, length_m=nominal.design.x, samples=Spread().samples(c, 400, 5))
    assert robust.nominal == again
    (req, kept), = again.margin_kept.items()
    assert kept < -0.03 and abs(again.nominal_margin[req]) < 0.01 and 0.35 < again.violation[req] < 0.65
    assert robust.check.margin_kept[req] >= 0.0 and robust.check.violation[req] <= 0.05
    assert robust.design.x == robust.length_m and robust.design.alpha_per_s == robust.alpha_per_s


def test_the_robust_ranking_puts_a_compound_robust_at_a_higher_nominal_cost_first():
    """Least force under a 12 mm ringing cap. The softer, lively compound (E 2 MPa, tan delta
    0.35: 11.4 mm of ringing at every length, zeta = tan delta / 2) wins the nominal ranking
    with two thirds of the damped one's force; but tan delta 30 % low rings past the cap
    (exp(-pi zeta / sqrt(1 - zeta^2)) of 20 mm), a third of its samples at every length, so it
    has no robust length; the damped compound (tan delta 1.6) is robust at its nominal
    optimum and ranks first once the spread counts."""
    damped, lively = (compound("damped", E_Pa=3e6, tan_delta=1.6), compound("lively", E_Pa=2e6, tan_delta=0.35))
    space = catalogue_space([damped, lively], CANTILEVER, (3.0, 8.0), spread=Spread())
    surrogate = synthetic_surrogate(space)
    req = Requirements.from_limits([Limit("ringing_amplitude_m", 0.012, label="ringing", unit="mm")])
    ranking = design_compounds(surrogate, [damped, lively], setup=DrumSetup(), first_mode=CANTILEVER,
                               requirements=req, verify=False)
    assert [d.compound.name for d in ranking.designs] == ["lively", "damped"] and ranking.designs[0].feasible
    robust = robust_catalogue(ranking, surrogate)
    assert [d.compound for d in robust.designs] == ["damped", "lively"] and robust.winner.compound == "damped"
    lively_robust = robust.designs[1]
    assert not lively_robust.feasible and 0.2 < lively_robust.nominal.worst < 0.45
    tau = 0.35 * np.array([0.7, 1.3])                          # the analytic fraction: ringing(tau) = 12 mm
    zeta = np.linspace(tau[0] / 2, tau[1] / 2, 100_001)
    limit = 2 * zeta[np.argmin(np.abs(0.02 * np.exp(-np.pi * zeta / np.sqrt(1 - zeta**2)) - 0.012))]
    assert lively_robust.nominal.worst == pytest.approx((limit - tau[0]) / (tau[1] - tau[0]), abs=0.08)
    assert robust.winner.check.worst <= 0.05 and robust.winner.objective > ranking.designs[0].objective_value
