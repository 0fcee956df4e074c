"""CCEDI on the paper's structures: SM-A rubber fingers of any length and the steel rod.

Impulse models (:class:`ccedi.models.ImpulseModel`) for :mod:`ccedi.rom.ccedi`, with run
lengths chosen from the first natural frequency so that a nearly critical response has
time to cross zero: t_end = load duration + 12 / omega_1 (:func:`run_length_s`). The
searches take any impulse model of the structure (default: the full FE one,
:func:`ccedi.fea.cases.studies.finger_impulse_model` or :func:`ccedi.fea.cases.steel_rod.steel_rod_impulse_model`; e.g. its
modal ROM from :func:`ccedi.rom.modal.reduce_impulse_model`).
"""
from dataclasses import dataclass
from functools import partial

import numpy as np

from ccedi.distributed import map_runs
from ccedi.fea.cases.steel_rod import steel_rod_impulse_model
from ccedi.fea.cases.studies import finger_impulse_model
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import SEMI_AXES, sm_a
from ccedi.fea.model import cantilever_model, face_node_weights
from ccedi.fea.solvers.explicit import max_von_mises
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.fea.solvers.static import static_solve
from ccedi.rom.ccedi import match_alpha
from ccedi.rom.damping import oscillates
from ccedi.rom.modal import reduce_impulse_model

from .ccedi import critical_alpha, critical_alpha_narrowed, paper_alpha_cr

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


def finger_omega1(length_in=None, *, material=RUBBER, semi_axes_m=SEMI_AXES, mesh=None):
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
    return float(natural_frequencies(cantilever_model(mesh, material), n_modes=1)[0])


def finger_alpha_cr(length_in=None, *, rtol=0.01, material=RUBBER, semi_axes_m=SEMI_AXES, model=None, n_outputs=400,
                    mesh=None, runs_per_round=2):
    """alpha_cr of the finger (SM-A of ``length_in``, or ``mesh``), starting from 2 omega_1.

    A model that runs several alphas in one batched pass (the full FE model,
    ``run_many``) is searched from the bracket its modal ROM gives
    (:func:`ccedi.rom.ccedi.critical_alpha_narrowed`: one round of ``runs_per_round`` runs
    usually settles it); any other by bisection (:func:`ccedi.rom.ccedi.critical_alpha`).

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
        :func:`ccedi.fea.cases.studies.finger_impulse_model`, 1 N for 10 ms); run for
        :func:`run_length_s` of its ``duration_s``.
    n_outputs : int, optional
        Output times per run.
    mesh : ccedi.fea.mesh.Mesh, optional
        Any clamped finger mesh (node sets ``root`` and ``tip``) instead of SM-A.
    runs_per_round : int, optional
        Full runs per round (default 2, 0.95 rtol apart around the ROM's alpha_cr: they
        bracket alpha_cr to rtol when the ROM is within 0.47 % of the full model, as on
        the paper's fingers, and each further run moves the missed end out by the
        bracket's width; fewer than :data:`ccedi.fea.solvers.batch.BATCH_MIN_RUNS` runs go
        one by one on every core, more in one batched pass); 1 for bisection on the full
        model alone.

    Returns
    -------
    tuple
        (:class:`ccedi.rom.ccedi.CriticalAlpha`, omega_1 [rad/s]).
    """
    mesh = sm_a(length_in=length_in, semi_axes_m=semi_axes_m) if mesh is None else mesh
    omega1 = finger_omega1(material=material, mesh=mesh)
    model = finger_impulse_model(material=material, mesh=mesh) if model is None else model
    t_end_s = run_length_s(model.duration_s, omega1)
    if runs_per_round > 1 and hasattr(model, "run_many"):
        reduced = reduce_impulse_model(model, n_modes=6)
        return critical_alpha_narrowed(model, reduced, 2.0 * omega1, t_end_s=t_end_s, rtol=rtol, n_outputs=n_outputs,
                                       runs_per_round=runs_per_round), omega1
    return critical_alpha(model, 2.0 * omega1, t_end_s, rtol=rtol, n_outputs=n_outputs), omega1


def rod_alpha_cr(omega1_guess=16.33, *, rtol=0.01, model=None, n_outputs=800):
    """alpha_cr of the steel rod, starting from 2 omega_1.

    Parameters
    ----------
    omega1_guess : float, optional
        First natural frequency [rad/s] (the measured 16.33 rad/s).
    rtol : float, optional
        Relative bracket width at the end.
    model : ccedi.models.ImpulseModel, optional
        The rod's impulse model (default: the full FE one,
        :func:`ccedi.fea.cases.steel_rod.steel_rod_impulse_model`); run for
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
    crit, omega1 = finger_alpha_cr(length_in, rtol=rtol, material=material, semi_axes_m=semi_axes_m)
    return {"length_in": float(length_in), "alpha_cr_per_s": crit.alpha_cr_per_s,
            "bracket_per_s": list(crit.bracket_per_s), "n_runs": crit.n_runs,
            "omega1_rad_s": omega1, "two_omega1_per_s": 2.0 * omega1,
            "paper_eq8_per_s": float(paper_alpha_cr(length_in))}


def alpha_cr_table(lengths_in=(3.0, 4.5, 6.0, 8.0), *, rtol=0.01, scheduler="serial", material=RUBBER,
                   semi_axes_m=SEMI_AXES):
    """alpha_cr, 2 omega_1 and the paper's Eq. (8) for each finger length.

    The paper's Eq. (8) holds for the paper's rubber and section only. One length per
    run of :func:`ccedi.distributed.map_runs` (``scheduler``).

    Parameters
    ----------
    lengths_in : tuple, optional
        Finger lengths [in].
    rtol : float, optional
        Relative bracket width.
    scheduler : str, optional
        :func:`ccedi.distributed.map_runs` scheduler.
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
    return map_runs(partial(_alpha_cr_row, rtol=rtol, material=material, semi_axes_m=semi_axes_m), lengths_in,
                    scheduler=scheduler, label="alpha_cr")


PAPER_FIG6 = {"alpha_per_s": 180.0, "dm_matching_alpha_per_s": 260.0}
"""The paper's Fig. 6: the alpha [1/s] of the comparison (simplified models over-damped, DM
under-damped) and the alpha at which the DM's response is like SM-A's."""


def quasi_static_peak_stress(model, tip_displacements_m):
    """Largest von Mises stress [Pa] of the linear static deflection under a uniform tip
    force (along y) scaled to each tip displacement: the stress at the peak of a response
    dominated by the first bending mode, whose shape a tip-loaded static deflection
    approximates (one sparse solve, the deflection then scaled; the neo-Hookean stress of
    the scaled positions).

    Parameters
    ----------
    model : ccedi.fea.model.Model
        A clamped finger (node sets ``root`` and ``tip``).
    tip_displacements_m : sequence of float
        Area-weighted mean tip displacements along y [m].

    Returns
    -------
    list of float
        Max von Mises stress [Pa] over the elements, one per displacement.
    """
    mesh = model.mesh
    tip = mesh.node_sets["tip"]
    w = face_node_weights(mesh, tip)
    f = np.zeros_like(mesh.nodes)
    f[tip, 1] = w
    u = static_solve(model, f, linear=True) - mesh.nodes
    u /= float(w @ u[tip, 1])
    return [float(max_von_mises(model, mesh.nodes + d * u)) for d in tip_displacements_m]


@dataclass(frozen=True)
class DetailedModelComparison:
    """Result of :func:`detailed_model_comparison` (paper Fig. 6 with the DM).

    Parameters
    ----------
    time_s : numpy.ndarray
        Output times [s].
    sm_a_tip_m, dm_tip_m, dm_matched_tip_m : numpy.ndarray
        Tip responses [m]: SM-A and the DM at ``alpha_per_s``, the DM at the matching alpha.
    alpha_per_s : float
        The comparison's alpha [1/s].
    match : ccedi.rom.ccedi.AlphaMatch
        The DM's alpha whose response is nearest SM-A's (RMS).
    dm_under_damped, sm_a_under_damped, dm_matched_under_damped : bool
        Whether each response crosses zero after its peak
        (:func:`ccedi.rom.damping.oscillates`).
    peak_stress_Pa : dict
        Quasi-static peak von Mises stress [Pa] (:func:`quasi_static_peak_stress`) of
        ``"SM-A"``, ``"DM"`` and ``"DM matched"``.
    omega1_rad_s : dict
        First modal frequency [rad/s] of ``"SM-A"`` and ``"DM"`` (the ROMs').
    """
    time_s: np.ndarray
    sm_a_tip_m: np.ndarray
    dm_tip_m: np.ndarray
    dm_matched_tip_m: np.ndarray
    alpha_per_s: float
    match: object
    dm_under_damped: bool
    sm_a_under_damped: bool
    dm_matched_under_damped: bool
    peak_stress_Pa: dict
    omega1_rad_s: dict


def detailed_model_comparison(dm_mesh, *, sm_a_mesh=None, alpha=PAPER_FIG6["alpha_per_s"], force_N=1.0,
                              duration_s=0.01, t_end_s=0.2, n_outputs=400, material=RUBBER, n_modes=6,
                              bounds_per_s=(100.0, 600.0), noise_band=1e-3):
    """Paper Fig. 6 with the detailed model: SM-A and the DM under the same tip pulse at
    ``alpha``, and the DM's alpha whose response is nearest SM-A's (:func:`ccedi.rom.ccedi.match_alpha`,
    least RMS difference over ``t_end_s``), all on the modal ROMs
    (:func:`ccedi.rom.modal.reduce_impulse_model`: ``n_modes`` modes of each FE model
    linearised at rest), which a full explicit run of the DM checks
    (``validation/dm_fig6.py``); peak stresses by :func:`quasi_static_peak_stress`.

    Parameters
    ----------
    dm_mesh : ccedi.fea.mesh.Mesh
        The DM (:func:`ccedi.fea.mesh.gmsh_fingers.detailed_model`).
    sm_a_mesh : ccedi.fea.mesh.Mesh, optional
        SM-A (default: the 4.5-in one).
    alpha : float, optional
        Mass-proportional damping of the comparison [1/s]. Default 180.
    force_N, duration_s : float, optional
        Tip pulse [N] along +y and how long it is held [s].
    t_end_s : float, optional
        Simulated time [s]. Default 0.2 (the paper's figure).
    n_outputs : int, optional
        Output times.
    material : ccedi.fea.material.NeoHookean, optional
        Finger material.
    n_modes : int, optional
        Modes of each ROM.
    bounds_per_s : tuple, optional
        Search bounds on the DM's matching alpha [1/s].
    noise_band : float, optional
        Zero-crossing band of the under-damped test, relative to the peak [-].

    Returns
    -------
    DetailedModelComparison
    """
    sm_a_mesh = sm_a(length_in=4.5) if sm_a_mesh is None else sm_a_mesh
    full = {name: finger_impulse_model(force_N=force_N, duration_s=duration_s, material=material, mesh=mesh)
            for name, mesh in (("SM-A", sm_a_mesh), ("DM", dm_mesh))}
    roms = {name: reduce_impulse_model(f, n_modes=n_modes, alpha=alpha) for name, f in full.items()}
    t, y_sm = roms["SM-A"].run(alpha, t_end_s, n_outputs).tip_signal()
    y_dm = roms["DM"].run(alpha, t_end_s, n_outputs).tip_signal()[1]
    match = match_alpha(roms["DM"], t, y_sm, bounds_per_s=bounds_per_s, t_end_s=t_end_s, n_outputs=n_outputs)
    y_match = roms["DM"].run(match.alpha_per_s, t_end_s, n_outputs).tip_signal()[1]
    dm_stress = quasi_static_peak_stress(full["DM"].fea_model(alpha), [y_dm.max(), y_match.max()])
    stress = {"SM-A": quasi_static_peak_stress(full["SM-A"].fea_model(alpha), [y_sm.max()])[0],
              "DM": dm_stress[0], "DM matched": dm_stress[1]}
    damped = {name: bool(oscillates(t, y, y_final=0.0, noise_band=noise_band))
              for name, y in (("sm", y_sm), ("dm", y_dm), ("match", y_match))}
    return DetailedModelComparison(
        time_s=t, sm_a_tip_m=y_sm, dm_tip_m=y_dm, dm_matched_tip_m=y_match, alpha_per_s=float(alpha), match=match,
        dm_under_damped=damped["dm"], sm_a_under_damped=damped["sm"], dm_matched_under_damped=damped["match"],
        peak_stress_Pa=stress, omega1_rad_s={n: float(r.rom.omega_rad_s.min()) for n, r in roms.items()})
