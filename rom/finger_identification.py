"""CCEDI on the paper's structures: SM-A rubber fingers of any length and the steel rod.

Simulators (``alpha -> (time_s, tip displacement m)``) for :mod:`ccedi.rom.ccedi`, with run
lengths chosen from the first natural frequency so that a nearly critical response has
time to cross zero: t_end = load duration + 12 / omega_1.
"""
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import SEMI_AXES, sm_a
from ccedi.fea.modal import natural_frequencies
from ccedi.fea.model import cantilever_model
from ccedi.fea.steel_rod import STEEL_ROD, steel_rod_model
from ccedi.fea.studies import impulse_model

from .ccedi import critical_alpha, fe_simulator, paper_alpha_cr

SETTLE_PERIODS = 12.0
"""Run length after the load, in units of 1 / omega_1 [-]."""


def finger_omega1(length_in, material=RUBBER, semi_axes_m=SEMI_AXES):
    """First natural frequency [rad/s] of the clamped SM-A finger (soft direction) of
    ``material`` with section semi-axes ``semi_axes_m`` [m]."""
    mesh = sm_a(length_in=length_in, semi_axes_m=semi_axes_m)
    return float(natural_frequencies(cantilever_model(mesh, material), 1)[0])


def finger_simulator(length_in, force_N=1.0, duration_s=0.01, t_end_s=None, n_outputs=400, material=RUBBER,
                     semi_axes_m=SEMI_AXES):
    """``simulate(alpha)`` for the SM-A finger impulse test (paper section 3.2)."""
    mesh = sm_a(length_in=length_in, semi_axes_m=semi_axes_m)
    if t_end_s is None:
        t_end_s = duration_s + SETTLE_PERIODS / finger_omega1(length_in, material, semi_axes_m)
    return fe_simulator(lambda alpha: impulse_model(alpha=alpha, force_N=force_N, duration_s=duration_s,
                                                    material=material, mesh=mesh), t_end_s, n_outputs)


def finger_alpha_cr(length_in, rtol=0.01, material=RUBBER, semi_axes_m=SEMI_AXES):
    """alpha_cr [1/s] of the SM-A finger by bisection, starting from 2 omega_1. Returns
    (CriticalAlpha, omega_1 [rad/s])."""
    omega1 = finger_omega1(length_in, material, semi_axes_m)
    simulate = finger_simulator(length_in, material=material, semi_axes_m=semi_axes_m)
    return critical_alpha(simulate, 2.0 * omega1, rtol=rtol), omega1


def rod_simulator(t_end_s=None, omega1_guess=16.33, n_outputs=800, **kwargs):
    """``simulate(alpha)`` for the steel rod of paper section 2.2 (tip impulse 0.003 N, 0.2 s)."""
    if t_end_s is None:
        t_end_s = STEEL_ROD["duration_s"] + SETTLE_PERIODS / omega1_guess
    return fe_simulator(lambda alpha: steel_rod_model(alpha=alpha, **kwargs), t_end_s, n_outputs)


def rod_alpha_cr(omega1_guess=16.33, rtol=0.01):
    """alpha_cr [1/s] of the steel rod, starting from 2 omega_1 (the measured 16.33 rad/s)."""
    return critical_alpha(rod_simulator(omega1_guess=omega1_guess), 2.0 * omega1_guess, rtol=rtol)


def _alpha_cr_row(length_in, rtol, material, semi_axes_m):
    crit, omega1 = finger_alpha_cr(length_in, rtol, material, semi_axes_m)
    return {"length_in": float(length_in), "alpha_cr_per_s": crit.alpha_cr_per_s,
            "bracket_per_s": list(crit.bracket_per_s), "n_runs": crit.n_runs,
            "omega1_rad_s": omega1, "two_omega1_per_s": 2.0 * omega1,
            "paper_eq8_per_s": float(paper_alpha_cr(length_in))}


def alpha_cr_table(lengths_in=(3.0, 4.5, 6.0, 8.0), rtol=0.01, scheduler="serial", material=RUBBER,
                   semi_axes_m=SEMI_AXES):
    """alpha_cr, 2 omega_1 and the paper's Eq. (8) (which holds for the paper's rubber and
    section only) for each finger length, one length per run of
    :func:`ccedi.fea.distributed.map_runs` (``scheduler``); a list of dicts."""
    from functools import partial

    from ccedi.fea.distributed import map_runs

    return map_runs(partial(_alpha_cr_row, rtol=rtol, material=material, semi_axes_m=semi_axes_m), lengths_in, scheduler, label="alpha_cr")
