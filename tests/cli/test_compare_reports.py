"""validation/compare_reports.py: two study folders compared value by value, wall times
left out; a moved figure is named with both values."""
import json
import subprocess
import sys

import pandas as pd
from conftest import ROOT

SCRIPT = ROOT / "validation" / "compare_reports.py"


def _study(folder, peak, wall):
    (folder / "impulse").mkdir(parents=True)
    (folder / "table1.json").write_text(json.dumps({"SM-A": {"dt_us": 4.411, "wall_time_s": wall,
                                                             "element_type": "hex8"}}))
    pd.DataFrame({"alpha_per_s": [7.5, 180.0], "peak_reaction_force_N": [peak, 3.0],
                  "wall_time_s": [wall, wall]}).to_csv(folder / "impulse" / "summary.csv", index=False)


def _compare(tmp_path, *args):
    out = tmp_path / "cmp.json"
    done = subprocess.run([sys.executable, str(SCRIPT), str(tmp_path / "a"), str(tmp_path / "b"), "--json", str(out),
                           *args], capture_output=True, text=True)
    return done.returncode, done.stdout, json.loads(out.read_text())


def test_same_figures_with_other_wall_times_compare_equal(tmp_path):
    _study(tmp_path / "a", 12.5, 10.0)
    _study(tmp_path / "b", 12.5 * (1 + 1e-12), 99.0)
    rc, stdout, result = _compare(tmp_path)
    assert rc == 0, stdout
    assert result["files"]["table1.json"]["compared"] == 2                  # dt_us and element_type
    assert result["files"]["impulse/summary.csv"]["compared"] == 4          # the wall times left out


def test_a_moved_figure_is_named_with_both_values(tmp_path):
    _study(tmp_path / "a", 12.5, 10.0)
    _study(tmp_path / "b", 12.6, 10.0)
    (tmp_path / "b" / "extra.json").write_text("{}")
    rc, stdout, result = _compare(tmp_path)
    assert rc == 1 and "peak_reaction_force_N[0]: 12.5 -> 12.6" in stdout
    assert result["files"]["impulse/summary.csv"]["beyond_rtol"] == {"peak_reaction_force_N[0]": [12.5, 12.6]}
    assert result["only_after"] == ["extra.json"]
    assert _compare(tmp_path, "--rtol", "0.01")[0] == 0
