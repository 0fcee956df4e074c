"""The 10-node quadratic tetrahedron: HRZ mass, locking-free tip deflection at nu = 0.499,
the stable step on a Gmsh finger with curved elements, and the energy balance of an impulse run (the checks it shares with the 4-node element are
parametrised in tests/unit/fea/test_tet4.py)."""
import numpy as np
import pytest
from conftest import BOX

from ccedi.fea.elements import tet10
from ccedi.fea.material import NeoHookean
from ccedi.fea.mesh import Mesh
from ccedi.fea.mesh.gmsh_fingers import tapered_finger
from ccedi.fea.mesh.tet_mesh import box_cantilever, quadratic_tets, split_hexes
from ccedi.fea.model import cantilever_model, tip_pulse
from ccedi.fea.solvers.explicit import critical_time_step, run
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.fea.solvers.static import tangent_stiffness, tip_deflection

RUBBER_499 = NeoHookean(6.1e6, 0.499, 1000.0)


def test_hrz_mass_of_a_straight_element():
    """Corners 6/216 and mid-edge nodes 32/216 of rho V on any straight-edged element."""
    corners = np.array([[0.0, 0, 0], [2e-3, 0, 0], [3e-4, 1.5e-3, 0], [5e-4, 4e-4, 1.8e-3]])
    mesh = quadratic_tets(Mesh(nodes=corners, tets4=np.array([[0, 1, 2, 3]])))
    group = tet10.tet10_group(mesh.nodes, mesh.tets10, NeoHookean(6.1e6, 0.49, 1000.0))
    m = tet10.lumped_mass(mesh.nodes, group, 1000.0)
    V = np.linalg.det(corners[1:] - corners[0]) / 6
    assert group.volume[0] == pytest.approx(V, rel=1e-12)
    assert np.allclose(m[:4], 1000.0 * V * 6 / 216, rtol=1e-12)
    assert np.allclose(m[4:], 1000.0 * V * 32 / 216, rtol=1e-12)


def test_no_volumetric_locking(converged_box_hex):
    """nu = 0.499: the 4 mm tet-10 cantilever's tip deflection within 3 % of the converged
    hexahedra."""
    model = cantilever_model(quadratic_tets(split_hexes(box_cantilever(*BOX, nx=3, ny=2, nz=15))), RUBBER_499)
    k = 0.01 / tip_deflection(model, 0.01, linear=True)
    assert k == pytest.approx(converged_box_hex, rel=0.03)


def test_impulse_run_balances_energy_and_rings_at_the_modal_frequency():
    """fea.explicit.run on a tet-10 cantilever with a tip pulse: energy balance within 1 %,
    no warnings, and the tip rings at the first natural frequency of the modal analysis."""
    mesh = quadratic_tets(split_hexes(box_cantilever(*BOX, nx=2, ny=2, nz=8)))
    model = cantilever_model(mesh, NeoHookean(6.1e6, 0.49, 1000.0), pulses=[tip_pulse(mesh, [0.0, 0.5, 0.0], 1e-3)])
    omega1 = natural_frequencies(model, n_modes=1)[0]
    res = run(model, 4 * 2 * np.pi / omega1, n_outputs=400)
    assert res.summary["energy_balance_error"] < 0.01
    assert [w for w in res.summary["warnings"] if "the step is set by" not in w] == []   # a sliver is named, no more
    h = res.history
    late = h[h.time_s > 1e-3]
    u = late.tip_uy_m.to_numpy() - late.tip_uy_m.mean()
    crossings = np.flatnonzero(np.diff(np.sign(u)) != 0)
    period = 2 * np.mean(np.diff(late.time_s.to_numpy()[crossings]))
    assert 2 * np.pi / period == pytest.approx(omega1, rel=0.03)


def test_stable_step_on_a_gmsh_finger_with_curved_elements():
    """A tapered Gmsh finger (optimised, curved 10-node elements; 8 mm, 2 in): the computed
    step equals the limit 2/omega_max of central differences (Lanczos on M^-1/2 K M^-1/2,
    free DOFs) within 1 % without exceeding it (a fixed factor 0.42 of the minimum altitude
    gave 1.77 times the limit here), and 0.9 of it runs a tip impulse stably."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla
    mesh = tapered_finger(8e-3, length_in=2.0)
    model = cantilever_model(mesh, NeoHookean(6.1e6, 0.49, 1000.0), pulses=[tip_pulse(mesh, [0.0, 2.0, 0.0], 2e-4)])
    free = np.setdiff1d(np.arange(mesh.n_nodes), model.fixed_nodes)
    dofs = (3 * free[:, None] + np.arange(3)).ravel()
    s = sp.diags(1 / np.sqrt(np.repeat(model.mass[free], 3)))
    A = s @ tangent_stiffness(model).tocsr()[dofs][:, dofs] @ s
    limit = 2 / np.sqrt(spla.eigsh(A, k=1, which="LA", return_eigenvectors=False, tol=1e-10)[0])
    dt = critical_time_step(model)
    assert dt <= limit * (1 + 1e-6)
    assert dt == pytest.approx(limit, rel=0.01)
    res = run(model, 3000 * 0.9 * dt, n_outputs=10)
    assert res.summary["steps"] >= 3000
    assert res.summary["energy_balance_error"] < 0.01
    assert [w for w in res.summary["warnings"] if "the step is set by" not in w] == []   # a sliver is named, no more
