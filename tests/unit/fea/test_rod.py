"""The discrete Kirchhoff rod and point mass: exact gradient, objectivity, Euler-Bernoulli
statics, and the paper's steel rod frequency (section 2.2)."""
import numpy as np
import pytest
from conftest import ROD_ELEMENTS
from scipy.spatial.transform import Rotation

from ccedi.errors import InputError
from ccedi.fea.cases.beam_theory import cantilever_frequencies
from ccedi.fea.cases.steel_rod import PAPER_ROD, STEEL_ROD, steel_rod_model
from ccedi.fea.elements.rod import RodSection, rod_arrays, rod_forces_numba, rod_forces_numpy, straight_rod
from ccedi.fea.mesh import Mesh
from ccedi.fea.model import ForcePulse, Model
from ccedi.fea.solvers.explicit import run
from ccedi.rom.damping import log_decrement

STEEL = RodSection(E=STEEL_ROD["E_Pa"], rho=STEEL_ROD["rho_kg_per_m3"], diameter_m=STEEL_ROD["diameter_m"])


def bent_rod(seed=0):
    nodes, rod, _, _ = straight_rod(0.1, 12, STEEL)
    rng = np.random.default_rng(seed)
    x = nodes + 2e-3 * rng.standard_normal(nodes.shape)
    return nodes, x, rod_arrays(nodes, [rod])


def forces(x, ra, kernel=rod_forces_numpy):
    f = np.zeros_like(x)
    energy, status = kernel(x, ra.segments, ra.rest_length, ra.axial_stiffness, ra.hinges, ra.bending_stiffness, f)
    assert status == -1
    return f, energy


def test_rod_forces_are_the_energy_gradient():
    _, x, ra = bent_rod()
    f, _ = forces(x, ra)
    h = 1e-8
    fd = np.empty(x.size)
    for d in range(x.size):
        dx = np.zeros(x.size)
        dx[d] = h
        fd[d] = (forces(x + dx.reshape(x.shape), ra)[1] - forces(x - dx.reshape(x.shape), ra)[1]) / (2 * h)
    assert np.allclose(f.ravel(), fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())


def test_numba_rod_kernel_matches_numpy():
    _, x, ra = bent_rod(1)
    f_ref, e_ref = forces(x, ra)
    f_nb, e_nb = forces(x, ra, rod_forces_numba)
    assert np.allclose(f_nb, f_ref, rtol=1e-10, atol=1e-12 * np.abs(f_ref).max()) and e_nb == pytest.approx(e_ref)


def test_rod_energy_is_invariant_under_large_rotation():
    _, x, ra = bent_rod(2)
    R = Rotation.from_rotvec([1.2, -0.4, 2.5]).as_matrix()
    f, e = forces(x, ra)
    f_rot, e_rot = forces(x @ R.T + [1.0, 2.0, 3.0], ra)
    assert e_rot == pytest.approx(e, rel=1e-10)
    assert np.allclose(f_rot, f @ R.T, atol=1e-9 * np.abs(f).max())


def test_rod_tip_stiffness_matches_euler_bernoulli():
    """Dynamic relaxation: a constant 1e-4 N tip load on a 20-element rod with near-critical
    mass damping settles to the Euler-Bernoulli deflection F L^3 / (3 E I)."""
    L, F = 0.4, 1e-4
    nodes, rod, root, tip = straight_rod(L, 20, STEEL)
    mesh = Mesh(nodes=nodes, hexes=np.zeros((0, 8), np.int64), node_sets={"root": root, "tip": np.array([tip])})
    omega1 = cantilever_frequencies(STEEL.E, STEEL.rho, L, area=STEEL.area, second_moment=STEEL.second_moment)[0]
    pulse = ForcePulse(nodes=np.array([tip]), weights=np.ones(1), force_N=[0, F, 0], t_start_s=0.0, t_end_s=10.0)
    model = Model(mesh=mesh, material=None, alpha=2.0 * omega1, fixed_nodes=root, pulses=(pulse,), rods=(rod,))
    res = run(model, 1.5, n_outputs=10)
    deflection = res.history.tip_uy_m.iloc[-1]
    assert deflection == pytest.approx(F * L**3 / (3 * STEEL.E * STEEL.second_moment), rel=0.02)


@pytest.fixture(scope="module")
def undamped_rod_response():
    """The paper's rod, undamped, on ROD_ELEMENTS elements (converged for mode 1, conftest)."""
    return run(steel_rod_model(alpha=0.0, n_elements=ROD_ELEMENTS), 1.4, n_outputs=1400).history


@pytest.mark.slow
def test_steel_rod_first_frequency_matches_paper(undamped_rod_response):
    """Paper section 2.2: 16.33 rad/s for the rod (0.9 g) with its 0.015 g tip mass."""
    h = undamped_rod_response
    free = h[h.time_s > STEEL_ROD["duration_s"]]
    ld = log_decrement(free.time_s.values, free.tip_uy_m.values, y_final=0.0)
    assert ld.omega_d_rad_s == pytest.approx(PAPER_ROD["omega1_rad_s"], rel=0.03)
    assert ld.zeta < 1e-3


@pytest.mark.slow
def test_steel_rod_energy_balance(undamped_rod_response):
    h = undamped_rod_response
    assert (h.external_work_J - h.kinetic_energy_J - h.internal_energy_J).abs().max() < 1e-3 * h.external_work_J.max()


def test_rod_input_errors():
    with pytest.raises(InputError, match="diameter_m"):
        RodSection(E=2e11, rho=7800.0, diameter_m=-1e-3)
    with pytest.raises(InputError, match="point_masses"):
        steel_rod_model(tip_mass_kg=-1.0)
