"""``ccedi calibrate``: the sidecar loader's errors, the model against physics, the CLI's
JSON keys, and bad data leaving no file behind."""
import json
import shutil

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT

from ccedi.calibrate import dynamics
from ccedi.calibrate.dynamics import integrate_tip, viscoelastic_pulse_response
from ccedi.calibrate.experiment import load_experiment
from ccedi.calibrate.finger_modes import finger_basis
from ccedi.calibrate.model import MODE_AMPLITUDE, rung_modes
from ccedi.calibrate.synthetic import Truth, declared_finger, solid_response, solid_system
from ccedi.errors import InputError
from ccedi.fea.cases.beam_theory import cantilever_frequencies, ellipse_section_properties
from ccedi.rom.modal import ModalROM, nrmse
from ccedi.study.cli import main
from ccedi.units import inch_to_m

DATA = ROOT / "data" / "measured"
RECORD = "time_delay_low"
AREA, INERTIA = ellipse_section_properties()
LENGTH = inch_to_m(8.0)


@pytest.fixture
def record(tmp_path):
    """A copy of one bundled record and its sidecar in tmp_path: (csv path, sidecar dict)."""
    csv = tmp_path / "rec.csv"
    shutil.copy(DATA / f"{RECORD}.csv", csv)
    return csv, json.loads((DATA / f"{RECORD}.json").read_text())


def _write(csv, meta, frame=None):
    csv.with_suffix(".json").write_text(json.dumps(meta))
    if frame is not None:
        frame.to_csv(csv, index=False)


@pytest.fixture(scope="module")
def basis():
    """The FE basis of the bundled records' declared finger (8 in, SM-A section)."""
    return finger_basis(LENGTH, (0.012, 0.00845), nu=0.49, rho_kg_m3=1000.0, E_Pa=6.1e6)


def test_fe_modes_match_euler_bernoulli_and_scale_as_sqrt_E(basis):
    """The solid's first mode and static tip flexibility are the slender beam's within the
    shear and mesh error (2 %); the FE mass is the prism's; E scales omega exactly."""
    modes = basis.modes()
    beam = cantilever_frequencies(6.1e6, 1000.0, LENGTH, area=AREA, second_moment=INERTIA, n_modes=3)
    assert modes.omega_rad_s[0] == pytest.approx(beam[0], rel=0.02)
    assert modes.omega_rad_s[1] == pytest.approx(beam[1], rel=0.03)
    assert modes.static_flexibility_m_N == pytest.approx(LENGTH**3 / (3 * 6.1e6 * INERTIA), rel=0.02)
    assert basis.mass_kg == pytest.approx(1000.0 * AREA * LENGTH, rel=0.02)
    assert modes.static_sag_per_g == pytest.approx(1000.0 * AREA * LENGTH**4 / (8 * 6.1e6 * INERTIA), rel=0.03)
    assert basis.modes(1.21).omega_rad_s == pytest.approx(1.1 * modes.omega_rad_s, rel=1e-12)


def test_ritz_additions_lower_the_modes_and_a_stiff_root_is_a_clamp(basis):
    modes = basis.modes(n_modes=3)
    heavy = basis.modes(tip_mass_kg=0.01, n_modes=3)
    soft = basis.modes(root_stiffness=1.0, n_modes=3)
    assert np.all(heavy.omega_rad_s < modes.omega_rad_s) and np.all(soft.omega_rad_s < modes.omega_rad_s)
    assert basis.modes(root_stiffness=1e7, n_modes=3).omega_rad_s == pytest.approx(modes.omega_rad_s, rel=1e-4)
    # a compliant root adds its rigid rotation's flexibility L^2 / k_r to the tip; a tip mass adds none
    k_r = 5.0
    assert basis.modes(root_stiffness=k_r).static_flexibility_m_N == pytest.approx(
        modes.static_flexibility_m_N + LENGTH**2 / k_r, rel=2e-3)


@pytest.mark.parametrize("kwargs", [{"tip_mass_kg": 0.008}, {"root_stiffness": 2.0}])
def test_ritz_additions_match_the_generators_modified_solid(basis, kwargs):
    """The calibration's Ritz tip mass and root rotation against the generator's FE solid with
    the mass spread on the tip face / the root face free to rotate (independent paths)."""
    gen = solid_system(LENGTH, 1.0, tip_mass_kg=kwargs.get("tip_mass_kg", 0.0),
                       root_stiffness=kwargs.get("root_stiffness"))
    bending = gen.omega_rad_s[np.abs(gen.tip) > 1e-3 * np.abs(gen.tip).max()]
    assert basis.modes(**kwargs).omega_rad_s[:3] == pytest.approx(bending[:3], rel=0.01)


@pytest.mark.parametrize("n_modes, pulse_s", [(6, 0.01), (10, 0.001)])
def test_rk4_matches_the_exact_pulse_response(basis, n_modes, pulse_s, monkeypatch):
    """Within a tenth of the bundled records' 1 % noise floor at the default step, and
    converging at fourth order: halving H_OMEGA cuts the error by at least 8 (16 in the limit)."""
    modes = basis.modes(n_modes=n_modes)
    t = np.arange(2001) * 1e-3
    zeta = 4.0 / (2.0 * modes.omega_rad_s)
    exact = ModalROM(modes.omega_rad_s, modes.tip**2, zeta_fitted=zeta).pulse_response(t, 1.0, pulse_s)
    coarse = nrmse(integrate_tip(t, modes, zeta, force_N=1.0, duration_s=pulse_s), exact)
    assert coarse < 1e-3
    monkeypatch.setattr(dynamics, "H_OMEGA", dynamics.H_OMEGA / 4.0)
    fine = nrmse(integrate_tip(t, modes, zeta, force_N=1.0, duration_s=pulse_s), exact)
    monkeypatch.setattr(dynamics, "H_OMEGA", dynamics.H_OMEGA / 2.0)
    finer = nrmse(integrate_tip(t, modes, zeta, force_N=1.0, duration_s=pulse_s), exact)
    assert finer < fine / 8.0 < coarse / 8.0


def test_viscoelastic_response_is_the_integrators_and_the_elastic_one_at_g_0(basis, monkeypatch):
    """The exact 3-state modal solution against RK4 on the same equations (a fine step), and
    at g = 0 against ModalROM's closed form (independent derivations)."""
    monkeypatch.setattr(dynamics, "H_OMEGA", 0.3)
    modes = basis.modes(n_modes=4)
    t = np.arange(1001) * 1e-3
    zeta = 4.0 / (2.0 * modes.omega_rad_s)
    pulse = {"force_N": 1.0, "duration_s": 0.01}
    relaxing = {"prony_g": 0.25, "prony_tau_s": 0.05}
    exact = viscoelastic_pulse_response(t - 0.02, modes, zeta, **pulse, **relaxing)
    assert nrmse(exact, integrate_tip(t, modes, zeta, **pulse, start_s=0.02, **relaxing)) < 1e-4
    elastic = ModalROM(modes.omega_rad_s, modes.tip**2, zeta_fitted=zeta).pulse_response(t, 1.0, 0.01)
    assert nrmse(viscoelastic_pulse_response(t, modes, zeta, **pulse, prony_g=0.0, prony_tau_s=0.05), elastic) < 1e-12
    # relaxation softens the finger: the late sag under a long pulse is 1 / (1 - g) times the elastic one
    long = viscoelastic_pulse_response(np.array([3.0]), modes, zeta, force_N=1.0, duration_s=10.0, **relaxing)
    assert long[0] == pytest.approx(modes.static_flexibility_m_N / 0.75, rel=0.02)


def test_the_modes_kept_are_those_the_pulse_rings(basis):
    """A shorter pulse rings more modes; every mode dropped from the pulse's response changes
    it by less than MODE_AMPLITUDE of the first mode's amplitude each."""
    modes = basis.modes()
    n_long, n_short = (rung_modes(modes.omega_rad_s, modes.tip, T) for T in (0.01, 0.001))
    assert 3 <= n_long < n_short <= len(modes.omega_rad_s)
    t = np.arange(2001) * 1e-3
    zeta = 4.0 / (2.0 * modes.omega_rad_s)
    for n, T in ((n_long, 0.01), (n_short, 0.001)):
        full = ModalROM(modes.omega_rad_s, modes.tip**2, zeta_fitted=zeta).pulse_response(t, 1.0, T)
        kept = ModalROM(modes.omega_rad_s[:n], modes.tip[:n]**2, zeta_fitted=zeta[:n]).pulse_response(t, 1.0, T)
        first = ModalROM(modes.omega_rad_s[:1], modes.tip[:1]**2, zeta_fitted=zeta[:1]).pulse_response(t, 1.0, T)
        dropped = len(modes.omega_rad_s) - n
        assert np.max(np.abs(full - kept)) <= dropped * MODE_AMPLITUDE * np.max(np.abs(first)) + 1e-15


@pytest.mark.slow
def test_generator_and_calibration_model_agree_on_linear_physics(basis):
    """The generator's 40-mode Newmark solid and the calibration's exact modal response."""
    t, w = solid_response(Truth(1.0, 4.0, 1.0), LENGTH, t_end_s=0.5)
    modes = basis.modes(n_modes=7)
    rom = ModalROM(modes.omega_rad_s, modes.tip**2, zeta_fitted=4.0 / (2.0 * modes.omega_rad_s))
    assert nrmse(rom.pulse_response(t[::40], 1.0, 0.01), w[::40]) < 1e-3


@pytest.mark.parametrize("edit, match", [
    (lambda m: m["finger"].pop("E_Pa"), "finger.E_Pa"),
    (lambda m: m["finger"].pop("length_in"), "finger.length_in"),
    (lambda m: m["finger"].update(nu=0.7), "finger.nu"),
    (lambda m: m["finger"].update(section_semi_axes_m=[0.012]), "finger.section_semi_axes_m"),
    (lambda m: m.update(kind="pluck"), "'kind'"),
    (lambda m: m["load"].update(at="root"), "load.at"),
    (lambda m: m["load"].pop("duration_s"), "load.duration_s"),
    (lambda m: m["load"].update(force_N=-1.0), "load.force_N"),
    (lambda m: m["sensor"].update(noise_std_m="small"), "sensor.noise_std_m"),
    (lambda m: m.update(tolerances={"E_Pa": 1.5}), "tolerances.E_Pa"),
    (lambda m: m["load"].update(force_N=3.0), "force_N column peaks"),
])
def test_sidecar_errors_name_the_field_and_write_nothing(record, edit, match, tmp_path, capsys):
    csv, meta = record
    edit(meta)
    _write(csv, meta)
    with pytest.raises(InputError, match=match):
        load_experiment(csv)
    out = tmp_path / "out.json"
    assert main(["calibrate", str(csv), "--json", str(out), "--report", str(tmp_path / "rep")]) == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err and "error" in err
    assert not out.exists() and not (tmp_path / "rep").exists()


def _bad_frames(frame):
    nan = frame.copy()
    nan.loc[100, "tip_displacement_m"] = np.nan
    back = frame.copy()
    back.loc[50, "time_s"] = back.loc[40, "time_s"]
    huge = frame.copy()
    huge["tip_displacement_m"] *= 250.0                         # a 5 m tip deflection of a 0.2 m finger
    slow = frame.copy()
    slow["time_s"] *= 1000.0                                    # milliseconds written as seconds
    return [(nan, "row 101"), (back, "strictly increasing"), (huge, "half the"), (slow, "quarter")]


@pytest.mark.parametrize("case", range(4))
def test_bad_samples_and_impossible_units_are_refused(record, case, tmp_path):
    csv, meta = record
    frame, match = _bad_frames(pd.read_csv(csv))[case]
    _write(csv, meta, frame)
    with pytest.raises(InputError, match=match):
        load_experiment(csv)
    out = tmp_path / "out.json"
    assert main(["calibrate", str(csv), "--json", str(out)]) == 1
    assert not out.exists()


def test_missing_sidecar_is_named(record, tmp_path):
    csv, _ = record
    with pytest.raises(InputError, match="sidecar not found"):
        load_experiment(csv)


def test_declared_finger_is_what_the_sidecars_say():
    meta = json.loads((DATA / f"{RECORD}.json").read_text())
    assert meta["finger"] == declared_finger()


@pytest.mark.slow
def test_cli_writes_the_documented_keys_and_the_report(record, tmp_path):
    csv, meta = record
    _write(csv, meta)
    out = tmp_path / "out.json"
    rep = tmp_path / "rep"
    assert main(["calibrate", str(csv), "--meta", str(csv.with_suffix(".json")), "--json", str(out),
                 "--report", str(rep)]) == 0
    result = json.loads(out.read_text())
    assert {"baseline", "effects_found", "selected_effect", "final_nrmse", "noise_floor_nrmse", "model_adequate",
            "adequacy", "calibrated", "ambiguous", "rejected_effects", "unexplained_residual", "sparse_term"} <= set(result)
    assert result["ambiguous"] is None and result["rejected_effects"] is None and result["unexplained_residual"] is False
    assert result["model_adequate"] is True
    assert {"nrmse", "params"} <= set(result["baseline"])
    for e in result["effects_found"]:
        assert {"name", "params", "nrmse_after"} <= set(e)
    assert result["selected_effect"] == "time_delay"
    assert result["final_nrmse"] <= result["baseline"]["nrmse"]
    assert sorted(p.name for p in rep.iterdir()) == ["fit.png", "report.md", "residual.png", "residuals.csv"]
    frame = pd.read_csv(rep / "residuals.csv")
    assert list(frame.columns) == ["time_s", "tip_displacement_m", "baseline_m", "final_m"]
