"""``ccedi design --compounds [CATALOGUE]``: every compound of a catalogue designed over the
length on its own E, density and alpha, ranked, each feasible one with its fastest drum, the
table and the drawing in the report;
the section's semi-thickness designed too, its b in the table, the JSON and the drawing;
what the compound design cannot take, and a section design's bad bounds, are refused in one
line before any ROM run."""
import json
import math
from dataclasses import replace
from functools import partial

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT

from ccedi.design import catalogue_design, recheck
from ccedi.design.catalogue_design import CompoundSurrogate, FirstMode, catalogue_space
from ccedi.design.compounds import CATALOGUE, catalogue_text, load_compounds
from ccedi.design.model_error import FeaCorrection
from ccedi.design.surrogate import Surrogate, grid_points, rom_factory
from ccedi.fea.contact.drum import DrumSetup
from ccedi.fea.material import NeoHookean
from ccedi.rom.finger_identification import finger_omega1
from ccedi.study.cli import main
from ccedi.units import INCH, m_to_inch


def _refused(capsys, argv, named):
    rc = main(argv)
    err = capsys.readouterr().err
    assert rc == 1 and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    assert named in err
    return err


@pytest.mark.parametrize("extra, named", [
    (["--compounds", "--vary", "drum_speed"], "--vary drum_speed"),
    (["--compounds", "--vary", "taper"], "--vary taper"),
    (["--compounds", "--alpha-of-length", "paper"], "--alpha-of-length paper"),
    (["--compounds", "--objective", "weighted", "--weights", "sensor_peak_force_N=1"], "--objective weighted"),
    (["--compounds", "no_such_catalogue.csv"], "no_such_catalogue.csv"),
    (["--vary", "semi_thickness", "--section-bounds-mm", "0.01", "5"], "--section-bounds-mm"),
    (["--vary", "semi_width", "--section-bounds-mm", "9", "3"], "--section-bounds-mm"),
    (["--vary", "semi_thickness", "--alpha-of-length", "fit"], "--alpha-of-length fit"),
    (["--robust"], "give --compounds too"),
    (["--compounds", "--robust", "1.5"], "--robust 1.5"),
    (["--compounds", "--robust", "--spread", "0.2", "2"], "--spread 0.2 2.0"),
    (["--compounds", "--spread", "0.1", "0.1"], "give --robust too"),
    (["--compounds", "--robust", "--spread-from", "no_such_result.json"], "no_such_result.json"),
    (["--compounds", "--robust", "--spread", "0.1", "0.1", "--spread-from", "x.json"], "give one spread"),
    (["--compounds", "--objective", "throughput"], "--rank-by fastest_drum ranks by the fastest drum"),
    (["--rank-by", "fastest_drum"], "--rank-by fastest_drum: the fastest drum per compound belongs to the compound"),
    (["--no-drum-speed"], "--no-drum-speed: the fastest drum per compound belongs to the compound design"),
    (["--compounds", "--rank-by", "fastest_drum", "--no-drum-speed"], "--rank-by fastest_drum with --no-drum-speed"),
    (["--compounds", "--vary", "semi_width"], "--compounds with --vary semi_width"),
    (["--compounds", "--vary", "semi_thickness", "--section-bounds-mm", "4", "13"],
     "--section-bounds-mm 4 13: with --compounds the semi-thickness b must stay within the semi-width a = 12 mm"),
    (["--compounds", "--vary", "semi_thickness", "--section-bounds-mm", "0.01", "9"], "--section-bounds-mm"),
    (["--vary", "semi_thickness", "--fea-correction", "2", "9"], "--fea-correction 2 9"),
])
def test_what_the_compound_design_cannot_take_is_refused_before_any_run(extra, named, tmp_path, capsys):
    out = tmp_path / "out"
    _refused(capsys, ["design", "--json", str(out / "d.json"), "--out", str(out), *extra], named)
    assert not (out / "rom_catalogue_grid.csv").exists()


def test_a_catalogue_is_ranked_the_damped_compound_first_on_its_own_alpha(tmp_path, capsys):
    """The paper's over-damped rubber meets the default requirements; natural rubber, its
    loss factor a tenth of it, rings past the 5 mm limit after breakaway and ranks second,
    short of it. The winner's alpha is its loss factor times the FE first mode of its
    finger at the chosen length."""
    rows = load_compounds(CATALOGUE)
    cat = tmp_path / "two.csv"
    cat.write_text(catalogue_text([rows["natural_rubber"], rows["paper_finger_rubber"]]))
    out = tmp_path / "out"
    rc = main(["design", "--compounds", str(cat), "--grid", "4", "4", "--no-fea-check", "--starts", "2",
               "--json", str(out / "d.json"), "--out", str(out)])
    assert rc == 0, capsys.readouterr().err
    result = json.loads((out / "d.json").read_text())
    table = result["compounds"]["table"]
    assert [r["compound"] for r in table] == ["paper_finger_rubber", "natural_rubber"]
    assert table[0]["feasible"] and not table[1]["feasible"] and table[1]["largest_shortfall"] > 0
    assert "ringing" in table[1]["binding"]
    win = table[0]
    paper = rows["paper_finger_rubber"]
    omega = finger_omega1(win["length_in"], material=NeoHookean(E=paper.E_nominal_Pa, nu=0.49, rho=paper.rho_kg_m3))
    assert win["alpha_per_s"] == pytest.approx(paper.tan_delta_nominal * omega, rel=0.005)
    report = (out / "design_report.md").read_text()
    assert "| 1 | paper_finger_rubber | yes |" in report and "| 2 | natural_rubber | **no** |" in report
    assert (out / "finger_drawing.png").stat().st_size > 10_000 and (out / "compounds.csv").exists()
    assert str(ROOT) not in result["catalogue"] or result["catalogue"] == str(cat)
    drum = result["drum_speed"]                  # the winner's fastest drum over the default 10-40 rpm
    assert drum["compound"] == "paper_finger_rubber" and drum["length_m"] / 0.0254 == pytest.approx(win["length_in"])
    assert drum["speeds_rpm"][0] == 10.0 and drum["speeds_rpm"][-1] == 40.0
    assert (drum["fastest_rpm"] is None) == (drum["worst_margin"][0] < 0) and "## Drum speed" in report
    assert win["fastest_drum_rpm"] == drum["fastest_rpm"] and win["drum_binding"] == drum["binding"]
    assert table[1]["fastest_drum_rpm"] is None and "| fastest drum [rpm] | stops a faster drum |" in report
    assert result["compounds"]["designs"]["paper_finger_rubber"]["drum_speed"] == drum


def test_robust_designs_are_ranked_beside_the_nominal_ones_within_the_asked_probability(tmp_path, capsys):
    """``--robust 0.9 --spread 0.1 0.2``: every compound's robust length misses no requirement
    in more than 10 % of the samples (or is marked as none), the robust ranking puts those
    with a robust length first by their objective, the nominal winner's own check is on the
    same samples, and the report shows both designs side by side with the spread as asked."""
    rows = load_compounds(CATALOGUE)
    cat = tmp_path / "two.csv"
    cat.write_text(catalogue_text([rows["natural_rubber"], rows["paper_finger_rubber"]]))
    out = tmp_path / "out"
    rc = main(["design", "--compounds", str(cat), "--robust", "0.9", "--spread", "0.1", "0.2", "--grid", "4", "4",
               "--no-fea-check", "--starts", "2", "--json", str(out / "d.json"), "--out", str(out)])
    assert rc == 0, capsys.readouterr().err
    result = json.loads((out / "d.json").read_text())
    robust = result["robust"]
    assert robust["probability"] == 0.9 and "E +-10%" in robust["spread"] and "tan delta +-20%" in robust["spread"]
    designs = robust["designs"]
    for d in designs:
        worst = max(d["robust"]["violation"].values())
        assert (worst <= 0.1 + 1e-12) == d["feasible"]
        for req, v in d["robust"]["violation"].items():   # kept margin: the 10 % quantile
            assert (d["robust"]["margin_kept"][req] < 0.0) == (v > 0.1)
    feasible = [d["objective"] for d in designs if d["feasible"]]
    assert feasible == sorted(feasible) and [d["feasible"] for d in designs] == sorted(
        (d["feasible"] for d in designs), reverse=True)
    assert robust["winner"] == "paper_finger_rubber"
    nominal = next(r for r in result["compounds"]["table"] if r["compound"] == result["compounds"]["winner"])
    own = next(d for d in designs if d["compound"] == nominal["compound"])["nominal"]
    assert own["length_in"] == pytest.approx(nominal["length_in"])
    report = (out / "design_report.md").read_text()
    assert "## Robust design" in report and "### Nominal and robust design side by side" in report
    assert "| 1 | paper_finger_rubber |" in report.split("## Robust design")[1]


def test_the_section_is_designed_beside_alpha_and_the_rom_verifies_it(tmp_path, capsys):
    """``--vary semi_thickness`` at the 5-in finger: the optimum's b inside its bounds, the
    ROM built at each verified section, and the report's plane is (alpha, b)."""
    out = tmp_path / "out"
    rc = main(["design", "--vary", "semi_thickness", "--section-bounds-mm", "5", "12", "--config", str(_toml(tmp_path)),
               "--grid", "4", "4", "--validation-runs", "1", "--pareto-points", "4", "--starts", "2", "--no-fea-check",
               "--no-model-error", "--json", str(out / "d.json"), "--out", str(out)])
    assert rc == 0, capsys.readouterr().err
    result = json.loads((out / "d.json").read_text())
    assert result["problem"]["variables"][1]["name"] == "semi_thickness_m"
    b = result["optimum"]["semi_thickness_mm"]
    assert 5.0 <= b <= 12.0
    steps = result["rom_verification"]
    assert steps and all(5.0 <= s["semi_thickness_mm"] <= 12.0 for s in steps)
    assert all(s["model"]["sensor_peak_force_N"] > 0.0 for s in steps)
    assert "b = " in (out / "design_report.md").read_text() and (out / "feasible_region.png").exists()


def test_the_section_design_runs_on_a_surrogate_corrected_by_the_reference_model(tmp_path, capsys, monkeypatch):
    """``--fea-correction 2 2``: the reference model (here a stand-in for the full FEA, the
    ROM of a finger 20 % stiffer, so that the test runs in seconds) runs at the four corners
    of (alpha, b); its force over the ROM's is the correction in the result and the report,
    above 1 at every corner, and the model-error margins give way to it."""
    stiffer = partial(_stiffer_rom, rom_factory)
    monkeypatch.setattr(recheck, "full_fea_factory", stiffer)
    out = tmp_path / "out"
    rc = main(["design", "--vary", "semi_thickness", "--section-bounds-mm", "5", "12", "--config", str(_toml(tmp_path)),
               "--grid", "4", "4", "--validation-runs", "1", "--pareto-points", "4", "--starts", "2", "--no-fea-check",
               "--fea-correction", "2", "2", "--json", str(out / "d.json"), "--out", str(out)])
    assert rc == 0, capsys.readouterr().err
    result = json.loads((out / "d.json").read_text())
    correction = result["surrogate"]["fea_correction"]
    force = correction["ratio_fea_over_model"]["sensor_peak_force_N"]
    assert len(force) == 2 and all(1.0 < r < 1.5 for row in force for r in row)
    assert correction["semi_thickness_mm"] == pytest.approx([5.0, 12.0]) and not result["model_error"]
    assert (out / "fea_training.csv").exists() and "## Surrogate corrected by the full FEA" in (
        out / "design_report.md").read_text()


def test_the_catalogue_surrogate_is_corrected_by_the_reference_model(tmp_path, capsys, monkeypatch):
    """``--compounds --fea-correction 2 2``: the reference model (a stand-in for the full
    FEA, the ROM of a finger 20 % stiffer) runs at the four corners of (alpha, L) on the
    set-up's own finger; its force ratio, above 1 at every corner, multiplies the catalogue
    surrogate: the winner's force over the uncorrected surrogate's at the same design (its
    compound's E' and density) is the ratio interpolated there. No model-error margin is
    carried, the ROM does not verify, and the report says so."""
    monkeypatch.setattr(recheck, "full_fea_factory", partial(_stiffer_rom, rom_factory))
    rows = load_compounds(CATALOGUE)
    compounds = [rows["natural_rubber"], rows["paper_finger_rubber"]]
    cat = tmp_path / "two.csv"
    cat.write_text(catalogue_text(compounds))
    out = tmp_path / "out"
    rc = main(["design", "--compounds", str(cat), "--grid", "4", "4", "--no-fea-check", "--no-drum-speed",
               "--starts", "2", "--max-ringing-amplitude-mm", "0", "--fea-correction", "2", "2",
               "--json", str(out / "d.json"), "--out", str(out)])
    assert rc == 0, capsys.readouterr().err
    result = json.loads((out / "d.json").read_text())
    trained = result["surrogate"]["fea_correction"]
    force = np.asarray(trained["ratio_fea_over_model"]["sensor_peak_force_N"])
    assert force.shape == (2, 2) and np.all((force > 1.02) & (force < 1.5))
    assert result["model_error_source"].startswith("none") and (out / "fea_training.csv").exists()
    win = result["compounds"]["winner"]
    design = result["compounds"]["designs"][win]
    assert not design["verification"]
    space = catalogue_space(compounds, FirstMode.of(DrumSetup(), (3.0, 8.0)), (3.0, 8.0))
    plain = CompoundSurrogate(Surrogate.fit(space, pd.read_csv(out / "rom_catalogue_grid.csv")),
                              E_Pa=rows[win].E_nominal_Pa, rho_kg_m3=rows[win].rho_kg_m3, reference_rho_kg_m3=1000.0)
    x = (design["design"]["alpha_per_s"], design["design"]["length_in"] * INCH)
    ratio = FeaCorrection(space[:2], [trained["alpha_per_s"], np.asarray(trained["length_in"]) * INCH],
                          {"sensor_peak_force_N": force}).ratio("sensor_peak_force_N", [x])[0]
    uncorrected = plain.evaluate([x])["sensor_peak_force_N"][0]
    assert design["design"]["sensor_peak_force_N"] / uncorrected == pytest.approx(ratio, rel=0.01)
    assert "## Surrogate corrected by the full FEA" in (out / "design_report.md").read_text()


def _stiffer_rom(factory, setup):
    return factory(replace(setup, finger_material=replace(setup.finger_material, E=1.2 * setup.finger_material.E)))


def _toml(tmp_path):
    path = tmp_path / "five_inch.toml"
    path.write_text("[finger]\ncontact_length_in = 5.0\n")
    return path


SLENDER = FirstMode((0.0, -2.0, math.log(1810.0 / 8.45), 1.0, 0.0, 0.0), 6.1e6, 1000.0, (3.0, 8.0), 0.0, (4.0, 12.0))
"""omega_1 ~ b / L^2 of a slender finger through the paper's (:func:`_stand_in_section_catalogue`)."""


def _stand_in_section_catalogue(monkeypatch):
    """A stand-in for the catalogue surrogate over (alpha, L, E', b) (the ROM's 4-D grid
    takes minutes): a slender finger, omega_1 ~ b / L^2, its force ~ b^2 / L^1.5 and its
    creep ~ alpha / omega_1^2; the compound design's ROM verification off. Returns the
    dict the grid shape and semi-thickness bounds asked of it land in."""
    asked = {}

    def stand_in(setup, compounds, *, shape, spread, semi_thickness_bounds_mm, length_bounds_in, **_):
        asked.update(shape=shape, bounds=semi_thickness_bounds_mm)
        space = catalogue_space(compounds, SLENDER, length_bounds_in, spread=spread)
        alpha, L, E, b = np.array(grid_points(space, (6, 6, 4, 6))).T
        w = SLENDER(m_to_inch(L), E_Pa=E, rho_kg_m3=1000.0, semi_thickness_m=b)
        outputs = {"sensor_peak_force_N": 3e-6 * E * (b / 0.00845) ** 2 * (0.1 / L) ** 1.5,
                   "recovery_deviation_m": 0.1 * alpha / w**2, "max_finger_stress_Pa": 1e6 + 0 * L,
                   "max_object_stress_Pa": 5e6 + 0 * L,
                   "ringing_amplitude_m": 0 * L, "first_contact_front_m": 0.005 + 0 * L,
                   "contact_patch_from_root_m": 0.05 + 0 * L, "contact_impulse_N_s": 3.0 + 0 * L}
        frame = pd.DataFrame({"alpha_per_s": alpha, "length_m": L, "youngs_modulus_Pa": E, "semi_thickness_m": b,
                              **outputs})
        return Surrogate.fit(space, frame), SLENDER, frame, False

    monkeypatch.setattr(catalogue_design, "catalogue_surrogate", stand_in)
    unverified = catalogue_design.design_compounds
    monkeypatch.setattr(catalogue_design, "design_compounds", lambda *a, **k: unverified(*a, **{**k, "verify": False}))
    return asked


def test_the_compounds_section_design_is_corrected_over_alpha_length_and_thickness(tmp_path, capsys, monkeypatch):
    """``--compounds --vary semi_thickness --fea-correction 2 2``: the reference model (the
    ROM of a finger 20 % stiffer) and the ROM run at the 2 x 2 x 2 corners of (alpha, L, b)
    on the set-up's own rubber; the ratios carry the three axes, b at its bounds."""
    _stand_in_section_catalogue(monkeypatch)
    monkeypatch.setattr(recheck, "full_fea_factory", partial(_stiffer_rom, rom_factory))
    rows = load_compounds(CATALOGUE)
    cat = tmp_path / "one.csv"
    cat.write_text(catalogue_text([rows["paper_finger_rubber"]]))
    out = tmp_path / "out"
    rc = main(["design", "--compounds", str(cat), "--vary", "semi_thickness", "--fea-correction", "2", "2",
               "--no-fea-check", "--no-drum-speed", "--starts", "2", "--json", str(out / "d.json"), "--out", str(out)])
    assert rc == 0, capsys.readouterr().err
    trained = json.loads((out / "d.json").read_text())["surrogate"]["fea_correction"]
    assert trained["semi_thickness_mm"] == pytest.approx([4.0, 12.0])
    force = np.asarray(trained["ratio_fea_over_model"]["sensor_peak_force_N"])
    assert force.shape == (2, 2, 2) and np.all((force > 1.0) & (force < 1.5)) and force.mean() > 1.1
    assert len(pd.read_csv(out / "fea_training.csv")) == 8


def test_the_compounds_section_is_designed_with_its_length_and_shown(tmp_path, capsys, monkeypatch):
    """``--compounds --vary semi_thickness --robust``, on a stand-in for the catalogue
    surrogate (a slender finger, omega_1 ~ b / L^2, its force ~ b^2 / L^1.5 and its creep
    ~ alpha / omega_1^2; the ROM's 4-D grid takes minutes) with the ROM verification off:
    the surrogate is asked over b 4-12 mm on the 9 x 7 x 4 x 4 grid; the least force meeting
    the 5 mm recovery is the thinnest section, flagged on its bound, at the longest finger
    that recovers (L^2 / b bound); b is in the table, the JSON, the report and the
    drawing's title, the robust design holds it."""
    asked = _stand_in_section_catalogue(monkeypatch)
    rows = load_compounds(CATALOGUE)
    cat = tmp_path / "one.csv"
    cat.write_text(catalogue_text([rows["paper_finger_rubber"]]))
    out = tmp_path / "out"
    rc = main(["design", "--compounds", str(cat), "--vary", "semi_thickness", "--robust", "0.9", "--spread", "0.05",
               "0.1", "--no-fea-check", "--no-drum-speed", "--starts", "2", "--json", str(out / "d.json"),
               "--out", str(out)])
    assert rc == 0, capsys.readouterr().err
    assert asked == {"shape": (9, 7, 4, 4), "bounds": (4.0, 12.0)}
    result = json.loads((out / "d.json").read_text())
    row = result["compounds"]["table"][0]
    assert row["feasible"] and row["semi_thickness_mm"] == pytest.approx(4.0, abs=0.01)
    paper = rows["paper_finger_rubber"]
    w = SLENDER(row["length_in"], E_Pa=paper.E_nominal_Pa, rho_kg_m3=paper.rho_kg_m3, semi_thickness_m=0.004)
    assert 0.1 * row["alpha_per_s"] / w**2 == pytest.approx(0.005, rel=0.01)          # the recovery binds
    design = result["compounds"]["designs"]["paper_finger_rubber"]
    assert design["semi_thickness_mm"] == row["semi_thickness_mm"] and "b at its lower bound 4 mm" in design["flags"]
    assert result["problem"]["semi_thickness_bounds_mm"] == [4.0, 12.0] and not result["model_error_source"]
    report = (out / "design_report.md").read_text()
    assert "| L [in] | b [mm] |" in report and "semi-thickness b 4-12 mm" in report and "b held at" in report
    assert (out / "finger_drawing.png").stat().st_size > 10_000 and result["robust"]["winner"] == "paper_finger_rubber"
