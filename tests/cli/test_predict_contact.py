"""``ccedi calibrate IMPULSE.csv --predict-contact CONTACT``: bad input refused in one line
naming what was typed (nothing written), and the ``prediction`` block of the JSON and the
report's table on a bundled impulse record with a bundled contact sidecar (the 8-in finger
of both)."""
import json
import shutil

import pytest
from conftest import ROOT

from ccedi.calibrate.prediction import FEATURES
from ccedi.study.cli import main

IMPULSE = ROOT / "data" / "measured" / "control_low.csv"
CONTACT = ROOT / "data" / "contact" / "control_180.csv"


def _run(capsys, *args):
    code = main(["calibrate", *map(str, args)])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize("case", ["suffix", "missing", "impulse as contact", "contact calibrated", "other finger",
                                  "no sidecar"])
def test_bad_prediction_input_is_one_line(case, tmp_path, capsys):
    impulse, contact, words = IMPULSE, CONTACT.with_suffix(".json"), None
    if case == "suffix":
        contact, words = CONTACT.with_suffix(".txt"), "give a contact record CSV"
    elif case == "missing":
        contact, words = tmp_path / "nothing.json", "not found"
    elif case == "impulse as contact":
        contact, words = ROOT / "data" / "measured" / "control_high.csv", "sidecar kind is 'impulse'"
    elif case == "contact calibrated":
        impulse, contact, words = CONTACT, CONTACT, "is a contact record"
    elif case == "other finger":
        impulse, words = ROOT / "data" / "measured" / "control_fea_solid.csv", "length 0.1143 vs 0.2032"
    else:
        contact, words = tmp_path / "control_180.csv", "no sidecar"
        shutil.copy(CONTACT, contact)
    code, out, err = _run(capsys, impulse, "--json", tmp_path / "out.json", "--predict-contact", contact)
    assert code == 1
    lines = err.strip().splitlines()
    assert len(lines) == 1 and words in lines[0] and "Traceback" not in err
    assert not (tmp_path / "out.json").exists()


@pytest.mark.parametrize("record, effects", [("control_low", []), ("time_delay_high", ["time_delay"])])
def test_prediction_block_and_report(record, effects, tmp_path, capsys):
    """The bundled impulse records' finger is lightly damped (alpha ~3 1/s): its contact
    set-up is predicted with intervals and no measured feature; an effect the impulse
    calibration selected is named as not carried, and its shift of E and alpha is given."""
    code, out, _ = _run(capsys, IMPULSE.with_name(f"{record}.csv"), "--json", tmp_path / "out.json", "--report",
                        tmp_path / "report", "--predict-contact", CONTACT.with_suffix(".json"))
    assert code == 0
    p = json.loads((tmp_path / "out.json").read_text())["prediction"]
    assert p["recorded"] is False and p["all_inside"] is None
    assert p["alpha_per_s"] == pytest.approx(json.loads((tmp_path / "out.json").read_text())["final_params"]
                                             ["alpha_per_s"])
    for name, unit in FEATURES.items():
        f = p["features"][name]
        lo, hi = f[f"interval_{unit}"]
        assert lo < f[f"predicted_{unit}"] < hi and f[f"measured_{unit}"] is None and f["inside"] is None
        assert f"predicted {f[f'predicted_{unit}']:.4g} {unit}" in out
    report = (tmp_path / "report" / "report.md").read_text()
    assert "## Prediction of the contact record" in report
    assert p["impulse_effects_not_carried"] == effects
    assert ("is not in the contact chain" in out) == bool(effects)
    assert ("are not in the contact chain" in report) == bool(effects)
    assert (p["selection_shift_E_factor"] != 0.0) == bool(effects)
    assert (tmp_path / "report" / "prediction.png").is_file()


def test_a_measured_contact_record_outside_the_prediction_is_said_so(tmp_path, capsys):
    """The bundled impulse record (alpha ~3 1/s) against the bundled contact record of alpha
    180 1/s: the measured contact start lies outside its interval, and the output, the JSON
    and the report say so."""
    code, out, _ = _run(capsys, IMPULSE, "--json", tmp_path / "out.json", "--report", tmp_path / "report",
                        "--predict-contact", CONTACT)
    assert code == 0
    p = json.loads((tmp_path / "out.json").read_text())["prediction"]
    start = p["features"]["contact_start_s"]
    assert p["recorded"] is True and p["all_inside"] is False
    assert start["inside"] is False and start["error_s"] > 0.05         # the lightly damped finger touches early
    assert start["error_s"] == pytest.approx(start["measured_s"] - start["predicted_s"])
    assert f"measured {start['measured_s']:.4g} s: OUTSIDE" in out
    assert "| contact start [s] |" in (tmp_path / "report" / "report.md").read_text()
    assert "**no**" in (tmp_path / "report" / "report.md").read_text()
