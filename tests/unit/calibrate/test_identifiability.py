"""How identifiable each fitted parameter is: the share of its signature the others cannot
mimic, and every candidate's fit in the report whether it is accepted or not."""
import numpy as np
import pytest
from conftest import ROOT

from ccedi.calibrate.experiment import load_experiment
from ccedi.calibrate.fit import unique_shares
from ccedi.calibrate.loop import calibrate, summary
from ccedi.study.calibration_report import write_report


@pytest.mark.parametrize("theta", [0.0, 0.3, np.pi / 4, np.pi / 2])
def test_unique_share_is_the_part_not_in_the_span_of_the_others(theta):
    """Column b = cos(theta) a + sin(theta) e with e orthogonal to a: the share of b the
    other column cannot mimic is sin^2(theta), and the same for a; a third column orthogonal
    to both keeps its whole signature. Column scales do not matter."""
    t = np.linspace(0.0, 1.0, 400)
    a = np.sin(2 * np.pi * t)
    e = np.cos(2 * np.pi * t)
    e -= (e @ a) / (a @ a) * a
    e *= np.linalg.norm(a) / np.linalg.norm(e)
    b = np.cos(theta) * a + np.sin(theta) * e
    c = np.sin(6 * np.pi * t) - np.sin(6 * np.pi * t) @ np.column_stack([a, e]) @ np.linalg.pinv(
        np.column_stack([a, e]))
    shares = unique_shares(np.column_stack([3.0 * a, 1e-4 * b, c]))
    assert shares[0] == pytest.approx(np.sin(theta) ** 2, abs=1e-9)
    assert shares[1] == pytest.approx(np.sin(theta) ** 2, abs=1e-9)
    assert shares[2] == pytest.approx(1.0, abs=1e-9)


def test_a_single_or_a_zero_column():
    assert unique_shares(np.ones((5, 1))) == [1.0]
    assert unique_shares(np.column_stack([np.zeros(5), np.arange(5.0)])) == [0.0, 1.0]


@pytest.fixture(scope="module")
def control():
    """A Coulomb-friction record with two wrong candidates: both tried, none accepted."""
    cal = calibrate(load_experiment(ROOT / "data" / "measured" / "coulomb_friction_high.csv"),
                    candidates=["tip_mass", "sensor_offset_drift"])
    return cal, summary(cal)


def test_candidates_are_reported_when_none_is_accepted(control, tmp_path):
    """Every candidate tried shows its fitted parameters, scores and identifiability in the
    summary and in report.md, though no effect was added."""
    cal, s = control
    assert s["effects_found"] == []
    tried = s["rounds"][0]["candidates"]
    assert set(tried) == {"tip_mass", "sensor_offset_drift"}
    assert set(tried["sensor_offset_drift"]["params"]) == {"offset_m", "drift_m_s"}
    for c in tried.values():
        assert all(0.0 <= share <= 1.0 for share in c["unique_share"].values())
        assert np.isfinite(c["delta_bic"])
    write_report(tmp_path, cal, s)
    text = (tmp_path / "report.md").read_text()
    assert "Candidates of round 1" in text and "tip_mass_kg = " in text and "share not mimicked" in text


def test_every_candidate_says_why_it_was_not_selected(control):
    """Posterior probabilities of the round's start and candidates sum to 1, and each
    candidate's verdict names the rule it failed with its figure: here both explain almost
    none of the friction record's excess over the noise."""
    r = control[1]["rounds"][0]
    total = r["posterior_of_start"] + sum(c["posterior"] for c in r["candidates"].values())
    assert total == pytest.approx(1.0, abs=1e-12)
    for c in r["candidates"].values():
        assert c["explained"] < 0.5
        assert c["verdict"].startswith(f"explains {c['explained']:.0%} of the excess over the noise")


def test_the_report_leads_with_the_calibrated_finger(tmp_path):
    """report.md opens with the result: the final alpha and E with their standard errors and
    the effect found with its final value, before the evidence and the baseline."""
    cal = calibrate(load_experiment(ROOT / "data" / "measured" / "time_delay_low.csv"),
                    candidates=["time_delay", "sensor_offset_drift"])
    s = summary(cal)
    write_report(tmp_path, cal, s)
    text = (tmp_path / "report.md").read_text()
    result = text[text.index("## Result"):text.index("## Evidence")]
    assert f"alpha = {s['final_params']['alpha_per_s']:.5g} 1/s" in result
    assert f"x {s['final_params']['E_factor']:.4f}" in result
    assert f"time_delay: delay_s = {s['effects_found'][0]['params_final']['delay_s']:.5g}" in result
    assert text.index("## Result") < text.index("Baseline parameters")


def test_a_small_tip_mass_is_mimicked_by_e(control):
    """A small tip mass lowers the frequency as a lower E does: almost all its signature is
    E's, and the report names E_factor as what mimics it."""
    tip = control[1]["rounds"][0]["candidates"]["tip_mass"]
    assert tip["unique_share"]["tip_mass_kg"] < 0.1
    assert tip["mimicked_by"]["tip_mass_kg"][0][0] == "E_factor"
