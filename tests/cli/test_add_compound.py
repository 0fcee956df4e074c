"""``ccedi calibrate IMPULSE.csv --add-compound NAME [--compounds PATH]``: measure, calibrate,
catalogue. On bundled impulse records of the 8-in finger (about 3 s each), the row holds
the calibrated alpha and E, the record's finger length and tan delta converted at the
finger's first mode, and it lands in ./compounds.csv unless a catalogue is named; a
contact record, an empty name and a bad catalogue are refused in one line before anything
is computed or written."""
import json
import math

import pytest
from conftest import ROOT

from ccedi.design.compounds import CATALOGUE, load_compounds, loss_factor_from_alpha
from ccedi.design.robust import CalibratedSpread
from ccedi.fea.material import NeoHookean
from ccedi.rom.finger_identification import finger_omega1
from ccedi.study.cli import main
from ccedi.units import m_to_inch

MEASURED = ROOT / "data" / "measured"
CONTACT = ROOT / "data" / "contact" / "control_80.csv"


def _run(capsys, *args):
    code = main(["calibrate", *map(str, args)])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_a_calibrated_record_becomes_a_catalogue_row(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    bundled = CATALOGUE.read_text()
    record = MEASURED / "control_low.csv"
    code, out, _ = _run(capsys, record, "--json", "low.json", "--add-compound", "sample_rubber")
    assert code == 0 and "added compound sample_rubber in compounds.csv" in out
    result = json.loads((tmp_path / "low.json").read_text())
    row = load_compounds(tmp_path / "compounds.csv")["sample_rubber"]
    meta = json.loads(record.with_suffix(".json").read_text())["finger"]
    alpha, E = result["final_params"]["alpha_per_s"], result["calibrated"]["E_Pa"]
    assert row.alpha_per_s == alpha and row.alpha_source == str(record)
    assert row.alpha_finger_length_in == pytest.approx(meta["length_in"])
    assert row.E_min_Pa < E < row.E_max_Pa and row.rho_kg_m3 == meta["rho_kg_m3"]
    truth = json.loads((MEASURED / "manifest.json").read_text())["records"]["control_low"]
    assert alpha == pytest.approx(truth["alpha_per_s"], rel=0.05)
    omega_1 = finger_omega1(meta["length_in"], material=NeoHookean(E=E, nu=meta["nu"], rho=meta["rho_kg_m3"]),
                            semi_axes_m=tuple(meta["section_semi_axes_m"]))
    assert row.tan_delta_min < loss_factor_from_alpha(alpha, omega_1) < row.tan_delta_max
    assert row.band_min_hz == pytest.approx(omega_1 / (2.0 * math.pi))
    assert result["compound"]["name"] == "sample_rubber" and result["compound"]["catalogue"] == "compounds.csv"
    spread = CalibratedSpread.from_calibration(tmp_path / "low.json")   # the calibration's spread for design
    assert spread.alpha_relative_std == pytest.approx(result["final_stderr"]["alpha_per_s"] / alpha)
    assert spread.E_relative_std == pytest.approx(result["final_stderr"]["E_factor"] / result["final_params"]["E_factor"])
    assert spread.correlation == result["final_correlation"]["alpha_per_s,E_factor"] and -1 < spread.correlation < 1

    # a second record under the same name replaces the row, in the catalogue named
    code, out, _ = _run(capsys, MEASURED / "control_high.csv", "--json", "high.json", "--add-compound",
                        "sample_rubber", "--compounds", tmp_path / "compounds.csv")
    assert code == 0 and "replaced compound sample_rubber" in out
    rows = load_compounds(tmp_path / "compounds.csv")
    assert list(rows) == ["sample_rubber"] and rows["sample_rubber"].alpha_source.endswith("control_high.csv")
    assert CATALOGUE.read_text() == bundled                  # never the bundled file unless named


@pytest.mark.parametrize("case", ["contact record", "empty name", "bad catalogue", "catalogue alone",
                                  "catalogue a directory"])
def test_refused_in_one_line_before_anything_is_written(case, tmp_path, capsys):
    record, name, catalogue = MEASURED / "control_low.csv", "x", tmp_path / "compounds.csv"
    if case == "catalogue alone":
        name, words = None, "give --add-compound NAME too"
    elif case == "catalogue a directory":
        catalogue, words = tmp_path, "--compounds"
    elif case == "contact record":
        record, words = CONTACT, "is a contact record; a compound's alpha is identified from an impulse record"
    elif case == "empty name":
        name, words = " ", "compound name is empty"
    else:
        catalogue.write_text(CATALOGUE.read_text().replace("neoprene,1.69e6", "neoprene,soft", 1))
        words = f"{catalogue}: line 3 (neoprene): E_min_Pa = 'soft': expected a number"
    before = catalogue.read_text() if catalogue.is_file() else None
    add = [] if name is None else ["--add-compound", name]
    code, out, err = _run(capsys, record, "--json", tmp_path / "out.json", *add, "--compounds", catalogue)
    lines = err.strip().splitlines()
    assert code == 1 and len(lines) == 1 and words in lines[0] and "Traceback" not in err, err
    assert not (tmp_path / "out.json").exists() and "calibrate:" not in out
    assert (catalogue.read_text() if catalogue.is_file() else None) == before


def test_the_finger_length_is_stored_in_inches(tmp_path, capsys):
    """A sidecar that declares length_m: the row still gives the finger in inches."""
    meta = json.loads((MEASURED / "control_low.json").read_text())
    length_m = 0.2032
    meta["finger"] = {k: v for k, v in meta["finger"].items() if k != "length_in"} | {"length_m": length_m}
    csv = tmp_path / "rec.csv"
    csv.write_text((MEASURED / "control_low.csv").read_text())
    csv.with_suffix(".json").write_text(json.dumps(meta))
    code, _, _ = _run(capsys, csv, "--json", tmp_path / "o.json", "--add-compound", "m", "--compounds",
                      tmp_path / "c.csv")
    assert code == 0
    assert load_compounds(tmp_path / "c.csv")["m"].alpha_finger_length_in == pytest.approx(m_to_inch(length_m))
