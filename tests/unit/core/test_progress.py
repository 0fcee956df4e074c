"""Progress: a bar on a terminal, cleared before an error line so the line is never glued
onto a bar; plain lines on stdout in a log."""
import io
import sys

from ccedi import progress
from ccedi.progress import close_progress_bars, progress_bar
from ccedi.study import cli


class Terminal(io.StringIO):
    """A stderr that says it is a terminal."""

    def isatty(self):
        return True


def test_error_line_starts_on_a_cleared_line(monkeypatch):
    monkeypatch.setattr(sys, "stderr", Terminal())
    bar = progress_bar(total=4, desc="impulse runs", unit="run")
    bar.update()
    bar.refresh()
    assert "impulse runs" in sys.stderr.getvalue()          # a bar was drawn
    assert cli._fail("impulse", "error: boom", 1) == 1
    text = sys.stderr.getvalue()
    before, line = text.rsplit("ccedi impulse:", 1)
    assert line == " error: boom\n"
    assert before.endswith("\r") or before.endswith("\n")    # the message starts at column 0 ...
    assert before.rsplit("\r", 2)[-2].strip() == ""          # ... of a line the bar was cleared from
    assert close_progress_bars() == 0                         # _fail closed it


def test_progress_is_lines_on_stdout_when_stderr_is_not_a_terminal(monkeypatch):
    """A log (stderr not a terminal): no bar and nothing on stderr; on stdout one line when
    the work starts, then at most one per LOG_INTERVAL_S (here 0: every item), each a
    whole line without carriage returns."""
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    monkeypatch.setattr(sys, "stdout", io.StringIO())
    monkeypatch.setattr(progress, "LOG_INTERVAL_S", 0.0)
    for _ in progress_bar(range(3), desc="runs", unit="run"):
        pass
    assert sys.stderr.getvalue() == ""
    lines = sys.stdout.getvalue().splitlines()
    assert "\r" not in sys.stdout.getvalue() and lines[0].startswith("runs:   0 % (0/3 runs)")
    assert any(line.startswith("runs:  67 % (2/3 runs)") for line in lines) and all("elapsed" in x for x in lines)


def test_progress_lines_are_rate_limited(monkeypatch):
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    monkeypatch.setattr(sys, "stdout", io.StringIO())
    for _ in progress_bar(range(1000), desc="outputs", unit="output"):
        pass
    assert sys.stdout.getvalue().splitlines() == ["outputs:   0 % (0/1000 outputs), 00:00 elapsed, ? left"]
