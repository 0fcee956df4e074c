"""Progress bars of the long computations: one style, shown only on a terminal.

A bar is drawn on stderr when stderr is a terminal and cleared when it closes. The command
line closes every open bar (:func:`close_progress_bars`) before it prints an error or an
interrupt, so that line starts on a clean line. When stderr is a file or a pipe no bar is
drawn: logs then hold only the commands' own lines, and an error is one line.

The bars share a thread lock, not tqdm's default multiprocessing lock: a Dask worker that
is stopped at the end of a run would otherwise leave that lock's semaphore behind, and
multiprocessing warns about it at exit.
"""
import threading
import weakref

_OPEN = weakref.WeakSet()
_LOCK = threading.RLock()


def progress_bar(iterable=None, total=None, desc="", unit="it"):
    """A tqdm progress bar over ``iterable``, or for ``total`` items updated by hand.

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
    from tqdm import tqdm

    if getattr(tqdm, "_lock", None) is not _LOCK:
        tqdm.set_lock(_LOCK)
    bar = tqdm(iterable, total=total, desc=desc, unit=unit, leave=False, disable=None)
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
