"""Studies of the paper's section 3.1: Table 1 (mesh, time step, stiffness) and the
impulse response of the 4.5-in finger for several alpha (Fig. 7)."""
import math
from functools import partial

import pandas as pd

from ccedi.distributed import LOCAL, SERIAL, map_runs
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import SEMI_AXES, sm_a, sm_b
from ccedi.fea.mesh.gmsh_fingers import detailed_model, sm_c
from ccedi.fea.model import cantilever_model, tip_pulse
from ccedi.fea.solvers.batch import BATCH_MIN_RUNS, batch_refusal, run_batch
from ccedi.fea.solvers.explicit import TSSFAC, critical_time_step, run
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.fea.solvers.static import tip_stiffness
from ccedi.fea.solvers.validity import cantilever_length_m, issue, run_label, tip_deflection_warnings
from ccedi.models import ImpulseResponse, validate_run_args
from ccedi.quantities import QUANTITIES

PAPER_TABLE1 = {
    "SM-A": {"element_type": "hex8", "average_length_mm": 4.0, "volume_cm3": 36.0, "nodes": 1080, "elements": 725,
             "dt_us": 4.04, "steps_to_0_2_s": 49505, "step_ratio": 1.0, "stiffness_N_per_m": 73.8},
    "SM-B": {"element_type": "hex8", "average_length_mm": 2.0, "volume_cm3": 36.0, "nodes": 5900, "elements": 4698,
             "dt_us": 1.43, "steps_to_0_2_s": 139860, "step_ratio": 2.83, "stiffness_N_per_m": 74.0},
    "SM-C": {"element_type": "tet10", "average_length_mm": 4.0, "volume_cm3": 36.0, "nodes": 7481,
             "elements": 4682, "dt_us": 1.26, "steps_to_0_2_s": 158730, "step_ratio": 3.21,
             "stiffness_N_per_m": 74.9},
    "DM": {"element_type": "tet10", "average_length_mm": 2.8, "volume_cm3": 30.0, "nodes": 36782, "elements": 23147,
           "dt_us": 0.22, "steps_to_0_2_s": 909091, "step_ratio": 18.36, "stiffness_N_per_m": 81.2},
}
"""The paper's Table 1 for the 4.5-in finger: simplified models A, B (hexahedra), C and the
detailed model DM (10-node tetrahedra); volumes as the paper gives them (36 and 30 cm^3)."""


def is_paper_finger(length_in, material, semi_axes_m):
    """True when the finger is the one of the paper's Table 1 (4.5 in, its rubber and section),
    so that Table 1 applies to it.

    Parameters
    ----------
    length_in : float
        Finger length [in].
    material : ccedi.fea.material.NeoHookean
        Finger material.
    semi_axes_m : tuple
        Section semi-axes [m].

    Returns
    -------
    bool
    """
    return length_in == 4.5 and material == RUBBER and tuple(semi_axes_m) == SEMI_AXES


def table1_row(mesh, material, *, stiffness=True, omega1=False):
    """One row of Table 1 for a clamped finger mesh (node sets ``root`` and ``tip``).

    Parameters
    ----------
    mesh : ccedi.fea.mesh.Mesh
        The finger.
    material : ccedi.fea.material.NeoHookean
        Finger material.
    stiffness : bool, optional
        Solve the nonlinear static tip stiffness (mean of F / delta at 1 N and 2 N along y,
        as the paper's ANSYS runs).
    omega1 : bool, optional
        Also the first natural frequency (eigenvalue of the linearised model).

    Returns
    -------
    dict
        ``element_type``, ``nodes``, ``elements``, ``average_length_mm`` (mean edge length),
        ``volume_cm3``, ``dt_us`` (TSSFAC x the smallest element step of paper Eq. 6),
        ``steps_to_0_2_s``; with ``stiffness``, ``stiffness_N_per_m``; with ``omega1``,
        ``omega1_rad_s``.
    """
    model = cantilever_model(mesh, material)
    dt = TSSFAC * critical_time_step(model)
    row = {"element_type": mesh.element_type, "nodes": mesh.n_nodes, "elements": mesh.n_elements,
           "average_length_mm": 1e3 * mesh.average_edge_length(),
           "volume_cm3": 1e6 * model.total_mass / material.rho, "dt_us": dt * 1e6,
           "steps_to_0_2_s": math.ceil(0.2 / dt)}
    if stiffness:
        row["stiffness_N_per_m"] = tip_stiffness(model, (1.0, 2.0))
    if omega1:
        row["omega1_rad_s"] = float(natural_frequencies(model, n_modes=1)[0])
    return row


def table1(length_in=4.5, *, material=RUBBER, stiffness=True, semi_axes_m=SEMI_AXES, finger=None, detailed=False,
           detailed_stiffness=None, detailed_omega1=True, progress=None):
    """Table 1 of the paper for SM-A, SM-B (hexahedra) and SM-C (10-node tetrahedra,
    :func:`ccedi.fea.mesh.gmsh_fingers.sm_c`) with section semi-axes ``semi_axes_m`` [m] (the
    detailed model DM, and a finger of the user's), each row from :func:`table1_row`, with
    the step ratio to SM-A.

    Parameters
    ----------
    length_in : float, optional
        Finger length [in] of the simplified models.
    material : ccedi.fea.material.NeoHookean, optional
        Finger material.
    stiffness : bool, optional
        Also solve the tip stiffness (two nonlinear static solves per mesh).
    semi_axes_m : tuple, optional
        Section semi-axes [m].
    finger : ccedi.fea.mesh.Mesh, optional
        A finger mesh of the user's: one more row, ``"finger"``, with its first natural
        frequency ``omega1_rad_s`` too.
    detailed : bool, optional
        One more row, ``"DM"``: the paper's detailed model
        (:func:`ccedi.fea.mesh.gmsh_fingers.detailed_model`, 4.5 in, 2.8 mm; its own geometry,
        whatever ``length_in`` and ``semi_axes_m``), with ``omega1_rad_s``. Its mesh (about
        28 000 nodes) adds a minute or so without its stiffness, and the nonlinear solves of
        some 83 000 DOFs with it (docs/validation.md: measured times).
    detailed_stiffness : bool, optional
        Solve the DM's stiffness too (default: as ``stiffness``).
    detailed_omega1 : bool, optional
        Solve the DM's first natural frequency (a modal solve of some 83 000 DOFs, about
        50 s here). Default True.
    progress : callable, optional
        Called with one line as each row starts (the model, its size and what it solves).

    Returns
    -------
    dict
        ``{model name: row}``, rows as :func:`table1_row` plus ``step_ratio`` (steps to
        0.2 s over SM-A's).
    """
    meshes = {"SM-A": sm_a(length_in=length_in, semi_axes_m=semi_axes_m),
              "SM-B": sm_b(length_in=length_in, semi_axes_m=semi_axes_m),
              "SM-C": sm_c(length_in=length_in, semi_axes_m=semi_axes_m)}
    say = progress or (lambda line: None)

    def row(name, mesh, solve_stiffness, omega1=False):
        solves = [what for what, wanted in (("tip stiffness (nonlinear static solves)", solve_stiffness),
                                            ("first frequency (modal solve)", omega1)) if wanted]
        say(f"{name}: {mesh.n_nodes} nodes, {mesh.n_elements} {mesh.element_type} elements"
            + (f"; {' and '.join(solves)}" if solves else ""))
        return table1_row(mesh, material, stiffness=solve_stiffness, omega1=omega1)

    out = {name: row(name, mesh, stiffness) for name, mesh in meshes.items()}
    if detailed:
        dm_stiffness = stiffness if detailed_stiffness is None else detailed_stiffness
        say("DM: meshing the detailed model (2.8 mm elements, about 28 000 nodes)")
        out["DM"] = row("DM", detailed_model(), dm_stiffness, omega1=detailed_omega1)
    if finger is not None:
        out["finger"] = row("finger", finger, stiffness, omega1=True)
    for name in out:
        out[name]["step_ratio"] = out[name]["steps_to_0_2_s"] / out["SM-A"]["steps_to_0_2_s"]
    return out


def impulse_model(length_in=4.5, *, alpha=180.0, force_N=1.0, duration_s=0.01, material=RUBBER, beta=0.0,
                  mesh=None, semi_axes_m=SEMI_AXES):
    """A clamped SM-A finger (section semi-axes ``semi_axes_m`` [m]; or ``mesh``) loaded by a
    tip force ``force_N`` [N] in the soft direction (+y) held for ``duration_s`` [s]: the
    paper's impulse test.

    Parameters
    ----------
    length_in : float, optional
        Finger length [in] (when ``mesh`` is None).
    alpha : float, optional
        Mass-proportional damping [1/s].
    force_N : float, optional
        Tip force [N] along +y.
    duration_s : float, optional
        How long the force is held [s].
    material : ccedi.fea.material.NeoHookean, optional
        Finger material.
    beta : float, optional
        Stiffness-proportional damping [s].
    mesh : ccedi.fea.mesh.Mesh, optional
        The finger mesh (default: SM-A of ``length_in``).
    semi_axes_m : tuple, optional
        Section semi-axes [m] of the default mesh.

    Returns
    -------
    ccedi.fea.model.Model
    """
    mesh = sm_a(length_in=length_in, semi_axes_m=semi_axes_m) if mesh is None else mesh
    return cantilever_model(mesh, material, alpha=alpha, beta=beta,
                            pulses=[tip_pulse(mesh, [0.0, force_N, 0.0], duration_s)])


def _checked_run(model, t_end_s, n_outputs):
    """Explicit run of an impulse test with its tip deflection check
    (:func:`ccedi.fea.solvers.validity.tip_deflection_warnings`).

    Parameters
    ----------
    model : ccedi.fea.model.Model
        A cantilever (node sets ``root`` and ``tip``) under a tip pulse along +y.
    t_end_s : float
        Simulated time [s].
    n_outputs : int
        Output times.

    Returns
    -------
    ccedi.fea.solvers.explicit.RunResult
        The solver's result; a tip deflection warning is added to
        ``summary["warnings"]`` (and issued as a :class:`ccedi.errors.ValidityWarning`).

    Raises
    ------
    SolverError
        The solver cannot continue, or the tip deflection reaches the length.
    """
    return _deflection_checked(model, run(model, t_end_s, n_outputs=n_outputs))


def _deflection_checked(model, res):
    """``res`` (a run of the cantilever ``model``) with its tip deflection check."""
    found = tip_deflection_warnings(res.history.tip_uy_m, cantilever_length_m(model.mesh))
    issue(found, run_label(model.alpha, model.damping))
    res.summary["warnings"] += found
    return res


class FullImpulseModel:
    """The full explicit FE model of an impulse test, a :class:`ccedi.models.ImpulseModel`
    (reduced by :func:`ccedi.rom.modal.reduce_impulse_model`).

    Parameters
    ----------
    model_factory : callable
        ``model_factory(alpha) -> ccedi.fea.model.Model``: the structure with its tip
        pulse and mass-proportional damping ``alpha`` [1/s].
    force_N : float or None
        The pulse's force [N] along +y (None when unknown).
    duration_s : float or None
        How long the force is held [s] (None when unknown).
    name : str, optional
        The ``model`` summary key.
    """
    def __init__(self, model_factory, *, force_N=None, duration_s=None, name="fea"):
        self.model_factory = model_factory
        self.force_N = force_N
        self.duration_s = duration_s
        self.name = name

    def fea_model(self, alpha):
        """The FE model at damping ``alpha`` [1/s].

        Parameters
        ----------
        alpha : float
            Mass-proportional damping coefficient [1/s].

        Returns
        -------
        ccedi.fea.model.Model
        """
        return self.model_factory(alpha)

    def run(self, alpha, t_end_s, n_outputs=400):
        """Explicit FE response to the pulse.

        Parameters
        ----------
        alpha : float
            Mass-proportional damping coefficient [1/s].
        t_end_s : float
            Simulated time [s].
        n_outputs : int, optional
            Output times.

        Returns
        -------
        ccedi.models.ImpulseResponse
            History: the solver's (core ``time_s``, ``tip_uy_m``; extras
            :data:`ccedi.models.FE_IMPULSE_EXTRA_COLUMNS`); summary: ``model``,
            ``alpha_per_s`` and the solver's summary (``wall_time_s``, ``steps``,
            ``warnings``, ...) of the explicit run, with the tip deflection check
            (:func:`ccedi.fea.solvers.validity.tip_deflection_warnings`).

        Raises
        ------
        InputError
            Invalid arguments (:func:`ccedi.models.validate_run_args`).
        SolverError
            The explicit solver cannot continue, or the tip deflection reaches the length.
        """
        alpha, t_end_s, n_outputs = validate_run_args(alpha, t_end_s, n_outputs)
        res = _checked_run(self.model_factory(alpha), t_end_s, n_outputs)
        return ImpulseResponse(history=res.history,
                               summary={"model": self.name, "alpha_per_s": alpha, **res.summary})

    def run_many(self, alphas, t_end_s, n_outputs=400, *, progress=False):
        """Responses at several alphas, advanced together in one batched pass
        (:func:`ccedi.fea.solvers.batch.run_batch`; each the same as :meth:`run`), or run
        by run when the models cannot be batched (:func:`ccedi.fea.solvers.batch.batch_refusal`)
        or are fewer than :data:`ccedi.fea.solvers.batch.BATCH_MIN_RUNS` (one by one on every
        core is then faster).

        Parameters
        ----------
        alphas : sequence of float
            Mass-proportional damping coefficients [1/s].
        t_end_s : float
            Simulated time of every run [s].
        n_outputs : int, optional
            Output times of every run.
        progress : bool, optional
            Show a progress bar over the batch's output times.

        Returns
        -------
        list of ccedi.models.ImpulseResponse

        Raises
        ------
        InputError
            Invalid arguments.
        SolverError
            A run cannot continue.
        """
        checked = [validate_run_args(alpha, t_end_s, n_outputs) for alpha in alphas]
        models = [self.model_factory(alpha) for alpha, _, _ in checked]
        if len(models) < BATCH_MIN_RUNS or batch_refusal(models) is not None:
            return [self.run(alpha, t_end_s, n_outputs) for alpha in alphas]
        _, t_end_s, n_outputs = checked[0]
        results = run_batch(models, t_end_s, n_outputs=n_outputs, progress=progress)
        return [ImpulseResponse(history=res.history,
                                summary={"model": self.name, "alpha_per_s": alpha, **_deflection_checked(m, res).summary})
                for (alpha, _, _), m, res in zip(checked, models, results)]


def finger_impulse_model(length_in=4.5, *, force_N=1.0, duration_s=0.01, material=RUBBER, beta=0.0, mesh=None,
                         semi_axes_m=SEMI_AXES):
    """The paper's impulse test of the clamped SM-A finger as a :class:`FullImpulseModel`.

    Parameters
    ----------
    length_in : float, optional
        Finger length [in] (when ``mesh`` is None).
    force_N : float, optional
        Tip force [N] in the soft direction (+y).
    duration_s : float, optional
        How long the force is held [s].
    material : ccedi.fea.material.NeoHookean, optional
        Finger material.
    beta : float, optional
        Stiffness-proportional damping [s].
    mesh : ccedi.fea.mesh.Mesh, optional
        The finger mesh (default: SM-A of ``length_in`` with ``semi_axes_m``), built once.
    semi_axes_m : tuple, optional
        Section semi-axes [m].

    Returns
    -------
    FullImpulseModel

    Raises
    ------
    ccedi.errors.InputError
        A length, section, force or duration outside :data:`ccedi.quantities.QUANTITIES`
        (the ranges of the study TOML and the calibration sidecar).
    """
    force_N = QUANTITIES["force_N"].check(force_N, "force_N")
    duration_s = QUANTITIES["pulse_duration_s"].check(duration_s, "duration_s")
    mesh = sm_a(length_in=length_in, semi_axes_m=semi_axes_m) if mesh is None else mesh
    return FullImpulseModel(lambda alpha: impulse_model(alpha=alpha, force_N=force_N, duration_s=duration_s,
                                                        material=material, beta=beta, mesh=mesh),
                            force_N=force_N, duration_s=duration_s)


def _impulse_run(alpha, finger, t_end_s, n_outputs):
    """One run of :func:`impulse_study`: (history DataFrame with an alpha_per_s column, summary)."""
    return _impulse_rows(alpha, finger_impulse_model(**finger).run(float(alpha), t_end_s, n_outputs))


def _impulse_rows(alpha, res):
    """(history DataFrame of the response ``res`` with an alpha_per_s column, summary)."""
    h = res.history[["time_s", "tip_uy_m", "max_von_mises_Pa", "reaction_y_N"]].copy()
    h.insert(0, "alpha_per_s", float(alpha))
    return h, res.summary


def impulse_study(alphas=(70.0, 120.0, 160.0, 180.0, 200.0), *, scheduler="serial", t_end_s=0.2, n_outputs=400,
                  **finger):
    """Fig. 7 analogue: tip responses for several alpha [1/s] of
    :func:`finger_impulse_model`: on this machine (``serial`` or ``local`` scheduler) through
    :meth:`FullImpulseModel.run_many` (one batched pass on its free cores from four alphas
    on, fewer one by one), else one run per
    alpha mapped through :func:`ccedi.distributed.map_runs` (a cluster's address). Returns (history, summaries): a long
    DataFrame with columns alpha_per_s, time_s, tip_uy_m, max_von_mises_Pa, reaction_y_N and
    a list of run summaries.

    Parameters
    ----------
    alphas : sequence of float, optional
        Damping coefficients [1/s].
    scheduler : str, optional
        :func:`ccedi.distributed.map_runs` scheduler.
    t_end_s : float, optional
        Simulated time of each run [s].
    n_outputs : int, optional
        Output times of each run.
    **finger
        The impulse test, passed to :func:`finger_impulse_model` (``length_in``,
        ``force_N``, ``duration_s``, ``material``, ``beta``, ``mesh``, ``semi_axes_m``).

    Returns
    -------
    tuple
        (history DataFrame, list of summaries).
    """
    if scheduler in (SERIAL, LOCAL) and len(alphas) > 1:
        alphas = [float(a) for a in alphas]
        responses = finger_impulse_model(**finger).run_many(alphas, t_end_s, n_outputs, progress=True)
        runs = [_impulse_rows(alpha, res) for alpha, res in zip(alphas, responses)]
    else:
        runs = map_runs(partial(_impulse_run, finger=finger, t_end_s=t_end_s, n_outputs=n_outputs), alphas,
                        scheduler=scheduler, label="impulse runs")
    return pd.concat([h for h, _ in runs], ignore_index=True), [s for _, s in runs]
