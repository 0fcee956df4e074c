"""What a careless user types, class by class: each bad input is refused before any
compute, with exit status 1 and one stderr line that names what was typed (flag, key or
file) and what is allowed; no traceback, no output left behind, no explicit step taken."""
import json
import resource
import signal
from contextlib import contextmanager
from pathlib import Path

import matplotlib.pyplot as plt
import meshio
import numpy as np
import pandas as pd
import pytest
from conftest import ROOT

from ccedi.distributed import check_scheduler
from ccedi.errors import InputError
from ccedi.fea.io.lsdyna import write_keyword
from ccedi.fea.io.vtu import write_vtu
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import Mesh, elliptical_cantilever, sm_a
from ccedi.fea.mesh.tet_mesh import box_cantilever, split_hexes
from ccedi.fea.model import cantilever_model
from ccedi.fea.solvers import explicit
from ccedi.fea.solvers.budget import STEPS_ENV
from ccedi.fea.solvers.explicit import critical_time_step, limiting_element, run, sliver_warnings
from ccedi.outputs import write_csv, write_figure, write_json, write_pdf_figures, write_text
from ccedi.study.cli import main
from ccedi.study.commands.fea import finger_of
from ccedi.study.config import load

BAD_SCHEDULERS = ["fast", "tcp://10.0.0.5", "10.0.0.5:port", "", "local ", "serial,local", "tcp://:8786",
                  "Serial"]
GOOD_SCHEDULERS = ["serial", "local", "tcp://10.0.0.5:8786", "scheduler.lab:8786", "tls://host-1.lab:443"]


def _no_step(*args):
    raise AssertionError("an explicit step was taken before the input was refused")


def _refused(capsys, argv, *named):
    """``ccedi argv`` exits 1 with one stderr line naming each of ``named``, without
    taking a single explicit step (the step loop raises if it is entered)."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(explicit, "_advance_numba", _no_step)
        patch.setattr(explicit, "_advance", _no_step)
        rc = main(argv)
    err = capsys.readouterr().err
    assert rc == 1 and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    for word in named:
        assert word in err
    return err


@pytest.mark.parametrize("scheduler", BAD_SCHEDULERS)
def test_a_scheduler_that_is_no_word_and_no_address_is_refused_before_anything(scheduler, tmp_path, capsys):
    """From the flag and from ``[study] scheduler``: one line naming it, and no study
    files (config.toml, study.json) written first."""
    out = tmp_path / "out"
    _refused(capsys, ["impulse", "--scheduler", scheduler, "--out", str(out)], "--scheduler", "tcp://")
    toml = tmp_path / "study.toml"
    toml.write_text(f'[study]\nscheduler = "{scheduler}"\n')
    _refused(capsys, ["study", "--config", str(toml), "--out", str(out)], "[study] scheduler", "tcp://")
    assert not out.exists()


@pytest.mark.parametrize("scheduler", GOOD_SCHEDULERS)
def test_known_words_and_addresses_with_a_port_pass(scheduler):
    assert check_scheduler(scheduler) == scheduler


def test_the_scheduler_check_can_fail():
    with pytest.raises(InputError, match="'fast'"):
        check_scheduler("fast")


@pytest.mark.parametrize("argv, named", [
    (["design", "--alpha-bounds", "7.5", "1e9"], "--alpha-bounds"),
    (["design", "--alpha-bounds", "600", "7.5"], "--alpha-bounds"),
    (["design", "--length-bounds-in", "3", "200"], "--length-bounds-in"),
    (["design", "--length-bounds-in", "0.5", "3"], "--length-bounds-in"),
    (["design", "--vary", "drum_speed", "--drum-speed-bounds-rpm", "0", "30"], "--drum-speed-bounds-rpm"),
    (["design", "--vary", "drum_speed", "--drum-speed-bounds-rpm", "10", "5000"], "--drum-speed-bounds-rpm"),
    (["design", "--allowable-root-stress-Pa", "-1"], "--allowable-root-stress-Pa"),
    (["damping-fits", "--lengths-in", "0.5", "3"], "--lengths-in"),
    (["damping-fits", "--lengths-in", "3", "200"], "--lengths-in"),
])
def test_design_space_flags_out_of_range_name_the_flag_before_any_run(argv, named, tmp_path, capsys):
    """Bounds are checked against the quantity's range in the flag's own unit, before the
    ROM grid or a cluster starts; the message names the flag, not an internal field."""
    out = tmp_path / "out"
    args = argv + (["--json", str(out / "d.json"), "--out", str(out)] if argv[0] == "design" else ["--out", str(out)])
    err = _refused(capsys, args, named)
    assert "finger_length_m" not in err and "DrumSetup" not in err
    assert not out.exists() or not any(out.iterdir())


@contextmanager
def small_disk():
    """Files of this process cannot grow past 4 kB (RLIMIT_FSIZE, SIGXFSZ ignored): a write
    beyond fails with OSError (EFBIG), as on a full disk."""
    old = resource.getrlimit(resource.RLIMIT_FSIZE)
    handler = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (4096, old[1]))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, old)
        signal.signal(signal.SIGXFSZ, handler)


def _writers(tmp_path):
    """(name, path, thunk) of every result writer, each with content well over 4 kB."""
    big = pd.DataFrame({"time_s": np.linspace(0.0, 1.0, 2000), "force_N": np.linspace(1.0, 2.0, 2000)})
    fig, ax = plt.subplots()
    ax.plot(big.time_s, np.sin(40 * big.time_s))
    png = tmp_path / "keep.png"
    write_figure(png, fig)                                   # before the limit: the PDF's page
    model = cantilever_model(elliptical_cantilever(0.1, 4, 30), RUBBER)
    return [("json", "r.json", lambda p: write_json(p, {"x": list(range(3000))})),
            ("csv", "r.csv", lambda p: write_csv(p, big)),
            ("text", "r.md", lambda p: write_text(p, "x" * 20000)),
            ("figure", "r.png", lambda p: write_figure(p, fig)),
            ("pdf", "r.pdf", lambda p: write_pdf_figures(p, [(png, "page")])),
            ("vtu", "r.vtu", lambda p: write_vtu(p, model)),
            ("lsdyna", "r.k", lambda p: write_keyword(model, p, 0.01))]


def test_every_writer_on_a_full_disk_names_its_file_and_leaves_nothing(tmp_path):
    """Each writer, its file unable to grow: an OSError naming the file the user asked
    for (not a temporary one), and neither a partial file nor a temporary left."""
    out = tmp_path / "out"
    for name, file, write in _writers(tmp_path):
        write(tmp_path / "warm" / name / file)          # compiled kernels cached on disk before the limit
        path = out / name / file
        with small_disk(), pytest.raises(OSError) as err:
            write(path)
        assert err.value.filename == str(path), name
        assert list(path.parent.iterdir()) == [], name
        write(path)                                         # the same write fits without the limit
        assert path.stat().st_size > 4096, name


def test_a_command_on_a_full_disk_names_the_file_in_one_line(tmp_path, capsys):
    deck = tmp_path / "deck.k"
    with small_disk():
        err = _refused(capsys, ["export", "--case", "impulse", "--format", "lsdyna", "--out", str(deck)], str(deck))
    assert "File too large" in err and not deck.exists() and list(tmp_path.iterdir()) == []


def test_a_study_checks_every_record_before_its_first_step(tmp_path, capsys):
    """A NaN in a measured record, a renamed time column, a record of three samples: the
    study stops before any step, naming the key and the file; no study files written."""
    src = ROOT / "data" / "measured" / "control_high"
    bad = []
    for k, edit in enumerate((lambda t: "\n".join(row if i != 5 else row.split(",")[0] + ",nan," + row.split(",")[2]
                                                  for i, row in enumerate(t.splitlines())),
                              lambda t: t.replace("time_s", "time_ms", 1),
                              lambda t: "\n".join(t.splitlines()[:4]))):
        record = tmp_path / f"record_{k}.csv"
        record.write_text(edit(src.with_suffix(".csv").read_text()))
        record.with_suffix(".json").write_text(src.with_suffix(".json").read_text())
        bad.append(record)
    for record in bad:
        toml = tmp_path / "study.toml"
        toml.write_text(f'[study]\nmeasured_records = ["{record}"]\n')
        out = tmp_path / "out"
        _refused(capsys, ["study", "--config", str(toml), "--only", "impulse", "calibrate", "--scheduler", "serial",
                          "--out", str(out)], "[study] measured_records", record.name)
        assert not out.exists()


@pytest.mark.filterwarnings("ignore::ccedi.errors.ValidityWarning")     # an unloaded run's energy balance
def test_a_run_beyond_its_step_budget_is_refused_with_its_count_and_time(tmp_path, capsys, monkeypatch):
    """E = 1e12 Pa with rho = 1 kg/m^3 (both in range): about 5e8 steps. Refused before it
    starts, from the command line and the library, naming the steps, the stable step and
    the expected time; ``--max-steps`` and CCEDI_MAX_STEPS move the budget."""
    toml = tmp_path / "stiff.toml"
    toml.write_text("[material]\nE_Pa = 1e12\nrho_kg_m3 = 1.0\n")
    out = tmp_path / "out"
    err = _refused(capsys, ["impulse", "--config", str(toml), "--alpha", "180", "--scheduler", "serial",
                            "--out", str(out)], "steps", "beyond the budget", "--max-steps")
    assert "stable step" in err and not out.exists()
    model = cantilever_model(elliptical_cantilever(0.05, 2, 6), RUBBER)
    dt = 0.9 * critical_time_step(model)
    with pytest.raises(InputError, match="beyond the budget of 10"):
        run(model, 20 * dt, max_steps=10)
    monkeypatch.setenv(STEPS_ENV, "10")
    with pytest.raises(InputError, match="beyond the budget of 10"):
        run(model, 20 * dt)
    assert run(model, 20 * dt, max_steps=100).summary["steps"] >= 20
    monkeypatch.setenv(STEPS_ENV, "many")
    with pytest.raises(InputError, match="CCEDI_MAX_STEPS = 'many'"):
        run(model, 20 * dt)
    monkeypatch.delenv(STEPS_ENV)
    _refused(capsys, ["impulse", "--max-steps", "0", "--out", str(out)], "--max-steps")


def test_the_configured_finger_length_is_what_table1_and_impulse_use(tmp_path, capsys):
    """``[finger] impulse_length_in`` in --config, no --length-in: Table 1 and the impulse
    command build the finger of the configured length, not the flag's old default 4.5."""
    toml = tmp_path / "c.toml"
    toml.write_text("[finger]\nimpulse_length_in = 6.0\n")
    table = tmp_path / "t.json"
    assert main(["table1", "--config", str(toml), "--no-stiffness", "--no-detailed-model", "--json", str(table)]) == 0
    nodes = json.loads(table.read_text())["SM-A"]["nodes"]
    assert nodes == sm_a(length_in=6.0).n_nodes != sm_a(length_in=4.5).n_nodes
    mesh, length_in, finger = finger_of(load(toml), None)
    assert mesh is None and length_in == 6.0 and finger["name"] == "SM-A 6-in finger"


def test_a_sliver_that_sets_the_step_is_named_with_where_it_is():
    """A surface node of a 4-node tetrahedral box pushed 90 % into its element layer: the
    elements there become slivers and set the step; the run's warnings name the element,
    its place (at the pushed node) and its size against the median, and suggest a
    remesh. The unpushed box has no such warning."""
    box = split_hexes(box_cantilever(0.06, 0.012, 0.012, nx=2, ny=2, nz=10))
    assert sliver_warnings(cantilever_model(box, RUBBER)) == []
    top = np.flatnonzero((box.nodes[:, 1] == box.nodes[:, 1].max()) & np.isclose(box.nodes[:, 2], 0.03)
                         & np.isclose(box.nodes[:, 0], 0.0))[0]
    nodes = box.nodes.copy()
    nodes[top, 1] -= 0.9 * 0.006
    model = cantilever_model(Mesh(nodes=nodes, tets4=box.tets4, node_sets=box.node_sets), RUBBER)
    e = limiting_element(model)
    assert np.linalg.norm(e["centroid_m"] - nodes[top]) < 0.006
    assert e["dt_s"] == pytest.approx(critical_time_step(model), rel=1e-9)
    (message,) = sliver_warnings(model)
    assert e["element"] in message and "mm across" in message and "remesh" in message


def test_one_rule_for_relative_paths_in_a_toml(tmp_path, monkeypatch):
    """``ccedi init``'s TOML read from another directory finds the bundled records; a
    relative record in a TOML resolves against the TOML's folder, as ``[finger] mesh`` does."""
    folder, elsewhere = tmp_path / "project", tmp_path / "elsewhere"
    folder.mkdir()
    elsewhere.mkdir()
    assert main(["init", str(folder / "study.toml")]) == 0
    monkeypatch.chdir(elsewhere)
    cfg = load(folder / "study.toml")
    assert cfg["study"]["measured_records"] and all(Path(r).is_file() for r in cfg["study"]["measured_records"])
    (folder / "mine.toml").write_text('[study]\nmeasured_records = ["records/r.csv"]\n'
                                      'design_calibration_record = "records/c.csv"\n')
    cfg = load(folder / "mine.toml")
    assert cfg["study"]["measured_records"] == [str(folder / "records" / "r.csv")]
    assert cfg["study"]["design_calibration_record"] == str(folder / "records" / "c.csv")


def test_quick_says_which_configured_values_it_replaces(tmp_path, capsys):
    toml = tmp_path / "s.toml"
    toml.write_text("[study]\ncontact_alphas_per_s = [80.0, 180.0]\n")
    assert main(["study", "--quick", "--config", str(toml), "--only", "table1", "--scheduler", "serial",
                 "--out", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert "--quick sets [study] contact_alphas_per_s = [600.0] instead of the configured [80.0, 180.0]" in out


def test_an_empty_record_path_is_refused_not_read_as_the_folder(tmp_path):
    """``measured_records = [""]`` would resolve to the TOML's own folder; it is named as an
    empty entry instead."""
    toml = tmp_path / "study.toml"
    toml.write_text('[study]\nmeasured_records = ["data/measured/control_high.csv", " "]\n')
    with pytest.raises(InputError, match=r"\[study\] measured_records: entry 2 is an empty path"):
        load(toml)


@pytest.mark.parametrize("record, length_in", [("control_low", 4.5), ("control_high", 4.5), ("control_low", 12.0)])
def test_identify_refuses_a_record_its_declared_finger_cannot_ring_at(record, length_in, tmp_path, capsys):
    """An 8-in finger's records identified as a 4.5-in or 12-in finger: the record's own
    first frequency (4.4 Hz) lies outside what the declared finger reaches; exit 3 before
    any FE run, one line naming both frequencies and --length-in, the evidence in --json."""
    out = tmp_path / "id.json"
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(explicit, "_advance_numba", _no_step)
        rc = main(["identify", str(ROOT / "data" / "measured" / f"{record}.csv"), "--length-in", str(length_in),
                   "--json", str(out)])
    err = capsys.readouterr().err
    assert rc == 3 and len(err.strip().splitlines()) == 1 and "--length-in" in err, err
    evidence = json.loads(out.read_text())
    assert not evidence["model_adequate"] and "alpha_per_s" not in evidence
    assert evidence["record_first_frequency_hz"] == pytest.approx(4.4, rel=0.05)
    low, high = evidence["allowed_band_hz"]
    assert not low <= evidence["record_first_frequency_hz"] <= high


def test_identify_checks_the_frequency_and_says_so_when_it_fits(tmp_path, capsys):
    """The same record with its true length (8 in) passes the check, named on stdout, and
    identifies alpha within 15 % of the record's true 3.15 1/s (modal ROM of the finger,
    6 modes; the record's E is 4 % below the declared one, which identify does not fit)."""
    out = tmp_path / "id.json"
    assert main(["identify", str(ROOT / "data" / "measured" / "control_low.csv"), "--length-in", "8", "--rom", "6",
                 "--json", str(out)]) == 0
    assert "declared model adequate" in capsys.readouterr().out
    result = json.loads(out.read_text())
    truth = json.loads((ROOT / "data" / "measured" / "manifest.json").read_text())["records"]["control_low"]
    assert result["model_adequate"] and result["alpha_per_s"] == pytest.approx(truth["alpha_per_s"], rel=0.15)


@pytest.mark.parametrize("command, argv, unused, used", [
    ("table1", ["--no-stiffness", "--no-detailed-model"], "[drum] friction", "impulse_length_in"),
    ("export", ["--case", "impulse"], "[drum] friction", "impulse_length_in"),
    ("export", ["--case", "contact"], "[finger] impulse_length_in", "friction"),
])
def test_a_configured_key_the_command_does_not_use_is_named(command, argv, unused, used, tmp_path, capsys):
    """A key the file sets (not to its default) that the command ignores is named in one
    warning line before the command runs; the keys it uses and the keys left at their
    defaults are not."""
    toml = tmp_path / "c.toml"
    toml.write_text("[finger]\nimpulse_length_in = 6.0\n[drum]\nfriction = 0.3\ndrum_radius_m = 0.08255\n")
    out = tmp_path / ("t.json" if command == "table1" else "deck.k")
    assert main([command, *argv, "--config", str(toml), "--" + ("json" if command == "table1" else "out"),
                 str(out)]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if "does not use" in line]
    assert len(lines) == 1 and unused in lines[0] and used not in lines[0] and "drum_radius_m" not in lines[0]


def test_table1_takes_its_switches_from_the_config(tmp_path, capsys):
    toml = tmp_path / "c.toml"
    toml.write_text("[study]\ntable1_stiffness = false\ndetailed_model = false\n")
    table = tmp_path / "t.json"
    assert main(["table1", "--config", str(toml), "--json", str(table)]) == 0
    rows = json.loads(table.read_text())
    assert "DM" not in rows and not any("stiffness_N_per_m" in row for row in rows.values())
    assert "does not use" not in capsys.readouterr().err


def _shifted_record(tmp_path, name, time_s, force_N):
    """A copy of the 8-in control_low record and its sidecar with its time column and its
    force column (None: dropped) replaced."""
    table = pd.read_csv(ROOT / "data" / "measured" / "control_low.csv")
    table["time_s"] = time_s(table["time_s"].to_numpy())
    table = table.drop(columns="force_N") if force_N is None else table.assign(force_N=force_N(table["force_N"]))
    csv = tmp_path / f"{name}.csv"
    table.to_csv(csv, index=False)
    csv.with_suffix(".json").write_text((ROOT / "data" / "measured" / "control_low.json").read_text())
    return csv


@pytest.mark.parametrize("name, time_s, force_N, identify_says, calibrate_says", [
    ("in_ms", lambda t: 1e3 * t, lambda f: f, "is time_s in seconds?", "not seconds"),
    ("late", lambda t: t + 100.0, lambda f: f, "shift time_s so that the pulse starts at 0", "time_s starts at 100 s"),
    ("late_no_force", lambda t: t + 100.0, None, "time_s starts at 100 s", "time_s starts at 100 s"),
    ("pulse_elsewhere", lambda t: t, lambda f: np.roll(f.to_numpy(), 500), "the force_N pulse starts at 0.5 s",
     "pulse starts at 0.5 s"),
])
def test_a_record_whose_time_is_not_the_pulses_is_named_as_such(name, time_s, force_N, identify_says,
                                                                 calibrate_says, tmp_path, capsys):
    """Time in ms, a record starting 100 s late (with and without its force column), a
    force pulse 0.5 s after the declared one: identify and calibrate name the time column
    and the fix, not an inferred duration, a mass mismatch or a run of 100 s."""
    csv = _shifted_record(tmp_path, name, time_s, force_N)
    assert identify_says in _refused(capsys, ["identify", str(csv), "--length-in", "8"])
    assert calibrate_says in _refused(capsys, ["calibrate", str(csv), "--json", str(tmp_path / "c.json")])
    assert not (tmp_path / "c.json").exists()


@pytest.mark.parametrize("argv", [
    ["contact", "--alpha", "7.5", "--n-outputs", "1000000000"],
    ["contact-sweep", "--alphas", "7.5", "--n-outputs", "0", "--scheduler", "serial"],
    ["rom-check", "--json", "r.json", "--n-outputs", "200000"],
])
def test_an_absurd_output_count_is_refused_with_its_range(argv, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    err = _refused(capsys, argv + ["--out", str(tmp_path / "out")] if argv[0] != "rom-check" else argv,
                   "--n-outputs", "1..100000")
    assert not any(tmp_path.iterdir()), err
    model = cantilever_model(elliptical_cantilever(0.05, 2, 6), RUBBER)
    with pytest.raises(InputError, match=r"n_outputs = 100001: must be an integer in 1..100000"):
        run(model, 1e-3, n_outputs=100_001)


@pytest.mark.parametrize("toml, argv, named", [
    ("[finger]\nsection_semi_axes_m = [0.09, 0.09]\nimpulse_length_in = 1.0\n", ["export"],
     "[finger] impulse_length_in = 1 in"),
    ("[finger]\nsection_semi_axes_m = [0.012, 0.09]\ncontact_length_in = 3.0\nimpulse_length_in = 8.0\n",
     ["design", "--json", "d.json"], "[finger] contact_length_in = 3 in"),
    ("[finger]\nsection_semi_axes_m = [0.03, 0.03]\n", ["impulse", "--length-in", "1"], "--length-in = 1 in"),
    ("[finger]\nsection_semi_axes_m = [0.03, 0.03]\n", ["table1", "--length-in", "1.1"], "--length-in = 1.1 in"),
])
def test_a_section_as_long_as_the_finger_is_refused_by_every_command(toml, argv, named, tmp_path, capsys,
                                                                      monkeypatch):
    """A 1-in finger with 90 mm semi-axes (the sidecar's rule: the section shorter than
    the finger), from the TOML or the --length-in flag: named with both inputs."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "c.toml").write_text(toml)
    out = ["--out", "out.k" if argv[0] == "export" else "out"] if argv[0] in ("export", "impulse", "design") else []
    err = _refused(capsys, argv + ["--config", "c.toml"] + out, "[finger] section_semi_axes_m", named)
    assert "cantilever longer than its section" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.toml"]


def test_an_imported_finger_lying_along_x_is_named_not_measured_along_z(tmp_path, capsys):
    """The 6-in finger turned to lie along x: refused (its z extent, the section, would
    have been its 'length'), with the extents and the fix."""
    mesh = elliptical_cantilever(0.15, 3, 20)
    along_x = mesh.nodes[:, [2, 1, 0]]
    path = tmp_path / "along_x.vtu"
    meshio.write(path, meshio.Mesh(along_x, [("hexahedron", mesh.hexes[:, [0, 3, 2, 1, 4, 7, 6, 5]])]))
    (tmp_path / "c.toml").write_text(f'[finger]\nmesh = "{path.name}"\n')
    err = _refused(capsys, ["export", "--config", str(tmp_path / "c.toml"), "--out", str(tmp_path / "o.k")],
                   "along_x.vtu", "along x", "rotate the mesh")
    assert "0.15 m along x" in err and "0.024 m along z" in err


def test_a_rounded_tip_that_z_max_takes_as_one_node_names_tip_and_the_fix(tmp_path, capsys):
    """The tip's centre node pushed 2 mm out: ``tip = "z_max"`` takes that node alone, no
    element face; the message names ``tip``, the node and the two fixes."""
    mesh = elliptical_cantilever(0.1, 2, 10)
    nodes = mesh.nodes.copy()
    centre = np.flatnonzero((nodes[:, 2] == nodes[:, 2].max()) & (np.abs(nodes[:, 0]) < 1e-9)
                            & (np.abs(nodes[:, 1]) < 1e-9))
    nodes[centre, 2] += 0.002
    path = tmp_path / "rounded.vtu"
    meshio.write(path, meshio.Mesh(nodes, [("hexahedron", mesh.hexes)]))
    (tmp_path / "c.toml").write_text(f'[finger]\nmesh = "{path.name}"\n')
    err = _refused(capsys, ["export", "--config", str(tmp_path / "c.toml"), "--out", str(tmp_path / "o.k")],
                   "tip = 'z_max' picks 1 node(s)", "no complete element face", "rounded tip", "node set")
    assert "[finger] tip" in err


def test_a_run_in_a_log_states_its_steps_and_expected_time_before_it_starts(tmp_path, capsys):
    """stdout and stderr not terminals (a batch job): the run's progress is a plain line on
    stdout when it starts, with its step count and expected time; stderr stays empty."""
    assert main(["contact", "--alpha", "180", "--t-end-s", "0.01", "--n-outputs", "5", "--out", str(tmp_path)]) == 0
    captured = capsys.readouterr()
    started = [line for line in captured.out.splitlines() if "steps" in line and "0 % (0/5 outputs)" in line]
    assert len(started) == 1 and started[0].startswith("t_end 0.01 s, ~") and "elapsed" in started[0]
    steps = float(started[0].split("~")[1].split(" steps")[0])
    summary = json.loads((tmp_path / "contact_alpha180_global.json").read_text())
    assert captured.err == "" and steps == pytest.approx(summary["steps"], rel=0.1)
