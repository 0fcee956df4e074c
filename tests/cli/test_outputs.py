"""VTU export (ParaView) and the ccedi command line."""
import json

import meshio
import numpy as np
import pytest

from ccedi.fea.cases.studies import PAPER_TABLE1
from ccedi.fea.io.vtu import write_series, write_vtu
from ccedi.fea.material import RUBBER, cauchy_von_mises
from ccedi.fea.mesh import elliptical_cantilever, sm_a, sm_b
from ccedi.fea.mesh.gmsh_fingers import sm_c as sm_c_mesh
from ccedi.fea.mesh.tet_mesh import box_cantilever, quadratic_tets, split_hexes
from ccedi.fea.model import cantilever_model, tip_pulse
from ccedi.fea.solvers.explicit import run
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.fea.solvers.static import tip_deflection
from ccedi.study.cli import main


@pytest.fixture(scope="module")
def model():
    mesh = elliptical_cantilever(0.05, 3, 4)
    return cantilever_model(mesh, RUBBER, alpha=10.0, pulses=[tip_pulse(mesh, [0.0, 1.0, 0.0], 1e-3)])


def test_vtu_round_trip(tmp_path, model):
    res = run(model, 2e-3, n_outputs=4, snapshot_every=2)
    path = write_vtu(tmp_path / "final.vtu", model, res.x)
    back = meshio.read(path)
    assert np.allclose(back.points, res.x)
    assert np.array_equal(back.cells_dict["hexahedron"], model.mesh.hexes)
    assert np.allclose(back.point_data["displacement_m"], res.x - model.mesh.nodes)
    assert back.cell_data["von_mises_Pa"][0].max() > 0.0
    pvd = write_series(tmp_path / "series", model, res)
    assert pvd.read_text().count("<DataSet") == len(res.snapshots) == 2


@pytest.mark.parametrize("kind", ["hex8", "tet4", "tet10"])
def test_vtu_of_every_element_type_under_a_homogeneous_stretch(tmp_path, kind):
    """A box of each element type stretched homogeneously: the VTU holds the mesh's own cells
    (type and connectivity), the displacement, and in every cell the von Mises stress of
    that deformation gradient (a wrong node order or gradient breaks the homogeneity)."""
    box = box_cantilever(0.03, 0.02, 0.01, nx=3, ny=2, nz=4)
    mesh = {"hex8": box, "tet4": split_hexes(box), "tet10": quadratic_tets(split_hexes(box))}[kind]
    model = cantilever_model(mesh, RUBBER)
    F = np.array([[1.02, 0.01, 0.0], [0.0, 0.99, 0.0], [0.0, 0.03, 1.01]])
    x = mesh.nodes @ F.T
    back = meshio.read(write_vtu(tmp_path / f"{kind}.vtu", model, x))
    vtk = {"hex8": "hexahedron", "tet4": "tetra", "tet10": "tetra10"}[kind]
    cells = {"hex8": mesh.hexes, "tet4": mesh.tets4, "tet10": mesh.tets10}[kind]
    assert list(back.cells_dict) == [vtk]
    np.testing.assert_array_equal(back.cells_dict[vtk], cells)
    np.testing.assert_allclose(back.points, x, rtol=0, atol=1e-15)
    np.testing.assert_allclose(back.point_data["displacement_m"], x - mesh.nodes, rtol=0, atol=1e-15)
    expected = cauchy_von_mises(F[None], RUBBER.mu, RUBBER.lam)[0]
    np.testing.assert_allclose(back.cell_data["von_mises_Pa"][0], expected, rtol=1e-9)
    assert expected > 1e5


@pytest.mark.slow
def test_cli_table1_writes_every_key(tmp_path):
    """``table1`` without the nonlinear static solves (SM-B's and SM-C's took minutes; the
    stiffness key is checked on SM-A's row in tests/verification/test_static.py): keys, counts, volume,
    steps and the step ratio. SM-C (Gmsh, 10-node tetrahedra) is the same finger as SM-A
    and SM-B: its small-load (linear) tip stiffness and its first frequency within 2 % of
    theirs (measured 70.91 N/m against 70.24 and 70.90; the nonlinear 1-2 N figures differ
    from these by the same geometric stiffening on each mesh), its node and element counts
    within 15 % of the paper's."""
    path = tmp_path / "t1.json"
    assert main(["table1", "--no-stiffness", "--json", str(path)]) == 0
    table = json.loads(path.read_text())
    for name, (nodes, elements) in {"SM-A": (1080, 725), "SM-B": (5900, 4698)}.items():
        row = table[name]
        assert set(row) == {"element_type", "nodes", "elements", "average_length_mm", "volume_cm3", "dt_us",
                            "steps_to_0_2_s", "step_ratio"}
        assert row["element_type"] == "hex8" and row["volume_cm3"] == pytest.approx(36.0, rel=0.01)
        assert (row["nodes"], row["elements"]) == (nodes, elements)
        assert row["steps_to_0_2_s"] == pytest.approx(0.2 / (row["dt_us"] * 1e-6), abs=1)
    assert table["SM-B"]["step_ratio"] == pytest.approx(2.83, rel=0.1)      # paper: 2.83
    sm_c = table["SM-C"]
    assert sm_c["element_type"] == "tet10"
    for key in ("nodes", "elements"):
        assert sm_c[key] == pytest.approx(PAPER_TABLE1["SM-C"][key], rel=0.15)
    models = {name: cantilever_model(make(length_in=4.5), RUBBER)
              for name, make in (("SM-A", sm_a), ("SM-B", sm_b), ("SM-C", sm_c_mesh))}
    assert models["SM-C"].mesh.n_nodes == sm_c["nodes"]
    k = {name: 1.0 / tip_deflection(model, 1.0, linear=True) for name, model in models.items()}
    omega1 = {name: natural_frequencies(model, n_modes=1)[0] for name, model in models.items()}
    for ref in ("SM-A", "SM-B"):
        assert k["SM-C"] == pytest.approx(k[ref], rel=0.02)
        assert omega1["SM-C"] == pytest.approx(omega1[ref], rel=0.02)


def test_cli_reports_bad_input_in_one_line(capsys):
    assert main(["impulse", "--alpha", "-5", "--t-end-s", "0.001", "--out", "/nonexistent/x"]) == 1
    err = capsys.readouterr().err
    assert "alpha" in err and "Traceback" not in err


def test_json_output_is_strict_json(tmp_path):
    """NaN and infinity become null, numpy scalars plain numbers: any JSON reader accepts the file."""
    from ccedi.outputs import write_json
    path = write_json(tmp_path / "x.json", {"a": float("nan"), "b": [np.float64(2.5), np.inf], "c": np.int64(3)})
    assert json.loads(path.read_text(), parse_constant=lambda c: pytest.fail(f"non-JSON constant {c}")) == \
        {"a": None, "b": [2.5, None], "c": 3}
