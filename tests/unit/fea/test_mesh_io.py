"""Finger meshes from outside (ccedi.fea.mesh.readers) and generated with Gmsh (ccedi.fea.mesh.gmsh_fingers):
every format reads back what was written, node orders give positive volumes and mid-edge
nodes at edge midpoints, sets by name and by plane agree, units and the bending direction
transform as documented, every bad mesh is one line naming the problem, and the generated
fingers match the paper's SM-C counts and the analytic / CAD volumes."""
import meshio
import numpy as np
import pytest

from ccedi.errors import InputError
from ccedi.fea.io.lsdyna import _card, _node_line, write_keyword
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import Mesh, elliptical_cantilever, sm_a, sm_b
from ccedi.fea.mesh.gmsh_fingers import sm_c, tapered_finger, tapered_volume, write_tapered_finger
from ccedi.fea.mesh.readers import FingerMeshSpec, element_volumes, gmsh_session, read_finger_mesh
from ccedi.fea.model import cantilever_model

L = 0.06
EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]


def _plane_sets(nodes):
    z = nodes[:, 2]
    return {"root": np.flatnonzero(np.isclose(z, z.min())), "tip": np.flatnonzero(np.isclose(z, z.max()))}


def _hex_to_tets(mesh):
    """Each hexahedron as six positively oriented tetrahedra (Kuhn split of the diagonal 0-6)."""
    paths = [(1, 2), (2, 3), (3, 7), (7, 4), (4, 5), (5, 1)]
    tets = np.concatenate([mesh.hexes[:, [0, a, b, 6]] for a, b in paths])
    v = element_volumes(Mesh(mesh.nodes, tets4=tets))
    tets[v < 0] = tets[v < 0][:, [0, 2, 1, 3]]
    return Mesh(mesh.nodes, tets4=tets, node_sets=mesh.node_sets)


def _tet4_to_tet10(mesh):
    """Straight-edged 10-node tetrahedra: mid-edge nodes at the edge midpoints (shared)."""
    pairs = np.sort(np.concatenate([mesh.tets4[:, e] for e in EDGES]), axis=1)
    unique, inverse = np.unique(pairs, axis=0, return_inverse=True)
    mid = len(mesh.nodes) + inverse.reshape(len(EDGES), -1).T
    nodes = np.concatenate([mesh.nodes, mesh.nodes[unique].mean(axis=1)])
    return Mesh(nodes, tets10=np.column_stack([mesh.tets4, mid]), node_sets=_plane_sets(nodes))


@pytest.fixture(scope="module")
def meshes():
    hexes = elliptical_cantilever(L, 2, 3)
    tets4 = _hex_to_tets(hexes)
    return {"hexahedron": hexes, "tetra": tets4, "tetra10": _tet4_to_tet10(tets4)}


def _cells(mesh):
    kind = {"hex8": "hexahedron", "tet4": "tetra", "tet10": "tetra10"}[mesh.element_type]
    return kind, {"hexahedron": mesh.hexes, "tetra": mesh.tets4, "tetra10": mesh.tets10}[kind]


@pytest.mark.parametrize("kind", ["hexahedron", "tetra", "tetra10"])
@pytest.mark.parametrize("fmt, suffix", [("gmsh", ".msh"), ("gmsh22", ".msh"), ("abaqus", ".inp"),
                                         ("vtu", ".vtu"), ("vtk", ".vtk")])
def test_every_format_reads_back_what_meshio_wrote(tmp_path, meshes, kind, fmt, suffix):
    mesh = meshes[kind]
    sets = {"ROOT": mesh.node_sets["root"], "TIP": mesh.node_sets["tip"]} if fmt == "abaqus" else {}
    path = tmp_path / f"finger{suffix}"
    meshio.write(path, meshio.Mesh(mesh.nodes, [(kind, _cells(mesh)[1])], point_sets=sets), file_format=fmt)
    back = read_finger_mesh(path)
    assert back.n_nodes == mesh.n_nodes and _cells(back)[0] == kind
    np.testing.assert_allclose(back.nodes, mesh.nodes, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(_cells(back)[1], _cells(mesh)[1])
    for name in ("root", "tip"):
        np.testing.assert_array_equal(back.node_sets[name], mesh.node_sets[name])
    if sets:
        named = read_finger_mesh(path, clamp="ROOT", tip="TIP")
        assert all(np.array_equal(named.node_sets[k], mesh.node_sets[k]) for k in ("root", "tip"))


def _keyword_deck(path, mesh, two_line):
    kind, cells = _cells(mesh)
    if kind == "tetra" and not two_line:
        cells = cells[:, [0, 1, 2, 3, 3, 3, 3, 3]]            # LS-DYNA's degenerate-hexahedron tetrahedron
    lines = ["*KEYWORD", "*NODE"] + [_node_line(i, x) for i, x in enumerate(mesh.nodes)] + ["*ELEMENT_SOLID"]
    for e, c in enumerate(cells):
        lines += [_card([e + 1, 1], 8), _card(list(c + 1), 8)] if two_line else [_card([e + 1, 1, *(c + 1)], 8)]
    lines += ["*SET_NODE_LIST", _card([7])] + [_card(list(mesh.node_sets["tip"][i:i + 8] + 1))
                                               for i in range(0, len(mesh.node_sets["tip"]), 8)]
    path.write_text("\n".join(lines + ["*END"]) + "\n")
    return path


@pytest.mark.parametrize("kind, two_line", [("hexahedron", False), ("tetra", False), ("tetra", True),
                                            ("tetra10", True)])
def test_lsdyna_solids_read_back(tmp_path, meshes, kind, two_line):
    mesh = meshes[kind]
    back = read_finger_mesh(_keyword_deck(tmp_path / "f.k", mesh, two_line), tip="7")
    assert _cells(back)[0] == kind
    np.testing.assert_array_equal(_cells(back)[1], _cells(mesh)[1])
    np.testing.assert_allclose(back.nodes, mesh.nodes, rtol=0, atol=1e-12)   # 15-character fields
    np.testing.assert_array_equal(back.node_sets["tip"], mesh.node_sets["tip"])


def test_the_deck_ccedi_writes_reads_back(tmp_path, meshes):
    mesh = meshes["hexahedron"]
    path = write_keyword(cantilever_model(mesh, RUBBER), tmp_path / "f.k", t_end_s=0.01)
    back = read_finger_mesh(path, clamp="1")                # *SET_NODE_LIST 1: the clamped nodes
    np.testing.assert_array_equal(back.hexes, mesh.hexes)
    np.testing.assert_array_equal(back.node_sets["root"], mesh.node_sets["root"])


def _box_msh(path, version, binary, order=2):
    """A 20 x 10 x 50 mm box meshed by Gmsh itself, physical groups clamp / tip / finger."""
    with gmsh_session("box") as gmsh:
        box = gmsh.model.occ.addBox(0, 0, 0, 0.02, 0.01, 0.05)
        gmsh.model.occ.synchronize()
        faces = {gmsh.model.occ.getCenterOfMass(2, t)[2]: t for _, t in gmsh.model.getBoundary([(3, box)])}
        gmsh.model.addPhysicalGroup(2, [faces[0.0]], name="clamp")
        gmsh.model.addPhysicalGroup(2, [faces[0.05]], name="tip")
        gmsh.model.addPhysicalGroup(3, [box], name="finger")
        for option, value in (("Mesh.MeshSizeMax", 0.008), ("Mesh.ElementOrder", order),
                              ("Mesh.MshFileVersion", version), ("Mesh.Binary", binary)):
            gmsh.option.setNumber(option, value)
        gmsh.model.mesh.generate(3)
        gmsh.write(str(path))
    return path


@pytest.mark.parametrize("version, binary", [(4.1, 0), (4.1, 1), (2.2, 0), (2.2, 1)])
def test_a_gmsh_tet10_has_positive_volumes_and_midpoint_nodes(tmp_path, version, binary):
    mesh = read_finger_mesh(_box_msh(tmp_path / "box.msh", version, binary), clamp="clamp", tip="tip")
    t = mesh.tets10
    volumes = element_volumes(mesh)
    assert mesh.element_type == "tet10" and volumes.min() > 0
    assert volumes.sum() == pytest.approx(0.02 * 0.01 * 0.05, rel=1e-12)
    for k, (i, j) in enumerate(EDGES):
        np.testing.assert_allclose(mesh.nodes[t[:, 4 + k]], (mesh.nodes[t[:, i]] + mesh.nodes[t[:, j]]) / 2,
                                   atol=1e-12)
    by_plane = read_finger_mesh(tmp_path / "box.msh")
    for name in ("root", "tip"):
        np.testing.assert_array_equal(mesh.node_sets[name], by_plane.node_sets[name])
    assert np.allclose(mesh.nodes[mesh.node_sets["tip"], 2], 0.05)


def test_millimetres_and_bending_along_x(tmp_path, meshes):
    mesh = meshes["hexahedron"]
    path = tmp_path / "mm.vtu"
    meshio.write(path, meshio.Mesh(mesh.nodes * 1e3, [("hexahedron", mesh.hexes)]))
    np.testing.assert_allclose(read_finger_mesh(path, mesh_unit="mm").nodes, mesh.nodes, rtol=1e-12)
    turned = FingerMeshSpec(str(path), "mm", bending_direction="x").load()
    x, y, z = mesh.nodes.T
    np.testing.assert_allclose(turned.nodes, np.column_stack([-y, x, z]), rtol=1e-12, atol=1e-15)
    assert element_volumes(turned).min() > 0                # a rotation: orientation kept
    # the file's x (12 mm semi-axis) is now ccedi's y, the bending direction
    assert np.ptp(turned.nodes[:, 1]) == pytest.approx(2 * 12e-3, rel=1e-6)


def _write(tmp_path, points, cells, name="bad.vtu", **kw):
    path = tmp_path / name
    meshio.write(path, meshio.Mesh(points, cells, **kw))
    return path


def _one_line(call, *fragments):
    with pytest.raises(InputError) as err:
        call()
    message = str(err.value)
    assert "\n" not in message and all(f in message for f in fragments), message
    return message


def test_bad_meshes_are_one_line_naming_the_problem(tmp_path, meshes):
    mesh = meshes["tetra"]
    x, t = mesh.nodes, mesh.tets4
    inverted = t.copy()
    inverted[5] = inverted[5][[1, 0, 2, 3]]
    _one_line(lambda: read_finger_mesh(_write(tmp_path, x, [("tetra", inverted)])),
              "1 inverted or degenerate tetra elements", "element 5", "centroid")
    flat = x.copy()
    flat[t[9, 3]] = flat[t[9, :3]].mean(axis=0)             # a node in its element's opposite face
    _one_line(lambda: read_finger_mesh(_write(tmp_path, flat, [("tetra", t)])), "degenerate", "element")
    free = np.concatenate([x, [[0.5e-3, 0.0, 0.02]]])
    _one_line(lambda: read_finger_mesh(_write(tmp_path, free, [("tetra", t), ("vertex", [[len(x)]])])),
              f"node {len(x)}", "belongs to no solid element")
    dropped = read_finger_mesh(_write(tmp_path, free, [("tetra", t)]))   # used by no cell at all: dropped
    assert dropped.n_nodes == len(x)
    apart = np.concatenate([x, x + [0.1, 0, 0]])
    _one_line(lambda: read_finger_mesh(_write(tmp_path, apart, [("tetra", np.concatenate([t, t + len(x)]))])),
              "2 disconnected parts", f"{len(t)}, {len(t)} elements")
    _one_line(lambda: read_finger_mesh(_write(tmp_path, x, [("wedge", t[:4, [0, 1, 2, 3, 0, 1]])])),
              "unsupported cell type wedge")
    _one_line(lambda: read_finger_mesh(_write(tmp_path, x, [("tetra", t), ("hexahedron", meshes["hexahedron"].hexes)])),
              "mixes solid cell types", "tetra", "hexahedron")
    _one_line(lambda: read_finger_mesh(_write(tmp_path, x, [("triangle", t[:, :3])])), "no solid cells", "triangle")
    good = _write(tmp_path, x, [("tetra", t)], name="good.inp", point_sets={"ROOT": mesh.node_sets["root"]})
    _one_line(lambda: read_finger_mesh(good, clamp="base"), "clamp = 'base': no such set", "ROOT", "z_min")
    _one_line(lambda: read_finger_mesh(good, clamp="ROOT", tip="z_min"), "share", "nodes")
    _one_line(lambda: read_finger_mesh(good, mesh_unit="mm"), "is mesh_unit right?", "mesh_unit = 'mm'")
    _one_line(lambda: read_finger_mesh(good, mesh_unit="cm"), "mesh_unit = 'cm'", "m, mm")
    _one_line(lambda: read_finger_mesh(good, bending_direction="z"), "bending_direction = 'z'", "y, x")
    _one_line(lambda: read_finger_mesh(tmp_path / "none.msh"), "none.msh: no such mesh file")
    _one_line(lambda: read_finger_mesh(good.rename(tmp_path / "good.stl")), "unknown mesh format '.stl'", ".msh")
    (tmp_path / "junk.msh").write_text("$MeshFormat\nnonsense\n")
    _one_line(lambda: read_finger_mesh(tmp_path / "junk.msh"), "junk.msh: cannot read the mesh")
    (tmp_path / "junk.k").write_text("*NODE\n       1  abc\n")
    _one_line(lambda: read_finger_mesh(tmp_path / "junk.k"), "junk.k: cannot read the LS-DYNA deck")


def test_sm_c_counts_and_volume_against_the_paper():
    mesh = sm_c()
    assert mesh.element_type == "tet10"
    assert mesh.n_nodes == pytest.approx(7481, rel=0.15) and mesh.n_elements == pytest.approx(4682, rel=0.15)
    volume = element_volumes(mesh)
    assert volume.min() > 0
    assert volume.sum() == pytest.approx(np.pi * 12e-3 * 8.45e-3 * 4.5 * 0.0254, rel=0.01)
    average_length = (6 * np.sqrt(2) * volume.sum() / mesh.n_elements) ** (1 / 3)
    assert average_length == pytest.approx(4e-3, rel=0.05)
    assert np.allclose(mesh.nodes[mesh.node_sets["root"], 2], 0.0)
    assert np.allclose(mesh.nodes[mesh.node_sets["tip"], 2], 4.5 * 0.0254)


def test_gmsh_meshes_are_deterministic():
    a, b = sm_c(length_in=2.0, element_size_m=6e-3), sm_c(length_in=2.0, element_size_m=6e-3)
    np.testing.assert_array_equal(a.tets10, b.tets10)
    np.testing.assert_array_equal(a.nodes, b.nodes)


@pytest.mark.parametrize("version, binary, order, size", [(4, False, 2, 8e-3), (2, True, 2, 8e-3), (4, True, 1, 4e-3)])
def test_tapered_finger_file_against_its_cad_volume(tmp_path, version, binary, order, size):
    path = tmp_path / "tapered.msh"
    cad = write_tapered_finger(path, size, order=order, msh_version=version, binary=binary)
    assert 0.95 * tapered_volume() < cad < tapered_volume()         # the hole takes a few per cent
    mesh = read_finger_mesh(path, clamp="clamp", tip="tip")
    volume = element_volumes(mesh)
    assert volume.min() > 0
    # 10-node tetrahedra follow the curved surface; 4-node ones cut it with flat facets
    assert volume.sum() == pytest.approx(cad, rel=2e-3 if order == 2 else 2.5e-2)
    by_plane = read_finger_mesh(path)
    assert all(np.array_equal(mesh.node_sets[k], by_plane.node_sets[k]) for k in ("root", "tip"))
    same = tapered_finger(size, order=order)
    np.testing.assert_allclose(same.nodes, mesh.nodes, rtol=0, atol=1e-12)


def test_generator_inputs_are_checked(tmp_path):
    _one_line(lambda: sm_c(length_in=20), "length_in = 20", "1..12")
    _one_line(lambda: tapered_finger(1.0), "element_size_m", "0.0001..0.05")
    _one_line(lambda: tapered_finger(5e-3, hole_radius_m=0.01), "hole_radius_m")
    _one_line(lambda: tapered_finger(5e-3, order=3), "order = 3")
    _one_line(lambda: write_tapered_finger(tmp_path / "x.msh", 5e-3, msh_version=3), "msh_version = 3")


@pytest.mark.parametrize("generator", [sm_a, sm_b])
def test_the_paper_hexahedral_meshes_pass_the_checks(tmp_path, generator):
    """SM-A's and SM-B's wedge-like section-corner elements are valid, not degenerate, and
    the planes z_min / z_max are the generators' own root and tip."""
    mesh = generator(length_in=4.5)
    path = _write(tmp_path, mesh.nodes, [("hexahedron", mesh.hexes)], name="sm.vtu")
    back = read_finger_mesh(path)
    assert all(np.array_equal(back.node_sets[k], mesh.node_sets[k]) for k in ("root", "tip"))
    assert element_volumes(back).sum() == pytest.approx(np.pi * 12e-3 * 8.45e-3 * 4.5 * 0.0254, rel=0.02)


BOX_SCRIPT = """SetFactory("OpenCASCADE");
Box(1) = {-0.005, -0.004, 0, 0.01, 0.008, 0.05};
Physical Volume("finger") = {1};
Mesh.MeshSizeMax = 0.004;
Mesh.ElementOrder = ORDER;
"""


@pytest.mark.parametrize("order, kind", [(1, "tet4"), (2, "tet10")])
def test_a_gmsh_script_is_meshed_and_read(tmp_path, order, kind):
    """A .geo script: Gmsh meshes it with the script's own settings (order), and the
    finger reads back with its volume and its clamp and tip planes."""
    path = tmp_path / "box.geo"
    path.write_text(BOX_SCRIPT.replace("ORDER", str(order)))
    mesh = read_finger_mesh(path)
    assert mesh.element_type == kind and mesh.n_elements > 20
    assert element_volumes(mesh).sum() == pytest.approx(0.01 * 0.008 * 0.05, rel=1e-9)
    assert np.allclose(mesh.nodes[mesh.node_sets["root"], 2], 0.0)
    assert np.allclose(mesh.nodes[mesh.node_sets["tip"], 2], 0.05)


def test_a_broken_gmsh_script_is_one_line(tmp_path):
    path = tmp_path / "broken.geo"
    path.write_text('SetFactory("OpenCASCADE");\nBox(1) = {0, 0, 0, 0.01, 0.01};\n')
    with pytest.raises(InputError, match=r"broken.geo: Gmsh could not mesh the script") as err:
        read_finger_mesh(path)
    assert "\n" not in str(err.value)
