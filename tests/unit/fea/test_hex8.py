"""The one-point hexahedron: patch tests, objectivity, and the numba kernel against numpy."""
import numpy as np
import pytest
from conftest import hex_forces
from scipy.spatial.transform import Rotation

from ccedi.fea.elements.hex8 import characteristic_length, element_geometry, element_time_step, internal_forces_numpy
from ccedi.fea.elements.hex8_kernels import internal_forces_numba
from ccedi.fea.material import RUBBER, first_piola
from ccedi.fea.mesh import elliptical_cantilever
from ccedi.fea.model import cantilever_model


@pytest.fixture(scope="module")
def small_model():
    return cantilever_model(elliptical_cantilever(0.05, 3, 5), RUBBER)


def test_homogeneous_deformation_patch_test(small_model):
    """x = F0 X: zero hourglass energy, interior nodes in equilibrium, and the first moment
    of the nodal forces equals P(F0) times the volume (divergence theorem)."""
    F0 = np.array([[1.1, 0.05, 0.0], [0.02, 0.95, 0.1], [0.0, -0.03, 1.2]])
    X = small_model.mesh.nodes
    f, (_, w, hg, _, status) = hex_forces(small_model, X @ F0.T)
    assert status == -1 and hg == pytest.approx(0.0, abs=1e-12 * w)
    volume = small_model.geometry.volume.sum()
    P = first_piola(F0[None], small_model.material.mu, small_model.material.lam)[0]
    assert np.allclose(f.T @ X, P * volume, rtol=1e-9, atol=1e-9 * np.abs(P).max() * volume)
    counts = np.bincount(small_model.mesh.hexes.ravel(), minlength=len(X))
    interior = counts == 8
    assert interior.any()
    assert np.abs(f[interior]).max() < 1e-9 * np.abs(f).max()


def test_rigid_rotation_produces_no_force(small_model):
    R = Rotation.from_rotvec([0.7, -1.1, 2.0]).as_matrix()
    X = small_model.mesh.nodes
    f, (_, w, hg, _, _) = hex_forces(small_model, X @ R.T + [0.3, -0.1, 2.0])
    assert np.abs(f).max() < 1e-6          # N; forces of a 1 % stretch are ~ 1e2 N here
    assert abs(w) < 1e-12 and abs(hg) < 1e-12


def test_numba_kernel_matches_numpy_reference(small_model):
    rng = np.random.default_rng(0)
    X = small_model.mesh.nodes
    x = X + 2e-4 * rng.standard_normal(X.shape)
    v = 0.05 * rng.standard_normal(X.shape)                # includes compression: bulk viscosity active
    f_ref, out_ref = hex_forces(small_model, x, v)
    f_nb, out_nb = hex_forces(small_model, x, v, kernel=internal_forces_numba)
    assert np.allclose(f_nb, f_ref, rtol=1e-10, atol=1e-12 * np.abs(f_ref).max())
    assert np.allclose(out_nb[:4], out_ref[:4], rtol=1e-10) and out_nb[4] == out_ref[4] == -1
    assert out_ref[3] > 0.0                                  # bulk viscosity dissipates


def test_inverted_element_is_reported(small_model):
    x = small_model.mesh.nodes.copy()
    e = 7
    nodes = small_model.mesh.hexes[e]
    x[nodes[4:]] = x[nodes[:4]] - (x[nodes[4:]] - x[nodes[:4]])     # fold the element through itself
    for kernel in (internal_forces_numpy, internal_forces_numba):
        *_, status = hex_forces(small_model, x, kernel=kernel)[1]
        assert status >= 0


def test_time_step_of_a_cube_is_side_over_wave_speed():
    """Unit-cube element at rest: Le = V / A_max = h, dt = h / c (paper Eq. 6, Q = 0)."""
    h = 2e-3
    nodes = h * np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    g = element_geometry(nodes, np.arange(8)[None])
    Le = characteristic_length(nodes[None], g.volume)
    assert Le[0] == pytest.approx(h)
    assert element_time_step(Le, RUBBER.wave_speed, np.zeros(1))[0] == pytest.approx(h / RUBBER.wave_speed)
    # compression adds bulk viscosity and shortens the step
    assert element_time_step(Le, RUBBER.wave_speed, -np.ones(1) * 100.0)[0] < h / RUBBER.wave_speed
