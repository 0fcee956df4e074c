"""Design optimiser: casadi optimum against brute force on the same surrogate,
physics direction of the optimum, the Pareto front, the FEA re-check plumbing and clear
errors for infeasible requests."""
import json

import numpy as np
import pytest

from ccedi.design.fea_check import fea_check
from ccedi.design.objectives import alpha_of_length, rom_segments
from ccedi.design.optimise import DesignProblem, brute_force, solve
from ccedi.design.pareto import pareto_front
from ccedi.design.surrogate import Surrogate, cached_rom_runs, design_space, grid_points
from ccedi.errors import InputError
from ccedi.fea.drum import DrumSetup
from ccedi.fea.units import inch_to_m, m_to_inch
from ccedi.rom.ccedi import paper_alpha
from ccedi.rom.contact_rom import ReducedContactModel
from ccedi.study.cli import main

GRID = (8, 6)


@pytest.fixture(scope="module")
def surrogate(tmp_path_factory):
    space = design_space()
    runs, _ = cached_rom_runs(DrumSetup(), grid_points(space, GRID), tmp_path_factory.mktemp("design") / "grid.csv")
    return Surrogate.fit(space, runs), runs


@pytest.mark.parametrize("weights", [(1.0, 1.0, 1.0), (3.0, 1.0, 1.0), (1.0, 2.0, 4.0)])
def test_casadi_optimum_is_the_best_point_of_a_brute_force_grid(surrogate, weights):
    """Acceptance 1: IPOPT (multi-start) against a 100 x 100 grid of the same surrogate:
    never worse, and every objective within 2 %."""
    problem = DesignProblem(surrogate[0], weights=weights)
    opt, info = solve(problem)
    grid = brute_force(problem, n=100)
    assert info["status"] in ("Solve_Succeeded", "Solved_To_Acceptable_Level")
    assert opt.J <= grid.J + 1e-6
    for k in problem.objective_outputs:
        assert opt.outputs[k] == pytest.approx(grid.outputs[k], rel=0.02), k


@pytest.mark.parametrize("mode", ["paper", "fit"])
def test_this_rubber_only_designs_sit_on_alpha_of_length(surrogate, mode):
    problem = DesignProblem(surrogate[0], weights=(1.0, 1.0, 1.0), alpha_of_length=mode)
    opt, _ = solve(problem)
    assert opt.alpha_per_s == pytest.approx(float(alpha_of_length(mode, m_to_inch(opt.length_m))), rel=1e-6)
    grid = brute_force(problem, n=100)
    assert opt.J <= grid.J + 1e-6
    for k in problem.objective_outputs:
        assert opt.outputs[k] == pytest.approx(grid.outputs[k], rel=0.02), k


def test_paper_alpha_of_length_is_eq7():
    x = np.array([3.0, 4.5, 6.0, 7.0, 8.0])
    assert np.allclose(alpha_of_length("paper", x), paper_alpha(x))
    with pytest.raises(InputError, match="alpha-of-length"):
        alpha_of_length("steel", 5.0)


@pytest.mark.parametrize("weights", [(0.0, 0.0, 1.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0)])
def test_single_objective_optima_go_to_high_damping(surrogate, weights):
    """Acceptance 4: all weight on oscillation -> high damping; all weight on contact
    duration or on the peak force -> high damping too, the paper's section 3.4 direction
    (higher alpha: shorter contact, lower peak force)."""
    opt, _ = solve(DesignProblem(surrogate[0], weights=weights))
    va = surrogate[0].variables[0]
    assert opt.alpha_per_s > np.sqrt(va.lo * va.hi) * 4          # upper part of the log range
    low = surrogate[0].evaluate([[va.lo, opt.length_m]])
    key = DesignProblem(surrogate[0], weights=weights).objective_outputs[int(np.argmax(weights))]
    assert opt.outputs[key] < low[key][0]


def test_rom_agrees_with_the_paper_direction_at_8_inches():
    """The physics under acceptance 4, on the ROM itself (8-in finger, as the paper):
    alpha 7.5 -> 180 -> 600 1/s delays first contact and shortens the contact."""
    rom = ReducedContactModel(DrumSetup(), n_segments=rom_segments(inch_to_m(8.0)))
    s = [rom.run(a).summary for a in (7.5, 180.0, 600.0)]
    assert s[0]["contact_start_s"] < s[1]["contact_start_s"] < s[2]["contact_start_s"]
    assert s[0]["contact_duration_s"] > s[1]["contact_duration_s"] > s[2]["contact_duration_s"]


def test_pareto_front_has_20_non_dominated_points_around_the_optimum(surrogate):
    problem = DesignProblem(surrogate[0], weights=(1.0, 1.0, 1.0))
    front = pareto_front(problem, n_points=24)
    assert len(front) >= 20
    c = DesignProblem(surrogate[0], weights=(1.0, 1.0, 0.0))
    pts = np.array([[c.J(d.outputs), d.outputs["residual_oscillation_m_s"]] for d in front])
    for p in pts:
        assert not np.any(np.all(pts <= p, axis=1) & np.any(pts < p - 1e-9, axis=1))
    opt, _ = solve(problem)
    q = np.array([c.J(opt.outputs), opt.outputs["residual_oscillation_m_s"]])
    assert not np.any(np.all(pts < q - 1e-6, axis=1))            # nothing on the front beats it in both


def test_fea_check_compares_like_with_like(surrogate):
    """At a grid node the surrogate equals the ROM; re-checked with the ROM as the 'full'
    model the relative errors must vanish (the plumbing: same outputs, same windows)."""
    sur, runs = surrogate
    row = runs.iloc[len(runs) // 2 + 2]
    problem = DesignProblem(sur)
    d = brute_force(problem)
    d.alpha_per_s, d.length_m = float(row.alpha_per_s), float(row.length_m)
    d.outputs = {k: float(v[0]) for k, v in sur.evaluate([[d.alpha_per_s, d.length_m]]).items()}

    def rom(setup):
        return ReducedContactModel(setup, n_segments=rom_segments(setup.finger_length_m))

    check = fea_check(DrumSetup(), [d], problem.objective_outputs, model_factory=rom, progress=None)[0]
    for k in problem.objective_outputs:
        assert abs(check["relative_error"][k]) < 1e-6, k
    assert check["fea"]["peak_reaction_force_N"] == pytest.approx(row.peak_reaction_force_N, rel=1e-9)


def test_infeasible_requests_end_with_a_clear_message(surrogate):
    sur = surrogate[0]
    with pytest.raises(InputError, match="contact start"):
        solve(DesignProblem(sur, contact_start_bounds_s=(0.0, 0.1)))
    with pytest.raises(InputError, match="max finger stress <= 100000 Pa"):
        solve(DesignProblem(sur, allowable_finger_stress_Pa=1e5))
    with pytest.raises(InputError, match="weights"):
        DesignProblem(sur, weights=(0.0, 0.0, 0.0))


def test_cli_bounds_that_exclude_contact(tmp_path, capsys):
    """1-1.5-in fingers never reach the object: one clear line, exit 1, no traceback."""
    rc = main(["design", "--length-bounds-in", "1", "1.5", "--grid", "4", "4", "--validation-runs", "1",
               "--no-fea-check", "--out", str(tmp_path), "--json", str(tmp_path / "d.json")])
    err = capsys.readouterr().err
    assert rc == 1 and "touches the object" in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    assert not (tmp_path / "d.json").exists()


def test_cli_bad_weights(tmp_path, capsys):
    assert main(["design", "--weights", "1,2", "--json", str(tmp_path / "d.json")]) == 1
    assert "--weights" in capsys.readouterr().err


@pytest.mark.slow
def test_cli_writes_the_documented_keys(tmp_path, capsys):
    """The result's keys; alpha bounds below the range the ROM was checked in are run,
    with one validity warning naming it."""
    out = tmp_path / "d.json"
    rc = main(["design", "--weights", "1,1,2", "--grid", "5", "4", "--validation-runs", "2", "--pareto-points", "20",
               "--alpha-bounds", "1", "600", "--no-fea-check", "--out", str(tmp_path), "--json", str(out)])
    assert rc == 0
    warned = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert len(warned) == 1 and "below 7.5 1/s where the contact ROM was checked" in warned[0]
    d = json.loads(out.read_text())
    assert {"optimum", "pareto", "fea_check", "solver"} <= set(d)
    assert {"alpha_per_s", "length_in", "residual_oscillation_m_s"} <= set(d["optimum"])
    assert 3.0 <= d["optimum"]["length_in"] <= 8.0 and 1.0 <= d["optimum"]["alpha_per_s"] <= 600.0
    assert len(d["pareto"]) >= 2 and {"status", "iterations", "wall_time_s"} <= set(d["solver"])
    assert (tmp_path / "pareto.png").exists()


def test_fea_check_count_out_of_range_is_refused_before_any_run(tmp_path):
    from ccedi.fea.drum import DrumSetup
    from ccedi.study.commands.design import DesignOptions, write_design

    with pytest.raises(InputError, match="fea_check_designs must be 1, 2 or 3, got 4"):
        write_design(DrumSetup(), DesignOptions(fea_check_designs=4), tmp_path / "d.json", tmp_path)
    assert not list(tmp_path.iterdir())
