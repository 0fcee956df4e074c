"""CalculiX interop (ccedi.fea.io.calculix): the deck reads back with meshio's Abaqus reader,
hex8 -> hex20 keeps the geometry, the consistent tip weights are the textbook ones, and,
where ``ccx`` is installed, CalculiX on a prismatic cantilever gives Timoshenko's tip
stiffness and the Euler-Bernoulli bending frequencies."""
import shutil

import meshio
import numpy as np
import pytest
from scipy.linalg import eigh

from ccedi.errors import InputError, SolverError
from ccedi.fea.elements.hex8 import element_geometry
from ccedi.fea.io.calculix import (
    TET10_EDGES,
    calculix_deck,
    calculix_matrices,
    ccx_version,
    hex8_to_hex20,
    run_calculix,
    tip_weights,
)
from ccedi.fea.material import NeoHookean
from ccedi.fea.mesh import Mesh

needs_ccx = pytest.mark.skipif(shutil.which("ccx") is None,
                               reason="CalculiX (ccx) not installed: apt-get install calculix-ccx")
STEEL_LIKE = NeoHookean(E=2.0e9, nu=0.3, rho=1000.0)


def block(lx, ly, lz, nx, ny, nz, jitter=0.0, seed=0):
    """Structured hexahedral block [0,lx] x [-ly/2,ly/2] x [0,lz] (VTK order), root z = 0 and
    tip z = lz node sets; interior nodes moved by up to ``jitter`` of an element size."""
    x, y, z = np.linspace(0, lx, nx + 1), np.linspace(-ly / 2, ly / 2, ny + 1), np.linspace(0, lz, nz + 1)
    Z, Y, X = np.meshgrid(z, y, x, indexing="ij")
    nodes = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
    inner = ((nodes[:, 0] > 0) & (nodes[:, 0] < lx) & (np.abs(nodes[:, 1]) < ly / 2)
             & (nodes[:, 2] > 0) & (nodes[:, 2] < lz))
    h = min(lx / nx, ly / ny, lz / nz)
    nodes[inner] += jitter * h * np.random.default_rng(seed).uniform(-1, 1, (inner.sum(), 3))
    m, p = nx + 1, (nx + 1) * (ny + 1)
    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    base = (k * p + j * m + i).ravel()
    quad = np.array([0, 1, m + 1, m])
    hexes = np.concatenate([base[:, None] + quad, base[:, None] + quad + p], axis=1)
    ids = np.arange(len(nodes))
    return Mesh(nodes=nodes, hexes=hexes, node_sets={"root": ids[nodes[:, 2] == 0.0],
                                                     "tip": ids[nodes[:, 2] == lz]})


def kuhn_tets(mesh):
    """Each hexahedron as six tetrahedra around its diagonal 0-6 (conforming on a
    structured block), positively oriented; 4-node connectivity."""
    tets = mesh.hexes[:, [[0, 1, 2, 6], [0, 1, 5, 6], [0, 3, 2, 6], [0, 3, 7, 6], [0, 4, 5, 6],
                          [0, 4, 7, 6]]].reshape(-1, 4)
    x = mesh.nodes[tets]
    neg = np.einsum("ij,ij->i", x[:, 1] - x[:, 0], np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 0])) < 0
    tets[neg, 1], tets[neg, 2] = tets[neg, 2], tets[neg, 1].copy()
    return tets


def tet10_block(mesh):
    """The block's Kuhn tetrahedra as straight-edged 10-node tetrahedra."""
    tets = kuhn_tets(mesh)
    edges, inverse = np.unique(np.sort(tets[:, TET10_EDGES].reshape(-1, 2), axis=1), axis=0, return_inverse=True)
    nodes = np.concatenate([mesh.nodes, mesh.nodes[edges].mean(axis=1)])
    tets10 = np.concatenate([tets, mesh.n_nodes + inverse.reshape(-1, 6)], axis=1)
    ids = np.arange(len(nodes))
    lz = mesh.nodes[:, 2].max()
    return Mesh(nodes=nodes, tets10=tets10, node_sets={"root": ids[nodes[:, 2] == 0.0],
                                                       "tip": ids[np.isclose(nodes[:, 2], lz, rtol=0, atol=1e-12)]})


def hex20_volumes(nodes, hexes20):
    """Volumes of 20-node hexahedra by 3x3x3 Gauss points of the serendipity map (its
    Jacobian by central differences: the map is a cubic polynomial)."""
    corners = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                        [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
    edges = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]
    mids = np.array([(corners[a] + corners[b]) / 2 for a, b in edges])
    ref = np.concatenate([corners, mids])

    def shape(p):
        n = np.empty(20)
        for a, r in enumerate(ref):
            lin = 1 + p * r
            if a < 8:
                n[a] = np.prod(lin) * (p @ r - 2) / 8
            else:
                zero = np.flatnonzero(r == 0)[0]
                n[a] = (1 - p[zero] ** 2) * np.prod(np.delete(lin, zero)) / 4
        return n

    g, w = np.polynomial.legendre.leggauss(3)
    x = nodes[hexes20]
    vol = np.zeros(len(hexes20))
    h = 1e-6
    for i in range(3):
        for j in range(3):
            for k in range(3):
                p = np.array([g[i], g[j], g[k]])
                J = np.stack([(shape(p + h * e) - shape(p - h * e)) / (2 * h) for e in np.eye(3)], axis=1)
                vol += w[i] * w[j] * w[k] * np.linalg.det(np.einsum("eki,kj->eij", x, J))
    return vol


# --- deck and hex20 (no ccx needed) -----------------------------------------------

@pytest.mark.parametrize("hex_element, meshio_type", [("C3D8I", "hexahedron"), ("C3D20R", "hexahedron20")])
def test_deck_reads_back_with_meshio(tmp_path, hex_element, meshio_type):
    mesh = block(0.01, 0.006, 0.03, 2, 2, 3, jitter=0.2)
    deck, ids, w, n_nodes, types = calculix_deck(mesh, STEEL_LIKE, force_N=1.0, direction=1, n_modes=2,
                                                 hex_element=hex_element)
    assert types == (hex_element,)
    (tmp_path / "job.inp").write_text(deck)
    back = meshio.read(tmp_path / "job.inp", file_format="abaqus")
    if hex_element == "C3D20R":
        ref = hex8_to_hex20(mesh)
        nodes, cells, sets = ref.nodes, ref.hexes20, ref.node_sets
    else:
        nodes, cells, sets = mesh.nodes, mesh.hexes, mesh.node_sets
    assert n_nodes == len(nodes)
    np.testing.assert_allclose(back.points, nodes, rtol=1e-12, atol=1e-15)   # 13 digits where 17 do not fit
    assert [c.type for c in back.cells] == [meshio_type]
    np.testing.assert_array_equal(back.cells[0].data, cells)
    np.testing.assert_array_equal(back.point_sets["ROOT"], sets["root"])
    np.testing.assert_array_equal(back.point_sets["TIP"], sets["tip"])
    np.testing.assert_array_equal(ids, sets["tip"])
    assert "*FREQUENCY\n2\n" in deck and deck.count("*CLOAD") == 1
    assert w.sum() == pytest.approx(1.0, abs=1e-12)


def test_tet_deck_reads_back_with_meshio(tmp_path):
    hexes = block(0.01, 0.006, 0.02, 1, 1, 2)
    quad = tet10_block(hexes)
    mesh = Mesh(nodes=quad.nodes, tets4=kuhn_tets(hexes), tets10=quad.tets10, node_sets=quad.node_sets)
    deck = calculix_deck(mesh, STEEL_LIKE, force_N=1.0, n_modes=0).text
    (tmp_path / "job.inp").write_text(deck)
    back = meshio.read(tmp_path / "job.inp", file_format="abaqus")
    assert [c.type for c in back.cells] == ["tetra", "tetra10"]
    np.testing.assert_array_equal(back.cells[0].data, mesh.tets4)
    np.testing.assert_array_equal(back.cells[1].data, mesh.tets10)
    assert "*FREQUENCY" not in deck


@pytest.mark.parametrize("nx, ny, nz", [(1, 1, 1), (2, 3, 4)])
def test_hex20_shares_midpoints_and_keeps_volumes(nx, ny, nz):
    mesh = block(0.01, 0.006, 0.03, nx, ny, nz, jitter=0.25, seed=nx)
    quad = hex8_to_hex20(mesh)
    expected = ((nx + 1) * (ny + 1) * (nz + 1) + nx * (ny + 1) * (nz + 1) + (nx + 1) * ny * (nz + 1)
                + (nx + 1) * (ny + 1) * nz)
    assert len(quad.nodes) == expected
    assert len(np.unique(quad.hexes20)) == expected                   # every node used, none duplicated
    mid = quad.nodes[quad.hexes20[:, 8:]]
    ends = quad.nodes[quad.hexes20[:, [0, 1, 2, 3, 4, 5, 6, 7, 0, 1, 2, 3]]] / 2 \
        + quad.nodes[quad.hexes20[:, [1, 2, 3, 0, 5, 6, 7, 4, 4, 5, 6, 7]]] / 2
    np.testing.assert_allclose(mid, ends, rtol=0, atol=1e-15)
    np.testing.assert_allclose(hex20_volumes(quad.nodes, quad.hexes20),
                               element_geometry(mesh.nodes, mesh.hexes).volume, rtol=1e-9)
    # tip set: the (nx+1)(ny+1) corners plus nx(ny+1) + (nx+1)ny mid-edge nodes of the tip face
    assert len(quad.node_sets["tip"]) == (nx + 1) * (ny + 1) + nx * (ny + 1) + (nx + 1) * ny
    assert np.all(quad.nodes[quad.node_sets["tip"], 2] == 0.03)


def test_consistent_tip_weights_are_the_textbook_ones():
    mesh = block(0.01, 0.006, 0.03, 1, 1, 2)
    ids, w = tip_weights(mesh, "C3D20R")
    corner = ids < mesh.n_nodes
    np.testing.assert_allclose(w[corner], -1.0 / 12.0, rtol=1e-12)   # rectangle: -A/12 at corners
    np.testing.assert_allclose(w[~corner], 1.0 / 3.0, rtol=1e-12)    # A/3 at mid-edge nodes
    tets = tet10_block(mesh)
    ids, w = tip_weights(tets)
    mid = np.isin(ids, tets.tets10[:, 4:])
    np.testing.assert_allclose(w[~mid], 0.0, atol=1e-14)              # flat 6-node triangle: 0 at corners
    # two triangles of area A/2 (split along a diagonal): (A/2)/3 on each of the four
    # boundary mid-edge nodes, twice that on the diagonal's
    np.testing.assert_allclose(np.sort(w[mid]), [1 / 6] * 4 + [1 / 3], rtol=1e-12)
    ids, w = tip_weights(mesh, "C3D8I")
    np.testing.assert_allclose(w, 0.25)
    mixed = Mesh(nodes=mesh.nodes, hexes=mesh.hexes[1:], tets4=kuhn_tets(Mesh(mesh.nodes, mesh.hexes[:1])),
                 node_sets=mesh.node_sets)                            # bilinear tip face by quadrature
    np.testing.assert_allclose(tip_weights(mixed, "C3D8I")[1], 0.25, rtol=1e-12)


def test_bad_inputs_give_one_line_errors():
    mesh = block(0.01, 0.006, 0.03, 1, 1, 2)
    with pytest.raises(InputError, match="hex_element must be one of"):
        calculix_deck(mesh, STEEL_LIKE, hex_element="C3D8R")
    with pytest.raises(InputError, match="weights cannot be given with C3D20R"):
        calculix_deck(mesh, STEEL_LIKE, weights=np.full(4, 0.25))
    with pytest.raises(InputError, match="weights must be 4 finite numbers"):
        calculix_deck(mesh, STEEL_LIKE, hex_element="C3D8I", weights=np.full(4, 0.3))
    with pytest.raises(InputError, match="store_matrices needs force_N=None"):
        calculix_deck(mesh, STEEL_LIKE, n_modes=2, store_matrices=True)
    with pytest.raises(InputError, match="nothing to compute"):
        calculix_deck(mesh, STEEL_LIKE, force_N=None, n_modes=0)
    with pytest.raises(InputError, match="no node set 'tip'"):
        calculix_deck(Mesh(nodes=mesh.nodes, hexes=mesh.hexes, node_sets={"root": mesh.node_sets["root"]}),
                      STEEL_LIKE)
    with pytest.raises(SolverError, match="apt-get install calculix-ccx") as err:
        run_calculix(mesh, STEEL_LIKE, executable="no-such-ccx-here")
    assert "\n" not in str(err.value)


# --- CalculiX against beam theory ---------------------------------------------------

BAR = dict(lx=0.012, ly=0.008, lz=0.16)          # slender: L / h_y = 20


def timoshenko_tip_stiffness(E, nu, b, h, L):
    """Cantilever end-load stiffness F / (F L^3 / (3 E I) + F L / (kappa G A)), rectangle
    b x h bent across h, kappa = 10 (1 + nu) / (12 + 11 nu) (Cowper)."""
    I, A, G = b * h**3 / 12, b * h, E / (2 * (1 + nu))
    kappa = 10 * (1 + nu) / (12 + 11 * nu)
    return 1.0 / (L**3 / (3 * E * I) + L / (kappa * G * A))


def euler_bernoulli_f1(E, rho, b, h, L):
    """First cantilever bending frequency (1.8751)^2 / (2 pi L^2) sqrt(E I / (rho A)) [Hz]."""
    return 1.8751040687**2 / (2 * np.pi * L**2) * np.sqrt(E * h**2 / 12 / rho)


@needs_ccx
@pytest.mark.parametrize("hex_element, tolerance", [("C3D20R", 0.015), ("C3D8I", 0.03)])
def test_cantilever_matches_beam_theory(hex_element, tolerance):
    """Tip stiffness within 1.5 % (C3D20R; measured +0.9 %, the clamped root's restrained
    Poisson contraction) or 3 % (C3D8I on 2 x 2 in the section; +2.0 %) of Timoshenko's, the
    two lowest frequencies (bending across the 8 mm and the 12 mm side) within 2 % of
    Euler-Bernoulli's (the locking full-integration C3D8 is 114 % too stiff here)."""
    mesh = block(BAR["lx"], BAR["ly"], BAR["lz"], 2, 2, 12)
    r = run_calculix(mesh, STEEL_LIKE, force_N=1.0, direction=1, n_modes=2, hex_element=hex_element)
    E, nu, rho = STEEL_LIKE.E, STEEL_LIKE.nu, STEEL_LIKE.rho
    assert r.stiffness_N_per_m == pytest.approx(timoshenko_tip_stiffness(E, nu, BAR["lx"], BAR["ly"], BAR["lz"]),
                                                rel=tolerance)
    expected = [euler_bernoulli_f1(E, rho, BAR["lx"], h, BAR["lz"]) for h in (BAR["ly"], BAR["lx"])]
    np.testing.assert_allclose(r.frequencies_hz, expected, rtol=0.02)
    np.testing.assert_allclose(r.omega_rad_s, 2 * np.pi * r.frequencies_hz, rtol=1e-5)
    assert r.n_elements == 48 and r.element_type == hex_element


@needs_ccx
def test_tet10_cantilever_matches_beam_theory():
    """C3D10 (the straight-edged Kuhn tetrahedra of the block) with its consistent tip
    weights: tip stiffness within 3 % of Timoshenko's, f1 within 3 % of Euler-Bernoulli's."""
    mesh = tet10_block(block(BAR["lx"], BAR["ly"], BAR["lz"], 2, 2, 12))
    r = run_calculix(mesh, STEEL_LIKE, force_N=1.0, direction=1, n_modes=1)
    E, nu, rho = STEEL_LIKE.E, STEEL_LIKE.nu, STEEL_LIKE.rho
    assert r.stiffness_N_per_m == pytest.approx(timoshenko_tip_stiffness(E, nu, BAR["lx"], BAR["ly"], BAR["lz"]),
                                                rel=0.03)
    assert r.frequencies_hz[0] == pytest.approx(euler_bernoulli_f1(E, rho, BAR["lx"], BAR["ly"], BAR["lz"]), rel=0.03)
    assert r.element_type == "C3D10"


@needs_ccx
def test_stored_matrices_give_ccx_frequencies():
    """K and M read from a matrix-storage step: symmetric, on the free degrees of freedom
    (every node but the clamped ones, 3 each), and their generalised eigenvalues are the
    frequencies CalculiX itself finds."""
    mesh = block(BAR["lx"], BAR["ly"], BAR["lz"], 2, 2, 6)
    mats = calculix_matrices(mesh, STEEL_LIKE, hex_element="C3D20")
    K, M = mats.stiffness.toarray(), mats.mass.toarray()
    np.testing.assert_array_equal(K, K.T)
    free = np.setdiff1d(np.arange(mats.n_nodes), hex8_to_hex20(mesh).node_sets["root"])
    np.testing.assert_array_equal(mats.dofs, np.column_stack([np.repeat(free, 3), np.tile([0, 1, 2], len(free))]))
    omega2 = eigh(K, M, eigvals_only=True, subset_by_index=[0, 2])
    r = run_calculix(mesh, STEEL_LIKE, force_N=None, direction=1, n_modes=3, hex_element="C3D20")
    np.testing.assert_allclose(np.sqrt(omega2), r.omega_rad_s, rtol=1e-5)


@needs_ccx
def test_ccx_reports_its_version():
    assert ccx_version().replace(".", "").isdigit()
