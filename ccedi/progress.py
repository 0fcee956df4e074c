"""Progress of the long computations: one style, a bar on a terminal, lines in a log.

On a terminal a bar is drawn on stderr and cleared when it closes. The command line closes
every open bar (:func:`close_progress_bars`) before it prints an error or an interrupt, so
that line starts on a clean line. When stderr is a file or a pipe (a batch job, a log) the
same progress is written as plain lines on stdout, among the command's own lines: one when
the work starts (what it is, how much, and for a run its expected time), then at most one
every :data:`LOG_INTERVAL_S`, so that a job killed after minutes leaves where it was; stderr
keeps one line per error.

The bars share a thread lock, not tqdm's default multiprocessing lock: a Dask worker that
is stopped at the end of a run would otherwise leave that lock's semaphore behind, and
multiprocessing warns about it at exit.
"""
import sys
import threading
import weakref

from tqdm import tqdm

_OPEN = weakref.WeakSet()
_LOCK = threading.RLock()

LOG_INTERVAL_S = 30.0
"""Least time between two progress lines when the output is not a terminal [s]."""

LOG_FORMAT = "{desc}: {percentage:3.0f} % ({n_fmt}/{total_fmt} {unit}s), {elapsed} elapsed, {remaining} left"
"""A progress line: ``t_end 1.5 s, ~3.4e5 steps, ~2 min: 40 % (120/300 outputs), 00:48
elapsed, 01:12 left``."""


class _Lines:
    """A stream for tqdm that turns each refresh of the bar into one line of ``stream``
    (the carriage returns dropped; the clearing of a closed bar writes nothing)."""

    def __init__(self, stream):
        self.stream = stream

    def write(self, text):
        line = text.replace("\r", "").strip()
        if line:
            self.stream.write(line + "\n")

    def flush(self):
        self.stream.flush()


def progress_bar(iterable=None, *, total=None, desc="", unit="it"):
    """A tqdm progress bar over ``iterable``, or for ``total`` items updated by hand: a bar on
    stderr when it is a terminal, else lines on stdout (module docstring).

    Parameters
    ----------
    iterable : iterable, optional
        Items to iterate over with the bar.
    total : int, optional
        Number of items (default: ``len(iterable)`` when it has one).
    desc : str, optional
        Label printed before the bar.
    unit : str, optional
        Name of one item ("run", "step", "output").

    Returns
    -------
    tqdm.tqdm
        The bar: iterate over it, or use it as a context manager and call ``update()``
        once per finished item.
    """
    if getattr(tqdm, "_lock", None) is not _LOCK:
        tqdm.set_lock(_LOCK)
    if sys.stderr.isatty():
        bar = tqdm(iterable, total=total, desc=desc, unit=unit, leave=False)
    else:
        bar = tqdm(iterable, total=total, desc=desc, unit=unit, leave=False, file=_Lines(sys.stdout),
                   bar_format=LOG_FORMAT, mininterval=LOG_INTERVAL_S, maxinterval=LOG_INTERVAL_S, miniters=1)
    _OPEN.add(bar)
    return bar


def close_progress_bars():
    """Close (and clear) every progress bar still open, e.g. one left by an exception.

    Returns
    -------
    int
        How many bars were closed.
    """
    bars = list(_OPEN)
    for bar in bars:
        bar.close()
    _OPEN.clear()
    return len(bars)
