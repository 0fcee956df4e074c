"""An alpha sweep through a 2-worker Dask local cluster equals the batched serial run."""
from functools import partial

import pandas as pd
import pytest

from ccedi.distributed import map_runs
from ccedi.errors import InputError
from ccedi.fea.cases.studies import _impulse_run, impulse_study


@pytest.mark.slow
def test_alpha_sweep_local_cluster_equals_serial():
    """Single runs on two Dask workers give, bit for bit, the sweep's one batched pass (four
    runs: fewer go one by one)."""
    alphas = (70.0, 180.0, 250.0, 400.0)
    serial, summaries = impulse_study(alphas=alphas, scheduler="serial", length_in=3.0, t_end_s=0.02, n_outputs=40)
    runs = map_runs(partial(_impulse_run, finger={"length_in": 3.0}, t_end_s=0.02, n_outputs=40), alphas,
                    scheduler="local")
    local = pd.concat([h for h, _ in runs], ignore_index=True)
    assert len(summaries) == 4 and summaries[0]["batch_runs"] == 4
    assert list(local.alpha_per_s.unique()) == list(alphas)
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
