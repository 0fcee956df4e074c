"""The blocked, threaded hexahedron kernel in a run: the same tip history as the numpy
reference path, and the same bits for one and two threads."""

import numba as nb
import numpy as np
import pytest

from ccedi.fea.elements.hex8_kernels import BLOCK
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import elliptical_cantilever
from ccedi.fea.model import cantilever_model, tip_pulse
from ccedi.fea.solvers.explicit import run


def _model(n_section, n_along):
    mesh = elliptical_cantilever(0.05, n_section, n_along)
    return cantilever_model(mesh, RUBBER, alpha=180.0, pulses=[tip_pulse(mesh, [0.2, 1.0, 0.0], 2e-3)])


def test_run_matches_the_numpy_reference_path():
    """A short impulse run (with bulk viscosity and hourglass modes active): the compiled
    blocked kernel and the numpy reference give the same tip history within 1e-9 of its
    peak, and the same step count."""
    model = _model(3, 5)
    assert len(model.mesh.hexes) > BLOCK                  # more than one block, one of them partial
    ref = run(model, 2e-3, n_outputs=10, backend="numpy")
    new = run(model, 2e-3, n_outputs=10)
    assert new.summary["steps"] == ref.summary["steps"] > 50
    for col in ("tip_uy_m", "tip_ux_m", "internal_energy_J", "hourglass_energy_J", "bulk_viscosity_energy_J"):
        a, b = new.history[col].to_numpy(), ref.history[col].to_numpy()
        assert np.abs(a - b).max() <= 1e-9 * np.abs(b).max(), col
    assert ref.history["hourglass_energy_J"].iloc[-1] > 0.0


@pytest.mark.skipif(nb.config.NUMBA_NUM_THREADS < 2, reason="needs 2 numba threads")
def test_two_threads_give_the_same_bits_as_one():
    """Blocks and nodes shared among 2 threads: every history column and the final state
    are identical, bit for bit, to the one-thread run."""
    model = _model(4, 10)
    one = run(model, 3e-3, n_outputs=6, threads=1)
    two = run(model, 3e-3, n_outputs=6, threads=2)
    assert (one.summary["threads"], two.summary["threads"]) == (1, 2)
    assert one.history.equals(two.history)
    assert np.array_equal(one.x, two.x) and np.array_equal(one.v, two.v)
    assert np.abs(one.history["tip_uy_m"]).max() > 0.0


def test_compiled_deformation_gradients_match_the_numpy_ones():
    """The run's output path (max stress and strain at each output) takes F from the
    compiled sum: the same F as the numpy reference for hexahedra (b / V0) and for
    integration-point elements (10-node tetrahedra, 4 points), at a random deformation."""
    from ccedi.fea.elements.hex8 import deformation_gradient
    from ccedi.fea.elements.tetra import deformation_gradients, deformation_gradients_numba

    model = _model(3, 5)
    rng = np.random.default_rng(1)
    x = model.mesh.nodes + 2e-3 * rng.standard_normal(model.mesh.nodes.shape)
    g = model.geometry
    ref = deformation_gradient(x[model.mesh.hexes], g)
    new = deformation_gradients_numba(x, model.mesh.hexes, (g.b / g.volume[:, None, None])[:, None])[:, 0]
    assert np.abs(new - ref).max() <= 1e-13 * np.abs(ref).max()
    conn = rng.integers(0, len(x), size=(7, 10))
    grad = rng.standard_normal((7, 4, 10, 3))
    assert np.allclose(deformation_gradients_numba(x, conn, grad), deformation_gradients(x, conn, grad),
                       rtol=1e-13, atol=1e-13)


def test_compiled_entry_calls_the_overload_of_the_arguments_types():
    """The run's per-output call skips numba's type dispatch: the entry point returns what
    the dispatcher returns, for the types it was made for."""
    from ccedi.fea.solvers.explicit import compiled_entry

    @nb.njit
    def weighted(a, group, s):
        return s * (a * group[0]).sum() + group[1].sum()

    a, group = np.arange(5.0), (np.ones(5), np.arange(3.0))
    entry = compiled_entry(weighted, a, group, 2.0)
    assert entry is not weighted
    assert entry(a, group, 3.0) == weighted(a, group, 3.0) == 3.0 * 10.0 + 3.0
