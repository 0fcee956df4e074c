"""Calibration of contact records: the sidecar, the calibration model against the physics
it must obey (exact E scaling, a drum-angle offset as a time shift, the transducer), the
loop on the bundled full-FEA records and the calibrated [drum] read back."""
import json
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT
from scipy.signal import butter, sosfiltfilt

from ccedi.calibrate.contact_model import ContactAdequacy, DrumContactModel, declared_setup, radially_offset
from ccedi.calibrate.contact_synthetic import declared_sidecar
from ccedi.calibrate.experiment import experiment_from, load_experiment
from ccedi.errors import InputError
from ccedi.fea.material import NeoHookean
from ccedi.rom.contact_rom import ReducedContactModel
from ccedi.rom.measurement import CONTACT_COLUMNS, response_from_frame
from ccedi.rom.sensor import Transducer
from ccedi.study.cli import main
from ccedi.study.config import drum_setup, load

DATA = ROOT / "data" / "contact"
T = np.arange(1, 1501) / 1000.0


def _experiment(force, noise=0.3, sidecar=None):
    frame = pd.DataFrame({"time_s": T, "reaction_force_N": force})
    return experiment_from(response_from_frame(frame, required=CONTACT_COLUMNS), sidecar or declared_sidecar(noise))


@pytest.fixture(scope="module")
def model():
    return DrumContactModel(_experiment(np.full_like(T, 5.0)))


@pytest.mark.parametrize("change, match", [
    (lambda s: s.pop("drum"), "'drum' is missing"),
    (lambda s: s["drum"].pop("friction"), "drum.friction' is missing"),
    (lambda s: s["drum"].update(omega_rad_s=-1.0), "drum.omega_rad_s"),
    (lambda s: s["drum"].update(object_center_m=[0.1]), "object_center_m' must be a list of two"),
    (lambda s: s["drum"].update(speed=2.0), "'drum.speed' is unknown"),
    (lambda s: s.update(damping="viscous"), "'damping' must be one of global, relative"),
    (lambda s: s["sensor"].update(noise_std_N=-0.1), "sensor.noise_std_N"),
])
def test_bad_contact_sidecars_name_the_field(change, match):
    sidecar = declared_sidecar(0.3)
    change(sidecar)
    with pytest.raises(InputError, match=match):
        _experiment(np.full_like(T, 5.0), sidecar=sidecar)


def test_a_contact_record_needs_its_force_column(tmp_path):
    (tmp_path / "r.csv").write_text("time_s,tip_displacement_m\n" + "".join(f"{t},{0.0}\n" for t in T[:20]))
    (tmp_path / "r.json").write_text(json.dumps(declared_sidecar(0.3)))
    with pytest.raises(InputError, match="missing column.*reaction_force_N"):
        load_experiment(tmp_path / "r.csv")


def test_a_record_without_contact_is_refused():
    with pytest.raises(InputError, match="shows no contact"):
        _experiment(np.full_like(T, 1.0), noise=0.3)


def test_young_modulus_scales_the_chain_exactly(model):
    """E x 1.07 by scaling the chain built at the declared E gives the force of a chain
    built at 1.07 E (the same model, only its stiffness and contact springs linear in E
    and its step as 1 / sqrt(E)): equal to round-off, and 7 % more force is not."""
    setup = declared_setup(model.exp)
    m = setup.finger_material
    stiff = replace(setup, finger_material=NeoHookean(E=1.07 * m.E, nu=m.nu, rho=m.rho))
    built = np.hypot(*ReducedContactModel(stiff).reaction_force(300.0, T).T)
    scaled = model.force({"alpha_per_s": 300.0, "E_factor": 1.07})
    declared = model.force({"alpha_per_s": 300.0, "E_factor": 1.0})
    assert np.max(np.abs(scaled - built)) < 1e-6 * built.max()
    assert np.max(np.abs(declared - built)) > 0.02 * built.max()


def test_a_drum_angle_offset_is_a_time_shift(model):
    """The drum turns at constant omega, so starting d_theta further round is the same run
    d_theta / omega earlier, once the start-up transient has died out (alpha = 300 1/s:
    e^(-alpha t / 2) < 1e-19 by the contact at ~0.3 s)."""
    v = {"alpha_per_s": 300.0, "E_factor": 1.0}
    d_theta = 0.02
    shifted = model.force(v | {"theta0_offset_rad": d_theta})
    reference = np.interp(T + d_theta / model.setup.omega_rad_s, T, model.force(v))
    err_shifted = np.sqrt(np.mean((shifted - reference) ** 2))
    err_unshifted = np.sqrt(np.mean((model.force(v) - reference) ** 2))
    assert err_shifted < 0.01 * reference.max()
    assert err_shifted < 0.25 * err_unshifted                       # the 9.5 ms shift is resolved


def test_radial_object_offset_keeps_the_direction_from_the_drum_axis():
    c = (0.1016, 0.18415)
    moved = radially_offset(c, 0.002)
    assert np.hypot(*moved) == pytest.approx(np.hypot(*c) + 0.002, rel=1e-12)
    assert c[0] * moved[1] - c[1] * moved[0] == pytest.approx(0.0, abs=1e-15)


def test_the_reading_is_the_transducer_of_the_force_plus_offset_and_drift(model):
    v = {"alpha_per_s": 300.0, "E_factor": 1.0}
    F = model.force(v)
    y = model.predict(v | {"sensor_hz": 30.0, "sensor_damping_ratio": 0.4, "offset_N": 0.2, "drift_N_s": -0.1})
    assert np.allclose(y, Transducer(30.0, 0.4).measured(T, F) + 0.2 - 0.1 * T, rtol=0.0, atol=1e-12)
    assert np.allclose(model.predict(v), Transducer().measured(T, F), rtol=0.0, atol=1e-12)


def test_timing_start_from_the_residual_is_near_the_truth(model):
    """The timing-offset start from the contact start and end errors (no fit) lands
    within 25 % of an injected 0.03 rad on a chain-made record."""
    from ccedi.calibrate.fit import Fit
    from ccedi.calibrate.likelihood import WHITE
    v = {"alpha_per_s": 200.0, "E_factor": 1.0}
    exp = _experiment(model.predict(v | {"theta0_offset_rad": 0.03}))
    m = DrumContactModel(exp)
    pred = m.predict(v)
    current = Fit(effects=(), values=v, stderr={}, prediction=pred, bic=0.0, log_evidence=0.0, noise=WHITE,
                  chi_square=float("nan"), holdout_rms_m=0.0, rms_m=0.0, nrmse=0.0, max_error_m=0.0, correlation={})
    start, _ = m.candidate_starts("timing_offset", current, m.analyse(current, 0.3))
    assert start["theta0_offset_rad"] == pytest.approx(0.03, rel=0.25)


def test_contact_write_config_holds_the_calibrated_drum(tmp_path):
    """ccedi calibrate on a bundled contact record (the offset effect only, to be quick)
    writes [drum] with the calibrated set-up; the study loader reads it back."""
    out, toml = tmp_path / "c.json", tmp_path / "calibrated.toml"
    assert main(["calibrate", str(DATA / "sensor_offset_drift_down.csv"), "--json", str(out), "--effects",
                 "sensor_offset_drift", "--write-config", str(toml)]) == 0
    result = json.loads(out.read_text())
    cfg = load(toml)
    assert result["kind"] == "contact" and result["selected_effect"] == "sensor_offset_drift"
    for key, value in result["calibrated"]["drum"].items():
        assert cfg["drum"][key] == pytest.approx(value, rel=1e-12)
    assert cfg["material"]["E_Pa"] == pytest.approx(result["calibrated"]["E_Pa"], rel=1e-12)
    assert drum_setup(cfg).finger_material.E == cfg["material"]["E_Pa"]


def test_baseline_finds_the_alpha_of_the_low_damping_control():
    """The force misfit over alpha is rough (stick-slip events come and go with alpha), so
    the baseline starts 10 % apart: on the full-FEA control at alpha = 80 1/s (E x 0.968)
    it lands within 5 % of the truth, and its error is within 15 % of the noise plus the
    chain's own error (starts 100 % apart ended at 100.8 1/s with 1.6 x that)."""
    from ccedi.calibrate.fit import fit_baseline

    exp = load_experiment(DATA / "control_80.csv")
    model = DrumContactModel(exp)
    base = fit_baseline(model)
    truth = json.loads((DATA / "manifest.json").read_text())["records"]["control_80"]
    assert base.values["alpha_per_s"] == pytest.approx(truth["alpha_per_s"], rel=0.05)
    assert base.rms_m < 1.15 * np.hypot(exp.noise_std_N, model.model_error)


def test_the_fea_correction_carries_the_smooth_discrepancy_and_counts_the_rest_as_model_error(monkeypatch):
    """The chain corrected by a full model (here a stand-in on the FEA's 0.5 ms outputs:
    the chain's own force plus a slow 0.4 N bias and a 150 Hz, 0.3 N ripple) reads what
    the full model reads but for the ripple: its residual against the full model's reading
    has no slow part left (below 3 Hz: under 5 % of the bias), and the model error is the
    RMS of that residual, the transducer's reading of the ripple (to 5 %), not the bias."""
    m = DrumContactModel(_experiment(np.full_like(T, 5.0)))
    v = {"alpha_per_s": 180.0, "E_factor": 1.0}
    t_fe = np.arange(0, 3001) * 0.5e-3
    F = np.interp(t_fe, T, m.force(v), left=0.0)
    bias = 0.4 * np.sin(np.pi * t_fe / 1.5)
    ripple = 0.3 * np.sin(2 * np.pi * 150.0 * t_fe)
    monkeypatch.setattr(m, "fea_force", lambda values: (t_fe, F + bias + ripple))
    chain_alone = m.predict(v)
    m.correct_at(v)
    full = np.interp(T, t_fe, Transducer().measured(t_fe, F + bias + ripple))
    residual = full - m.predict(v)
    slow = sosfiltfilt(butter(2, 3.0, fs=1000.0, output="sos"), residual)[100:-100]   # no filter start-up
    assert np.abs(slow).max() < 0.05 * 0.4
    assert np.sqrt(np.mean((full - chain_alone) ** 2)) > 3.0 * np.sqrt(np.mean(residual**2))
    assert m.model_error == pytest.approx(np.sqrt(np.mean(residual**2)), rel=1e-9)
    ripple_reading = np.interp(T, t_fe, Transducer().measured(t_fe, ripple))
    assert m.model_error == pytest.approx(np.sqrt(np.mean(ripple_reading**2)), rel=0.05)


def test_a_contact_record_tells_which_damping_kind_it_supports():
    """A record made by the chain with relative damping (alpha 180 1/s, 100 Hz transducer,
    0.3 N noise) and declared global: the calibration says relative and goes on with it
    (the damping kind is a structural choice made from the record), with the alpha the
    record was made with; the same record declared relative says relative too."""
    from ccedi.calibrate.fit import fit_baseline
    from ccedi.calibrate.loop import calibrate, calibration_model, damping_kind_support

    exp = _experiment(np.full_like(T, 5.0))
    rom = ReducedContactModel(declared_setup(exp))
    force = Transducer().measured(T, np.hypot(*rom.reaction_force(180.0, T, damping="relative").T))
    noisy = force + np.random.default_rng(3).normal(0.0, 0.3, len(T))
    wrong = _experiment(noisy, sidecar=declared_sidecar(0.3) | {"damping": "global"})
    cal = calibrate(wrong, candidates=())
    assert cal.damping_kind["declared"] == "global" and cal.damping_kind["supported"] == "relative"
    assert cal.experiment.damping == "relative" and cal.damping_kind["used"] == "relative"
    assert cal.final.values["alpha_per_s"] == pytest.approx(180.0, rel=0.05)
    right = _experiment(noisy, sidecar=declared_sidecar(0.3) | {"damping": "relative"})
    support = damping_kind_support(right, fit_baseline(calibration_model(right)))
    assert support["declared"] == "relative" and support["supported"] == support["used"] == "relative"
    assert support["relative"]["alpha_per_s"] == pytest.approx(180.0, rel=0.05)




def test_a_smooth_misfit_whitened_by_a_near_random_walk_is_not_at_the_noise_level():
    """Innovations at chi-square 1 (an AR(1) model with phi 0.95 has whitened a smooth
    misfit away) but a residual of 1.7 noise std: not at the noise level; the same
    innovations with the residual at 1.02 std: at the noise level."""
    from ccedi.calibrate.likelihood import NoiseModel
    from ccedi.calibrate.loop import at_noise_level

    noise = NoiseModel(np.array([0.95]), innovation_std=0.3 * np.sqrt(1 - 0.95**2))
    assert not at_noise_level(SimpleNamespace(rms_m=1.7 * 0.3, noise=noise, chi_square=1.0), 0.3, 1500)
    assert at_noise_level(SimpleNamespace(rms_m=1.02 * 0.3, noise=noise, chi_square=1.0), 0.3, 1500)


def test_a_force_level_an_effect_explains_is_not_a_wrong_declaration():
    """E on its bound alone is provisional: resolved adequate by a fit with effects whose E
    is off the bound, kept inadequate when the fit's E stays on it; a record without
    contact is not provisional."""
    pressed = ContactAdequacy(failed=("E_factor",), reasons=("E on its bound",), E_factor=1.2,
                              E_factor_bounds=(0.8, 1.2), peak_over_noise=50.0)
    assert pressed.effect_may_explain and not pressed.adequate
    assert pressed.resolved_by(SimpleNamespace(values={"E_factor": 1.04})).adequate
    assert not pressed.resolved_by(SimpleNamespace(values={"E_factor": 1.1999})).adequate
    no_contact = replace(pressed, failed=("contact", "E_factor"))
    assert not no_contact.effect_may_explain
    assert not no_contact.resolved_by(SimpleNamespace(values={"E_factor": 1.0})).adequate


def test_candidates_restart_at_the_declared_E_when_E_is_pressed_on_its_bound():
    """With the current E on its bound every candidate gets starts at E x 1 and alpha / 3,
    alpha and 3 alpha; with E inside, none of them."""
    model = DrumContactModel(_experiment(np.full_like(T, 5.0)))
    evidence = {"start_error_s": 0.01, "end_error_s": 0.01}
    prediction = np.where((T > 0.4) & (T < 1.2), 10.0, 0.0)
    for e, expected in ((1.2, True), (1.05, False)):
        current = SimpleNamespace(values={"alpha_per_s": 60.0, "E_factor": e}, prediction=prediction)
        for name in ("drum_speed", "timing_offset", "sensor_bandwidth", "friction"):
            _, extra = model.candidate_starts(name, current, evidence)
            restarts = {round(s["alpha_per_s"], 6) for s in extra if s.get("E_factor") == 1.0 and "alpha_per_s" in s}
            assert (restarts == {20.0, 60.0, 180.0}) is expected, (name, e, extra)
