"""Ctrl-C on ``ccedi study`` with a local Dask cluster: one line, exit 130, no partial file.

The interrupt is sent as a terminal sends it, to the whole process group (the command and
its worker processes), once a step has finished, i.e. while the next one is running.
"""
import json
import os
import signal
import subprocess
import sys
import time

import pytest
from conftest import ROOT


def _interruptible():
    """In the child before it starts: SIGINT's default action, as a terminal gives it. A
    command started in the background by a non-interactive shell (``cmd &``, how a CI
    job or a session may start the suite) inherits SIGINT ignored, and Python then
    installs no KeyboardInterrupt for it: the study would not see the interrupt at all."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.mark.slow
def test_sigint_on_a_running_study_prints_one_line(tmp_path):
    """Table 1 as --quick makes it, and a contact step of 2 s simulated beside it: the
    contact step is still running when Table 1 is done on a loaded machine (with
    --quick's 1 s it finished first when the rest of the suite ran beside it); the running
    step ends before the command does, so the wait after the interrupt is generous."""
    out = tmp_path / "study"
    config = tmp_path / "study.toml"
    config.write_text("[study]\ntable1_stiffness = false\ndetailed_model = false\n"
                      "contact_alphas_per_s = [600.0]\ncontact_t_end_s = 2.0\n")
    command = [sys.executable, "-m", "ccedi", "study", "--config", str(config), "--scheduler", "local", "--only",
               "table1", "contact", "--out", str(out)]
    proc = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, preexec_fn=_interruptible)
    try:
        deadline = time.monotonic() + 300
        for line in proc.stdout:
            if "table1 done" in line:
                break
            assert time.monotonic() < deadline, "table1 did not finish in 300 s"
        assert proc.poll() is None, "the study ended before it could be interrupted"
        os.killpg(proc.pid, signal.SIGINT)
        stdout, stderr = proc.communicate(timeout=300)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130
    assert stderr.splitlines() == ["ccedi study: interrupted; no partial outputs were written"], stderr
    assert (out / "table1.json").is_file()                  # the finished step is kept
    assert list(json.loads((out / "study.json").read_text())["wall_time_s"]) == ["table1"]
    assert not [p for p in out.rglob("*") if p.is_file() and ".tmp" in p.name]
