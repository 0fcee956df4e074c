import numpy as np
import pytest

from ccedi.errors import InputError
from ccedi.fea.elements.hex8 import FACES, element_geometry
from ccedi.fea.mesh import SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR, Mesh, elliptical_cantilever, refine_hexes, sm_a, sm_b
from ccedi.units import inch_to_m


@pytest.mark.parametrize("make, nodes, elements", [(sm_a, 1080, 725), (sm_b, 5900, 4698)])
def test_table1_node_and_element_counts(make, nodes, elements):
    mesh = make(length_in=4.5)
    assert (mesh.n_nodes, mesh.n_elements) == (nodes, elements)


def test_refined_mesh_volume_converges_to_ellipse():
    exact = np.pi * SEMI_AXIS_MAJOR * SEMI_AXIS_MINOR * inch_to_m(4.5)
    errors = [abs(element_geometry(m.nodes, m.hexes).volume.sum() - exact) / exact
              for m in (elliptical_cantilever(inch_to_m(4.5), n, 4) for n in (3, 5, 9))]
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 0.01


def test_element_length_scales_with_finger_length():
    assert sm_a(length_in=8.0).n_elements == 25 * 51     # the paper's 8-in finger, 1275 elements
    assert sm_b(length_in=3.0).n_elements == 81 * 2 * 19


def test_root_and_tip_sets_are_the_end_faces(mesh_a):
    z = mesh_a.nodes[:, 2]
    assert np.all(z[mesh_a.node_sets["root"]] == 0.0)
    assert np.allclose(z[mesh_a.node_sets["tip"]], inch_to_m(4.5))
    assert len(mesh_a.node_sets["root"]) == len(mesh_a.node_sets["tip"]) == 36


@pytest.mark.parametrize("kwargs, field", [({"length_in": -1.0}, "length_in"), ({"length_in": float("nan")}, "length_in"),
                                           ({}, "exactly one"), ({"length_in": 1.0, "length_m": 0.1}, "exactly one")])
def test_bad_lengths_are_named(kwargs, field):
    with pytest.raises(InputError, match=field):
        sm_a(**kwargs)


@pytest.mark.parametrize("n", [1, 2, 3])
def test_refine_hexes_keeps_the_geometry_and_stays_conforming(n):
    """SM-A at 1 in split n x n x n: (5n+1)^2 (7n+1) nodes, 175 n^3 elements, the same
    volume and boundary area, every face either shared by two children or on the
    boundary (n^2 times SM-A's boundary faces), root and tip sets refined with their faces."""
    coarse = sm_a(length_in=1.0)
    fine = refine_hexes(coarse, n)
    nz = len(coarse.hexes) // 25
    assert fine.n_nodes == (5 * n + 1) ** 2 * (nz * n + 1) and len(fine.hexes) == len(coarse.hexes) * n**3
    assert element_geometry(fine.nodes, fine.hexes).volume.sum() == pytest.approx(
        element_geometry(coarse.nodes, coarse.hexes).volume.sum(), rel=1e-12)

    def boundary_faces(mesh):
        faces = np.sort(mesh.hexes[:, FACES].reshape(-1, 4), axis=1)
        _, counts = np.unique(faces, axis=0, return_counts=True)
        assert counts.max() == 2
        return int((counts == 1).sum())
    assert boundary_faces(fine) == n**2 * boundary_faces(coarse)
    for name, z in (("root", 0.0), ("tip", coarse.nodes[:, 2].max())):
        assert len(fine.node_sets[name]) == (5 * n + 1) ** 2
        assert np.allclose(fine.nodes[fine.node_sets[name], 2], z)
    assert np.array_equal(fine.nodes[:coarse.n_nodes], coarse.nodes)


def test_refine_hexes_rejects_bad_input():
    with pytest.raises(InputError, match="n"):
        refine_hexes(sm_a(length_in=1.0), 0)
    with pytest.raises(InputError, match="tetrahedra"):
        refine_hexes(Mesh(nodes=np.eye(4, 3), tets4=[[0, 1, 2, 3]]), 2)
