"""``ccedi identify``: the 3-in finger (alpha_cr, and over-damped matching of a noisy
response at alpha = 600 1/s) and measured-file errors."""
import json

import numpy as np
import pandas as pd
import pytest

from ccedi.fea.cases.studies import finger_impulse_model
from ccedi.rom.ccedi import paper_alpha_cr
from ccedi.rom.measurement import load_response
from ccedi.study.cli import main


@pytest.mark.slow
def test_alpha_cr_of_3_in_finger(tmp_path, capsys):
    path = tmp_path / "acr.json"
    assert main(["identify", "--length-in", "3", "--alpha-cr", "--rtol", "0.02", "--json", str(path)]) == 0
    out = json.loads(path.read_text())
    assert out["alpha_cr_per_s"] == pytest.approx(float(paper_alpha_cr(3.0)), rel=0.15)
    assert out["alpha_cr_per_s"] == pytest.approx(out["two_omega1_per_s"], rel=0.05)
    assert out["n_fe_runs"] == len(out["runs"])
    assert out["warnings"] == []                                   # 1 N: a healthy small deflection
    run_lines = [line for line in capsys.readouterr().out.splitlines() if line.startswith("identify: run ")]
    assert [float(line.split("alpha = ")[1].split()[0]) for line in run_lines] == \
        pytest.approx([run["alpha_per_s"] for run in out["runs"]], rel=1e-3)   # one line per FE run, as it runs


@pytest.mark.slow
def test_alpha_cr_json_records_the_runs_validity_warnings(tmp_path, capsys):
    path = tmp_path / "acr.json"
    assert main(["identify", "--length-in", "3", "--alpha-cr", "--force-N", "30", "--rtol", "0.2",
                 "--json", str(path)]) == 0
    warned = json.loads(path.read_text())["warnings"]
    assert warned and all("tip deflection" in w for w in warned)
    err = capsys.readouterr().err
    assert all(w in err for w in warned) and err.count("ccedi identify: warning: ") == len(warned)


@pytest.mark.slow
def test_identify_overdamped_3_in_from_csv(tmp_path):
    t, y = finger_impulse_model(3.0).run(600.0, 0.08, 320).tip_signal()
    y = y + 0.02 * np.abs(y).max() * np.random.default_rng(7).standard_normal(len(t))
    force = np.where(t <= 0.01, 1.0, 0.0)
    csv = tmp_path / "measured.csv"
    pd.DataFrame({"time_s": t, "tip_displacement_m": y, "force_N": force}).to_csv(csv, index=False)
    path = tmp_path / "id.json"
    assert main(["identify", str(csv), "--length-in", "3", "--rtol", "0.05", "--json", str(path)]) == 0
    out = json.loads(path.read_text())
    assert out["regime"] == "over-damped"
    assert out["alpha_per_s"] == pytest.approx(600.0, rel=0.05)
    assert out["impulse_force_N"] == pytest.approx(1.0)


@pytest.mark.parametrize("text, match", [
    ("time_s,tip_displacement_m\n0,0\n1,1\n", "at least 8"),
    ("time_s,displacement\n" + "".join(f"{i},{i}\n" for i in range(10)), "missing column"),
    ("time_s,tip_displacement_m\n" + "".join(f"{i % 5},{i}\n" for i in range(10)), "strictly increasing"),
    ("time_s,tip_displacement_m\n" + "".join(f"{i},{'nan' if i == 4 else i}\n" for i in range(10)), "row 5"),
])
def test_bad_measured_files_are_named(tmp_path, text, match, capsys):
    csv = tmp_path / "bad.csv"
    csv.write_text(text)
    with pytest.raises(Exception, match=match):
        load_response(csv)
    assert main(["identify", str(csv), "--length-in", "3"]) == 1
    assert "Traceback" not in capsys.readouterr().err


def test_identify_needs_a_length(capsys):
    assert main(["identify", "--alpha-cr"]) == 1
    assert "--length-in" in capsys.readouterr().err
