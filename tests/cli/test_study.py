"""ccedi study orchestration: Ctrl-C keeps finished steps and no partial files; the
report is built only from the run's files."""
import json

from ccedi.outputs import write_json
from ccedi.study import run as study_run
from ccedi.study.cli import main
from ccedi.study.report import write_index


def test_interrupt_leaves_finished_steps_and_no_temporary_files(tmp_path, monkeypatch, capsys):
    def first():
        write_json(tmp_path / "first" / "result.json", {"x_m": 1.0})

    def second():
        def interrupted(tmp):
            open(tmp, "w").write("half")
            raise KeyboardInterrupt
        from ccedi.outputs import atomic_write
        atomic_write(tmp_path / "second" / "result.json", interrupted)

    monkeypatch.setattr(study_run, "steps", lambda cfg, out, scheduler: [("finger", "one", first),
                                                                       ("impulse", "two", second)])
    assert main(["study", "--out", str(tmp_path), "--scheduler", "serial"]) == 130
    assert "interrupted" in capsys.readouterr().err
    assert json.loads((tmp_path / "first" / "result.json").read_text()) == {"x_m": 1.0}
    assert list(json.loads((tmp_path / "study.json").read_text())["wall_time_s"]) == ["finger"]
    assert not list(tmp_path.rglob("*.tmp")) and not (tmp_path / "second" / "result.json").exists()
    assert not (tmp_path / "index.html").exists()


def test_a_failed_step_keeps_the_others_and_the_report(tmp_path, monkeypatch, capsys):
    """A step whose run fails (an inverted element) is recorded with its message; the steps
    after it still run, the index is written and says why, and the exit status is 1."""
    from ccedi.errors import SolverError

    def failing():
        raise SolverError("tet4 element 7 inverted (J <= 0) at t = 0.5 s, step 100")

    def last():
        write_json(tmp_path / "last" / "result.json", {"x_m": 2.0})

    monkeypatch.setattr(study_run, "steps", lambda cfg, out, scheduler: [("contact", "one", failing),
                                                                       ("calibrate", "two", last)])
    assert main(["study", "--out", str(tmp_path), "--scheduler", "serial"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "1 step(s) failed (contact)" in err[0]
    record = json.loads((tmp_path / "study.json").read_text())
    assert record["failed"] == {"contact": "tet4 element 7 inverted (J <= 0) at t = 0.5 s, step 100"}
    assert json.loads((tmp_path / "last" / "result.json").read_text()) == {"x_m": 2.0}
    assert "element 7 inverted" in (tmp_path / "index.html").read_text()


def test_index_reports_the_numbers_of_the_run_and_marks_missing_steps(tmp_path):
    write_json(tmp_path / "table1.json", {"SM-A": {"nodes": 1080, "elements": 725, "dt_us": 4.411,
                                                   "steps_to_0_2_s": 45340, "step_ratio": 1.0,
                                                   "stiffness_N_per_m": 74.35}})
    page = write_index(tmp_path).read_text()
    assert "4.411" in page and "74.35" in page and "tip stiffness [N/m]" in page
    assert page.count("did not run") == 9


def test_export_csv_vtu_and_parquet(tmp_path, capsys):
    import importlib.util

    import pandas as pd

    args = ["export", "--case", "impulse", "--length-in", "3", "--t-end-s", "0.004"]
    assert main(args + ["--format", "csv", "--out", str(tmp_path / "h.csv")]) == 0
    h = pd.read_csv(tmp_path / "h.csv")
    assert {"time_s", "tip_uy_m"} <= set(h.columns) and h.time_s.iloc[-1] >= 0.004
    assert main(args + ["--format", "vtu", "--out", str(tmp_path / "vtu")]) == 0
    assert (tmp_path / "vtu" / "impulse.pvd").exists() and list((tmp_path / "vtu").glob("impulse_*.vtu"))
    rc = main(args + ["--format", "parquet", "--out", str(tmp_path / "h.parquet")])
    if importlib.util.find_spec("pyarrow") is None:
        assert rc == 1 and "pyarrow" in capsys.readouterr().err
        assert not list(tmp_path.glob("*.parquet*"))
    else:
        assert rc == 0 and pd.read_parquet(tmp_path / "h.parquet").equals(h)


def test_index_shows_the_inputs_and_the_paper_table_only_for_the_paper_finger(tmp_path):
    from ccedi.study.config import CONFIG_NAME, to_toml, validate

    write_json(tmp_path / "table1.json", {"SM-A": {"nodes": 1080, "elements": 725, "dt_us": 3.438,
                                                   "steps_to_0_2_s": 58179, "step_ratio": 1.0,
                                                   "stiffness_N_per_m": 202.6}})
    page = write_index(tmp_path).read_text()                # no config.toml: the paper's finger
    assert "SM-A paper" in page
    (tmp_path / CONFIG_NAME).write_text(to_toml(validate({"material": {"E_Pa": 12.2e6}})))
    page = write_index(tmp_path).read_text()
    assert "SM-A paper" not in page and "not the paper's" in page
    assert "[material] E_Pa</td><td>1.22e+07</td><td>Pa" in page


def test_index_shows_the_impulse_step_of_a_real_run(tmp_path):
    """The impulse section reads what ``ccedi impulse`` writes (the finger's description)."""
    assert main(["impulse", "--alpha", "180", "--length-in", "3", "--t-end-s", "0.002",
                 "--out", str(tmp_path / "impulse")]) == 0
    peak = json.loads((tmp_path / "impulse" / "impulse_summary.json").read_text())["peaks"]["180"]
    page = write_index(tmp_path).read_text()
    assert "SM-A 3-in finger (" in page and "hex8 elements" in page
    assert f"{peak['peak_tip_uy_m']:.4g}" in page


def _recording_steps(ran):
    """A stand-in for the study's steps that records which ran, in order."""
    from ccedi.study.steps import STEP_NAMES

    return lambda cfg, out, scheduler: [(name, name, lambda name=name: ran.append(name)) for name in STEP_NAMES]


def test_a_study_is_the_fingers_and_the_paper_is_its_own_part(tmp_path, monkeypatch):
    """Without --paper the study runs the finger's steps only; --paper (or [study] paper)
    adds the paper's reproduction after them; --only names any step."""
    from ccedi.study.steps import FINGER_STEPS, PAPER_STEPS

    for args, expected in ((["--scheduler", "serial"], FINGER_STEPS),
                           (["--scheduler", "serial", "--paper"], FINGER_STEPS + PAPER_STEPS),
                           (["--scheduler", "serial", "--only", "table1", "impulse"], ("impulse", "table1"))):
        ran = []
        monkeypatch.setattr(study_run, "steps", _recording_steps(ran))
        out = tmp_path / "-".join(args)
        assert main(["study", "--out", str(out)] + args) == 0
        assert tuple(ran) == expected
    toml = tmp_path / "paper.toml"
    toml.write_text("[study]\npaper = true\n")
    ran = []
    monkeypatch.setattr(study_run, "steps", _recording_steps(ran))
    assert main(["study", "--config", str(toml), "--scheduler", "serial", "--out", str(tmp_path / "p")]) == 0
    assert tuple(ran) == FINGER_STEPS + PAPER_STEPS


def test_inputs_listed_are_those_the_steps_used():
    from ccedi.study.config import validate
    from ccedi.study.report import used_inputs

    def keys(cfg, ran):
        return {f"[{sec}] {key}" for sec, key, _ in used_inputs(cfg, set(ran))}

    generated = validate({})
    assert keys(generated, ["finger", "impulse"]) == {"[material] E_Pa", "[material] nu", "[material] rho_kg_m3",
                                                      "[finger] impulse_length_in", "[finger] section_semi_axes_m"}
    with_drum = keys(generated, ["finger", "contact"])
    assert "[finger] contact_length_in" in with_drum and "[drum] omega_rad_s" in with_drum
    assert "[damping] kind" in with_drum and not any(k.startswith("[requirements]") for k in with_drum)
    assert "[requirements] max_object_force_N" in keys(generated, ["design"])
    meshed = {**generated, "finger": {**generated["finger"], "mesh": "f.msh"}}
    assert not {"[finger] impulse_length_in", "[finger] contact_length_in",
                "[finger] section_semi_axes_m"} & keys(meshed, ["finger", "impulse", "contact"])
    assert "[finger] impulse_length_in" in keys(meshed, ["finger", "table1"])      # the paper's finger
