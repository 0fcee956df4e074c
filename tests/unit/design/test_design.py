"""Design optimiser: the outputs of a run against analytic histories, the requirements,
the casadi optimum against brute force on the same surrogate, the physics of relative
damping, infeasible requests answered with a report, model-error margins, the FEA
re-check plumbing and the command line."""
import json
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from ccedi.design import (
    DesignProblem,
    Limit,
    ModelError,
    Requirements,
    Surrogate,
    binding,
    brute_force,
    design_outputs,
    design_space,
    fea_check,
    on_bounds,
    pareto_front,
    sensitivities,
    solve,
    verified_optimum,
)
from ccedi.design.model_error import model_errors, output_error
from ccedi.design.outputs import overshoot, rom_segments, settling_time_s, setup_at
from ccedi.design.rubber import alpha_of_length
from ccedi.design.surrogate import cached_rom_runs, grid_points, run_rom, speed_space
from ccedi.errors import InputError, RequirementsUnmet, SolverError
from ccedi.fea.contact.drum import DrumSetup, ObjectStress
from ccedi.rom.ccedi import paper_alpha
from ccedi.rom.contact_rom import ReducedContactModel
from ccedi.study.cli import main
from ccedi.units import inch_to_m, m_to_inch, rpm_to_rad_s

GRID = (8, 6)


@pytest.fixture(scope="module")
def surrogate(tmp_path_factory):
    space = design_space()
    runs, _ = cached_rom_runs(DrumSetup(), grid_points(space, GRID), tmp_path_factory.mktemp("design") / "grid.csv",
                              damping="relative")
    return Surrogate.fit(space, runs), runs


def _history(setup, t, lag_m, force_N=None, point=(0.1, 0.2)):
    """A contact history whose tip trails the rigidly turning tip by ``lag_m`` and whose
    force on the object is ``force_N`` along x (contact where it is > 0)."""
    force = np.zeros_like(t) if force_N is None else force_N
    r = setup.drum_radius_m + setup.finger_length_m
    th0, th = setup.theta0_rad, setup.theta0_rad + setup.omega_rad_s * t
    x = r * np.cos(th) + lag_m * np.sin(th)            # behind = against e_theta = (-sin, cos)
    y = r * np.sin(th) - lag_m * np.cos(th)
    on = force > 0
    return pd.DataFrame({"time_s": t, "reaction_force_N": force, "contact_force_x_N": force,
                         "contact_force_y_N": 0.0 * t, "contact_nodes": on.astype(int),
                         "contact_point_x_m": np.where(on, point[0], np.nan),
                         "contact_point_y_m": np.where(on, point[1], np.nan),
                         "max_penetration_m": 0.0 * t, "max_von_mises_Pa": 1e6 + 1e5 * on,
                         "tip_ux_m": x - r * np.cos(th0), "tip_uy_m": y - r * np.sin(th0)})


def test_outputs_of_an_analytic_history():
    """A slow 10 N force held 0.2-0.6 s, then a tip released from 50 mm behind ringing as
    one damped mode: the transducer reads the force, the impulse is 10 N x 0.4 s, the
    ringing is the first overshoot e^(-zeta pi / sqrt(1 - zeta^2)) x 50 mm, the recovery
    the envelope at the next arrival."""
    setup = DrumSetup(cycle_time_s=1.0)
    t = np.arange(1, 3001) * 5e-4
    force = np.where((t >= 0.2) & (t <= 0.6), 10.0, 0.0)
    zeta, wn = 0.1, 2 * np.pi * 8.0
    wd, tr = wn * np.sqrt(1 - zeta**2), np.clip(t - 0.6, 0.0, None)
    free = 0.05 * np.exp(-zeta * wn * tr) * (np.cos(wd * tr) + zeta * wn / wd * np.sin(wd * tr))
    lag = np.where(t < 0.2, 0.0, np.where(t <= 0.6, 0.05 * (t - 0.2) / 0.4, free))
    out = design_outputs(setup, _history(setup, t, lag, force), ObjectStress(setup))
    assert out["contact_start_s"] == pytest.approx(0.2, abs=1e-3)
    assert out["sensor_peak_force_N"] == pytest.approx(10.0, rel=0.05)
    assert out["contact_impulse_N_s"] == pytest.approx(4.0, rel=0.01)
    first = 0.05 * np.exp(-zeta * np.pi / np.sqrt(1 - zeta**2))
    assert out["ringing_amplitude_m"] == pytest.approx(first, rel=0.01)
    window = (t >= 1.2 - 0.15) & (t <= 1.2)
    assert out["recovery_deviation_m"] == pytest.approx(np.abs(lag[window]).max(), rel=1e-6)
    assert out["root_stress_before_contact_Pa"] == 1e6 and out["max_finger_stress_Pa"] == 1.1e6
    assert out["contact_patch_from_root_m"] == pytest.approx(np.hypot(0.1, 0.2) - setup.drum_radius_m)


def test_a_finger_that_creeps_back_does_not_ring():
    assert overshoot(np.array([-0.05, -0.03, -0.01, -0.001])) == 0.0
    assert overshoot(np.array([-0.05, 0.0, 0.004, -0.001])) == pytest.approx(0.004)
    t = np.linspace(0.0, 1.0, 11)
    dev = np.column_stack([0 * t, np.where(t < 0.5, 0.01, 0.0)])
    assert settling_time_s(t, dev, t_from=0.2, tolerance_m=0.005) == pytest.approx(0.3)
    assert settling_time_s(t, dev + 0.01, t_from=0.2, tolerance_m=0.005) is None


def test_the_run_must_reach_the_next_arrival():
    setup = DrumSetup()
    t = np.arange(1, 1001) * 1e-3
    with pytest.raises(InputError, match="before the next object arrives"):
        design_outputs(setup, _history(setup, t, 0 * t, np.where(t > 0.3, 1.0, 0.0)), ObjectStress(setup))


def test_requirements_margins_and_switches():
    r = Requirements()
    names = {lim.output for lim in r.limits()}
    assert {"sensor_peak_force_N", "max_finger_stress_Pa", "recovery_deviation_m", "ringing_amplitude_m",
            "first_contact_front_m", "contact_impulse_N_s"} <= names
    force = next(lim for lim in r.limits() if lim.output == "sensor_peak_force_N")
    assert force.margin(20.0) == pytest.approx(0.2) and force.margin(30.0) == pytest.approx(-0.2)
    impulse = next(lim for lim in r.limits() if lim.output == "contact_impulse_N_s")
    assert impulse.margin(1.0) < 0 < impulse.margin(3.0)
    off = Requirements(max_object_force_N=None, front_side_first=False)
    assert "sensor_peak_force_N" not in {lim.output for lim in off.limits()}
    assert "first_contact_front_m" not in {lim.output for lim in off.limits()}
    with pytest.raises(InputError, match="allowable_root_stress_Pa"):
        Requirements(allowable_root_stress_Pa=-1.0)
    assert force.describe() == "object force (transducer) <= 25 N"


def test_relative_damping_raises_the_force_of_a_long_finger():
    """Physics behind a real trade-off: under relative damping the 8-in finger pushes
    harder on the object the more it is damped (it cannot yield); under global damping
    the drag bends it back first and the force falls (the paper's direction)."""
    setup = DrumSetup()
    rom = ReducedContactModel(setup, n_segments=rom_segments(setup.finger_length_m))
    peak = {k: [rom.run(a, damping=k, t_end_s=1.4, n_outputs=1400).summary["peak_reaction_force_N"]
                for a in (7.5, 600.0)] for k in ("relative", "global")}
    assert peak["relative"][1] > 1.3 * peak["relative"][0]
    assert peak["global"][1] < peak["global"][0]


def test_default_relative_design_is_interior_and_the_grid_agrees(surrogate):
    """Acceptance 1's first half on the surrogate: the optimum's alpha is not within 5 %
    of either bound, IPOPT is no worse than a 100 x 100 grid, and every requirement is met."""
    problem = DesignProblem(surrogate[0])
    opt, info = solve(problem)
    va = surrogate[0].variables[0]
    assert va.lo * 1.05 < opt.alpha_per_s < va.hi / 1.05
    assert not on_bounds(problem, opt)
    grid = brute_force(problem, n=100)
    assert opt.J <= grid.J + 1e-6
    margins = problem.constraint_margins(opt.outputs, opt.alpha_per_s, opt.x)
    assert min(margins.values()) >= -1e-6


@pytest.mark.parametrize("mode", ["paper", "fit"])
def test_this_rubber_only_designs_sit_on_alpha_of_length(surrogate, mode):
    problem = DesignProblem(surrogate[0], requirements=Requirements(max_ringing_amplitude_m=None),
                            alpha_of_length=mode)
    opt, _ = solve(problem)
    assert opt.alpha_per_s == pytest.approx(float(alpha_of_length(mode, m_to_inch(opt.x))), rel=1e-6)
    assert opt.J <= brute_force(problem, n=100).J + 1e-6


def test_paper_alpha_of_length_is_eq7():
    x = np.array([3.0, 4.5, 6.0, 7.0, 8.0])
    assert np.allclose(alpha_of_length("paper", x), paper_alpha(x))
    with pytest.raises(InputError, match="alpha-of-length"):
        alpha_of_length("steel", 5.0)


def test_a_binding_requirement_moves_the_design_and_relaxing_it_pays(surrogate):
    """Shortest contact (it grows with the finger's length) against a contact impulse the
    task needs (it grows too): the impulse binds, relaxing it shortens the contact,
    relaxing a slack requirement changes nothing."""
    sur = surrogate[0]
    quick = dict(objective="weighted", weights={"contact_duration_s": 1.0})
    free, _ = solve(DesignProblem(sur, requirements=Requirements(min_contact_impulse_N_s=None), **quick))
    need = free.outputs["contact_impulse_N_s"] + 1.5
    strict = DesignProblem(sur, requirements=Requirements(min_contact_impulse_N_s=need), **quick)
    opt, _ = solve(strict)
    name = next(lim.describe() for lim in strict.limits if lim.output == "contact_impulse_N_s")
    assert name in binding(strict, opt)
    assert opt.outputs["contact_impulse_N_s"] == pytest.approx(need, rel=1e-4)
    assert opt.outputs["contact_duration_s"] > free.outputs["contact_duration_s"]
    s = sensitivities(strict, opt)
    assert s[name]["binding"] and s[name]["objective_change"] < 0
    slack = [v for k, v in s.items() if not v["binding"]]
    assert slack and all(abs(v["objective_change"]) < 1e-6 for v in slack)


def test_infeasible_requirements_name_the_miss(surrogate):
    sur = surrogate[0]
    with pytest.raises(RequirementsUnmet) as err:
        solve(DesignProblem(sur, requirements=Requirements(max_object_force_N=5.0)))
    assert "object force (transducer) <= 5 N" in str(err.value) and "\n" not in str(err.value)
    miss = err.value.misses["object force (transducer) <= 5 N"]
    assert miss["value"] > 5.0 and miss["miss"] == pytest.approx(miss["value"] - 5.0)


def test_model_error_tightens_where_the_rom_strays(surrogate):
    """A ROM that reads the force 20 % low at long fingers only: the force limit is
    tightened there, and the design that meets it on the surrogate meets it once the
    error is added back."""
    sur = surrogate[0]
    err = ModelError([7.5, 600.0], [inch_to_m(3.0), inch_to_m(8.0)], under=[[0.0, 0.2], [0.0, 0.2]],
                     over=np.zeros((2, 2)))
    under, _ = err.at(np.array([100.0, 100.0]), np.array([inch_to_m(3.0), inch_to_m(5.5)]))
    np.testing.assert_allclose(under, [0.0, 0.1], atol=1e-12)
    req = Requirements(max_object_force_N=18.0)
    plain, _ = solve(DesignProblem(sur, requirements=req, objective="root_stress"))
    opt, _ = solve(DesignProblem(sur, requirements=req, objective="root_stress",
                                 model_error={"sensor_peak_force_N": err}))
    u, _ = err.at(opt.alpha_per_s, opt.x)
    assert opt.outputs["sensor_peak_force_N"] / (1.0 - float(u)) <= 18.0 * (1 + 1e-6)
    u_plain, _ = err.at(plain.alpha_per_s, plain.x)
    if plain.outputs["sensor_peak_force_N"] / (1.0 - float(u_plain)) > 18.0:
        assert (opt.alpha_per_s, opt.x) != (plain.alpha_per_s, plain.x)


def test_model_errors_from_check_cases():
    cases = [{"damping": "relative", "alpha_per_s": a, "length_in": L,
              "rom": {"sensor_peak_force_N": 8.5 if a < 100 else 10.0, "ringing_amplitude_m": 0.0004},
              "fea": {"sensor_peak_force_N": 10.0, "ringing_amplitude_m": 0.0}}
             for a in (7.5, 600.0) for L in (3.0, 8.0)]
    errs = model_errors(cases, damping="relative", alpha_bounds_per_s=(7.5, 600.0), length_bounds_in=(3.0, 8.0))
    assert set(errs) == {"sensor_peak_force_N"}                    # 0.4 mm of ringing is within 10 % of 5 mm
    assert errs["sensor_peak_force_N"].largest() == pytest.approx((0.15, 0.0))
    under, _ = errs["sensor_peak_force_N"].at(np.array([7.5, 600.0]), inch_to_m(5.0))
    np.testing.assert_allclose(under, [0.15, 0.0], atol=1e-12)
    assert output_error("ringing_amplitude_m", 0.001, 0.0) == pytest.approx(0.2)
    assert not model_errors(cases, damping="global", alpha_bounds_per_s=(7.5, 600.0), length_bounds_in=(3.0, 8.0))


def test_pareto_front_is_non_dominated(surrogate):
    problem = DesignProblem(surrogate[0])
    front = pareto_front(problem, second="ringing_amplitude_m", n_points=12)
    assert len(front) >= 4
    pts = np.array([[problem.J(d.outputs), d.outputs["ringing_amplitude_m"]] for d in front])
    for p in pts:
        assert not np.any(np.all(pts <= p, axis=1) & np.any(pts < p - 1e-9, axis=1))
    opt, _ = solve(problem)                     # meets the ringing limit too: nothing on the front is worse
    q = np.array([problem.J(opt.outputs), opt.outputs["ringing_amplitude_m"]])
    assert not np.any(np.all(pts >= q - 1e-9, axis=1) & np.any(pts > q + 1e-6, axis=1))


def test_fea_check_compares_like_with_like(surrogate):
    """At a grid node the surrogate equals the ROM; re-checked with the ROM as the 'full'
    model the errors vanish and the requirements read the same."""
    sur, runs = surrogate
    row = runs.iloc[len(runs) // 2 + 2]
    problem = DesignProblem(sur)
    d = replace(brute_force(problem), alpha_per_s=float(row.alpha_per_s), x=float(row.length_m))
    d.outputs = {k: float(v[0]) for k, v in sur.evaluate([[d.alpha_per_s, d.x]]).items()}

    def rom(setup):
        return ReducedContactModel(setup, n_segments=rom_segments(setup.finger_length_m))

    check = fea_check(DrumSetup(), [d], damping="relative", limits=problem.limits, model_factory=rom,
                      progress=None)[0]
    for k in ("sensor_peak_force_N", "max_finger_stress_Pa", "contact_impulse_N_s"):
        assert abs(check["relative_error"][k]) < 1e-6, k
    assert check["fea"]["sensor_peak_force_N"] == pytest.approx(row.sensor_peak_force_N, rel=1e-9)
    assert set(check["requirements"]) == {lim.describe() for lim in problem.limits}


class _StoppedModel:
    """A contact model whose solver stops every run (an inverted element, say)."""

    def __init__(self, setup):
        self.setup = setup

    def run(self, alpha, **kwargs):
        raise SolverError(f"element 7 inverted (J <= 0) at alpha {alpha:g}: refine it")


def test_a_run_the_solver_stops_is_reported_and_the_other_designs_kept(surrogate):
    """The re-check of two designs, the model's solver stopping the longer finger's run:
    that row says so (outputs None, every requirement unmet, the solver's message), the
    other keeps its outputs; the verification stops at such a run and returns the design
    it ran, unverified, with the message in its step."""
    sur, runs = surrogate
    problem = DesignProblem(sur)
    designs = []
    for k in (2, len(runs) - 3):
        row = runs.iloc[k]
        d = replace(brute_force(problem), alpha_per_s=float(row.alpha_per_s), x=float(row.length_m))
        d.outputs = {k: float(v[0]) for k, v in sur.evaluate([[d.alpha_per_s, d.x]]).items()}
        designs.append(d)
    short = min(d.x for d in designs)

    def model(setup):
        if setup.finger_length_m > short:
            return _StoppedModel(setup)
        return ReducedContactModel(setup, n_segments=rom_segments(setup.finger_length_m))

    said = []
    rows = fea_check(DrumSetup(), designs, damping="relative", limits=problem.limits, model_factory=model,
                     progress=said.append)
    ok, stopped = sorted(rows, key=lambda r: r["length_in"])
    assert ok["failed"] is None and ok["fea"]["sensor_peak_force_N"] > 0.0
    assert "element 7 inverted" in stopped["failed"] and not stopped["meets_requirements"]
    assert all(v is None for v in stopped["fea"].values()) and all(v is None for v in stopped["relative_error"].values())
    assert not any(q["met"] for q in stopped["requirements"].values())
    assert sum("the FE run failed: element 7 inverted" in line for line in said) == 1
    long_design = max(designs, key=lambda d: d.x)
    design, _, steps = verified_optimum(problem, DrumSetup(), model_factory=_StoppedModel, start=long_design)
    assert design is long_design and steps[-1]["model"] is None and "inverted" in steps[-1]["failed"]


def test_user_defined_output_and_limit(surrogate):
    sur = surrogate[0]
    extra = Limit("contact_duration_s", 0.5, upper=False, label="contact duration", unit="s")
    problem = DesignProblem(sur, requirements=Requirements(extra=(extra,)))
    opt, _ = solve(problem)
    assert opt.outputs["contact_duration_s"] >= 0.5 - 1e-6
    with pytest.raises(InputError, match="lacks"):
        DesignProblem(sur, requirements=Requirements(extra=(Limit("no_such_output", 1.0),)))


def test_cli_infeasible_writes_the_report_and_exits_4(tmp_path, capsys):
    """The allowable-stress case: a design, or a report naming the miss (exit 4), never a crash."""
    out = tmp_path / "d.json"
    rc = main(["design", "--allowable-finger-stress-Pa", "1.0e6", "--grid", "4", "4", "--validation-runs", "1",
               "--no-fea-check", "--no-model-error", "--out", str(tmp_path), "--json", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 4 and len(err) == 1 and "root stress over the cycle <= 1 MPa" in err[0]
    d = json.loads(out.read_text())
    assert d["feasible"] is False and "root stress over the cycle <= 1 MPa" in d["misses"]
    assert "No design meets the requirements" in (tmp_path / "design_report.md").read_text()


def test_cli_bounds_that_exclude_contact(tmp_path, capsys):
    """1-1.5-in fingers never reach the object: one clear line, exit 1, no traceback."""
    rc = main(["design", "--length-bounds-in", "1", "1.5", "--grid", "4", "4", "--validation-runs", "1",
               "--no-fea-check", "--out", str(tmp_path), "--json", str(tmp_path / "d.json")])
    err = capsys.readouterr().err
    assert rc == 1 and "never reaches the object" in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    assert not (tmp_path / "d.json").exists()


def test_cli_bad_weights_and_outputs(tmp_path, capsys):
    assert main(["design", "--objective", "weighted", "--weights", "nonsense", "--json", str(tmp_path / "d.json")]) == 1
    assert "--weights" in capsys.readouterr().err
    assert main(["design", "--pareto-output", "x", "--json", str(tmp_path / "d.json")]) == 1
    assert "--pareto-output" in capsys.readouterr().err


@pytest.mark.slow
def test_cli_writes_the_documented_keys(tmp_path, capsys):
    """The result's keys, the report and the figures; the damping kind is recorded."""
    out = tmp_path / "d.json"
    rc = main(["design", "--grid", "6", "5", "--validation-runs", "2", "--pareto-points", "8", "--damping", "global",
               "--no-fea-check", "--out", str(tmp_path), "--json", str(out)])
    assert rc == 0
    d = json.loads(out.read_text())
    assert {"optimum", "binding", "on_bounds", "sensitivities", "pareto", "fea_check", "solver", "model_error"} <= set(d)
    assert d["problem"]["damping"] == "global" and d["feasible"] is True
    assert {"alpha_per_s", "length_in", "sensor_peak_force_N", "margins"} <= set(d["optimum"])
    for name in ("feasible_region.png", "pareto.png", "design_report.md", "pareto.csv"):
        assert (tmp_path / name).exists()
    assert "## Decision" in (tmp_path / "design_report.md").read_text()


def test_fea_check_count_out_of_range_is_refused_before_any_run(tmp_path):
    from ccedi.study.commands.design import DesignOptions, write_design

    with pytest.raises(InputError, match="fea_check_designs must be 1, 2 or 3, got 4"):
        write_design(DrumSetup(), DesignOptions(fea_check_designs=4), json_path=tmp_path / "d.json", out=tmp_path)
    assert not list(tmp_path.iterdir())


def test_drum_speed_design_turns_the_drum_at_each_points_speed():
    """Runs over (alpha, drum speed): each run's set-up turns at its point's speed, and the
    time between objects follows it (2 objects per revolution: 2 pi / (2 omega))."""
    space = speed_space(speed_bounds_rpm=(15.0, 45.0))
    points = [(180.0, rpm_to_rad_s(15.0)), (180.0, rpm_to_rad_s(45.0))]
    runs = run_rom(DrumSetup(), points, variables=space)
    np.testing.assert_allclose(runs["drum_speed_rad_s"], [p[1] for p in points])
    np.testing.assert_allclose(runs["cycle_time_s"], [np.pi / p[1] for p in points], rtol=1e-12)
    assert runs["contact_start_s"][1] < runs["contact_start_s"][0] / 2     # the faster drum gets there sooner
    assert setup_at(DrumSetup(), [v.name for v in space], points[1]).omega_rad_s == points[1][1]
    assert space[1].describe(points[1][1]) == "drum speed = 45 rpm"


def test_throughput_needs_the_drum_speed_as_a_variable(surrogate, tmp_path, capsys):
    sur, _ = surrogate
    with pytest.raises(InputError, match="needs the drum speed as a design variable"):
        DesignProblem(sur, objective="throughput")
    toml = tmp_path / "fixed.toml"
    toml.write_text("[drum]\ncycle_time_s = 1.0\n")
    for args in (["--objective", "throughput"],
                 ["--objective", "throughput", "--vary", "drum_speed", "--config", str(toml)],
                 ["--vary", "drum_speed", "--alpha-of-length", "paper"],
                 ["--vary", "drum_speed", "--drum-speed-bounds-rpm", "30", "10"]):
        assert main(["design", *args, "--json", str(tmp_path / "d.json"), "--out", str(tmp_path)]) == 1
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not (tmp_path / "d.json").exists() and not (tmp_path / "rom_grid.csv").exists()
