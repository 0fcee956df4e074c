"""The runnable examples under examples/ run and answer what they say."""
import json
import subprocess
import sys

import pytest
from conftest import ROOT

EXAMPLES = ROOT / "examples"


def test_design_script_meets_the_designers_requirements():
    """The design script: a user-defined output with its own limit, the optimum re-checked
    (by the ROM here) and found to meet every requirement, its own included."""
    run = subprocess.run([sys.executable, str(EXAMPLES / "design_script.py"), "--grid", "6", "5"],
                         capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert lines[0].startswith("optimum: alpha = ")
    assert any(line.startswith("Pareto front") for line in lines)
    assert lines[-1] == "re-check (contact ROM): meets every requirement"


def _run(script, *args):
    run = subprocess.run([sys.executable, str(EXAMPLES / script), *args], capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr
    return run.stdout.splitlines()


def test_own_finger_gives_its_table1_row_and_an_alpha_cr_near_two_omega_1():
    """A tapered finger from a mesh file: a positive tip stiffness, and alpha_cr within
    15 % of 2 omega_1 (critical mass-proportional damping of the first mode alone)."""
    mesh, stiffness, crit = _run("own_finger.py")
    assert mesh.startswith("mesh: ") and "tet4 elements" in mesh
    assert float(stiffness.split("tip stiffness ")[1].split(" N/m")[0]) > 0.0
    alpha_cr = float(crit.split("alpha_cr = ")[1].split(" 1/s")[0])
    two_omega1 = float(crit.split("2 omega_1 = ")[1].split(" 1/s")[0])
    assert abs(alpha_cr / two_omega1 - 1.0) < 0.15


def test_calibrating_a_control_record_finds_its_alpha_and_adds_nothing():
    """control_low (no effect in it): adequate, alpha within 10 % of the true one the
    manifest holds, no effect added."""
    adequacy, params, effects = _run("calibrate_record.py")
    truth = json.loads((EXAMPLES.parent / "data" / "measured" / "manifest.json").read_text())["records"]["control_low"]
    assert adequacy == "control_low.csv: declared model adequate"
    assert float(params.split("alpha = ")[1].split(" 1/s")[0]) == pytest.approx(truth["alpha_per_s"], rel=0.1)
    assert effects.startswith("effects added: none")


def test_robust_compounds_ranks_by_force_and_keeps_each_robust_design_within_five_percent():
    """Three compounds: the robust ranking lists those with a robust length first by their
    force, each missing no requirement in more than 5 % of its samples; the chosen finger is
    the robust winner, with its fastest drum inside the 10-40 rpm searched."""
    lines = _run("robust_compounds.py")
    nominal = [line for line in lines if line.startswith("nominal ")]
    robust = [line for line in lines if line.startswith("robust ")]
    assert len(nominal) == len(robust) == 3
    rows = [(float(line.split("force ")[1].split(" N")[0]),
             float(line.split("largest violation ")[1].split("%")[0]) / 100.0,
             "(no robust length)" in line) for line in robust]
    feasible = [force for force, _, none in rows if not none]
    assert feasible == sorted(feasible) and all(v <= 0.05 for _, v, none in rows if not none)
    assert [none for *_, none in rows] == sorted(none for *_, none in rows)
    chosen = lines[-1]
    assert chosen.startswith("chosen: " + robust[0].split(". ")[1].split(":")[0])
    if "drum up to " in chosen:
        assert 10.0 <= float(chosen.split("drum up to ")[1].split(" rpm")[0]) <= 40.0
