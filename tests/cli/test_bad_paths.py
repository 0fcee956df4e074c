"""Bad paths and bad values are refused before anything is computed: one line on stderr,
exit status 1, no file written, and the computation never started."""
from pathlib import Path

import pytest
from conftest import ROOT

from ccedi.study import cli
from ccedi.study.commands import calibrate, design, fea


def _fails_in_one_line(argv, capsys, *needles):
    assert cli.main(argv) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    for needle in needles:
        assert needle in err, err
    return err


@pytest.fixture
def nothing_runs(monkeypatch):
    """Make every computing entry point fail loudly: a test passes only if none is reached."""
    def forbidden(*a, **k):
        raise AssertionError("the computation started")
    for module, name in ((fea, "write_table1"), (fea, "write_impulse"), (fea, "write_contact_sweep"),
                         (calibrate, "write_calibration"), (design, "write_design")):
        monkeypatch.setattr(module, name, forbidden)
    import ccedi.design.surrogate as surrogate
    monkeypatch.setattr(surrogate, "cached_rom_runs", forbidden)


def test_json_that_is_a_directory(tmp_path, capsys, nothing_runs):
    _fails_in_one_line(["table1", "--json", str(tmp_path)], capsys, "--json", "is a directory")


def test_output_under_a_file(tmp_path, capsys, nothing_runs):
    blocker = tmp_path / "file.txt"
    blocker.write_text("x")
    _fails_in_one_line(["impulse", "--out", str(blocker / "sub")], capsys, "--out", "is a file, not a directory")
    _fails_in_one_line(["table1", "--json", str(blocker / "t.json")], capsys, "--json", "not a directory")


def test_report_that_is_a_file(tmp_path, capsys, nothing_runs):
    report = tmp_path / "report"
    report.write_text("x")
    _fails_in_one_line(["calibrate", "data/measured/control_low.csv", "--json", str(tmp_path / "c.json"),
                        "--report", str(report)], capsys, "--report")
    assert not (tmp_path / "c.json").exists()


def test_init_and_export_into_a_directory(tmp_path, capsys):
    _fails_in_one_line(["init", str(tmp_path)], capsys, "is a directory")
    _fails_in_one_line(["export", "--format", "lsdyna", "--out", str(tmp_path)], capsys, "is a directory")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("value", ["-1", "nan", "inf", "0"])
def test_export_refuses_a_bad_end_time(tmp_path, capsys, value):
    _fails_in_one_line(["export", "--t-end-s", value, "--out", str(tmp_path / "deck.k")], capsys, "--t-end-s")
    assert not (tmp_path / "deck.k").exists()


def test_every_alpha_is_checked_before_the_first_run(tmp_path, capsys, nothing_runs):
    _fails_in_one_line(["impulse", "--alpha", "180", "-50", "--out", str(tmp_path)], capsys, "--alpha", "-50")
    _fails_in_one_line(["contact-sweep", "--alphas", "7.5", "nan", "--out", str(tmp_path)], capsys, "--alphas")


def test_zero_weights_are_refused_before_the_rom_grid(tmp_path, capsys, monkeypatch):
    import ccedi.design.surrogate as surrogate

    def forbidden(*a, **k):
        raise AssertionError("the ROM grid started")
    monkeypatch.setattr(surrogate, "cached_rom_runs", forbidden)
    _fails_in_one_line(["design", "--weights", "0,0,0", "--json", str(tmp_path / "d.json"), "--out",
                        str(tmp_path), "--no-fea-check"], capsys, "weights")


def test_command_line_ranges_are_the_inputs_schema(capsys, nothing_runs):
    from ccedi.study.config import SCHEMA

    spec = SCHEMA["finger"]["impulse_length_in"]
    err = _fails_in_one_line(["table1", "--length-in", "20"], capsys, "--length-in")
    assert f"must be in {spec.lo:g}..{spec.hi:g} (in)" in err
    _fails_in_one_line(["impulse", "--force-N", "1e4"], capsys, "--force-N")
    _fails_in_one_line(["identify", "--alpha-cr", "--length-in", "4.5", "--noise-band", "-1"], capsys,
                       "--noise-band")


def test_config_that_is_a_directory_or_binary(tmp_path, capsys, nothing_runs):
    _fails_in_one_line(["table1", "--config", str(tmp_path)], capsys, "is a directory")
    binary = tmp_path / "b.toml"
    binary.write_bytes(bytes(range(256)))
    _fails_in_one_line(["table1", "--config", str(binary)], capsys, "not a text file")


def test_an_os_error_is_one_line(capsys, monkeypatch):
    def denied(*a, **k):
        raise PermissionError(13, "Permission denied", "/somewhere/table1.json")
    monkeypatch.setattr(fea, "write_table1", denied)
    _fails_in_one_line(["table1"], capsys, "/somewhere/table1.json", "Permission denied")


def test_study_outside_the_project_finds_its_records_and_a_missing_one_stops_it(tmp_path, capsys, monkeypatch):
    """The default records resolve against ccedi's own folder, whatever the working
    directory; a record named in a TOML resolves against the TOML's folder, and a missing
    one stops the study before its first step."""
    from ccedi.study.config import load

    monkeypatch.chdir(tmp_path)
    assert all(Path(r).is_file() for r in load(None)["study"]["measured_records"])
    toml = tmp_path / "s.toml"
    toml.write_text('[study]\nmeasured_records = ["gone.csv"]\n')
    _fails_in_one_line(["study", "--config", str(toml), "--out", str(tmp_path / "out"), "--scheduler", "serial"],
                       capsys, "measured_records", "no such file", str(tmp_path / "gone.csv"))
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("key, bad", [("nu", 0.6), ("nu", -0.5), ("E_Pa", 1.0), ("rho_kg_m3", 1e9),
                                      ("length_in", 20.0), ("length_m", 0.01)])
def test_the_sidecar_and_the_toml_share_one_range(key, bad):
    from ccedi.calibrate.experiment import parse_finger
    from ccedi.errors import InputError
    from ccedi.study.config import validate

    section, toml_key = ("finger", "impulse_length_in") if key.startswith("length") else ("material", key)
    with pytest.raises(InputError) as toml:
        validate({section: {toml_key: bad * (1 / 0.0254 if key == "length_m" else 1)}})
    finger = {"length_in": 4.5, "section_semi_axes_m": [0.012, 0.00845], "E_Pa": 6.1e6, "nu": 0.49,
              "rho_kg_m3": 1000.0}
    if key == "length_m":
        del finger["length_in"]
    finger[key] = bad
    with pytest.raises(InputError) as sidecar:
        parse_finger(finger, "record.json")
    rule = str(sidecar.value).split(": must be in ", 1)[1]
    if key == "length_m":
        assert rule == "0.0254..0.3048 (m)"        # the TOML's 1..12 in, in metres
    else:
        assert rule == str(toml.value).split(": must be in ", 1)[1]


def test_identify_refuses_a_record_in_milliseconds_before_any_fe_run(tmp_path, capsys, monkeypatch):
    import numpy as np

    import ccedi.rom.ccedi as ccedi_search

    def forbidden(*a, **k):
        raise AssertionError("an FE run started")
    monkeypatch.setattr(ccedi_search, "critical_alpha", forbidden)
    t_ms = np.arange(0.0, 200.0, 1.0)                      # 0.2 s sampled at 1 kHz, written in ms
    csv = tmp_path / "ms.csv"
    csv.write_text("time_s,tip_displacement_m\n" + "".join(f"{t},{1e-3 * np.exp(-t / 50.0)}\n" for t in t_ms))
    _fails_in_one_line(["identify", str(csv), "--length-in", "3"], capsys, "time_s steps up to 1 s",
                       "not seconds")


SIDECAR_FIELDS = [("load", "force_N", "force_N", 500.0), ("load", "duration_s", "pulse_duration_s", 0.0),
                  ("load", "start_s", "pulse_start_s", -0.1), (None, "alpha_per_s", "alpha_per_s", -3.0),
                  ("sensor", "noise_std_m", "noise_std_m", 0.5), ("tolerances", "E_Pa", "E_tolerance", 1.5),
                  ("load", "force_N", "force_N", "1.5"), ("sensor", "noise_std_m", "noise_std_m", float("nan"))]


@pytest.mark.parametrize("section, key, quantity, bad", SIDECAR_FIELDS)
def test_sidecar_load_sensor_and_tolerances_are_on_the_one_table(tmp_path, capsys, section, key, quantity, bad):
    import json
    import shutil

    from ccedi.calibrate.experiment import load_experiment
    from ccedi.errors import InputError
    from ccedi.quantities import QUANTITIES

    csv = tmp_path / "rec.csv"
    shutil.copy("data/measured/control_low.csv", csv)
    meta = json.loads(open("data/measured/control_low.json").read())
    (meta.setdefault(section, {}) if section else meta)[key] = bad
    csv.with_suffix(".json").write_text(json.dumps(meta))
    q = QUANTITIES[quantity]
    name = f"{section}.{key}" if section else key
    rule = f"must be in {q.lo:g}..{q.hi:g}" + (f" ({q.unit})" if q.unit != "-" else "")
    with pytest.raises(InputError) as err:
        load_experiment(csv)
    assert str(err.value) == f"{csv.with_suffix('.json')}: sidecar field '{name}' = {bad!r}: {rule}"
    assert cli.main(["calibrate", str(csv), "--json", str(tmp_path / "c.json")]) == 1
    assert capsys.readouterr().err.strip() == f"ccedi calibrate: error: {err.value}"
    assert not (tmp_path / "c.json").exists()


@pytest.mark.parametrize("section, key", [("tolerances", "E"), ("sensor", "noise_std"), (None, "alpha"),
                                          ("finger", "length_mm"), ("load", "force")])
def test_a_misspelt_sidecar_field_is_refused_not_ignored(tmp_path, capsys, section, key):
    """A misspelt optional field would otherwise leave its default in force, silently."""
    import json
    import shutil

    csv = tmp_path / "rec.csv"
    shutil.copy("data/measured/control_low.csv", csv)
    meta = json.loads(open("data/measured/control_low.json").read())
    (meta.setdefault(section, {}) if section else meta)[key] = 0.5
    csv.with_suffix(".json").write_text(json.dumps(meta))
    name = f"{section}.{key}" if section else key
    _fails_in_one_line(["calibrate", str(csv), "--json", str(tmp_path / "c.json")], capsys,
                       f"sidecar field '{name}' is unknown")
    assert not (tmp_path / "c.json").exists()


@pytest.mark.parametrize("toml_key, quantity", [("impulse_force_N", "force_N"),
                                                ("impulse_duration_s", "pulse_duration_s"),
                                                ("impulse_alphas_per_s", "alpha_per_s"),
                                                ("mesh_comparison_alpha_per_s", "alpha_per_s"),
                                                ("contact_alphas_per_s", "alpha_per_s")])
def test_the_toml_load_and_damping_keys_share_the_sidecar_range(toml_key, quantity):
    from ccedi.quantities import QUANTITIES
    from ccedi.study.config import SCHEMA

    spec, q = SCHEMA["study"][toml_key], QUANTITIES[quantity]
    assert (spec.unit, spec.lo, spec.hi) == (q.unit, q.lo, q.hi)


def test_the_data_readme_states_the_table_ranges():
    """data/README.md's sidecar table gives each field the range of ccedi.quantities."""
    import re

    from ccedi.quantities import QUANTITIES

    readme = (ROOT / "data" / "README.md").read_text()
    rows = dict(re.findall(r"^\| `([A-Za-z0-9_.]+)`[^|]*\|[^|]*\| ([^|]*) \|", readme, re.MULTILINE))
    for field, quantity in [("finger.E_Pa", "E_Pa"), ("finger.nu", "nu"), ("finger.rho_kg_m3", "rho_kg_m3"),
                            ("load.force_N", "force_N"), ("load.duration_s", "pulse_duration_s"),
                            ("load.start_s", "pulse_start_s"), ("alpha_per_s", "alpha_per_s"),
                            ("sensor.noise_std_m", "noise_std_m"), ("tolerances.E_Pa", "E_tolerance")]:
        q = QUANTITIES[quantity]
        assert [float(x) for x in rows[field].split("..")] == [q.lo, q.hi], field
