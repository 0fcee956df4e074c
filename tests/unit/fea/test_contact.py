"""Penalty contact and Coulomb friction against rigid surfaces, on small cases with
analytic answers."""
import numpy as np
import pytest

from ccedi.errors import InputError
from ccedi.fea.contact.penalty import (
    Contact,
    ContactGroup,
    RigidEllipse,
    RigidPlane,
    _ellipse_gap,
    boundary_nodes,
    contact_damping,
    contact_forces,
)
from ccedi.fea.material import NeoHookean
from ccedi.fea.mesh import elliptical_cantilever
from ccedi.fea.mesh.tet_mesh import box_cantilever, quadratic_tets, split_hexes
from ccedi.fea.model import ForcePulse, Model, face_node_weights
from ccedi.fea.solvers.explicit import run

STIFF = NeoHookean(E=2e8, nu=0.3, rho=1000.0)


def block_on_plane(normal_N, tangential_N=0.0, alpha=0.0, mu=0.0, t_start=0.0, damping_ratio=0.0):
    """A 24 x 17 x 10 mm block (elliptical prism) standing on the rigid plane z = 0,
    pushed down by ``normal_N`` and sideways (+x) by ``tangential_N`` on its top face."""
    mesh = elliptical_cantilever(0.01, 2, 2)
    top = mesh.node_sets["tip"]
    w = face_node_weights(mesh, top)
    pulses = [ForcePulse(nodes=top, weights=w, force_N=[tangential_N, 0.0, -normal_N], t_start_s=t_start,
                         t_end_s=10.0)]
    contact = Contact(nodes=mesh.node_sets["root"], surface=RigidPlane((0, 0, 0), (0, 0, 1), mu=mu,
                                                                       damping_ratio=damping_ratio))
    return Model(mesh=mesh, material=STIFF, alpha=alpha, pulses=tuple(pulses), contact=contact)


def test_pressed_block_settles_on_its_penalty_springs():
    """The damped dynamic run settles where the static problem of the block on springs of
    the penalty stiffness puts it: contact force = load, and each bottom node's
    penetration equals the static spring compression."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from ccedi.fea.contact.penalty import penalty_stiffness
    from ccedi.fea.solvers.explicit import critical_time_step
    from ccedi.fea.solvers.static import tangent_stiffness

    F = 50.0
    model = block_on_plane(F, alpha=2000.0)
    res = run(model, 0.03, n_outputs=30)
    h = res.history
    assert h.contact_force_z_N.iloc[-1] == pytest.approx(-F, rel=0.01)     # the plane is pushed down
    bottom = model.contact.nodes
    k = penalty_stiffness(model.mass[bottom], critical_time_step(model))
    springs = np.zeros((model.mesh.n_nodes, 3))
    springs[bottom, 2] = k
    springs[bottom, :2] = 1e-6 * k[:, None]                 # removes the free in-plane motion
    K = tangent_stiffness(model) + sp.diags(springs.ravel())
    top = model.mesh.node_sets["tip"]
    f = np.zeros_like(model.mesh.nodes)
    f[top, 2] = -F * face_node_weights(model.mesh, top)
    u = spla.spsolve(K.tocsc(), f.ravel()).reshape(-1, 3)
    penetration_dynamic = -(res.x[bottom, 2] - model.mesh.nodes[bottom, 2])
    assert np.allclose(penetration_dynamic, -u[bottom, 2], rtol=0.01)
    assert h.max_penetration_m.iloc[-1] == pytest.approx(-u[bottom, 2].min(), rel=0.01)


def test_sliding_block_feels_mu_times_normal_force():
    """Pushed sideways harder than mu N, the block slides and the plane feels mu N of
    friction; pushed more gently it sticks and the friction balances the push."""
    N, mu = 20.0, 0.4
    slide = run(block_on_plane(N, tangential_N=2.0 * mu * N, alpha=0.0, mu=mu), 0.02, n_outputs=40).history
    late = slide[slide.time_s > 0.01]
    assert late.contact_force_x_N.mean() == pytest.approx(mu * late.contact_force_z_N.abs().mean(), rel=0.02)
    stick = run(block_on_plane(N, tangential_N=0.5 * mu * N, alpha=500.0, mu=mu), 0.03, n_outputs=30).history
    assert stick.contact_force_x_N.iloc[-1] == pytest.approx(0.5 * mu * N, rel=0.02)
    assert abs(stick.tip_ux_m.iloc[-1] - stick.tip_ux_m.iloc[-10]) < 1e-6


def test_block_balance_of_energy_with_friction():
    h = run(block_on_plane(20.0, tangential_N=16.0, mu=0.4), 0.02, n_outputs=20).history
    stored = (h.kinetic_energy_J + h.internal_energy_J + h.hourglass_energy_J + h.damping_energy_J
              + h.bulk_viscosity_energy_J)
    assert (h.external_work_J - stored).abs().max() < 0.01 * h.external_work_J.abs().max()
    assert h.friction_work_J.iloc[-1] < 0.0                  # friction only dissipates


@pytest.mark.parametrize("a, b", [(0.05, 0.03), (0.02, 0.04)])
def test_ellipse_closest_point_and_normal(a, b):
    """p = q + d n with |d| below the smallest radius of curvature (min(a,b)^2 / max(a,b))
    has q as its closest boundary point and |d| as its distance."""
    rng = np.random.default_rng(1)
    for _ in range(200):
        th = rng.uniform(0, 2 * np.pi)
        q = np.array([a * np.cos(th), b * np.sin(th)])
        n = np.array([q[0] / a**2, q[1] / b**2])
        n /= np.linalg.norm(n)
        depth = rng.uniform(-2e-3, 2e-3)
        p = q + depth * n
        gap, nx, ny = _ellipse_gap(p[0], p[1], a, b)
        assert gap == pytest.approx(depth, abs=1e-12)
        assert np.allclose([nx, ny], n, atol=1e-9)


def test_rotated_ellipse_pushes_along_its_normal():
    surface = RigidEllipse(center_m=(0.1, 0.2), a_m=0.05, b_m=0.03, angle_rad=0.6, mu=0.0)
    # a point 1 mm inside the end of the a-axis
    u = np.array([np.cos(0.6), np.sin(0.6), 0.0])
    x = np.array([[0.1, 0.2, 0.0] + (0.05 - 1e-3) * u])
    f = np.zeros_like(x)
    out = np.zeros(8)
    kind, params = surface.params()
    group = ContactGroup(np.array([0]), np.array([1e4]), np.zeros(1), kind, params, 0.0, np.zeros_like(x),
                         np.zeros(1), out)
    contact_forces(x, np.zeros_like(x), group, f)
    assert np.allclose(f[0], 1e4 * 1e-3 * u, rtol=1e-6)
    assert out[4] == pytest.approx(1e-3)


def test_contact_damping_acts_on_the_penetration_rate_and_never_pulls():
    """f_n = max(k d + c d', 0) with d' = -v . n: a node 1 mm into the plane z = 0 moving
    further in at 0.1 m/s feels k d + 0.1 c; moving out at 0.1 m/s, k d - 0.1 c; moving out
    fast enough, nothing (the dashpot does not glue the node to the surface). The damping
    coefficient is the ratio's share of critical, 2 zeta sqrt(k m)."""
    k, m, zeta = 1e4, 0.01, 0.2
    c = contact_damping(np.array([k]), np.array([m]), zeta)
    assert c[0] == pytest.approx(2.0 * zeta * np.sqrt(k * m))
    kind, params = RigidPlane((0, 0, 0), (0, 0, 1), damping_ratio=zeta).params()
    x = np.array([[0.0, 0.0, -1e-3]])
    for vz, expected in ((-0.1, k * 1e-3 + 0.1 * c[0]), (0.1, k * 1e-3 - 0.1 * c[0]), (10.0, 0.0)):
        f, out = np.zeros_like(x), np.zeros(8)
        group = ContactGroup(np.array([0]), np.array([k]), c, kind, params, 0.0, np.zeros_like(x), np.zeros(1), out)
        contact_forces(x, np.array([[0.0, 0.0, vz]]), group, f)
        assert f[0, 2] == pytest.approx(expected, rel=1e-12, abs=1e-15)


def test_contact_damping_dissipates_and_the_energy_still_balances():
    """The block pressed onto the plane from rest (alpha = 500 1/s) rings on its contact
    springs. Without contact damping the normal contact force is conservative (its work
    on the body is minus the penalty energy, to 5 %); with zeta = 0.2 it dissipates more
    than half the penalty energy, the ringing of the contact force dies (its late std
    falls more than tenfold), and the run's external work still matches the stored and
    damped energies to 3 % at the end (as without; during the first impact of the step load
    on the stiff block the balance is off by up to 7 % either way)."""
    runs = {z: run(block_on_plane(20.0, alpha=500.0, damping_ratio=z), 0.01, n_outputs=50).history
            for z in (0.0, 0.2)}
    lost = {z: -(h.normal_contact_work_J + h.penalty_energy_J).iloc[-1] for z, h in runs.items()}
    assert abs(lost[0.0]) < 0.05 * runs[0.0].penalty_energy_J.iloc[-1]
    assert lost[0.2] > 0.5 * runs[0.2].penalty_energy_J.iloc[-1]
    late = {z: h.contact_force_z_N[h.time_s > 0.005].std() for z, h in runs.items()}
    assert late[0.2] < 0.1 * late[0.0]
    for h in runs.values():
        stored = (h.kinetic_energy_J + h.internal_energy_J + h.hourglass_energy_J + h.damping_energy_J
                  + h.bulk_viscosity_energy_J)
        assert abs(h.external_work_J.iloc[-1] - stored.iloc[-1]) < 0.03 * h.external_work_J.iloc[-1]


@pytest.mark.parametrize("zeta", [-0.1, 0.25, float("nan")])
def test_contact_damping_outside_its_stable_range_is_refused(zeta):
    with pytest.raises(InputError, match="damping_ratio"):
        RigidPlane((0, 0, 0), (0, 0, 1), damping_ratio=zeta)


def test_boundary_nodes_of_a_block():
    mesh = elliptical_cantilever(0.01, 3, 3)
    nb = boundary_nodes(mesh)
    assert len(nb) == mesh.n_nodes - 2 * 2 * 2             # the 2x2x2 interior nodes are not on it


@pytest.mark.parametrize("kind", ["hex8", "tet4", "tet10"])
def test_boundary_nodes_of_a_box_are_the_nodes_on_its_faces(kind):
    """Hexahedra, their 4-node split and its 10-node version: the surface nodes are exactly
    the nodes on the box's six planes (straight edges put every mid-edge node of a face on
    its plane, and every interior edge's strictly inside)."""
    mesh = box_cantilever(0.03, 0.02, 0.01, nx=3, ny=2, nz=4)
    mesh = {"hex8": mesh, "tet4": split_hexes(mesh), "tet10": quadratic_tets(split_hexes(mesh))}[kind]
    X = mesh.nodes
    lo, hi = X.min(axis=0), X.max(axis=0)
    on_planes = np.flatnonzero((np.isclose(X, lo, atol=1e-12) | np.isclose(X, hi, atol=1e-12)).any(axis=1))
    assert mesh.element_type == kind
    assert np.array_equal(boundary_nodes(mesh), on_planes)
    assert len(on_planes) < mesh.n_nodes                    # the box has interior nodes
