"""Independent runs (alpha sweeps, alpha_cr over lengths) mapped over a Dask cluster.

``scheduler`` everywhere in ccedi is one of:

* ``"serial"``: in this process, one after the other (no Dask needed);
* ``"local"``: a ``dask.distributed.LocalCluster`` of ``n_workers`` single-threaded
  worker processes, started for the call and shut down after it;
* an address such as ``tcp://10.0.0.5:8786``: an existing Dask scheduler (its workers
  must have ccedi installed).

A function mapped over a cluster may itself map runs (a study step sweeping alpha): the
inner runs go to the same cluster. Each run is a pure function of its item, computed by the same code in whichever
process runs it, so the results are identical to the serial ones; they come back in
input order. A progress bar (:func:`ccedi.progress.progress_bar`) counts finished runs.
The warnings a run issues (e.g. the validity warnings of :mod:`ccedi.fea.solvers.validity`) are
recorded where it runs and issued again in the caller, in input order, once the progress
bar is closed: none is lost on a worker, none is printed into the bar.

Ctrl-C reaches only the process that started a local cluster: its worker processes are
started with SIGINT ignored, so an interrupt is one ``KeyboardInterrupt`` in the caller,
which shuts the cluster down, rather than a traceback from every worker.
"""
import logging
import re
import signal
import threading
import warnings
from contextlib import ExitStack, contextmanager
from functools import partial

from ccedi.errors import InputError
from ccedi.progress import progress_bar

SERIAL, LOCAL = "serial", "local"
CONNECT_TIMEOUT = "10s"
"""How long to wait for a remote scheduler."""
LOCAL_WORKERS = 2
"""Worker processes of the default local cluster (this machine has 2 cores)."""


RUN_PRIORITY = 10
"""Dask priority of mapped runs: above queued study steps, so a step's sweep runs before
the next step starts."""


_ADDRESS = re.compile(r"^(?:[a-z][a-z0-9+.-]*://)?[A-Za-z0-9_.-]+:[0-9]{1,5}$")
"""A Dask scheduler address: an optional protocol (``tcp://``), a host and a port."""


def check_scheduler(scheduler, where="--scheduler"):
    """Check a scheduler before anything runs: ``serial``, ``local`` or an address with a port.

    Parameters
    ----------
    scheduler : str
        What the user gave.
    where : str, optional
        How the message names it (the flag, or ``[study] scheduler``).

    Returns
    -------
    str
        ``scheduler``.

    Raises
    ------
    InputError
        Anything else, in one line.
    """
    if scheduler in (SERIAL, LOCAL) or (isinstance(scheduler, str) and _ADDRESS.match(scheduler)):
        return scheduler
    raise InputError(f"{where} = {scheduler!r}: must be serial, local or a Dask scheduler address with its port, "
                     "such as tcp://10.0.0.5:8786")


def client(stack, scheduler, n_workers=LOCAL_WORKERS):
    """A ``dask.distributed.Client`` for ``scheduler``, closed when ``stack`` closes.

    Parameters
    ----------
    stack : contextlib.ExitStack
        Owns the client (and the local cluster, if one is started).
    scheduler : str
        ``"local"`` (start a LocalCluster of single-threaded worker processes) or the
        address of a running scheduler, e.g. ``tcp://10.0.0.5:8786``.
    n_workers : int, optional
        Worker processes of a local cluster. Default 2.

    Returns
    -------
    dask.distributed.Client
        The connected client.

    Raises
    ------
    InputError
        If dask.distributed is not installed, or the scheduler at the address cannot be
        reached within 10 s.
    """
    try:
        from dask.distributed import Client, LocalCluster  # dask loads only when runs are distributed
    except ImportError:
        raise InputError("--scheduler needs dask.distributed: pip install 'dask[distributed]' "
                         "(or use --scheduler serial)") from None
    if scheduler == LOCAL:
        with _interrupt_ignored():
            cluster = stack.enter_context(LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                                                       dashboard_address=":0", silence_logs=logging.CRITICAL))
            return stack.enter_context(Client(cluster))
    try:
        return stack.enter_context(Client(scheduler, timeout=CONNECT_TIMEOUT))
    except OSError as err:
        raise InputError(f"--scheduler {scheduler}: cannot connect ({err})") from None


@contextmanager
def _interrupt_ignored():
    """Ignore SIGINT in the body, which starts a local cluster and its client.

    The worker processes started in the body inherit the disposition and keep it, so only
    this process acts on a later Ctrl-C, and shuts the cluster down. And the cluster and
    its client are made together or not at all: an interrupt in between used to leave a
    half-made client that failed in its finaliser. A Ctrl-C during the start (a few
    seconds) is therefore lost. (Blocking SIGINT instead, to deliver it afterwards, does
    not reach the workers: they are started from Dask's event-loop thread, whose signal
    mask they inherit.) Only the main thread handles signals; elsewhere this does nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def in_worker():
    """Whether the caller runs inside a task on a Dask worker.

    Returns
    -------
    bool
        True inside a task running on a Dask worker (False also without Dask).
    """
    try:
        from distributed import get_worker  # dask loads only when runs are distributed
        get_worker()
        return True
    except (ImportError, ValueError):
        return False


def recording_warnings(function, *args):
    """``function(*args)`` and the warnings it issued, recorded instead of shown.

    Parameters
    ----------
    function : callable
        The call.
    *args
        Its arguments.

    Returns
    -------
    tuple
        (result, list of ``(message, category, filename, lineno)``), for
        :func:`reissue_warnings` (picklable, so it can come back from a Dask worker).
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = function(*args)
    return result, [(w.message, w.category, w.filename, w.lineno) for w in caught]


def reissue_warnings(recorded):
    """Issue warnings recorded by :func:`recording_warnings` in this process, under its
    warning filters (a warning repeated within ``recorded`` is shown once, unless the
    filters say "always").

    Parameters
    ----------
    recorded : list of tuple
        ``(message, category, filename, lineno)`` each.
    """
    registry = {}
    for message, category, filename, lineno in recorded:
        warnings.warn_explicit(message, category, filename, lineno, registry=registry)


def map_runs(function, items, *, scheduler=SERIAL, n_workers=LOCAL_WORKERS, label="runs"):
    """``[function(item) for item in items]``, computed according to ``scheduler``.

    Called from a task already running on a Dask worker (a study step), the runs go to
    that task's cluster (``worker_client``: the waiting task gives its worker slot to the
    runs). A progress bar (:func:`ccedi.progress.progress_bar`) counts finished runs.

    Parameters
    ----------
    function : callable
        One run; must be importable by the workers (a module-level function or a
        ``functools.partial`` of one).
    items : iterable
        The run inputs.
    scheduler : str, optional
        ``"serial"``, ``"local"`` or a scheduler address (see the module docstring).
        Default ``"serial"``.
    n_workers : int, optional
        Worker processes of a local cluster. Default 2.
    label : str, optional
        Progress bar label. Default ``"runs"``.

    Returns
    -------
    list
        The results, in the order of ``items``, identical to the serial ones. The runs'
        warnings are issued again after the progress bar closes.
    """
    items = list(items)
    run = partial(recording_warnings, function)
    with ExitStack() as stack:
        bar = stack.enter_context(progress_bar(total=len(items), desc=label, unit="run"))
        if scheduler == SERIAL or not items:
            runs = []
            for item in items:
                runs.append(run(item))
                bar.update()
        else:
            from dask.distributed import as_completed, worker_client  # dask loads only when runs are distributed

            dask = stack.enter_context(worker_client()) if in_worker() else client(stack, scheduler, n_workers)
            futures = dask.map(run, items, pure=False, priority=RUN_PRIORITY)
            for _ in as_completed(futures):
                bar.update()
            runs = dask.gather(futures)
    reissue_warnings([w for _, recorded in runs for w in recorded])
    return [result for result, _ in runs]

