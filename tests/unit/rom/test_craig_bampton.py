"""Craig-Bampton reduction: static condensation is exact for boundary loads, and keeping
every interior mode reproduces the full model's frequencies."""
import numpy as np
import pytest
from scipy.linalg import eigh

from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import elliptical_cantilever, sm_a
from ccedi.fea.model import cantilever_model, face_node_weights
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.fea.solvers.static import tip_deflection
from ccedi.rom.craig_bampton import craig_bampton, fe_matrices


def tip_dofs(model, direction=1):
    return 3 * model.mesh.node_sets["tip"] + direction


def test_static_condensation_reproduces_tip_stiffness():
    model = cantilever_model(sm_a(length_in=4.5), RUBBER)
    K, M, dofs = fe_matrices(model)
    tip = model.mesh.node_sets["tip"]
    boundary = np.concatenate([3 * tip, 3 * tip + 1, 3 * tip + 2])
    cb = craig_bampton(K, M, dofs, boundary_dofs=boundary, n_modes=0)
    f = np.zeros(len(dofs))
    f[np.searchsorted(dofs, tip_dofs(model))] = face_node_weights(model.mesh, tip)
    z = np.linalg.solve(cb.K_r, cb.reduce_force(f))
    u = cb.expand(z)
    deflection = face_node_weights(model.mesh, tip) @ u[np.searchsorted(dofs, tip_dofs(model))]
    assert deflection == pytest.approx(tip_deflection(model, 1.0, linear=True), rel=1e-9)


def test_all_interior_modes_reproduce_frequencies():
    model = cantilever_model(elliptical_cantilever(0.05, 2, 3), RUBBER)
    K, M, dofs = fe_matrices(model)
    boundary = tip_dofs(model)
    n_interior = len(dofs) - len(boundary)
    cb = craig_bampton(K, M, dofs, boundary_dofs=boundary, n_modes=n_interior)
    w2 = eigh(cb.K_r, cb.M_r, eigvals_only=True)
    assert np.allclose(np.sqrt(w2[:6]), natural_frequencies(model, n_modes=6), rtol=1e-8)


def test_few_modes_converge_from_above():
    """Rayleigh-Ritz: a reduced basis can only raise the frequencies, and more
    interface modes bring them down towards the full values."""
    model = cantilever_model(sm_a(length_in=4.5), RUBBER)
    K, M, dofs = fe_matrices(model)
    full = natural_frequencies(model, n_modes=3)
    errors = []
    for n in (2, 6, 12):
        cb = craig_bampton(K, M, dofs, boundary_dofs=tip_dofs(model), n_modes=n)
        w = np.sqrt(eigh(cb.K_r, cb.M_r, eigvals_only=True)[:3])
        assert np.all(w >= full * (1 - 1e-9))
        errors.append(w[0] / full[0] - 1)
    assert errors[0] >= errors[1] >= errors[2] and errors[2] < 1e-3


def test_bad_boundary_is_named():
    from ccedi.errors import InputError
    model = cantilever_model(elliptical_cantilever(0.05, 2, 3), RUBBER)
    K, M, dofs = fe_matrices(model)
    with pytest.raises(InputError, match="boundary_dofs"):
        craig_bampton(K, M, dofs, boundary_dofs=3 * model.mesh.node_sets["root"], n_modes=2)   # clamped DOFs
