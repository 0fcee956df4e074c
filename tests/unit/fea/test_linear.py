"""The factorised tangent: the solvers against a direct solve, the static solves that reuse
their factors against full Newton, and the modal solve's repeatability."""
import numpy as np
import pytest
import scipy.sparse as sp

from ccedi.errors import SolverError
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import elliptical_cantilever
from ccedi.fea.mesh.tet_mesh import box_cantilever, quadratic_tets, split_hexes
from ccedi.fea.model import cantilever_model
from ccedi.fea.solvers import linear, static
from ccedi.fea.solvers.linear import Factorization
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.fea.solvers.static import free_dofs, tangent_stiffness, tip_stiffness

SOLVERS = ["superlu"] + (["pardiso"] if linear.pypardiso is not None else [])


@pytest.fixture(scope="module")
def tangent():
    model = cantilever_model(elliptical_cantilever(0.05, 3, 8), RUBBER)
    free = free_dofs(model)
    return tangent_stiffness(model)[free][:, free].tocsc()


@pytest.mark.parametrize("solver", SOLVERS)
def test_a_factorisation_solves_the_tangent(tangent, solver):
    """K x = b for one and for several right-hand sides, to round-off, as a dense solve."""
    rng = np.random.default_rng(1)
    b = rng.standard_normal((tangent.shape[0], 3))
    factors = Factorization(tangent, solver=solver)
    x = factors.solve(b)
    ref = np.linalg.solve(tangent.toarray(), b)
    assert np.abs(x - ref).max() <= 1e-9 * np.abs(ref).max()
    scale = np.abs(x).max()
    assert np.abs(factors.solve(b[:, 0]) - x[:, 0]).max() <= 1e-12 * scale
    assert np.abs(factors.operator().matvec(b[:, 1]) - x[:, 1]).max() <= 1e-12 * scale


@pytest.mark.parametrize("solver", SOLVERS)
def test_an_indefinite_tangent_is_solved(tangent, solver):
    """A Newton iterate away from equilibrium can have an indefinite tangent: the tangent
    shifted between its 3rd and 4th eigenvalues (three negative) is solved as by a dense
    solve."""
    low = np.linalg.eigvalsh(tangent.toarray())[:4]
    shifted = (tangent - 0.5 * (low[2] + low[3]) * sp.eye(tangent.shape[0])).tocsc()
    b = np.random.default_rng(2).standard_normal(tangent.shape[0])
    ref = np.linalg.solve(shifted.toarray(), b)
    assert np.abs(Factorization(shifted, solver=solver).solve(b) - ref).max() <= 1e-8 * np.abs(ref).max()


@pytest.mark.skipif(linear.pypardiso is None, reason="pypardiso (MKL) is not installed here")
def test_pardiso_and_superlu_give_the_same_tip_stiffness(monkeypatch):
    """The nonlinear tip stiffness (whose Newton iterates pass through indefinite tangents)
    is the same with either library, within the Newton tolerance."""
    model = cantilever_model(elliptical_cantilever(0.1, 3, 12), RUBBER)
    results = {}
    for solver in ("pardiso", "superlu"):
        monkeypatch.setattr(linear, "SOLVER", solver)
        results[solver] = tip_stiffness(model, (1.0, 2.0))
    assert results["pardiso"] == pytest.approx(results["superlu"], rel=1e-7)


@pytest.mark.parametrize("solver", SOLVERS)
def test_a_singular_tangent_is_an_error_not_a_huge_solution(tangent, solver):
    """A tangent with a free rigid-body motion (a DOF decoupled with zero stiffness): SuperLU
    finds the factor singular, PARDISO perturbs the pivot and would solve on; both raise
    the same SolverError, on a first factorisation and on a refactorisation."""
    K = tangent.tolil()
    K[:, 0] = 0.0
    K[0, :] = 0.0
    K = K.tocsc()
    with pytest.raises(SolverError, match="singular.*check the supports"):
        Factorization(K, solver=solver)
    with pytest.raises(SolverError, match="singular"):
        Factorization(tangent, solver=solver).refactorized(K)


def test_an_unknown_solver_or_a_rectangular_matrix_is_refused(tangent):
    with pytest.raises(ValueError, match="solver = 'umfpack'"):
        Factorization(tangent, solver="umfpack")
    with pytest.raises(ValueError, match="square"):
        Factorization(sp.eye(4, 3, format="csc"), solver="superlu")


@pytest.mark.parametrize("make", [lambda: elliptical_cantilever(0.05, 3, 8),
                                  lambda: quadratic_tets(split_hexes(box_cantilever(0.05, 0.012, 0.008, nx=2, ny=2,
                                                                                    nz=10)))],
                         ids=["hex8", "tet10"])
def test_reused_factors_give_full_newtons_stiffness_with_fewer_factorisations(make, monkeypatch):
    """The tip stiffness (two nonlinear static solves) with each correction solved by
    conjugate gradients on an earlier tangent's factors equals direct full Newton's within
    1e-9, and factorises fewer times."""
    model = cantilever_model(make(), RUBBER)
    made = []

    class Counted(Factorization):
        def __init__(self, K, solver=None):
            made.append(K.shape[0])
            super().__init__(K, solver)

    monkeypatch.setattr(static, "Factorization", Counted)
    monkeypatch.setattr(linear, "SOLVER", "superlu")        # the reuse is SuperLU's strategy
    reused = tip_stiffness(model, (0.2, 0.4))
    n_reused = len(made)
    monkeypatch.setattr(static, "PRECONDITIONED_ITERATIONS", {"superlu": 0})
    made.clear()
    full = tip_stiffness(model, (0.2, 0.4))
    assert reused == pytest.approx(full, rel=1e-9)
    assert n_reused < len(made), (n_reused, len(made))


def test_the_modal_solve_is_repeatable_to_the_bit():
    model = cantilever_model(elliptical_cantilever(0.05, 3, 8), RUBBER)
    a = natural_frequencies(model, n_modes=4, return_modes=True)
    b = natural_frequencies(model, n_modes=4, return_modes=True)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])


@pytest.mark.parametrize("solver", SOLVERS)
def test_refactorized_factors_solve_the_new_matrix(tangent, solver):
    """Factors of a matrix with the same pattern and other values (PARDISO: on the kept
    analysis) solve it as a dense solve; the factors handed over can no longer solve."""
    first = Factorization(tangent, solver=solver)
    changed = (tangent + 0.3 * sp.diags(tangent.diagonal())).tocsc()
    b = np.random.default_rng(3).standard_normal(tangent.shape[0])
    second = first.refactorized(changed)
    ref = np.linalg.solve(changed.toarray(), b)
    assert np.abs(second.solve(b) - ref).max() <= 1e-9 * np.abs(ref).max()
    if solver == "pardiso":
        with pytest.raises(RuntimeError, match="handed over"):
            first.solve(b)
