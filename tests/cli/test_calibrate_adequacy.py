"""``ccedi calibrate`` refuses a declared finger that cannot explain the record: a wrong
length, an E off by a factor of 1.5 or more, a record too short to show the declared first
mode, a load that presses E onto its bound, or, on a record too damped to show a frequency, E pressed
onto its bound. Each
case ends with one line on stderr naming the failed check and the record's own first-mode
frequency, exit status 3, a complete JSON with ``model_adequate: false`` and the evidence,
and no effect added. The records are fresh synthetic ones (:mod:`ccedi.calibrate.synthetic`,
the linear FE solid integrated by Newmark) with a known truth."""
import json
import shutil

import numpy as np
import pytest
from conftest import ROOT

from ccedi.calibrate.adequacy import EFFECT_ALLOWANCE, FREQUENCY_MARGIN, assess, record_first_mode
from ccedi.calibrate.experiment import load_experiment
from ccedi.calibrate.fit import fit_baseline
from ccedi.calibrate.model import FingerModel
from ccedi.calibrate.residual import noise_std
from ccedi.calibrate.synthetic import Truth, record, solid_system
from ccedi.study.cli import main
from ccedi.units import inch_to_m

DATA = ROOT / "data" / "measured"
ALPHA = 4.2
"""True mass-proportional damping of the synthetic records [1/s] (zeta_1 = 0.075)."""


@pytest.fixture(scope="module")
def f1_hz():
    """The generator's (FE solid's) first frequency of the declared 8-in finger at its declared E [Hz]."""
    return float(solid_system(inch_to_m(8.0), 1.0).omega_rad_s[0]) / (2.0 * np.pi)


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory, f1_hz):
    """A clean record of the declared 8-in finger (true E = declared, alpha 4.2 1/s) and
    a critically damped one: {name: (frame, sidecar)}."""
    clean = record(Truth(E_factor=1.0, alpha_per_s=ALPHA, force_N=1.5), seed=7)
    critical = record(Truth(E_factor=1.0, alpha_per_s=2.0 * 2.0 * np.pi * f1_hz, force_N=1.5), seed=8)
    return {"clean": clean, "critical": critical}


def _write(tmp_path, frame, meta, name="rec"):
    csv = tmp_path / f"{name}.csv"
    frame.to_csv(csv, index=False)
    csv.with_suffix(".json").write_text(json.dumps(meta))
    return csv


def _declared(meta, **finger):
    return json.loads(json.dumps(meta)) | {"finger": meta["finger"] | finger}


WRONG = {
    "length 4.5 in for the 8-in finger": (lambda f, m: (f, _declared(m, length_in=4.5)), ["frequency"]),
    "E x 2": (lambda f, m: (f, _declared(m, E_Pa=2.0 * m["finger"]["E_Pa"])), ["frequency"]),
    "E x 1.5": (lambda f, m: (f, _declared(m, E_Pa=1.5 * m["finger"]["E_Pa"])), ["frequency"]),
    "E x 0.5": (lambda f, m: (f, _declared(m, E_Pa=0.5 * m["finger"]["E_Pa"])), ["frequency"]),
    "E x 10": (lambda f, m: (f, _declared(m, E_Pa=10.0 * m["finger"]["E_Pa"])), ["frequency"]),
    "shorter than one period": (lambda f, m: (f[f.time_s <= 0.2], m), ["record_length", "frequency"]),
    "1.6 periods": (lambda f, m: (f[f.time_s <= 0.4], m), ["record_length"]),
    "load 3 x the real one": (lambda f, m: (f.drop(columns=["force_N"]), m | {"load": m["load"] | {"force_N": 4.5}}),
                              ["E_bound"]),
}


@pytest.mark.parametrize("case", WRONG)
def test_a_wrong_declaration_ends_with_exit_3_and_no_effect(synthetic, f1_hz, case, tmp_path, capsys):
    edit, checks = WRONG[case]
    csv = _write(tmp_path, *edit(*synthetic["clean"]))
    out = tmp_path / "out.json"
    assert main(["calibrate", str(csv), "--json", str(out)]) == 3
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert "model inadequate" in err and f"({', '.join(checks)})" in err, err
    assert "record's own first-mode frequency" in err and "Traceback" not in err
    result = json.loads(out.read_text())               # written in full, then exit 3
    a = result["adequacy"]
    assert result["model_adequate"] is False and a["model_adequate"] is False
    assert a["failed_checks"] == checks
    assert result["effects_found"] == [] and result["selected_effect"] is None
    assert result["final_params"] == result["baseline"]["params"]
    assert result["final_suggestions"] == []
    if a["record_first_frequency_hz"] is not None:     # the record's own frequency, whatever was declared
        assert a["record_first_frequency_hz"] == pytest.approx(f1_hz, rel=0.01)
        assert f"{a['record_first_frequency_hz']:.4g} Hz" in err
    else:
        assert "not measurable" in err
    for key in ("declared_first_frequency_hz", "allowed_band_hz", "E_factor", "E_factor_bounds", "periods_covered"):
        assert a[key] is not None, key
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.json", "rec.csv", "rec.json"]


def test_the_report_is_written_in_full_for_an_inadequate_model(synthetic, tmp_path, capsys):
    frame, meta = synthetic["clean"]
    csv = _write(tmp_path, frame, _declared(meta, E_Pa=2.0 * meta["finger"]["E_Pa"]))
    rep = tmp_path / "rep"
    assert main(["calibrate", str(csv), "--json", str(tmp_path / "out.json"), "--report", str(rep)]) == 3
    assert sorted(p.name for p in rep.iterdir()) == ["fit.png", "report.md", "residual.png", "residuals.csv"]
    md = (rep / "report.md").read_text()
    assert "declared model inadequate (frequency)" in md and "not measurable" not in md


def test_a_record_too_damped_to_ring_skips_the_frequency_check(synthetic, tmp_path, capsys):
    """Critically damped, declared right: adequate, and the JSON says the frequency was not checked."""
    csv = _write(tmp_path, *synthetic["critical"])
    out = tmp_path / "out.json"
    assert main(["calibrate", str(csv), "--json", str(out)]) == 0
    a = json.loads(out.read_text())["adequacy"]
    assert a["record_first_mode"]["measurable"] is False and a["record_first_frequency_hz"] is None
    assert a["failed_checks"] == [] and len(a["skipped_checks"]) == 1
    assert a["skipped_checks"][0].startswith("frequency") and "too damped" in a["skipped_checks"][0]


@pytest.mark.parametrize("finger", [{"length_in": 4.5}, {"E_factor": 2.0}])
def test_a_wrong_declaration_of_a_record_too_damped_to_ring_is_refused(synthetic, finger, tmp_path, capsys):
    frame, meta = synthetic["critical"]
    change = ({"E_Pa": finger["E_factor"] * meta["finger"]["E_Pa"]} if "E_factor" in finger else finger)
    csv = _write(tmp_path, frame, _declared(meta, **change))
    out = tmp_path / "out.json"
    assert main(["calibrate", str(csv), "--json", str(out)]) == 3
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "model inadequate (E_bound)" in err and "not measurable" in err, err
    result = json.loads(out.read_text())
    assert result["model_adequate"] is False and result["effects_found"] == []


def test_the_right_declaration_is_adequate(synthetic, f1_hz, tmp_path, capsys):
    csv = _write(tmp_path, *synthetic["clean"])
    out = tmp_path / "out.json"
    assert main(["calibrate", str(csv), "--json", str(out)]) == 0
    a = json.loads(out.read_text())["adequacy"]
    assert a["model_adequate"] is True and a["failed_checks"] == []
    assert a["record_first_frequency_hz"] == pytest.approx(f1_hz, rel=0.002)
    assert a["periods_covered"] >= 2.0


def test_the_record_first_mode_is_measured_without_the_model(synthetic, f1_hz, tmp_path):
    exp = load_experiment(_write(tmp_path, *synthetic["clean"]))
    mode = record_first_mode(exp, noise_std(exp))
    assert mode.measurable
    assert mode.frequency_hz == pytest.approx(f1_hz, rel=0.002)
    assert mode.damping_ratio == pytest.approx(ALPHA / (2.0 * 2.0 * np.pi * f1_hz), rel=0.05)


@pytest.mark.parametrize("name, low, high", [
    ("control_fea_solid", 0.99, 1.01),                  # the explicit 3-D FEA rings at the FE modes' frequency
    ("tip_mass+quadratic_damping_high", 0.79, 0.82),    # the bundled record nearest the band's lower edge
    ("root_compliance_high", 0.85, 0.88),
    ("viscoelastic_low", 0.91, 0.94),
])
def test_bundled_records_are_adequate_inside_the_band(name, low, high):
    exp = load_experiment(DATA / f"{name}.csv")
    model = FingerModel(exp)
    a = assess(model, fit_baseline(model), noise_std(exp))
    assert a.adequate, a.message()
    assert low <= a.record_hz / a.declared_hz <= high
    reach = np.sqrt(1.0 - exp.E_tolerance) * (1.0 - FREQUENCY_MARGIN) * (1.0 - EFFECT_ALLOWANCE)
    assert a.band_hz[0] / a.declared_hz == pytest.approx(reach)


def test_the_study_records_an_inadequate_model_and_carries_on(synthetic, tmp_path, capsys):
    from ccedi.study.report import _calibrate
    from ccedi.study.run import calibrate_records

    frame, meta = synthetic["clean"]
    wrong = _write(tmp_path, frame, _declared(meta, length_in=4.5), "wrong")
    right = _write(tmp_path, frame, meta, "right")
    out = tmp_path / "study" / "calibrate"
    messages = calibrate_records([wrong, right], out)
    assert len(messages) == 1 and "wrong.csv" in messages[0] and "(frequency)" in messages[0]
    assert "model inadequate" in capsys.readouterr().out
    assert json.loads((out / "wrong.json").read_text())["model_adequate"] is False
    assert json.loads((out / "right.json").read_text())["model_adequate"] is True
    page = _calibrate(tmp_path / "study")
    assert "NO: frequency" in page and "cannot explain 1 record" in page


def test_a_pulse_after_the_record_is_an_input_error(tmp_path, capsys):
    csv = tmp_path / "rec.csv"
    shutil.copy(DATA / "control_low.csv", csv)
    meta = json.loads((DATA / "control_low.json").read_text())
    meta["load"]["start_s"] = 5.0
    csv.with_suffix(".json").write_text(json.dumps(meta))
    assert main(["calibrate", str(csv), "--json", str(tmp_path / "out.json")]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "the pulse" in err and "ends at 5.01 s" in err
    assert not (tmp_path / "out.json").exists()
