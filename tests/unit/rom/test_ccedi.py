"""CCEDI (paper Fig. 2): the critical-alpha bisection and over-damped matching, first on
exact single-DOF responses (fast), then on the paper's FE structures."""
import numpy as np
import pandas as pd
import pytest
from conftest import ROD_ELEMENTS

from ccedi.errors import InputError
from ccedi.fea.cases.steel_rod import PAPER_ROD, STEEL_ROD, steel_rod_impulse_model
from ccedi.fea.cases.studies import finger_impulse_model
from ccedi.models import ImpulseModel, ImpulseResponse, pulse_times, validate_run_args
from ccedi.rom.ccedi import (
    critical_alpha,
    critical_alpha_narrowed,
    identify,
    match_alpha,
    paper_alpha,
    paper_alpha_cr,
    power_law_fit,
)
from ccedi.rom.damping import log_decrement
from ccedi.rom.finger_identification import finger_alpha_cr, rod_alpha_cr

OMEGA = 50.0


class SDOF:
    """Exact impulse response of x'' + alpha x' + omega^2 x = delta(t) (mass damping only),
    an :class:`ccedi.models.ImpulseModel`: a unit impulse (force_N = 1, duration_s = 0)."""

    name = "sdof"
    force_N = 1.0
    duration_s = 0.0

    def __init__(self, omega=OMEGA):
        self.omega = omega

    def run(self, alpha, t_end_s, n_outputs=400):
        alpha, t_end_s, n_outputs = validate_run_args(alpha, t_end_s, n_outputs)
        t, w, s = pulse_times(t_end_s, n_outputs), self.omega, alpha / 2.0
        if s < w:
            wd = np.sqrt(w**2 - s**2)
            y = np.exp(-s * t) * np.sin(wd * t) / wd
        elif s == w:
            y = t * np.exp(-s * t)
        else:
            r = np.sqrt(s**2 - w**2)
            y = (np.exp((-s + r) * t) - np.exp((-s - r) * t)) / (2 * r)
        return ImpulseResponse(history=pd.DataFrame({"time_s": t, "tip_uy_m": y}),
                               summary={"model": self.name, "alpha_per_s": alpha, "wall_time_s": 0.0,
                                        "warnings": []})


RUN = {"t_end_s": 2.0, "n_outputs": 4000}
"""The SDOF runs: 2 s, 4000 outputs."""


def test_sdof_is_an_impulse_model():
    assert isinstance(SDOF(), ImpulseModel)


@pytest.mark.parametrize("guess", [100.0, 40.0, 300.0])
def test_critical_alpha_of_sdof_is_two_omega(guess):
    crit = critical_alpha(SDOF(), guess, rtol=0.005, **RUN)
    assert crit.alpha_cr_per_s == pytest.approx(2 * OMEGA, rel=0.03)
    assert crit.alpha_cr_per_s < 2 * OMEGA                  # the band resolves zeta up to ~0.97
    assert crit.n_runs == len(crit.runs) >= 3
    lo, hi = crit.bracket_per_s
    assert (hi - lo) <= 0.005 * hi



class BatchedSDOF(SDOF):
    """The SDOF with a batched ``run_many`` that records the size of each batch."""

    name = "sdof-batched"

    def __init__(self, omega=OMEGA):
        super().__init__(omega)
        self.batches = []

    def run_many(self, alphas, t_end_s, n_outputs=400):
        self.batches.append(len(alphas))
        return [self.run(alpha, t_end_s, n_outputs) for alpha in alphas]


def test_rounds_of_batched_runs_find_the_bisection_bracket():
    """k-section with 5 runs a round: the same alpha_cr as bisection within rtol, the first
    round one batch of 5 spread over the bracket, each later round 5 inside it."""
    bisection = critical_alpha(SDOF(), 100.0, rtol=0.005, **RUN)
    model = BatchedSDOF()
    crit = critical_alpha(model, 100.0, rtol=0.005, runs_per_round=5, **RUN)
    assert crit.alpha_cr_per_s == pytest.approx(bisection.alpha_cr_per_s, rel=0.005)
    lo, hi = crit.bracket_per_s
    assert hi - lo <= 0.005 * hi and lo <= bisection.alpha_cr_per_s <= hi + 0.005 * hi
    assert model.batches[0] == 5 and set(model.batches[1:]) == {5}
    assert len(model.batches) < bisection.n_runs


def test_reduced_model_sets_the_bracket_of_one_batched_round():
    """A reduced model 2 % off in frequency: its alpha_cr centres one round of 8 full runs
    0.95 rtol apart, which brackets the full alpha_cr to rtol."""
    full, reduced = BatchedSDOF(OMEGA), SDOF(1.02 * OMEGA)
    crit = critical_alpha_narrowed(full, reduced, 80.0, rtol=0.01, runs_per_round=8, **RUN)
    truth = critical_alpha(SDOF(), 100.0, rtol=0.001, **RUN).alpha_cr_per_s
    assert crit.reduced_alpha_cr_per_s == pytest.approx(1.02 * truth, rel=0.003)
    lo, hi = crit.bracket_per_s
    assert lo <= truth <= hi and hi - lo <= 0.01 * hi
    assert full.batches == [8] and crit.n_runs == 8


@pytest.mark.parametrize("off", [1.02, 0.98])
def test_a_reduced_model_a_little_off_costs_a_run_or_two_more(off):
    """Two full runs 0.95 rtol apart around a reduced model 2 % off miss alpha_cr; the end
    that does not bracket moves out by the bracket's width, one run at a time, and the
    bracket is within rtol with far fewer runs than bisection."""
    full, reduced = BatchedSDOF(OMEGA), SDOF(off * OMEGA)
    crit = critical_alpha_narrowed(full, reduced, 80.0, rtol=0.01, runs_per_round=2, **RUN)
    truth = critical_alpha(SDOF(), 100.0, rtol=0.001, **RUN).alpha_cr_per_s
    lo, hi = crit.bracket_per_s
    assert lo <= truth <= hi and hi - lo <= 0.01 * hi
    assert full.batches[0] == 2 and 3 <= crit.n_runs <= 5, crit.runs


def test_a_reduced_model_far_off_only_starts_the_search():
    """A reduced model 40 % off: the search starts afresh from its value and still finds
    the full model's alpha_cr to rtol."""
    full, reduced = BatchedSDOF(OMEGA), SDOF(1.4 * OMEGA)
    crit = critical_alpha_narrowed(full, reduced, 80.0, rtol=0.01, runs_per_round=2, **RUN)
    truth = critical_alpha(SDOF(), 100.0, rtol=0.001, **RUN).alpha_cr_per_s
    lo, hi = crit.bracket_per_s
    assert lo <= truth <= hi and hi - lo <= 0.01 * hi


def test_widen_must_be_a_factor_above_one():
    with pytest.raises(InputError, match="widen must be a factor > 1, got 1.0"):
        critical_alpha(SDOF(), 100.0, widen=1.0, **RUN)


def test_runs_per_round_must_be_a_positive_integer():
    with pytest.raises(InputError, match="runs_per_round must be an integer >= 1, got 0"):
        critical_alpha(SDOF(), 100.0, runs_per_round=0, **RUN)

def test_match_alpha_recovers_overdamped_sdof_with_noise():
    sdof = SDOF()
    t, y = sdof.run(160.0, **RUN).tip_signal()
    noise = 0.02 * y.max()
    y = y + noise * np.random.default_rng(0).standard_normal(len(t))
    m = match_alpha(sdof, t, y, bounds_per_s=(50.0, 500.0), **RUN)
    assert m.alpha_per_s == pytest.approx(160.0, rel=0.01)
    assert m.n_runs == len(m.evaluations) < 40
    assert m.rms_error_m == pytest.approx(noise, rel=0.1)          # what is left is the noise


def test_identify_under_damped_sdof_gives_zeta_times_alpha_cr():
    sdof, run = SDOF(), {"t_end_s": 4.0, "n_outputs": 8000}
    t, y = sdof.run(10.0, **run).tip_signal()               # zeta = 10 / (2 * 50) = 0.1
    ident = identify(t, y, sdof, alpha_guess=100.0, **run)
    assert ident.regime == "under-damped"
    assert ident.zeta == pytest.approx(0.1, rel=0.02)
    assert ident.alpha_per_s == pytest.approx(ident.zeta * ident.alpha_cr_per_s, rel=1e-12)
    assert ident.alpha_per_s == pytest.approx(10.0, rel=0.05)


def test_identify_over_damped_sdof_matches():
    sdof = SDOF()
    t, y = sdof.run(250.0, **RUN).tip_signal()
    ident = identify(t, y, sdof, alpha_guess=100.0, **RUN)
    assert ident.regime == "over-damped" and ident.alpha_per_s == pytest.approx(250.0, rel=0.01)


def test_power_law_and_paper_equations():
    x = np.array([3.0, 4.5, 6.0, 8.0])
    c, p = power_law_fit(x, paper_alpha_cr(x))
    assert (c, p) == (pytest.approx(3120.4), pytest.approx(-1.983))
    assert paper_alpha(x) == pytest.approx([600.0, 180.0, 15.0, 7.5], abs=0.1)   # the paper's identified alphas
    with pytest.raises(InputError):
        power_law_fit([1.0], [2.0])


def test_bad_bracket_and_tolerance_are_named():
    with pytest.raises(InputError, match="bracket"):
        critical_alpha(SDOF(), 100.0, bracket=(1.2, 0.8), **RUN)
    with pytest.raises(InputError, match="rtol"):
        critical_alpha(SDOF(), 100.0, rtol=2.0, **RUN)
    with pytest.raises(InputError, match="bounds"):
        match_alpha(SDOF(), *SDOF().run(100.0, **RUN).tip_signal(), bounds_per_s=(300.0, 100.0))


def test_searches_take_impulse_models_only():
    """A bare simulate(alpha) callable is not an impulse model: named, not run."""
    def simulate(alpha):
        return SDOF().run(alpha, **RUN).tip_signal()

    t, y = simulate(100.0)
    with pytest.raises(InputError, match="impulse model"):
        critical_alpha(simulate, 100.0, **RUN)
    with pytest.raises(InputError, match="impulse model"):
        match_alpha(simulate, t, y, bounds_per_s=(50.0, 500.0))
    with pytest.raises(InputError, match="impulse model"):
        identify(t, y, simulate, alpha_guess=100.0)


# ---- the paper's structures (explicit FEA) ----------------------------------------------

@pytest.fixture(scope="module")
def rod_critical():
    """alpha_cr of the paper's rod on ROD_ELEMENTS elements (converged for mode 1, conftest)."""
    return rod_alpha_cr(omega1_guess=PAPER_ROD["omega1_rad_s"], rtol=0.02,
                        model=steel_rod_impulse_model(n_elements=ROD_ELEMENTS))


@pytest.mark.slow
def test_steel_rod_alpha_cr_matches_paper(rod_critical):
    """Paper section 2.2: alpha_cr = 30 1/s."""
    assert rod_critical.alpha_cr_per_s == pytest.approx(PAPER_ROD["alpha_cr_per_s"], rel=0.15)


@pytest.mark.slow
def test_steel_rod_alpha_from_zeta_reproduces_zeta(rod_critical):
    """alpha = zeta alpha_cr with the measured zeta = 0.0055: the simulated free vibration
    has a log-decrement damping ratio within 10 % of 0.0055."""
    alpha = PAPER_ROD["zeta"] * rod_critical.alpha_cr_per_s
    t, y = steel_rod_impulse_model(n_elements=ROD_ELEMENTS).run(alpha, 4.0, 4000).tip_signal()
    free = t > STEEL_ROD["duration_s"]
    ld = log_decrement(t[free], y[free], y_final=0.0)
    assert ld.zeta == pytest.approx(PAPER_ROD["zeta"], rel=0.10)
    assert ld.n_cycles >= 8


@pytest.mark.slow
def test_finger_alpha_cr_45_in():
    """Acceptance: within 15 % of paper Eq. (8) and within 5 % of 2 omega_1 of our model."""
    crit, omega1 = finger_alpha_cr(4.5, rtol=0.02)
    assert crit.alpha_cr_per_s == pytest.approx(float(paper_alpha_cr(4.5)), rel=0.15)
    assert crit.alpha_cr_per_s == pytest.approx(2 * omega1, rel=0.05)


@pytest.mark.slow
def test_overdamped_match_45_in_alpha_180_with_noise():
    model, run = finger_impulse_model(4.5), {"t_end_s": 0.12, "n_outputs": 240}
    t, y = model.run(180.0, **run).tip_signal()
    y_meas = y + 0.02 * np.abs(y).max() * np.random.default_rng(4).standard_normal(len(t))
    m = match_alpha(model, t, y_meas, bounds_per_s=(60.0, 400.0), xatol_rel=0.005, **run)
    assert m.alpha_per_s == pytest.approx(180.0, rel=0.05)
