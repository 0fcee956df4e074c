"""Guards on the range of validity (ccedi.fea.solvers.validity): each check measured on healthy
runs and made to fire on a broken one; warnings recorded in the summaries and the JSON,
printed once on stderr; a meaningless result an error of one line."""
import json
import warnings

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ccedi.errors import SolverError, ValidityWarning
from ccedi.fea.cases.studies import finger_impulse_model
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import elliptical_cantilever
from ccedi.fea.model import ForcePulse, cantilever_model, face_node_weights, tip_pulse
from ccedi.fea.solvers.explicit import run
from ccedi.fea.solvers.static import static_solve
from ccedi.fea.solvers.validity import (
    ENERGY_BALANCE_TOLERANCE,
    HOURGLASS_FRACTION_LIMIT,
    TIP_DEFLECTION_WARNING_FRACTION,
    energy_balance_error,
    max_log_strain,
    run_checks,
    tip_deflection_warnings,
)
from ccedi.rom.modal import ModalImpulseModel, reduce_impulse_model
from ccedi.study.cli import main

COARSE = elliptical_cantilever(0.05, 3, 6)
"""A 50 mm finger of 3 x 3 x 6 hexahedra: fast runs."""


def quiet_run(*args, **kwargs):
    """:func:`ccedi.fea.solvers.explicit.run` with its validity warnings recorded, not shown."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = run(*args, **kwargs)
    return res, [str(w.message) for w in caught if issubclass(w.category, ValidityWarning)]


def rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(0.3, 3.0), min_size=3, max_size=3), st.floats(0.0, 3.1),
       st.lists(st.floats(-1, 1), min_size=3, max_size=3).filter(lambda a: np.linalg.norm(a) > 0.1))
def test_max_log_strain_is_the_largest_principal_log_strain(stretches, angle, axis):
    """F = R U with U of known principal stretches, turned by a rotation Q: the largest
    |ln lambda| whatever the rotations (the measure is objective)."""
    Q = rotation(axis[::-1], 0.7 * angle)
    U = Q @ np.diag(stretches) @ Q.T
    F = np.stack([rotation(axis, angle) @ U, np.eye(3)])
    assert max_log_strain(F) == pytest.approx(np.abs(np.log(stretches)).max(), abs=1e-6)


def test_a_rigid_rotation_is_no_strain():
    assert max_log_strain(rotation([1.0, 2.0, 0.5], 2.0)[None]) == pytest.approx(0.0, abs=1e-12)


def test_compiled_log_strain_equals_the_numpy_reference():
    """The closed-form eigenvalues of the kernel against numpy's symmetric eigensolver."""
    rng = np.random.default_rng(3)
    F = np.eye(3) + 0.4 * rng.standard_normal((500, 3, 3))
    F = F[np.linalg.det(F) > 0.1]
    stretches_sq = np.linalg.eigvalsh(F.swapaxes(1, 2) @ F)
    reference = float(np.abs(0.5 * np.log(stretches_sq)).max())
    assert max_log_strain(F) == pytest.approx(reference, rel=1e-9)
    for f in F[:50]:
        one = float(np.abs(0.5 * np.log(np.linalg.eigvalsh(f.T @ f))).max())
        assert max_log_strain(f[None]) == pytest.approx(one, rel=1e-9, abs=1e-12)


@pytest.fixture(scope="module")
def released():
    """The coarse finger let go from a static tip deflection: free vibration, no load."""
    model = cantilever_model(COARSE, RUBBER, alpha=100.0)
    tip = COARSE.node_sets["tip"]
    f = np.zeros_like(COARSE.nodes)
    f[tip, 1] = 0.05 * face_node_weights(COARSE, tip)
    x0 = static_solve(model, f)
    return quiet_run(model, 0.01, n_outputs=50, x0=x0)[0]


def test_energy_balance_counts_the_initial_energy(released):
    """Released from a deflected state, no work is done on the finger: the strain energy
    it starts with turns into kinetic energy and damping. The balance holds with the
    initial energy (measured 1e-4) and fails completely without it."""
    h = released.history
    assert h.external_work_J.abs().max() < 1e-12
    assert h.damping_energy_J.iloc[-1] > 0.1 * h.internal_energy_J.iloc[0]
    assert released.summary["energy_balance_error"] < 0.1 * ENERGY_BALANCE_TOLERANCE
    assert energy_balance_error(h, initial_energy_J=0.0) > 0.9


def test_energy_balance_check_fires_on_a_broken_record():
    """A healthy pulse run from rest balances (measured 0.24 %); the same history with 3 %
    of the work gone from the damping record after the first quarter fails the check."""
    res, _ = quiet_run(coarse_pulse_model(False, 1.0), 6e-3, n_outputs=30)
    h = res.history
    assert res.summary["energy_balance_error"] < 0.25 * ENERGY_BALANCE_TOLERANCE
    assert not any(w.startswith("energy balance") for w in res.summary["warnings"])
    broken = h.copy()
    broken.loc[broken.index >= len(h) // 4, "damping_energy_J"] -= 0.03 * h.external_work_J.max()
    checks = run_checks(broken)
    assert checks["energy_balance_error"] > ENERGY_BALANCE_TOLERANCE
    assert any(w.startswith("energy balance error") for w in checks["warnings"])


def coarse_pulse_model(point_load, hourglass_coefficient):
    """The coarse finger, a 0.5 N tip pulse spread over the tip face or on one corner node."""
    tip = COARSE.node_sets["tip"]
    if point_load:
        corner = tip[np.argmax(COARSE.nodes[tip, 1])]
        pulse = ForcePulse(nodes=np.array([corner]), weights=np.ones(1), force_N=np.array([0.0, 0.5, 0.0]),
                           t_start_s=0.0, t_end_s=2e-3)
    else:
        pulse = tip_pulse(COARSE, [0.0, 0.5, 0.0], 2e-3)
    return cantilever_model(COARSE, RUBBER, alpha=200.0, pulses=[pulse], hourglass_coefficient=hourglass_coefficient)


def test_hourglass_check_fires_on_a_point_load_with_weak_hourglass_control():
    """With a small hourglass coefficient (0.02 of the physical stiffness), a load spread
    over the tip face bends the finger through the elements' strain (hourglass energy 4.9 %
    of the internal energy); the same load on one corner node drives the hourglass modes
    (36 %)."""
    face, face_warnings = quiet_run(coarse_pulse_model(False, 0.02), 6e-3, n_outputs=30)
    point, point_warnings = quiet_run(coarse_pulse_model(True, 0.02), 6e-3, n_outputs=30)
    assert face.summary["hourglass_energy_fraction"] < 0.5 * HOURGLASS_FRACTION_LIMIT
    assert point.summary["hourglass_energy_fraction"] > 2.0 * HOURGLASS_FRACTION_LIMIT
    assert face.summary["warnings"] == face_warnings == []
    assert [w for w in point.summary["warnings"] if w.startswith("hourglass energy")]
    assert len(point_warnings) == len(point.summary["warnings"])          # each issued once, with the run's alpha
    assert all(w.startswith("alpha = 200 1/s: ") for w in point_warnings)


@pytest.mark.parametrize("fraction, expected", [(0.1, 0), (0.35, 1)])
def test_tip_deflection_warns_beyond_small_deflection(fraction, expected):
    found = tip_deflection_warnings([0.0, -fraction * 0.2, 0.01], 0.2)
    assert len(found) == expected
    assert all(f"{round(100 * fraction)}% of the length" in w for w in found)


@pytest.mark.parametrize("tip", [[0.0, 0.2], [0.1, np.nan]])
def test_tip_deflection_of_the_length_or_nan_is_an_error(tip):
    with pytest.raises(SolverError, match="tip deflection"):
        tip_deflection_warnings(tip, 0.2)


def test_the_modal_rom_gets_the_same_tip_check():
    """The reduced model keeps the full model's length and flags (or refuses) its linear
    answer exactly where the full model's check would."""
    full = finger_impulse_model(mesh=elliptical_cantilever(0.05, 2, 3), duration_s=0.05)
    rom = reduce_impulse_model(full, n_modes=3)
    assert rom.length_m == pytest.approx(0.05)
    unit = rom.run(400.0, 0.1, 100)
    peak = np.abs(unit.tip_signal()[1]).max() / rom.length_m             # per newton
    assert unit.summary["warnings"] == []
    bigger = ModalImpulseModel(rom.rom, 0.5 / peak, rom.duration_s, length_m=rom.length_m)
    with pytest.warns(ValidityWarning, match="modal-3, alpha = 400 1/s: tip deflection .* 50% of the length"):
        response = bigger.run(400.0, 0.1, 100)
    assert len(response.summary["warnings"]) == 1
    with pytest.raises(SolverError, match="150% of the length"):
        ModalImpulseModel(rom.rom, 1.5 / peak, rom.duration_s, length_m=rom.length_m).run(400.0, 0.1, 100)


def impulse_cli(tmp_path, capsys, force_N, t_end_s):
    """``ccedi impulse`` at alpha = 180 1/s: (exit status, stderr lines a terminal shows,
    the summary JSON or None)."""
    rc = main(["impulse", "--alpha", "180", "--force-N", str(force_N), "--t-end-s", str(t_end_s),
               "--out", str(tmp_path)])
    err = capsys.readouterr().err
    shown = [line for line in err.replace("\r", "\n").splitlines() if line.strip() and "impulse runs" not in line]
    path = tmp_path / "impulse_summary.json"
    return rc, shown, json.loads(path.read_text()) if path.exists() else None


def test_healthy_impulse_carries_no_warnings(tmp_path, capsys):
    rc, shown, summary = impulse_cli(tmp_path, capsys, 1.0, 0.02)
    assert rc == 0 and shown == []
    run_summary = summary["runs"][0]
    assert summary["warnings"] == run_summary["warnings"] == []
    assert run_summary["energy_balance_error"] < 1e-3                       # measured 2e-4
    assert run_summary["hourglass_energy_fraction"] < HOURGLASS_FRACTION_LIMIT
    assert run_summary["max_log_strain"] < 0.05


def test_a_10_N_impulse_is_flagged_in_the_json_and_once_on_stderr(tmp_path, capsys):
    """10 N bends the 4.5-in finger by 41 mm, 36 % of its length."""
    rc, shown, summary = impulse_cli(tmp_path, capsys, 10.0, 0.03)
    assert rc == 0
    assert len(shown) == 1 and shown[0].startswith("ccedi impulse: warning: alpha = 180 1/s: tip deflection")
    assert summary["warnings"] == [shown[0].removeprefix("ccedi impulse: warning: ")]
    assert summary["runs"][0]["warnings"] == [summary["warnings"][0].removeprefix("alpha = 180 1/s: ")]
    assert summary["peaks"]["180"]["peak_tip_uy_m"] > TIP_DEFLECTION_WARNING_FRACTION * 0.1143


def test_a_100_N_impulse_is_an_error_of_one_line(tmp_path, capsys):
    """100 N (the largest --force-N) would deflect the 4.5-in finger's tip by more than its
    length: the run ends with one error line, exit 1, and writes nothing."""
    rc, shown, summary = impulse_cli(tmp_path, capsys, 100.0, 0.02)
    assert rc == 1 and summary is None
    assert len(shown) == 1 and shown[0].startswith("ccedi impulse: error: tip deflection")
    assert "% of the length 0.1143 m" in shown[0]


def test_a_solver_error_inside_the_runs_is_one_line(tmp_path, capsys, monkeypatch):
    """An inverted element in a mapped run: the progress bar is closed before the error
    line, which stands alone."""
    import ccedi.fea.cases.studies as studies

    def inverted(alpha, **kwargs):
        raise SolverError("element 3 inverted (J <= 0) at t = 0.001 s, step 250")
    monkeypatch.setattr(studies, "_impulse_run", inverted)
    rc, shown, _ = impulse_cli(tmp_path, capsys, 1.0, 0.02)
    assert rc == 1 and shown == ["ccedi impulse: error: element 3 inverted (J <= 0) at t = 0.001 s, step 250"]


def test_mapped_runs_bring_their_warnings_back_once():
    from ccedi.distributed import map_runs

    def flagged(x):
        warnings.warn(f"run {x}: flagged", ValidityWarning)
        return 2 * x

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert map_runs(flagged, [1, 2, 3]) == [2, 4, 6]
    assert [str(w.message) for w in caught] == ["run 1: flagged", "run 2: flagged", "run 3: flagged"]


def test_contact_report_lists_the_sweep_warnings():
    from ccedi.fea.cases.contact_study import WARNING_SEPARATOR, validity_lines

    table = pd.DataFrame({"alpha_per_s": [7.5, 600.0], "damping": ["global", "global"],
                          "warnings": [np.nan, WARNING_SEPARATOR.join(["a", "b"])]})       # as read back from CSV
    assert validity_lines(table) == ["- alpha = 600 1/s: a", "- alpha = 600 1/s: b"]
    assert validity_lines(table.iloc[:1])[0].startswith("None")


def test_study_records_step_warnings_and_the_index_lists_them(tmp_path, monkeypatch, capsys):
    from ccedi.study import run as study_run

    def flagged_step():
        warnings.warn("alpha = 70 1/s: tip deflection 40 mm is 35% of the length", ValidityWarning)

    monkeypatch.setattr(study_run, "steps", lambda cfg, out, scheduler: [("impulse", "one", flagged_step),
                                                                       ("finger", "two", lambda: None)])
    assert main(["study", "--out", str(tmp_path), "--scheduler", "serial"]) == 0
    err = capsys.readouterr().err
    assert err.count("ccedi study: warning: impulse: alpha = 70 1/s: tip deflection") == 1
    record = json.loads((tmp_path / "study.json").read_text())
    assert record["warnings"] == {"impulse": ["alpha = 70 1/s: tip deflection 40 mm is 35% of the length"],
                                  "finger": []}
    page = (tmp_path / "index.html").read_text()
    assert "Validity warnings (1)" in page and "tip deflection 40 mm is 35% of the length" in page


@pytest.mark.slow
def test_healthy_contact_run_carries_no_warnings():
    """The 8-in SM-A finger on the drum through its first contact (0.32 s at alpha =
    7.5 1/s); over the whole sweep (1.5 s) the energy balance error is 1.4e-4, the
    hourglass fraction 9.2 % and the largest log strain 0.32."""
    from ccedi.fea.contact.drum import DrumSetup, FullContactModel

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        response = FullContactModel(DrumSetup(), object_stress=False).run(7.5, t_end_s=0.45, n_outputs=45)
    s = response.summary
    assert s["contact_start_s"] is not None
    assert s["warnings"] == [] and not [w for w in caught if issubclass(w.category, ValidityWarning)]
    assert s["energy_balance_error"] < 1e-3
    assert s["hourglass_energy_fraction"] < HOURGLASS_FRACTION_LIMIT
