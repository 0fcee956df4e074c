"""Finger material, section and drum set-up from the inputs TOML reach the models: the
first natural frequency scales as the beam theory says, the stable step as the wave speed,
and every study step that builds a finger is handed the study's resolved inputs."""
import json
import tomllib

import numpy as np
import pytest

from ccedi.fea.contact.drum import finger_mesh
from ccedi.rom.finger_identification import finger_omega1
from ccedi.rom.superelement import finger_chain
from ccedi.study import run as study_run
from ccedi.study.cli import main
from ccedi.study.config import drum_setup, finger_inputs, load, validate


def _write(tmp_path, text, name="inputs.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def _omega1(cfg):
    material, semi_axes = finger_inputs(cfg)
    return finger_omega1(4.5, material=material, semi_axes_m=semi_axes)


def test_first_frequency_follows_the_material_and_section_of_the_inputs():
    base = validate({})
    w0 = _omega1(base)
    E, rho = base["material"]["E_Pa"], base["material"]["rho_kg_m3"]
    # Linear modes: omega scales exactly as sqrt(E / rho) for a fixed shape and nu.
    assert _omega1(validate({"material": {"E_Pa": 4 * E}})) / w0 == pytest.approx(2.0, rel=1e-8)
    assert _omega1(validate({"material": {"rho_kg_m3": 4 * rho}})) / w0 == pytest.approx(0.5, rel=1e-8)
    # Euler-Bernoulli: omega_1 ~ sqrt(E I / (rho A)) ~ b for I = pi a b^3 / 4, A = pi a b.
    a, b = base["finger"]["section_semi_axes_m"]
    thicker = _omega1(validate({"finger": {"section_semi_axes_m": [a, 1.25 * b]}}))
    assert thicker / w0 == pytest.approx(1.25, rel=0.03)


def test_table1_command_reads_the_material_of_the_config(tmp_path, capsys):
    base, stiff = tmp_path / "base.json", tmp_path / "stiff.json"
    config = _write(tmp_path, "[material]\nE_Pa = 24.4e6\nrho_kg_m3 = 1000.0\n")
    assert main(["table1", "--no-stiffness", "--no-detailed-model", "--json", str(base)]) == 0
    assert "(paper" in capsys.readouterr().out                    # the paper's finger: compared with Table 1
    assert main(["table1", "--no-stiffness", "--no-detailed-model", "--json", str(stiff), "--config", str(config)]) == 0
    assert "(paper" not in capsys.readouterr().out                # another rubber: no paper column
    b, s = json.loads(base.read_text()), json.loads(stiff.read_text())
    for name in ("SM-A", "SM-B"):     # dt ~ h / c, c = sqrt(M / rho): 4 x E halves the stable step
        assert s[name]["dt_us"] / b[name]["dt_us"] == pytest.approx(0.5, rel=1e-12)


def test_drum_setup_and_contact_rom_take_the_section_of_the_inputs():
    cfg = validate({"finger": {"section_semi_axes_m": [0.010, 0.007], "contact_length_in": 6.0},
                    "drum": {"friction": 0.3}})
    setup = drum_setup(cfg)
    mesh = finger_mesh(setup)
    assert np.abs(mesh.nodes[:, 0]).max() == pytest.approx(0.010)
    assert np.abs(mesh.nodes[:, 1]).max() == pytest.approx(0.007)
    assert mesh.nodes[:, 2].max() == pytest.approx(6.0 * 0.0254)
    assert setup.object_surface.mu == 0.3
    chain = finger_chain(mesh, setup.finger_material, n_segments=8)
    assert chain.half_thickness_m == pytest.approx(0.007)       # the ROM's contact points sit on the faces


def test_every_finger_step_of_the_study_gets_the_resolved_inputs(tmp_path, monkeypatch):
    from ccedi.study.commands import design, fea, rom

    config = _write(tmp_path, "[material]\nE_Pa = 5.0e6\n[finger]\nimpulse_length_in = 3.0\n"
                              "[study]\ncalibration_fea_correction = false\n", "study.toml")
    cfg = load(config)
    calls, mesh_args = {}, []
    for module, name in ((fea, "write_table1"), (fea, "write_impulse"), (rom, "write_damping_fits"),
                         (fea, "write_contact_sweep"), (design, "write_design")):
        monkeypatch.setattr(module, name, lambda *a, _name=name, **k: calls.setdefault(_name, (a, k)))
    monkeypatch.setattr(study_run.paper_steps, "mesh_comparison", lambda *a, **k: mesh_args.append(k))
    out = tmp_path / "out"
    for name in ("table1", "impulse", "mesh", "damping_fits", "contact", "design"):
        study_run._run_step(name, cfg, out, "serial")
    assert list(calls) == ["write_table1", "write_impulse", "write_damping_fits", "write_contact_sweep",
                           "write_design"]
    for name in ("write_table1", "write_impulse", "write_damping_fits"):
        assert calls[name][0][0] is cfg                      # the inputs object itself, parsed once
    for name in ("write_contact_sweep", "write_design"):
        setup = calls[name][0][0]
        assert setup.finger_material.E == 5.0e6 and setup.finger_semi_axes_m == tuple(cfg["finger"]["section_semi_axes_m"])
    assert calls["write_table1"][0][1] == 3.0
    assert calls["write_design"][0][1].damping == cfg["damping"]["kind"] == "relative"
    assert calls["write_design"][0][1].requirements.max_object_force_N == cfg["requirements"]["max_object_force_N"]
    material, semi_axes = mesh_args[0]["material"], mesh_args[0]["semi_axes_m"]
    assert material.E == 5.0e6 and semi_axes == tuple(cfg["finger"]["section_semi_axes_m"])
    # the study records its resolved inputs
    monkeypatch.setattr(study_run, "steps", lambda cfg, out, scheduler: [])
    monkeypatch.setattr(study_run, "write_index", lambda out: out / "index.html")
    study_run.run_study(cfg, out, scheduler="serial")
    assert validate(tomllib.loads((out / study_run.CONFIG_NAME).read_text())) == cfg
