"""Static stiffness against the paper's Table 1 and Euler-Bernoulli; the consistent tangent."""
import numpy as np
import pytest
from conftest import finite_difference_tangent

from ccedi.errors import InputError
from ccedi.fea.cases.studies import table1_row
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import elliptical_cantilever, sm_a, sm_b
from ccedi.fea.model import cantilever_model
from ccedi.fea.solvers.static import static_path, static_solve, tangent_stiffness, tip_deflection, tip_stiffness


def test_tangent_is_derivative_of_internal_force():
    model = cantilever_model(elliptical_cantilever(0.04, 2, 3), RUBBER)
    rng = np.random.default_rng(3)
    x = model.mesh.nodes + 1e-3 * rng.standard_normal(model.mesh.nodes.shape)
    K = tangent_stiffness(model, x).toarray()
    h = 1e-8
    K_fd = finite_difference_tangent(model, x, h)
    assert np.abs(K - K_fd).max() < 1e-6 * np.abs(K).max()


@pytest.mark.slow
def test_sm_a_tip_stiffness_matches_paper_table1():
    """Paper Table 1: 73.8 N/m for SM-A from tip loads of 1 N and 2 N, as the table1
    command's row computes it (tip_stiffness, nonlinear static solves)."""
    assert table1_row(sm_a(length_in=4.5), RUBBER)["stiffness_N_per_m"] == pytest.approx(73.8, rel=0.10)


def test_refined_small_load_stiffness_matches_euler_bernoulli(euler_bernoulli):
    model = cantilever_model(sm_b(length_in=4.5), RUBBER)
    k = 1.0 / tip_deflection(model, 1.0, linear=True)
    assert k == pytest.approx(euler_bernoulli["k_tip"], rel=0.05)


def test_newton_converges_to_linear_answer_at_small_load():
    model = cantilever_model(sm_a(length_in=4.5), RUBBER)
    u_lin = tip_deflection(model, 1e-3, linear=True)
    u_nl = tip_deflection(model, 1e-3)
    assert u_nl == pytest.approx(u_lin, rel=1e-3)


def test_static_solve_rejects_bad_load(mesh_a):
    from ccedi.errors import InputError
    model = cantilever_model(mesh_a, RUBBER)
    f = np.zeros_like(mesh_a.nodes)
    f[0, 0] = np.nan
    with pytest.raises(InputError, match="f_ext"):
        static_solve(model, f)


def test_a_load_path_reaches_the_equilibria_of_separate_solves():
    """The equilibria along one load path (1 N, then 2 N at the tip of a coarse 4.5-in
    finger, 14 % of its length at 2 N) are those of separate solves from rest, and the
    Table 1 stiffness from the path is the mean of F / delta of the separate solves."""
    model = cantilever_model(elliptical_cantilever(0.1143, 3, 20), RUBBER)
    tip = model.mesh.node_sets["tip"]
    f = np.zeros_like(model.mesh.nodes)
    f[tip, 1] = 2.0 / len(tip)
    path = static_path(model, f, (0.5, 1.0))
    for factor, x in zip((0.5, 1.0), path):
        alone = static_solve(model, factor * f)
        np.testing.assert_allclose(x, alone, atol=1e-9)
    assert np.max(np.abs(path[1] - path[0])) > 1e-3                 # two different equilibria
    separate = np.mean([F / tip_deflection(model, F) for F in (1.0, 2.0)])
    assert tip_stiffness(model) == pytest.approx(separate, rel=1e-7)
    for loads in ((0.0, 1.0), (1.0, 1.0), (-1.0,)):
        with pytest.raises(InputError, match="loads_N"):
            tip_stiffness(model, loads)
    with pytest.raises(InputError, match="load_factors"):
        static_path(model, f, (1.0, 0.5))
