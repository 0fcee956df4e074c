"""The drum/object set-up of the paper's section 3.3: geometry, the object stress solve,
and the command line (short run). Full-length contact runs are in reports/ and the
contact benchmark, not here."""
import json

import numpy as np
import pandas as pd
import pytest

from ccedi.errors import InputError
from ccedi.fea.contact.drum import DrumSetup, ObjectStress, finger_frame, finger_on_drum, first_contact_angle
from ccedi.study.cli import main


def test_finger_matches_table2_and_sits_on_the_drum():
    setup = DrumSetup(theta0_rad=0.3)
    model, v0 = finger_on_drum(setup, 7.5)
    assert (model.mesh.n_elements, model.mesh.n_nodes) == (1275, 1872)
    root = model.mesh.nodes[model.mesh.node_sets["root"]]
    assert np.allclose(root @ [np.cos(0.3), np.sin(0.3), 0.0], setup.drum_radius_m)
    assert np.isclose(np.linalg.det(finger_frame(0.3)), 1.0)
    assert np.allclose(v0, setup.omega_rad_s * np.column_stack([-model.mesh.nodes[:, 1], model.mesh.nodes[:, 0],
                                                                 np.zeros(model.mesh.n_nodes)]))


def test_rigid_first_contact_angle_for_a_round_object():
    """A circle of radius r at distance D, polar angle phi: the finger's leading face (the
    soft half-thickness h = 8.45 mm off its axis) touches it at theta = phi - asin((r + h) / D)."""
    r, phi, D = 0.03, 1.0, 0.2
    setup = DrumSetup(object_center_m=(D * np.cos(phi), D * np.sin(phi)), object_semi_axes_m=(r, r), theta0_rad=0.0)
    expected = phi - np.arcsin((r + 8.45e-3) / D)
    assert first_contact_angle(setup, samples=20000) == pytest.approx(expected, abs=2e-3)


def test_object_stress_is_linear_and_balanced():
    stress = ObjectStress(DrumSetup())
    c = np.array([*DrumSetup().object_center_m, 0.0])
    p = c + [0.0, -DrumSetup().object_semi_axes_m[1], 0.0]           # on the side facing the drum
    s1 = stress.max_von_mises(p[None], np.array([[0.0, 1.0, 0.0]]))
    s2 = stress.max_von_mises(p[None], np.array([[0.0, 3.0, 0.0]]))
    assert s1 > 0.0 and s2 == pytest.approx(3.0 * s1, rel=1e-6)
    assert stress.max_von_mises(np.zeros((0, 3)), np.zeros((0, 3))) == 0.0


def test_object_overlapping_the_drum_is_refused():
    with pytest.raises(InputError, match="overlaps the drum"):
        DrumSetup(object_center_m=(0.05, 0.05))


def test_cli_contact_short_run_writes_summary(tmp_path):
    path = tmp_path / "c.json"
    assert main(["contact", "--alpha", "7.5", "--t-end-s", "0.02", "--n-outputs", "4", "--out", str(tmp_path),
                 "--json", str(path)]) == 0
    summary = json.loads(path.read_text())
    for key in ("contact_start_s", "contact_end_s", "contact_duration_s", "peak_reaction_force_N",
                "max_finger_stress_Pa", "max_object_stress_Pa", "first_contact_point_m", "last_contact_point_m",
                "wall_time_s"):
        assert key in summary
    assert summary["contact_start_s"] is None                      # 20 ms: the finger has not arrived yet
    assert (tmp_path / "contact_alpha7.5_global.csv").exists()


def test_a_sweep_that_never_touches_reports_no_contact(tmp_path, capsys):
    from ccedi.study.commands.fea import write_contact_sweep

    coarse = DrumSetup(finger_section_elements=3, finger_elements_along=26)
    write_contact_sweep(coarse, [180.0], tmp_path, t_end_s=0.05, n_outputs=5, scheduler="serial")
    report = (tmp_path / "contact_report.md").read_text()
    assert "| 180 | no contact within the run |" in report
    summary = pd.read_csv(tmp_path / "contact_summary_global.csv")
    assert summary.contact_start_s.isna().all() and summary.first_contact_side.isna().all()


def test_a_relative_damping_sweep_alone_has_its_report(tmp_path):
    """A sweep with relative damping only (a user's study) gets its own report table, without
    the paper's global-damping timings beside it."""
    from ccedi.study.commands.fea import write_contact_sweep

    coarse = DrumSetup(finger_section_elements=3, finger_elements_along=26)
    write_contact_sweep(coarse, [180.0], tmp_path, damping="relative", t_end_s=0.05, n_outputs=5, scheduler="serial")
    report = (tmp_path / "contact_report.md").read_text()
    assert "## Relative damping" in report and "(paper)" not in report and "## Global damping" not in report
    assert "| 180 | no contact within the run |" in report
