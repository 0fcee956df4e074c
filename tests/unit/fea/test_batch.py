"""Batched runs (lanes across runs): every run the same bits as the run alone."""
import numpy as np
import pytest

from ccedi.errors import InputError, SolverError
from ccedi.fea.elements.hex8 import internal_forces_numpy
from ccedi.fea.elements.hex8_kernels import internal_forces_numba
from ccedi.fea.elements.hex8_lanes import LANE_COUNTS, full_stiffness, lanes_kernel
from ccedi.fea.material import RUBBER, NeoHookean
from ccedi.fea.mesh import elliptical_cantilever
from ccedi.fea.mesh.tet_mesh import box_cantilever, split_hexes
from ccedi.fea.model import cantilever_model, tip_pulse
from ccedi.fea.solvers.batch import batch_refusal, run_batch
from ccedi.fea.solvers.explicit import SolidMaterial, run


@pytest.fixture(scope="module")
def mesh():
    return elliptical_cantilever(0.05, 3, 6)


def _model(mesh, alpha, force=1.0, **kw):
    return cantilever_model(mesh, RUBBER, alpha=alpha, pulses=[tip_pulse(mesh, [0.2, force, 0.0], 2e-3)], **kw)


def _perturbed_states(mesh, lanes, seed=0):
    rng = np.random.default_rng(seed)
    x = mesh.nodes[:, :, None] + 2e-4 * rng.standard_normal(mesh.nodes.shape + (lanes,))
    v = 0.2 * rng.standard_normal(x.shape)
    return np.ascontiguousarray(x), np.ascontiguousarray(v)


@pytest.mark.parametrize("lanes", LANE_COUNTS)
def test_lanes_kernel_gives_each_run_the_single_run_kernels_bits(mesh, lanes):
    """Internal forces, critical step and energies of each lane equal, bit for bit, the
    single-run kernel's on that lane's state (compressed and stretched elements, so the
    bulk viscosity is on in some), and agree with the numpy reference to 1e-12."""
    model = _model(mesh, 0.0)
    group, material = model.hexahedra, SolidMaterial(*model.solid_constants)
    x, v = _perturbed_states(mesh, lanes)
    f = np.zeros_like(x)
    result = np.zeros((5, lanes))
    lanes_kernel(lanes)(x, v, group, full_stiffness(group), material, 0, f, result)
    for k in range(lanes):
        xk, vk = np.ascontiguousarray(x[:, :, k]), np.ascontiguousarray(v[:, :, k])
        single = np.zeros_like(xk)
        values = internal_forces_numba(xk, vk, group, material, single)
        assert np.array_equal(f[:, :, k], single)
        assert tuple(result[:4, k]) == values[:4] and result[4, k] == values[4] == -1
        reference = np.zeros_like(xk)
        internal_forces_numpy(xk, vk, group.hexes, b=group.b, volume=group.volume, gamma=group.gamma,
                              kappa=group.kappa, length_factor=group.length_factor, mu=material.mu,
                              lam=material.lam, rho=material.rho, c=material.c, f=reference)
        assert np.abs(f[:, :, k] - reference).max() <= 1e-12 * np.abs(reference).max()


def _same(single, batched):
    """Every history column, the step count and the final state identical."""
    for column in single.history.columns:
        assert np.array_equal(single.history[column].to_numpy(), batched.history[column].to_numpy()), column
    assert single.summary["steps"] == batched.summary["steps"]
    assert single.summary["dt_min_s"] == batched.summary["dt_min_s"]
    assert np.array_equal(single.x, batched.x) and np.array_equal(single.v, batched.v)


@pytest.mark.parametrize("threads", [1, 2])
def test_batched_runs_are_the_single_runs_bit_for_bit(mesh, threads):
    """Five runs (a partly filled group of lanes) differing in alpha, load and initial
    velocity, each with its own CFL step and step count."""
    rng = np.random.default_rng(1)
    models = [_model(mesh, alpha, force) for alpha, force in
              [(0.0, 1.0), (50.0, 2.0), (180.0, 0.5), (400.0, 1.0), (90.0, -1.0)]]
    v0 = [None, 0.01 * rng.standard_normal(mesh.nodes.shape), None, None, None]
    batched = run_batch(models, 4e-3, n_outputs=7, v0=v0, threads=threads)
    steps = set()
    for k, model in enumerate(models):
        single = run(model, 4e-3, n_outputs=7, v0=v0[k], threads=1)
        _same(single, batched[k])
        steps.add(single.summary["steps"])
    assert len(steps) > 1                      # the runs' steps differ: each lane keeps its own clock


def test_stiffness_damping_in_a_batch_is_the_single_run(mesh):
    models = [_model(mesh, alpha, beta=2e-6) for alpha in (10.0, 200.0)]
    for single_model, batched in zip(models, run_batch(models, 2e-3, n_outputs=4)):
        _same(run(single_model, 2e-3, n_outputs=4), batched)


def test_a_failed_run_is_named(mesh):
    """A lane that starts from a mirrored (inverted) finger fails as its run alone does,
    and the error names its run; the other lane is unaffected until then."""
    models = [_model(mesh, 100.0), _model(mesh, 100.0)]
    mirrored = mesh.nodes * np.array([1.0, 1.0, -1.0])
    with pytest.raises(SolverError, match=r"run 1 of the batch \(alpha = 100 1/s\): .*inverted"):
        run_batch(models, 2e-3, n_outputs=4, x0=[None, mirrored], threads=1)
    with pytest.raises(SolverError, match="inverted"):
        run(models[1], 2e-3, n_outputs=4, x0=mirrored)


def test_batch_refusal_names_what_differs(mesh):
    assert batch_refusal([_model(mesh, 10.0), _model(mesh, 20.0, force=3.0)]) is None
    soft = NeoHookean(0.5 * RUBBER.E, RUBBER.nu, RUBBER.rho)
    other = cantilever_model(mesh, soft, alpha=10.0)
    assert "material" in batch_refusal([_model(mesh, 10.0), other])
    assert "beta" in batch_refusal([_model(mesh, 10.0), _model(mesh, 10.0, beta=1e-6)])
    tets = split_hexes(box_cantilever(0.01, 0.01, 0.01, nx=2, ny=2, nz=3))
    assert "hexahedra only" in batch_refusal([cantilever_model(tets, RUBBER, alpha=1.0)])
    with pytest.raises(InputError, match="cannot be batched: .*material"):
        run_batch([_model(mesh, 10.0), other], 1e-3)
