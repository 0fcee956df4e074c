"""The contact prediction from an impulse calibration (:mod:`ccedi.calibrate.prediction`):
the features of a force pulse of known start, end and peak; the sigma points; the chain's
bias line and its widening std; the interval widening with the parameters' covariance
around the chain's features at the calibrated values (bias removed); a contact set-up of
another finger refused; the chain error the library holds is the one
validation/predict_contact.py measured."""
import json
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from conftest import ROOT

from ccedi.calibrate.contact_model import DrumContactModel
from ccedi.calibrate.experiment import load_experiment
from ccedi.calibrate.prediction import (
    CHAIN_ERROR,
    CHAIN_RUNS,
    chain_error,
    check_same_finger,
    contact_features,
    fea_equivalent,
    load_contact_setup,
    predict_contact,
    sigma_points,
)
from ccedi.errors import InputError

T = np.arange(1, 1501) / 1000.0
START_S, END_S, PEAK_N = 0.45, 1.30, 15.0


def _pulse(t):
    """A drum-like contact force: jumps to 5 N at START_S, rises to PEAK_N at 0.75 s, falls
    to 4 N at END_S and drops to zero."""
    up = np.interp(t, [START_S, 0.75, END_S], [5.0, PEAK_N, 4.0])
    return np.where((t >= START_S) & (t <= END_S), up, 0.0)


def test_features_of_a_known_pulse():
    """Start and end within 10 ms of the jumps (the 20 Hz low-pass spreads each over ~10 ms,
    and 10 % of the peak is a third of the way up the jump), the peak within 2 %."""
    f = contact_features(T, _pulse(T))
    assert f["contact_start_s"] == pytest.approx(START_S, abs=0.01)
    assert f["contact_end_s"] == pytest.approx(END_S, abs=0.01)
    assert f["contact_duration_s"] == pytest.approx(f["contact_end_s"] - f["contact_start_s"])
    assert f["filtered_peak_force_N"] == pytest.approx(PEAK_N, rel=0.02)


def test_features_survive_the_records_noise():
    """2 % noise (the bundled records') moves the features by a few ms and below 1 %."""
    noisy = _pulse(T) + 0.02 * PEAK_N * np.random.default_rng(1).standard_normal(len(T))
    clean, f = contact_features(T, _pulse(T)), contact_features(T, noisy)
    assert abs(f["contact_start_s"] - clean["contact_start_s"]) < 0.003
    assert abs(f["contact_end_s"] - clean["contact_end_s"]) < 0.003
    assert f["filtered_peak_force_N"] == pytest.approx(clean["filtered_peak_force_N"], rel=0.01)


@pytest.mark.parametrize("reading, words", [(np.zeros_like(T), "no contact"),
                                            (np.where(T > 0.5, 10.0, 0.0), "last sample")])
def test_features_refuse_a_reading_without_the_whole_contact(reading, words):
    with pytest.raises(InputError, match=words):
        contact_features(T, reading)


def test_sigma_points_carry_mean_and_covariance():
    mean, cov = np.array([0.97, 250.0]), np.array([[4e-6, -1e-4], [-1e-4, 0.2]])
    p = sigma_points(mean, cov)
    assert p.shape == (4, 2)
    np.testing.assert_allclose(p.mean(axis=0), mean)
    np.testing.assert_allclose(np.cov(p.T, bias=True), cov, rtol=1e-9, atol=1e-15)


def test_chain_bias_line_and_its_widening_std():
    mid = CHAIN_RUNS["alpha_geometric_mean_per_s"]
    c = CHAIN_ERROR["contact_start_s"]
    bias, std = chain_error("contact_start_s", mid)
    assert bias == pytest.approx(c["at_mean"])
    assert std == pytest.approx(c["residual_std"] * np.sqrt(1.0 + 1.0 / CHAIN_RUNS["runs"]))
    far_bias, far_std = chain_error("contact_start_s", mid * np.e)
    assert far_bias == pytest.approx(c["at_mean"] + c["per_ln_alpha"])
    assert far_std > std
    corrected, stds = fea_equivalent({"contact_start_s": 0.5, "filtered_peak_force_N": 10.0}, mid)
    assert corrected["contact_start_s"] == pytest.approx(0.5 - c["at_mean"])
    peak_bias = CHAIN_ERROR["filtered_peak_force_fraction"]["at_mean"]
    assert corrected["filtered_peak_force_N"] == pytest.approx(10.0 / (1.0 + peak_bias))
    assert stds["filtered_peak_force_N"] == pytest.approx(
        chain_error("filtered_peak_force_fraction", mid)[1] * corrected["filtered_peak_force_N"])


def _calibration(E_factor, alpha, stderr_E, stderr_alpha, baseline_E_factor=None):
    """A stand-in for an impulse Calibration of the bundled 8-in finger (its baseline at
    ``baseline_E_factor``: an effect was added that moved E; default the final fit)."""
    final = SimpleNamespace(effects=(), values={"E_factor": E_factor, "alpha_per_s": alpha},
                            stderr={"E_factor": stderr_E, "alpha_per_s": stderr_alpha},
                            correlation={("alpha_per_s", "E_factor"): -0.2})
    baseline = final if baseline_E_factor is None else SimpleNamespace(
        values={"E_factor": baseline_E_factor, "alpha_per_s": alpha}, stderr=final.stderr, correlation={})
    return SimpleNamespace(experiment=load_experiment(ROOT / "data" / "measured" / "control_low.csv"), final=final,
                           baseline=baseline)


@pytest.fixture(scope="module")
def setup():
    """The bundled 8-in contact set-up (sidecar alone) and its chain's force at E x 0.97,
    alpha 250 1/s."""
    contact, recorded = load_contact_setup(ROOT / "data" / "contact" / "control_180.json")
    assert not recorded
    return contact, DrumContactModel(contact).predict({"E_factor": 0.97, "alpha_per_s": 250.0})


def test_interval_widens_with_the_parameters_covariance(setup):
    contact, chain = setup
    exact = predict_contact(_calibration(0.97, 250.0, 0.0, 0.0), contact, recorded=False)
    loose = predict_contact(_calibration(0.97, 250.0, 0.03, 25.0), contact, recorded=False)
    expected, chain_std = fea_equivalent(contact_features(contact.time_s, chain), 250.0)
    for name, value in expected.items():
        assert exact.features[name].predicted == pytest.approx(value, rel=1e-12)
        assert loose.features[name].predicted == pytest.approx(value, rel=1e-12)
        assert exact.features[name].std_parameters == 0.0
        assert loose.features[name].std_parameters > 0.0
        lo, hi = exact.features[name].interval
        lo2, hi2 = loose.features[name].interval
        assert lo2 < lo < value < hi < hi2
        assert exact.features[name].measured is None and exact.features[name].inside is None
        assert exact.features[name].std_chain == pytest.approx(chain_std[name])
    assert loose.features["filtered_peak_force_N"].std_noise > 0.0      # the sidecar declares the noise
    shifted = predict_contact(_calibration(0.97, 250.0, 0.0, 0.0, baseline_E_factor=1.02), contact, recorded=False)
    assert shifted.summary()["selection_shift_E_factor"] == pytest.approx(-0.05)
    assert shifted.features["filtered_peak_force_N"].predicted == exact.features["filtered_peak_force_N"].predicted
    assert shifted.features["filtered_peak_force_N"].std_parameters > 0.01 * exact.features["filtered_peak_force_N"].predicted
    assert exact.summary()["features"]["contact_start_s"]["predicted_s"] == exact.features["contact_start_s"].predicted


def test_a_contact_sidecar_declaring_another_E_gets_the_same_modulus(setup, tmp_path):
    """The contact sidecar declares twice the impulse record's E: the chain runs at half its
    E factor, the same modulus, and predicts the same features."""
    contact, _ = setup
    sidecar = json.loads((ROOT / "data" / "contact" / "control_180.json").read_text())
    sidecar["finger"]["E_Pa"] *= 2.0
    (tmp_path / "stiff.json").write_text(json.dumps(sidecar))
    stiff, _ = load_contact_setup(tmp_path / "stiff.json")
    calibration = _calibration(0.97, 250.0, 0.0, 0.0)
    a = predict_contact(calibration, contact, recorded=False)
    b = predict_contact(calibration, stiff, recorded=False)
    assert b.values["E_factor"] == pytest.approx(0.5 * a.values["E_factor"])
    for name, f in a.features.items():
        assert b.features[name].predicted == pytest.approx(f.predicted, rel=1e-3), name


def test_a_contact_set_up_of_another_finger_is_refused(setup):
    contact, _ = setup
    impulse = load_experiment(ROOT / "data" / "measured" / "control_low.csv")
    check_same_finger(impulse, contact)
    thinner = replace(contact, finger=replace(contact.finger, semi_axes_m=(0.012, 0.007)))
    with pytest.raises(InputError, match=r"section semi-axes \(0.012, 0.00845\) vs \(0.012, 0.007\)"):
        check_same_finger(impulse, thinner)


def test_chain_error_is_the_validations():
    measured = json.loads((ROOT / "validation" / "predict_contact.json").read_text())["chain_error"]["regression"]
    for name, value in CHAIN_RUNS.items():
        assert value == pytest.approx(measured[name], rel=1e-3), name
    for name, line in CHAIN_ERROR.items():
        for term, value in line.items():
            assert value == pytest.approx(measured[name][term], rel=1e-3, abs=1e-7), (name, term)
