"""CCEDI on the paper's structures: SM-A rubber fingers of any length and the steel rod.

Impulse models (:class:`ccedi.models.ImpulseModel`) for :mod:`ccedi.rom.ccedi`, with run
lengths chosen from the first natural frequency so that a nearly critical response has
time to cross zero: t_end = load duration + 12 / omega_1 (:func:`run_length_s`). The
searches take any impulse model of the structure (default: the full FE one,
:func:`ccedi.fea.studies.finger_impulse_model` or :func:`ccedi.fea.steel_rod.steel_rod_impulse_model`; e.g. its
modal ROM from :func:`ccedi.rom.modal.reduce_impulse_model`).
"""
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import SEMI_AXES, sm_a
from ccedi.fea.modal import natural_frequencies
from ccedi.fea.model import cantilever_model
from ccedi.fea.steel_rod import steel_rod_impulse_model
from ccedi.fea.studies import finger_impulse_model

from .ccedi import critical_alpha, paper_alpha_cr

SETTLE_PERIODS = 12.0
"""Run length after the load, in units of 1 / omega_1 [-]."""


def run_length_s(duration_s, omega1_rad_s):
    """Length of a CCEDI run: the load, then ``SETTLE_PERIODS`` / omega_1 for a nearly
    critical response to cross zero.

    Parameters
    ----------
    duration_s : float
        How long the tip force is held [s].
    omega1_rad_s : float
        First natural frequency [rad/s].

    Returns
    -------
    float
        ``duration_s + SETTLE_PERIODS / omega1_rad_s`` [s].
    """
    return duration_s + SETTLE_PERIODS / omega1_rad_s


def finger_omega1(length_in=None, material=RUBBER, semi_axes_m=SEMI_AXES, mesh=None):
    """First natural frequency of the clamped finger: SM-A of ``length_in``, or ``mesh``.

    Parameters
    ----------
    length_in : float, optional
        Finger length [in] of the SM-A finger (when ``mesh`` is None).
    material : ccedi.fea.material.NeoHookean, optional
        Finger material.
    semi_axes_m : tuple, optional
        Section semi-axes [m] of the SM-A finger.
    mesh : ccedi.fea.mesh.Mesh, optional
        Any clamped finger mesh (node set ``root``) instead of SM-A.

    Returns
    -------
    float
        omega_1 [rad/s].
    """
    mesh = sm_a(length_in=length_in, semi_axes_m=semi_axes_m) if mesh is None else mesh
    return float(natural_frequencies(cantilever_model(mesh, material), 1)[0])


def finger_alpha_cr(length_in=None, rtol=0.01, material=RUBBER, semi_axes_m=SEMI_AXES, model=None, n_outputs=400,
                    mesh=None):
    """alpha_cr of the finger (SM-A of ``length_in``, or ``mesh``) by bisection, starting
    from 2 omega_1.

    Parameters
    ----------
    length_in : float, optional
        Finger length [in] of the SM-A finger (when ``mesh`` is None).
    rtol : float, optional
        Relative bracket width at the end.
    material : ccedi.fea.material.NeoHookean, optional
        Finger material.
    semi_axes_m : tuple, optional
        Section semi-axes [m] of the SM-A finger.
    model : ccedi.models.ImpulseModel, optional
        The finger's impulse model, full or reduced (default:
        :func:`ccedi.fea.studies.finger_impulse_model`, 1 N for 10 ms); run for
        :func:`run_length_s` of its ``duration_s``.
    n_outputs : int, optional
        Output times per run.
    mesh : ccedi.fea.mesh.Mesh, optional
        Any clamped finger mesh (node sets ``root`` and ``tip``) instead of SM-A.

    Returns
    -------
    tuple
        (:class:`ccedi.rom.ccedi.CriticalAlpha`, omega_1 [rad/s]).
    """
    mesh = sm_a(length_in=length_in, semi_axes_m=semi_axes_m) if mesh is None else mesh
    omega1 = finger_omega1(material=material, mesh=mesh)
    model = finger_impulse_model(material=material, mesh=mesh) if model is None else model
    t_end_s = run_length_s(model.duration_s, omega1)
    return critical_alpha(model, 2.0 * omega1, t_end_s, rtol=rtol, n_outputs=n_outputs), omega1


def rod_alpha_cr(omega1_guess=16.33, rtol=0.01, model=None, n_outputs=800):
    """alpha_cr of the steel rod, starting from 2 omega_1.

    Parameters
    ----------
    omega1_guess : float, optional
        First natural frequency [rad/s] (the measured 16.33 rad/s).
    rtol : float, optional
        Relative bracket width at the end.
    model : ccedi.models.ImpulseModel, optional
        The rod's impulse model (default: the full FE one,
        :func:`ccedi.fea.steel_rod.steel_rod_impulse_model`); run for
        :func:`run_length_s` of its ``duration_s`` and ``omega1_guess``.
    n_outputs : int, optional
        Output times per run.

    Returns
    -------
    ccedi.rom.ccedi.CriticalAlpha
    """
    model = steel_rod_impulse_model() if model is None else model
    t_end_s = run_length_s(model.duration_s, omega1_guess)
    return critical_alpha(model, 2.0 * omega1_guess, t_end_s, rtol=rtol, n_outputs=n_outputs)


def _alpha_cr_row(length_in, rtol, material, semi_axes_m):
    crit, omega1 = finger_alpha_cr(length_in, rtol, material, semi_axes_m)
    return {"length_in": float(length_in), "alpha_cr_per_s": crit.alpha_cr_per_s,
            "bracket_per_s": list(crit.bracket_per_s), "n_runs": crit.n_runs,
            "omega1_rad_s": omega1, "two_omega1_per_s": 2.0 * omega1,
            "paper_eq8_per_s": float(paper_alpha_cr(length_in))}


def alpha_cr_table(lengths_in=(3.0, 4.5, 6.0, 8.0), rtol=0.01, scheduler="serial", material=RUBBER,
                   semi_axes_m=SEMI_AXES):
    """alpha_cr, 2 omega_1 and the paper's Eq. (8) for each finger length.

    The paper's Eq. (8) holds for the paper's rubber and section only. One length per
    run of :func:`ccedi.fea.distributed.map_runs` (``scheduler``).

    Parameters
    ----------
    lengths_in : tuple, optional
        Finger lengths [in].
    rtol : float, optional
        Relative bracket width.
    scheduler : str, optional
        :func:`ccedi.fea.distributed.map_runs` scheduler.
    material : ccedi.fea.material.NeoHookean, optional
        Finger material.
    semi_axes_m : tuple, optional
        Section semi-axes [m].

    Returns
    -------
    list of dict
        Per length: ``length_in``, ``alpha_cr_per_s``, ``bracket_per_s``, ``n_runs``,
        ``omega1_rad_s``, ``two_omega1_per_s``, ``paper_eq8_per_s``.
    """
    from functools import partial

    from ccedi.fea.distributed import map_runs

    return map_runs(partial(_alpha_cr_row, rtol=rtol, material=material, semi_axes_m=semi_axes_m), lengths_in,
                    scheduler, label="alpha_cr")
