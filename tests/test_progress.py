"""Progress bars: drawn on a terminal only, and cleared before an error line, so the line
is never glued onto a bar."""
import io
import sys

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


def test_no_bar_when_stderr_is_not_a_terminal(monkeypatch):
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    for _ in progress_bar(range(3), desc="runs", unit="run"):
        pass
    assert sys.stderr.getvalue() == ""
