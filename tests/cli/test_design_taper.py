"""``ccedi design --vary taper``: the generated finger's taper (its tip's semi-axes over its
root's) designed beside alpha at its length. A tapered finger is softer and lighter: it
pushes the object less, and less impulse goes into it; a minimum impulse then sets the
taper. Bad bounds, and a taper asked of a finger mesh, are refused in one line before
any run; ``[finger] contact_taper_ratio`` reaches the drum set-up."""
import json

import numpy as np
import pytest

import ccedi.design.surrogate as surrogate_module
from ccedi.design import recheck
from ccedi.errors import SolverError, ValidityWarning
from ccedi.fea.contact.drum import DrumSetup, finger_mesh
from ccedi.fea.mesh.gmsh_fingers import write_tapered_finger
from ccedi.study.cli import main
from ccedi.study.commands.design import DesignOptions, write_design
from ccedi.study.commands.fea import contact_setup
from ccedi.study.config import load


def _toml(tmp_path, text="[finger]\ncontact_length_in = 5.0\n"):
    path = tmp_path / "finger.toml"
    path.write_text(text)
    return path


def _design(tmp_path, capsys, *extra):
    out = tmp_path / "out"
    check = [] if "--fea-check-designs" in extra else ["--no-fea-check"]
    rc = main(["design", "--vary", "taper", "--config", str(_toml(tmp_path)), "--grid", "5", "5",
               "--validation-runs", "2", "--pareto-points", "4", "--starts", "2", *check,
               "--json", str(out / "d.json"), "--out", str(out), *extra])
    assert rc == 0, capsys.readouterr().err
    return json.loads((out / "d.json").read_text()), out


def test_a_minimum_impulse_sets_the_taper_of_the_least_force(tmp_path, capsys):
    """Least object force with the impulse at least 6 N s (the 5-in prism gives 7.5-9 N s,
    a 0.6 taper about 5): the taper comes down from the prism until the impulse binds,
    strictly between its bounds; the ROM verifies it (every verification run at a taper
    within the bounds, the impulse within 3 % of 6 N s at the last)."""
    result, out = _design(tmp_path, capsys, "--min-contact-impulse-N-s", "6")
    assert result["problem"]["variables"][1]["name"] == "taper_ratio"
    taper = result["optimum"]["taper_ratio"]
    assert 0.62 < taper < 0.95
    assert any("impulse" in b for b in result["binding"])
    steps = result["rom_verification"]
    assert steps and all(0.6 <= s["taper_ratio"] <= 1.0 for s in steps)
    assert steps[-1]["model"]["contact_impulse_N_s"] == pytest.approx(6.0, rel=0.03)
    assert "taper ratio = " in (out / "design_report.md").read_text()


class _CrushedTip:
    """A full model whose solver stops every run, as on a tip too thin for its elements."""

    def __init__(self, setup):
        self.setup = setup

    def run(self, alpha, **kwargs):
        raise SolverError("element 794 inverted (J <= 0) at t = 0.93 s: the mesh is too coarse for the deformation "
                          "there; refine it")


def test_a_design_whose_fea_the_solver_stops_is_written_and_says_so(tmp_path, capsys, monkeypatch):
    """The FEA verification and re-check stopped by the solver (an element inverted): the
    design is still written, exit 0, its JSON rows carry the solver's message and the
    report says the run failed and the design is not verified."""
    monkeypatch.setattr(recheck, "full_fea_factory", _CrushedTip)
    result, out = _design(tmp_path, capsys, "--fea-check-designs", "1", "--scheduler", "serial")
    step = result["rom_verification"][-1]
    assert result["problem"]["verified_by"] == "full FEA" and "inverted" in step["failed"] and step["model"] is None
    (row,) = result["fea_check"]
    assert "inverted" in row["failed"] and not row["meets_requirements"]
    report = (out / "design_report.md").read_text()
    assert "**the run failed** (element 794 inverted" in report and "**run failed**" in report


@pytest.mark.parametrize("extra, named", [
    (["--vary", "taper", "--taper-bounds", "0.1", "0.8"], "--taper-bounds"),
    (["--vary", "taper", "--taper-bounds", "0.9", "0.5"], "--taper-bounds 0.9 0.5"),
    (["--vary", "taper", "--alpha-of-length", "paper"], "--alpha-of-length paper"),
])
def test_bad_taper_requests_are_refused_before_any_run(extra, named, tmp_path, capsys):
    out = tmp_path / "out"
    rc = main(["design", "--json", str(out / "d.json"), "--out", str(out), *extra])
    err = capsys.readouterr().err
    assert rc == 1 and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    assert named in err and not (out / "rom_grid.csv").exists()


def test_a_taper_below_where_the_fea_holds_is_warned_of_before_any_run(tmp_path, monkeypatch):
    def stop(*args, **kwargs):
        raise RuntimeError("no ROM run in this test")

    monkeypatch.setattr(surrogate_module, "cached_rom_runs", stop)
    options = DesignOptions(vary="taper", taper_bounds=(0.3, 1.0))
    with pytest.warns(ValidityWarning, match="--taper-bounds reach 0.3, below 0.6"), pytest.raises(RuntimeError):
        write_design(DrumSetup(), options, json_path=tmp_path / "d.json", out=tmp_path)


def test_a_taper_on_a_finger_mesh_is_refused_and_the_generated_finger_takes_it(tmp_path, capsys):
    write_tapered_finger(tmp_path / "finger.msh", 0.012, order=1)
    text = '[finger]\nmesh = "finger.msh"\nclamp = "clamp"\ntip = "tip"\n'
    rc = main(["design", "--vary", "taper", "--config", str(_toml(tmp_path, text)), "--json",
               str(tmp_path / "d.json"), "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert rc == 1 and "--vary taper" in err and len(err.strip().splitlines()) == 1, err
    rc = main(["design", "--config", str(_toml(tmp_path, text + "contact_taper_ratio = 0.5\n")), "--json",
               str(tmp_path / "d.json"), "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert rc == 1 and "contact_taper_ratio = 0.5" in err and len(err.strip().splitlines()) == 1, err
    setup = contact_setup(load(_toml(tmp_path, "[finger]\ncontact_length_in = 5.0\ncontact_taper_ratio = 0.6\n")))
    tip = finger_mesh(setup).nodes[finger_mesh(setup).node_sets["tip"]]
    assert setup.finger_taper_ratio == 0.6
    np.testing.assert_allclose(np.abs(tip[:, 1]).max(), 0.6 * setup.finger_semi_axes_m[1], rtol=1e-12)
