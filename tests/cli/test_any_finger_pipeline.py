"""The pipeline on a finger that is not a prism (the tapered finger with a hole, written by
Gmsh into a .msh file and given as ``[finger] mesh``): contact on the drum, export, the
design re-check, ``ccedi design`` on it and ``ccedi study``."""
import json
from dataclasses import replace

import meshio
import numpy as np
import pandas as pd
import pytest

from ccedi.design.optimise import Design
from ccedi.design.outputs import OUTPUTS, design_outputs, setup_for_length
from ccedi.design.recheck import fea_check
from ccedi.errors import InputError
from ccedi.fea.contact.drum import DrumSetup, ObjectStress, finger_frame, finger_on_drum, first_contact_angle
from ccedi.fea.contact.penalty import boundary_nodes
from ccedi.fea.io.lsdyna import read_keyword
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import Mesh
from ccedi.fea.mesh.gmsh_fingers import write_tapered_finger
from ccedi.fea.mesh.readers import read_finger_mesh
from ccedi.fea.model import cantilever_model
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.models import ContactResponse
from ccedi.rom.contact_rom import ReducedContactModel
from ccedi.study.cli import main
from ccedi.units import inch_to_m

SIZE_M = 0.012         # coarse: 933 nodes, 417 ten-node tetrahedra
LEAD_S = 0.001         # the finger reaches the object this long after the start
T_END_S = 0.006


def _toml(directory, order):
    write_tapered_finger(directory / "finger.msh", SIZE_M, order=order)
    toml = directory / "finger.toml"
    toml.write_text('[finger]\nmesh = "finger.msh"\nclamp = "clamp"\ntip = "tip"\n')
    return toml, read_finger_mesh(directory / "finger.msh", clamp="clamp", tip="tip")


@pytest.fixture(scope="module")
def finger(tmp_path_factory):
    """(TOML, mesh) of the coarse tapered finger of 10-node tetrahedra."""
    return _toml(tmp_path_factory.mktemp("finger"), order=2)


def _theta0(mesh):
    """The initial angle at which the undeformed finger touches the object after LEAD_S."""
    setup = DrumSetup(finger=mesh, theta0_rad=0.0)
    return first_contact_angle(setup) - setup.omega_rad_s * LEAD_S


@pytest.fixture(scope="module")
def contact(finger, tmp_path_factory):
    """``ccedi contact`` on the finger: (setup, JSON summary, CSV history, VTU directory)."""
    toml, mesh = finger
    out = tmp_path_factory.mktemp("contact")
    theta0 = _theta0(mesh)
    assert main(["contact", "--config", str(toml), "--alpha", "7.5", "--t-end-s", str(T_END_S), "--n-outputs", "15",
                 "--theta0-rad", repr(theta0), "--out", str(out), "--vtu", str(out / "vtu")]) == 0
    stem = "contact_alpha7.5_global"
    return (DrumSetup(finger=mesh, theta0_rad=theta0), json.loads((out / f"{stem}.json").read_text()),
            pd.read_csv(out / f"{stem}.csv"), out / "vtu")


def test_the_finger_is_mounted_root_on_the_drum(finger):
    _, mesh = finger
    moved = Mesh(nodes=mesh.nodes + [0.01, -0.02, 0.03], tets10=mesh.tets10, node_sets=mesh.node_sets)
    setup = DrumSetup(finger=moved)
    assert setup.finger_length_m == pytest.approx(inch_to_m(4.5), rel=1e-9)      # root face to tip face
    np.testing.assert_allclose(setup.finger.nodes, DrumSetup(finger=mesh).finger.nodes, rtol=0, atol=1e-15)
    model, v0 = finger_on_drum(setup, alpha=7.5)
    local = model.mesh.nodes @ finger_frame(setup.theta0_rad)               # (wide, soft, radial)
    root = model.mesh.node_sets["root"]
    np.testing.assert_allclose(local[root, 2], setup.drum_radius_m, rtol=0, atol=1e-12)
    np.testing.assert_allclose(local[root, :2].mean(axis=0), 0.0, atol=1e-12)
    assert np.array_equal(model.rotating.nodes, root) and model.mesh.element_type == "tet10"
    np.testing.assert_array_equal(model.contact.nodes, boundary_nodes(model.mesh))
    speed = np.linalg.norm(v0, axis=1)                                      # rigid turning: omega r
    np.testing.assert_allclose(speed, setup.omega_rad_s * np.hypot(*model.mesh.nodes[:, :2].T), rtol=1e-12)


@pytest.mark.parametrize("change, message", [
    (lambda m: {"finger": m, "finger_length_m": 0.2}, "the finger mesh sets the length"),
    (lambda m: {"finger": "finger.msh"}, "must be a ccedi.fea.mesh.Mesh"),
    (lambda m: {"finger": Mesh(nodes=m.nodes, tets10=m.tets10, node_sets={"root": m.node_sets["root"]})},
     "node set 'tip' missing"),
    (lambda m: {"finger": Mesh(nodes=m.nodes * [1, 1, -1], tets10=m.tets10[:, [0, 2, 1, 3, 6, 5, 4, 7, 9, 8]],
                               node_sets=m.node_sets)}, "below the root"),
])
def test_a_bad_finger_is_refused_in_one_line(finger, change, message):
    _, mesh = finger
    with pytest.raises(InputError, match=message) as err:
        DrumSetup(**change(mesh))
    assert "\n" not in str(err.value)


def test_contact_on_an_imported_finger_balances_energy(contact):
    """The finger reaches the object, slides on it with friction, and the energy balance
    (contact and friction work included) closes within 2 %; the contact's work is more than
    2 % of the energies involved, so a contact force missing from the balance would fail it."""
    setup, summary, h, _ = contact
    assert summary["contact_start_s"] is not None and summary["contact_start_s"] < T_END_S / 2
    assert summary["peak_reaction_force_N"] > 0.1 and summary["warnings"] == []
    assert summary["energy_balance_error"] < 0.02
    absorbed = h.kinetic_energy_J + h.internal_energy_J + h.hourglass_energy_J + h.damping_energy_J \
        + h.bulk_viscosity_energy_J
    contact_work = abs(h.normal_contact_work_J.iloc[-1] + h.friction_work_J.iloc[-1])
    assert contact_work > 0.02 * absorbed.max()
    assert 0 < summary["penetration_to_thickness"] < 0.01
    assert summary["penetration_to_thickness"] == pytest.approx(summary["max_penetration_m"]
                                                                / setup.finger_thickness_m, rel=1e-12)


def test_contact_vtu_of_an_imported_finger(contact, finger):
    _, mesh = finger
    frames = sorted(contact[3].glob("*.vtu"))
    assert len(frames) == 3
    back = meshio.read(frames[-1])
    np.testing.assert_array_equal(back.cells_dict["tetra10"], mesh.tets10)
    assert back.cell_data["von_mises_Pa"][0].max() > 0.0


class _Replay:
    """A contact model that answers with a recorded history, and records the set-ups it is built on."""

    built = []

    def __init__(self, setup, history, summary):
        self.history, self.summary = history, summary
        _Replay.built.append(setup)

    def run(self, alpha, *, damping="global", t_end_s=1.5, n_outputs=300, progress=False):
        return ContactResponse(history=self.history, summary={"model": "fea", **self.summary})


def test_fea_check_runs_the_given_finger_at_its_length(contact):
    """The re-check hands the model factory the set-up with the finger mesh; with the
    recorded FE history as both surrogate and full model the errors vanish."""
    setup, summary, h, _ = contact
    setup = replace(setup, cycle_time_s=T_END_S - 2 * LEAD_S)         # the next object within the short run
    outputs = design_outputs(setup, h, ObjectStress(setup))
    design = Design(alpha_per_s=7.5, x=setup.finger_length_m, outputs=outputs, J=0.0)
    _Replay.built.clear()
    rows = fea_check(setup, [design], model_factory=lambda s: _Replay(s, h, summary), progress=None)
    assert _Replay.built[0].finger is setup.finger
    assert all(v in (None, 0.0) for v in rows[0]["relative_error"].values())
    assert rows[0]["fea"]["contact_start_s"] == outputs["contact_start_s"] is not None
    assert set(OUTPUTS) <= set(outputs)


def test_another_length_and_the_face_contact_rom_are_refused_for_a_given_finger(finger, tmp_path):
    _, mesh = finger
    setup = DrumSetup(finger=mesh)
    with pytest.raises(InputError, match="only the generated finger takes another length"):
        setup_for_length(setup, 0.2032)
    assert setup_for_length(setup, setup.finger_length_m) is setup
    design = Design(alpha_per_s=180.0, x=0.1, outputs={}, J=0.0)
    with pytest.raises(InputError, match="only the generated finger"):
        fea_check(setup, [design], model_factory=lambda s: pytest.fail("ran"), progress=None)
    with pytest.raises(InputError, match="'face' contact needs the generated elliptical finger") as err:
        ReducedContactModel(setup, contact="face")
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("case", ["impulse", "contact"])
def test_export_lsdyna_of_an_imported_finger(finger, tmp_path, case):
    toml, mesh = finger
    deck = tmp_path / f"{case}.k"
    assert main(["export", "--case", case, "--format", "lsdyna", "--config", str(toml), "--out", str(deck)]) == 0
    back = read_keyword(deck)
    assert back.elform == 16 and len(back.hexes) == len(back.tets4) == 0
    np.testing.assert_array_equal(back.tets10, mesh.tets10)
    if case == "impulse":
        np.testing.assert_allclose(back.nodes, mesh.nodes, rtol=0, atol=1e-12)
    else:
        model, _ = finger_on_drum(DrumSetup(finger=mesh), alpha=180.0)
        np.testing.assert_allclose(back.nodes, model.mesh.nodes, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(back.contact["nodes"], boundary_nodes(mesh))


def test_export_length_beside_a_mesh_is_refused(finger, tmp_path, capsys):
    toml, _ = finger
    assert main(["export", "--length-in", "3", "--config", str(toml), "--out", str(tmp_path / "x.k")]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--length-in" in err[0] and "mesh" in err[0]


def test_quick_study_with_a_mesh_states_why_it_skips_steps(finger, tmp_path, capsys):
    """The steps of the generated finger are skipped with their reasons, in study.json and
    index.html; Table 1 has the finger's row."""
    toml, mesh = finger
    out = tmp_path / "study"
    assert main(["study", "--quick", "--config", str(toml), "--scheduler", "serial", "--out", str(out),
                 "--only", "table1", "mesh", "damping_fits", "design"]) == 0
    record = json.loads((out / "study.json").read_text())
    assert set(record["skipped"]) == {"mesh", "damping_fits", "design"} and set(record["wall_time_s"]) == {"table1"}
    page = (out / "index.html").read_text()
    assert "Steps skipped for this finger" in page and "ccedi design --config FILE" in page
    row = json.loads((out / "table1.json").read_text())["finger"]
    assert (row["element_type"], row["nodes"]) == ("tet10", mesh.n_nodes)
    assert "design skipped" in capsys.readouterr().out


def test_a_study_of_a_mesh_reports_that_finger_first_and_only_the_inputs_it_used(finger, tmp_path):
    """The finger step describes the mesh (its first frequency, the element that sets its
    step); the page leads with it, has no paper section, and lists the mesh's keys but not
    the generated finger's lengths, which the mesh overrides."""
    toml, mesh = finger
    out = tmp_path / "study"
    assert main(["study", "--quick", "--config", str(toml), "--scheduler", "serial", "--out", str(out),
                 "--only", "finger"]) == 0
    row = json.loads((out / "finger.json").read_text())
    omega1 = natural_frequencies(cantilever_model(mesh, RUBBER), n_modes=1)[0]
    assert (row["element_type"], row["nodes"], row["mesh_file"]) == ("tet10", mesh.n_nodes, str(toml.parent / "finger.msh"))
    assert row["length_m"] == pytest.approx(inch_to_m(4.5), rel=1e-6)           # as Gmsh placed the tip
    assert row["f1_hz"] == pytest.approx(omega1 / (2 * np.pi), rel=1e-9)
    assert row["alpha_cr_first_mode_per_s"] == pytest.approx(2 * omega1, rel=1e-9)
    page = (out / "index.html").read_text()
    assert page.index("ccedi design study of finger.msh") < page.index("The finger: stable step")
    assert "Reproduction of the paper" not in page and "SM-B" not in page
    assert "[finger] mesh" in page and "impulse_length_in" not in page and "contact_length_in" not in page
    assert f"{row['f1_hz']:.4g}" in page


@pytest.mark.slow
def test_whole_quick_study_on_an_imported_finger(tmp_path):
    """``ccedi study --quick --config FILE`` with a [finger] mesh (4-node tetrahedra, coarse)
    runs every step that applies and writes the report."""
    toml, mesh = _toml(tmp_path, order=1)
    out = tmp_path / "study"
    assert main(["study", "--quick", "--config", str(toml), "--scheduler", "serial", "--out", str(out)]) == 0
    record = json.loads((out / "study.json").read_text())
    assert set(record["wall_time_s"]) == {"finger", "impulse", "contact", "calibrate"}
    assert set(record["skipped"]) == {"design"}
    summary = pd.read_csv(out / "contact" / "contact_summary_relative.csv")      # [damping] kind
    assert (summary.energy_balance_error < 0.02).all()
    assert (out / "index.html").exists() and "given mesh" in (out / "contact" / "contact_report.md").read_text()


@pytest.mark.parametrize("command", [["rom-check", "--json", "r.json"], ["damping-fits", "--out", "fits"]])
def test_commands_of_the_generated_finger_refuse_the_mesh(finger, tmp_path, capsys, command):
    """A command that works on the generated finger only says so in one line instead of
    running the prism without a word about the configured mesh."""
    toml, _ = finger
    args = [command[0], "--config", str(toml), command[1], str(tmp_path / command[2])]
    assert main(args) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "[finger] mesh" in err[0] and command[0] in err[0]
    assert not (tmp_path / command[2]).exists()


@pytest.mark.slow
def test_design_of_an_imported_tetrahedral_finger_is_checked_by_its_fea(tmp_path, capsys):
    """``ccedi design --config`` with the tapered finger of 4-node tetrahedra: the contact ROM
    is built on the mesh, the design varies alpha and the drum speed (its length is its
    own), the optimum is verified by the full FEA of the mesh, and that FEA meets every
    requirement at the design (the throughput objective: the fastest drum that does)."""
    toml, mesh = _toml(tmp_path, order=1)
    toml.write_text(toml.read_text() + '\n[requirements]\nallowable_root_stress_Pa = 4e6\nobjective = "throughput"\n')
    out = tmp_path / "design.json"
    rc = main(["design", "--config", str(toml), "--drum-speed-bounds-rpm", "20", "40", "--grid", "5", "4",
               "--validation-runs", "2", "--pareto-points", "4", "--starts", "2", "--fea-check-designs", "1",
               "--scheduler", "serial", "--out", str(tmp_path / "design"), "--json", str(out)])
    assert rc == 0, capsys.readouterr().err
    d = json.loads(out.read_text())
    assert d["finger_mesh"]["element_type"] == "tet4" and d["finger_mesh"]["elements"] == mesh.n_elements
    assert [v["name"] for v in d["problem"]["variables"]] == ["alpha_per_s", "drum_speed_rad_s"]
    assert d["problem"]["verified_by"] == "full FEA" and d["model_error"] == {}
    check = d["fea_check"][0]
    assert check["meets_requirements"] and all(r["met"] for r in check["requirements"].values())
    assert check["drum_speed_rpm"] == pytest.approx(d["optimum"]["drum_speed_rpm"], rel=1e-12)
    assert check["fea"]["cycle_time_s"] == pytest.approx(30.0 / d["optimum"]["drum_speed_rpm"], rel=1e-9)
    assert d["rom_verification"][-1]["missed"] == []
    assert "drum speed" in (tmp_path / "design" / "design_report.md").read_text()
