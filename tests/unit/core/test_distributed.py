"""An alpha sweep through a 2-worker Dask local cluster equals the serial run."""
import pandas as pd
import pytest

from ccedi.distributed import map_runs
from ccedi.errors import InputError
from ccedi.fea.cases.studies import impulse_study


@pytest.mark.slow
def test_alpha_sweep_local_cluster_equals_serial():
    kwargs = dict(alphas=(70.0, 180.0, 400.0), length_in=3.0, t_end_s=0.02, n_outputs=40)
    serial, _ = impulse_study(scheduler="serial", **kwargs)
    local, summaries = impulse_study(scheduler="local", **kwargs)
    assert len(summaries) == 3
    assert list(local.alpha_per_s.unique()) == [70.0, 180.0, 400.0]
    pd.testing.assert_frame_equal(local, serial, check_exact=True)


def test_unreachable_scheduler_is_one_clear_error(monkeypatch):
    monkeypatch.setattr("ccedi.distributed.CONNECT_TIMEOUT", "1s")
    with pytest.raises(InputError, match="cannot connect"):
        map_runs(abs, [1.0], scheduler="tcp://127.0.0.1:1")


@pytest.mark.slow
def test_warnings_of_runs_on_workers_come_back_once():
    """A warning issued on a Dask worker is issued again in the caller, once, in input order."""
    import warnings
    from functools import partial

    from ccedi.errors import ValidityWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        map_runs(partial(warnings.warn, category=ValidityWarning), ["first", "second"], scheduler="local")
    assert [(str(w.message), w.category) for w in caught] == [("first", ValidityWarning),
                                                               ("second", ValidityWarning)]
