"""Explicit dynamics of the 4.5-in SM-A finger: free vibration, Rayleigh damping, energy
balance, and clear errors."""
import numpy as np
import pytest

from ccedi.errors import InputError, SolverError
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import elliptical_cantilever
from ccedi.fea.model import cantilever_model, face_node_weights, tip_pulse
from ccedi.fea.solvers.explicit import TSSFAC, critical_time_step, run
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.fea.solvers.static import static_solve
from ccedi.rom.damping import log_decrement

PAPER_DT_US = {"SM-A": 4.04, "SM-B": 1.43}


@pytest.fixture(scope="module")
def released(mesh_a):
    """Initial positions: the small static deflection under a 0.05 N tip load (mostly mode 1)."""
    model = cantilever_model(mesh_a, RUBBER)
    tip = mesh_a.node_sets["tip"]
    f = np.zeros_like(mesh_a.nodes)
    f[tip, 1] = 0.05 * face_node_weights(mesh_a, tip)
    return static_solve(model, f, linear=True)


def free_vibration(mesh, x0, alpha):
    res = run(cantilever_model(mesh, RUBBER, alpha=alpha), 0.3, n_outputs=1500, x0=x0)
    h = res.history
    return log_decrement(h.time_s.values, h.tip_uy_m.values, y_final=0.0), res


def test_critical_time_step_near_paper(mesh_a):
    from ccedi.fea.mesh import sm_b
    for name, mesh in (("SM-A", mesh_a), ("SM-B", sm_b(length_in=4.5))):
        dt_us = 1e6 * TSSFAC * critical_time_step(cantilever_model(mesh, RUBBER))
        assert dt_us == pytest.approx(PAPER_DT_US[name], rel=0.25)


@pytest.mark.slow
def test_free_vibration_frequency_matches_euler_bernoulli(mesh_a, released, euler_bernoulli):
    ld, res = free_vibration(mesh_a, released, alpha=0.0)
    assert ld.omega_d_rad_s == pytest.approx(euler_bernoulli["omega1"], rel=0.05)
    assert ld.zeta < 0.005                                 # undamped: no artificial dissipation
    assert ld.omega_d_rad_s == pytest.approx(natural_frequencies(res_model(mesh_a), n_modes=1)[0], rel=0.01)


def res_model(mesh):
    return cantilever_model(mesh, RUBBER)


@pytest.mark.slow
def test_mass_proportional_damping_ratio(mesh_a, released):
    """Paper Eq. (3b) with beta = 0: zeta_1 = alpha / (2 omega_1)."""
    alpha = 20.0
    ld, res = free_vibration(mesh_a, released, alpha=alpha)
    omega1 = natural_frequencies(res_model(mesh_a), n_modes=1)[0]
    assert ld.zeta == pytest.approx(alpha / (2.0 * omega1), rel=0.05)
    assert ld.n_cycles >= 3


@pytest.mark.slow
def test_alpha_180_is_overdamped_with_energy_balance(mesh_a):
    """The paper's over-damped case: after the impulse the tip creeps back without
    overshooting. External work = KE + IE + HG + damping + bulk viscosity within 1 %
    (measured 0.017 %), and the run's validity checks find nothing (hourglass energy
    9.8 % of the internal energy, largest log strain 0.011)."""
    model = cantilever_model(mesh_a, RUBBER, alpha=180.0, pulses=[tip_pulse(mesh_a, [0.0, 1.0, 0.0], 0.01)])
    res = run(model, 0.2, n_outputs=400)
    h = res.history
    assert res.summary["energy_balance_error"] < 1e-3
    assert res.summary["warnings"] == []
    assert res.summary["max_log_strain"] < 0.02
    i_peak = int(h.tip_uy_m.idxmax())
    assert h.tip_uy_m[i_peak] > 1e-3
    assert h.tip_uy_m[i_peak:].min() > -0.01 * h.tip_uy_m[i_peak]
    stored = (h.kinetic_energy_J + h.internal_energy_J + h.hourglass_energy_J
              + h.damping_energy_J + h.bulk_viscosity_energy_J)
    assert (h.external_work_J - stored).abs().max() < 0.01 * h.external_work_J.max()
    assert h.damping_energy_J.iloc[-1] > 0.9 * h.external_work_J.iloc[-1]       # damping took it all
    i_ie = int(h.internal_energy_J.idxmax())
    assert h.hourglass_energy_J[i_ie] < 0.10 * h.internal_energy_J[i_ie]


@pytest.fixture(scope="module")
def small_model():
    mesh = elliptical_cantilever(0.05, 3, 6)
    return cantilever_model(mesh, RUBBER, alpha=50.0, beta=1e-6,
                            pulses=[tip_pulse(mesh, [0.3, 2.0, -0.5], 2e-3)])


def test_numba_and_numpy_backends_agree(small_model):
    a = run(small_model, 1e-3, n_outputs=3, backend="numba")
    b = run(small_model, 1e-3, n_outputs=3, backend="numpy")
    assert a.summary["steps"] == b.summary["steps"] > 100
    assert np.allclose(a.x, b.x, rtol=0, atol=1e-12)
    assert np.allclose(a.history.values, b.history.values, rtol=1e-8, atol=1e-15)


def _model_without_hexahedra(kind):
    """A short run's model whose only elements are rods, 4- or 10-node tetrahedra."""
    from ccedi.fea.cases.steel_rod import steel_rod_model
    from ccedi.fea.mesh.tet_mesh import box_cantilever, quadratic_tets, split_hexes

    if kind == "rod":
        return steel_rod_model(alpha=30.0, n_elements=10, force_N=0.03, duration_s=2e-3)
    mesh = split_hexes(box_cantilever(0.04, 0.01, 0.01, nx=2, ny=2, nz=6))
    mesh = quadratic_tets(mesh) if kind == "tet10" else mesh
    return cantilever_model(mesh, RUBBER, alpha=50.0, pulses=[tip_pulse(mesh, [0.3, 2.0, -0.5], 2e-3)])


@pytest.mark.parametrize("kind", ["rod", "tet4", "tet10"])
def test_models_without_hexahedra_agree_on_both_backends(kind):
    """The compiled step skips the kernels of element kinds a model lacks (the hexahedra's
    kernel is the one that zeroes the internal force): rods and tetrahedra alone must still
    give the reference path's motion and energies."""
    model = _model_without_hexahedra(kind)
    a = run(model, 2e-3, n_outputs=4, backend="numba", threads=1)
    b = run(model, 2e-3, n_outputs=4, backend="numpy")
    assert a.summary["steps"] == b.summary["steps"] > 20
    assert np.abs(a.x - model.mesh.nodes).max() > 1e-7             # it moved
    assert np.allclose(a.x, b.x, rtol=0, atol=1e-12)
    for column in a.history.columns:      # each within 1e-8 of its own scale (NaN: no solid strain)
        ref = b.history[column].to_numpy()
        scale = np.abs(ref).max() if np.isfinite(ref).any() else 0.0
        assert np.allclose(a.history[column], ref, rtol=0, atol=1e-8 * scale, equal_nan=True), column


def test_energy_balance_with_stiffness_damping(small_model):
    """Central-difference energy error grows with (omega dt)^2 of the excited modes: a
    pulse long against the element transit time keeps it small."""
    h = run(small_model, 4e-3, n_outputs=20).history
    stored = (h.kinetic_energy_J + h.internal_energy_J + h.hourglass_energy_J
              + h.damping_energy_J + h.bulk_viscosity_energy_J)
    assert (h.external_work_J - stored).abs().max() < 0.01 * h.external_work_J.max()


def test_time_step_above_cfl_is_refused(small_model):
    dt = critical_time_step(small_model)
    with pytest.raises(InputError, match="CFL"):
        run(small_model, 1e-3, dt_s=1.01 * dt)


def test_inverted_element_stops_the_run():
    """An element turned inside out (here in the initial positions) stops the solver with
    the element and the step, instead of producing a negative volume."""
    mesh = elliptical_cantilever(0.05, 2, 4)
    x0 = mesh.nodes.copy()
    top = mesh.hexes[5, 4:]
    x0[top, 2] -= 2.0 * (x0[top, 2] - mesh.nodes[mesh.hexes[5, :4], 2])
    with pytest.raises(SolverError, match=r"element \d+ inverted .* step 0"):
        run(cantilever_model(mesh, RUBBER), 1e-3, x0=x0)


def test_inverted_mesh_is_refused():
    mesh = elliptical_cantilever(0.05, 2, 4)
    mesh.hexes[3] = mesh.hexes[3][[4, 5, 6, 7, 0, 1, 2, 3]]
    with pytest.raises(InputError, match="element 3 is inverted"):
        cantilever_model(mesh, RUBBER)


def test_divergence_reports_the_step():
    mesh = elliptical_cantilever(0.05, 2, 4)
    model = cantilever_model(mesh, RUBBER, pulses=[tip_pulse(mesh, [0.0, 1e300, 0.0], 1e-3)])
    with pytest.raises(SolverError, match=r"diverged .* at step 1,"):
        run(model, 1e-3)


@pytest.mark.parametrize("kwargs, field", [({"alpha": -1.0}, "alpha"), ({"alpha": float("nan")}, "alpha"),
                                           ({"beta": -1e-6}, "beta")])
def test_bad_damping_is_named(mesh_a, kwargs, field):
    with pytest.raises(InputError, match=field):
        cantilever_model(mesh_a, RUBBER, **kwargs)


def test_bad_initial_state_is_named(small_model):
    x0 = small_model.mesh.nodes.copy()
    x0[3, 1] = np.nan
    with pytest.raises(InputError, match="x0"):
        run(small_model, 1e-4, x0=x0)
    with pytest.raises(InputError, match="t_end_s"):
        run(small_model, -1.0)
