"""What a careless user types, class by class: each bad input is refused before any
compute, with exit status 1 and one stderr line that names what was typed (flag, key or
file) and what is allowed; no traceback, no output left behind, within a few seconds."""
import time

import pytest

from ccedi.errors import InputError
from ccedi.fea.distributed import check_scheduler
from ccedi.study.cli import main

BAD_SCHEDULERS = ["fast", "tcp://10.0.0.5", "10.0.0.5:port", "", "local ", "serial,local", "tcp://:8786",
                  "Serial"]
GOOD_SCHEDULERS = ["serial", "local", "tcp://10.0.0.5:8786", "scheduler.lab:8786", "tls://host-1.lab:443"]


def _refused(capsys, argv, *named):
    t0 = time.perf_counter()
    rc = main(argv)
    wall = time.perf_counter() - t0
    err = capsys.readouterr().err
    assert rc == 1 and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    for word in named:
        assert word in err
    assert wall < 5.0
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
