"""Beyond selection: the sparse force term on a residual (recovers a known term, finds
nothing in noise), a root-compliance record is not called a tip mass, and the loop
closes (``ccedi calibrate --write-config`` read back by every ``--config`` command)."""
import json

import numpy as np
import pytest
from conftest import ROOT

from ccedi.calibrate.experiment import load_experiment
from ccedi.calibrate.finger_modes import finger_basis
from ccedi.calibrate.loop import calibrate, separating_measurement, summary
from ccedi.calibrate.sparse import impulse_response, sparse_term
from ccedi.rom.modal import ModalROM
from ccedi.study.cli import main
from ccedi.study.config import drum_setup, load
from ccedi.units import inch_to_m

DATA = ROOT / "data" / "measured"


@pytest.fixture(scope="module")
def modes():
    return finger_basis(inch_to_m(8.0), (0.012, 0.00845), nu=0.49, rho_kg_m3=1000.0, E_Pa=6.1e6).modes(n_modes=5)


def test_impulse_response_is_the_pulse_response_of_a_short_pulse(modes):
    """h(t) against the exact modal response to a pulse 1e-6 s long, per unit impulse."""
    t = np.arange(1, 1001) * 1e-3
    zeta = 4.0 / (2.0 * modes.omega_rad_s)
    pulse = ModalROM(modes.omega_rad_s, modes.tip**2, zeta_fitted=zeta).pulse_response(t, 1.0, 1e-6) / 1e-6
    assert np.max(np.abs(impulse_response(modes, zeta, t) - pulse)) < 1e-4 * np.max(np.abs(pulse))


@pytest.mark.parametrize("term, coef", [("u^2", 40.0), ("sign(v)", 0.004)])
def test_sparse_term_recovers_a_known_missing_force(modes, term, coef):
    """A residual made as the response to coef x term is explained by that term alone."""
    from scipy.signal import fftconvolve

    from ccedi.calibrate.sparse import LIBRARY
    t = np.arange(2001) * 1e-3
    zeta = 4.0 / (2.0 * modes.omega_rad_s)
    u = ModalROM(modes.omega_rad_s, modes.tip**2, zeta_fitted=zeta).pulse_response(t, 1.5, 0.01)
    v = np.gradient(u, t)
    r = fftconvolve(coef * LIBRARY[term][0](u, v), impulse_response(modes, zeta, t))[:len(t)] * 1e-3
    noisy = r + 0.02 * np.ptp(r) * np.random.default_rng(1).standard_normal(len(t))
    found = sparse_term(t, noisy, u, modes=modes, zeta=zeta)
    assert list(found.terms) == [term]
    assert found.terms[term] == pytest.approx(coef, rel=0.05)
    assert found.error_reduction > 0.8
    noise_only = sparse_term(t, noisy - r, u, modes=modes, zeta=zeta)
    assert noise_only.error_reduction < 0.05


def test_root_compliance_is_not_called_a_tip_mass():
    """Both lower the first frequency; the higher modes and the static flexibility differ."""
    cal = calibrate(load_experiment(DATA / "root_compliance_high.csv"), candidates=["tip_mass", "root_compliance"])
    s = summary(cal)
    if s["ambiguous"]:
        assert set(s["ambiguous"]["effects"]) == {"tip_mass", "root_compliance"}
    else:
        assert s["selected_effect"] == "root_compliance"
    fits = [r.candidates for r in cal.rounds if r.candidates][0]
    sep = separating_measurement(cal.model, fits["root_compliance"], fits["tip_mass"])
    assert sep["quantity"] in ("static_tip_flexibility_m_N", "mode_2_frequency_hz", "mode_3_frequency_hz")
    assert sep["relative_difference"] > 0.05


def test_an_effect_that_leaves_the_residual_above_the_noise_is_not_accepted():
    """The magnet record (a tip force F_m (d / (d - u))^2, outside the catalogue) offered only
    cubic stiffening, its nearest stand-in: the cubic lowers BIC and removes most of the misfit
    but leaves the residual above the noise, so it is rejected, the final model is the
    baseline, and the residual is flagged unexplained with a sparse term."""
    cal = calibrate(load_experiment(DATA / "outside_magnet_attraction_high.csv"), candidates=["geometric_nonlinearity"])
    s = summary(cal)
    assert s["effects_found"] == [] and s["selected_effect"] is None
    assert s["rejected_effects"]["effects"] == ["geometric_nonlinearity"]
    assert s["rejected_effects"]["rms_over_noise"] > 1.1 and s["rejected_effects"]["nrmse"] < s["baseline"]["nrmse"]
    assert s["final_params"] == s["baseline"]["params"]
    assert s["unexplained_residual"] is True and s["sparse_term"]["terms"]


def test_write_config_is_read_back_by_every_config_command(tmp_path):
    """calibrate --write-config, then the study config loader (what design, study, impulse
    and contact read) gets the calibrated E and alpha; the drum's finger has that E."""
    out, toml = tmp_path / "c.json", tmp_path / "calibrated.toml"
    assert main(["calibrate", str(DATA / "control_high.csv"), "--json", str(out), "--effects", "gravity",
                 "--write-config", str(toml)]) == 0
    result = json.loads(out.read_text())
    cfg = load(toml)
    assert cfg["material"]["E_Pa"] == pytest.approx(result["calibrated"]["E_Pa"], rel=1e-12)
    assert cfg["material"]["alpha_per_s"] == pytest.approx(result["calibrated"]["alpha_per_s"], rel=1e-12)
    assert cfg["material"]["E_Pa"] != pytest.approx(6.1e6, rel=1e-3)       # the record's E is not the declared one
    assert drum_setup(cfg).finger_material.E == cfg["material"]["E_Pa"]
    declared = json.loads((DATA / "control_high.json").read_text())["finger"]["length_in"]
    assert cfg["finger"]["impulse_length_in"] == pytest.approx(declared, rel=1e-9)    # the record's finger, not 4.5 in
    assert cfg["finger"]["impulse_length_in"] != pytest.approx(load(None)["finger"]["impulse_length_in"])


@pytest.mark.slow
def test_design_runs_on_the_calibrated_config(tmp_path):
    toml = tmp_path / "calibrated.toml"
    assert main(["calibrate", str(DATA / "control_high.csv"), "--json", str(tmp_path / "c.json"), "--effects",
                 "gravity", "--write-config", str(toml)]) == 0
    out = tmp_path / "d.json"
    assert main(["design", "--config", str(toml), "--grid", "4", "4", "--validation-runs", "1", "--no-fea-check",
                 "--out", str(tmp_path), "--json", str(out)]) == 0
    d = json.loads(out.read_text())
    assert d["finger_material"]["E_Pa"] == pytest.approx(load(toml)["material"]["E_Pa"], rel=1e-12)
    assert d["measured_finger"] is None or d["measured_finger"]["alpha_per_s"] == pytest.approx(
        load(toml)["material"]["alpha_per_s"])


def test_the_study_design_is_rerun_with_the_calibrated_inputs(tmp_path):
    """The study's design step on a contact record whose friction is not the declared one:
    the calibrated design is made on the calibrated drum (its friction and E, not the
    declared ones) and the report shows it beside the declared model's design."""
    from ccedi.study.commands.design import CALIBRATED, DesignOptions, write_designs
    from ccedi.study.config import validate
    from ccedi.study.report import write_index

    record = ROOT / "data" / "contact" / "friction_low.csv"
    cfg = validate({"study": {"calibration_fea_correction": False}})
    options = DesignOptions(grid=(4, 4), validation_runs=1, pareto_points=4, starts=1, fea_check=False)
    out = tmp_path / "design"
    write_designs(cfg, options, str(record), out=out, scheduler="serial")
    declared = json.loads((out / "design.json").read_text())
    calibrated = json.loads((out / CALIBRATED / "design.json").read_text())
    cal = json.loads((out / CALIBRATED / "calibration.json").read_text())["calibrated"]
    assert calibrated["drum"]["friction"] == pytest.approx(cal["drum"]["friction"], rel=1e-12)
    assert calibrated["finger_material"]["E_Pa"] == pytest.approx(cal["E_Pa"], rel=1e-12)
    assert declared["drum"]["friction"] == cfg["drum"]["friction"] != pytest.approx(cal["drum"]["friction"], rel=0.05)
    page = write_index(tmp_path).read_text()
    assert "Design with the calibrated inputs" in page and "friction_low.csv: optimum" in page
