"""Static stiffness against the paper's Table 1 and Euler-Bernoulli; the consistent tangent."""
import numpy as np
import pytest
from conftest import finite_difference_tangent

from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import elliptical_cantilever, sm_a, sm_b
from ccedi.fea.model import cantilever_model
from ccedi.fea.static import static_solve, tangent_stiffness, tip_deflection
from ccedi.fea.studies import table1_row


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
