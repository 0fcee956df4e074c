"""How many threads a compiled kernel uses: the free cores, unless told.

Every explicit step waits at a barrier for all its threads, so a thread on a core another
job also uses stalls the whole run; the default therefore takes only the cores nothing
else is busy on, and one core inside Dask (a sweep runs one model per worker).
"""
import os
import sys

import numba as nb
import psutil

from ccedi.errors import InputError

THREADS_ENV = "CCEDI_THREADS"
"""Environment variable that sets the default thread count of an explicit run (an integer in
1 .. the cores), e.g. 1 in a test suite whose workers share the cores."""

IDLE_CPU_PERCENT = 50.0
"""A core counts as free for a run when it was busy less than this share [%] of a short
sampling window (:func:`free_cores`)."""


def free_cores(window_s=0.05):
    """Cores nothing else is using (psutil's per-CPU times).

    Parameters
    ----------
    window_s : float, optional
        Sampling window [s]. Default 0.05.

    Returns
    -------
    int
        The cores busy less than :data:`IDLE_CPU_PERCENT` of the window, at least 1.
    """
    busy = psutil.cpu_percent(interval=window_s, percpu=True)
    return max(1, sum(1 for p in busy if p < IDLE_CPU_PERCENT))


def _shares_cores_with_dask():
    """True in a Dask worker, and in a process with a Dask client: its workers run beside
    it, so the cores that look free between their tasks are not."""
    if "distributed" not in sys.modules:
        return False
    from distributed import get_worker  # only to ask whether this process is a Dask worker or client
    from distributed.client import _get_global_client  # only to ask whether this process is a Dask worker or client

    try:
        get_worker()
    except ValueError:
        return _get_global_client() is not None
    return True


def thread_count(threads=None):
    """Number of threads the compiled force kernels of a run use.

    Parameters
    ----------
    threads : int, optional
        Requested count, 1 .. ``numba.config.NUMBA_NUM_THREADS`` (the cores, unless the
        environment variable NUMBA_NUM_THREADS sets fewer). Default None: the variable
        :data:`THREADS_ENV` if set; 1 in a Dask worker (a sweep runs one model per
        worker) and in a process with a Dask client (its workers share the cores); else
        every free core (:func:`free_cores`). Every step waits at a barrier
        for all its threads, so a thread on a core that another job also uses stalls it
        (measured: 2 threads 18 x slower than 1 at load 20 on 2 cores): hence only the
        free cores.

    Returns
    -------
    int
        The thread count. Results do not depend on it (bit for bit).

    Raises
    ------
    InputError
        If ``threads`` or :data:`THREADS_ENV` is not an integer in that range.
    """
    top = nb.config.NUMBA_NUM_THREADS
    if threads is None:
        env = os.environ.get(THREADS_ENV)
        if env is not None:
            try:
                threads = int(env)
            except ValueError:
                raise InputError(f"{THREADS_ENV} = {env!r}: must be an integer in 1..{top}") from None
            if not 1 <= threads <= top:
                raise InputError(f"{THREADS_ENV} = {env!r}: must be an integer in 1..{top}")
            return threads
        if _shares_cores_with_dask():
            return 1
        return min(top, free_cores())
    if isinstance(threads, bool) or int(threads) != threads or not 1 <= threads <= top:
        raise InputError(f"threads = {threads!r}: must be an integer in 1..{top}")
    return int(threads)
