"""The thread count of the compiled kernels: a request checked against numba's threads,
else the environment variable, else the free cores, and one core beside Dask."""
import os

import numba as nb
import pytest
from distributed import Client, LocalCluster

from ccedi import threads
from ccedi.errors import InputError
from ccedi.threads import thread_count


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, 10**6])
def test_thread_count_out_of_range_is_refused(bad):
    with pytest.raises(InputError, match="threads"):
        thread_count(bad)


def test_thread_count_default_takes_the_free_cores(monkeypatch):
    """Without a request: the environment variable, else the free cores (never more than
    numba has), and a bad variable is refused with its name."""
    top = nb.config.NUMBA_NUM_THREADS
    monkeypatch.delenv(threads.THREADS_ENV, raising=False)
    for free in (1, top, top + 5):
        monkeypatch.setattr(threads, "free_cores", lambda free=free: free)
        assert thread_count() == min(free, top)
    monkeypatch.setenv(threads.THREADS_ENV, "1")
    assert thread_count() == 1
    for bad in ("0", "two", str(top + 1)):
        monkeypatch.setenv(threads.THREADS_ENV, bad)
        with pytest.raises(InputError, match=threads.THREADS_ENV):
            thread_count()
    assert thread_count(top) == top


def test_free_cores_counts_at_least_one_and_at_most_the_cpus():
    assert 1 <= threads.free_cores(0.01) <= os.cpu_count()


def test_a_process_driving_dask_runs_on_one_thread(monkeypatch):
    """With a Dask client its workers share the cores, which may look free between their
    tasks: the default is then one thread, in the client's process and in the workers."""
    monkeypatch.delenv(threads.THREADS_ENV, raising=False)
    monkeypatch.setattr(threads, "free_cores", lambda: 2)
    top = min(2, nb.config.NUMBA_NUM_THREADS)
    assert thread_count() == top
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        assert thread_count() == 1
        assert client.submit(threads._shares_cores_with_dask).result()
    assert thread_count() == top
