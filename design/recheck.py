"""Re-check of designs with a full model run (by default the explicit FEA,
:class:`ccedi.fea.contact.drum.FullContactModel`): the same design outputs
(:func:`ccedi.design.outputs.design_outputs`) from the full model beside the surrogate's,
output by output, with the error of the surrogate (:func:`ccedi.design.model_error.output_error`:
(surrogate - full) / |full|, lengths at the 5 mm scale of their requirements) and whether
the full model meets each requirement.

Any finger: a set-up whose finger is a given mesh (``DrumSetup(finger=mesh)``, hexahedra or
tetrahedra) is re-checked with that mesh on the drum, at its own length and the design's
drum speed; a design of another length is refused in one line
(:func:`ccedi.design.outputs.setup_for_length`).

The surrogate corrected by the full FEA (:func:`fea_correction`): the ROM and the full FEA
run at a small tensor grid of the design variables, bounds included, and their ratio
(:class:`ccedi.design.model_error.FeaCorrection`) multiplies the ROM's grid runs before the
surrogate is fitted."""
import time
from dataclasses import replace
from functools import partial

from ccedi.distributed import map_runs
from ccedi.errors import InputError, RequirementsUnmet, SolverError
from ccedi.fea.contact.drum import DrumSetup, FullContactModel, ObjectStress

from .model_error import FeaCorrection, output_error
from .optimise import solve
from .outputs import OUTPUTS, design_outputs, output_count, run_time_s, setup_at
from .requirements import Requirements, met
from .surrogate import cached_rom_runs, design_space, grid_points, rom_factory, run_rom


def full_fea_factory(setup: DrumSetup):
    """The re-check's default contact model: the full FEA without the per-output object
    stress (the design outputs compute their own, :class:`ccedi.fea.contact.drum.ObjectStress`).

    Parameters
    ----------
    setup : DrumSetup
        The set-up at the design's finger length.

    Returns
    -------
    ccedi.fea.contact.drum.FullContactModel
    """
    return FullContactModel(setup, object_stress=False)


TRAINING_LEVELS = (2, 5)
"""Least and most training values per design variable of :func:`fea_correction`."""


def fea_correction(setup: DrumSetup, variables, *, levels=(3, 3), damping="relative", directory=None, progress=None,
                   model_factory=None):
    """The correction of the ROM by the full FEA over the design variables: both models run
    at the ``levels`` tensor grid of ``variables`` (their bounds included), the ratio fitted
    (:meth:`ccedi.design.model_error.FeaCorrection.fit`).

    Parameters
    ----------
    setup : DrumSetup
        The base set-up.
    variables : tuple of ccedi.design.surrogate.Variable
        The design variables.
    levels : tuple of int, optional
        Training values per variable, each in :data:`TRAINING_LEVELS`. Default (3, 3): nine
        full FE runs.
    damping : {"relative", "global"}, optional
        Damping kind of the runs.
    directory : pathlib.Path, optional
        Where the runs are cached (``rom_training.csv``, ``fea_training.csv``); None: not cached.
    progress : callable, optional
        ``progress(done, total)`` after every full FE run.
    model_factory : callable, optional
        The reference model (default :func:`full_fea_factory`).

    Returns
    -------
    correction : FeaCorrection
    fea_runs : pandas.DataFrame
        The reference model's training runs.
    cached : bool
        True when the reference runs were read from ``directory``.

    Raises
    ------
    InputError
        Levels outside :data:`TRAINING_LEVELS` or not one per variable.
    """
    lo, hi = TRAINING_LEVELS
    if len(levels) != len(variables) or not all(isinstance(n, int) and lo <= n <= hi for n in levels):
        raise InputError(f"FEA correction training levels {tuple(levels)!r}: one integer in [{lo}, {hi}] per design "
                         f"variable ({len(variables)})")
    reference = model_factory or full_fea_factory
    points = grid_points(tuple(variables), tuple(levels))
    if directory is None:
        rom = run_rom(setup, points, damping=damping, variables=variables)
        fea, cached = run_rom(setup, points, damping=damping, variables=variables, model_factory=reference,
                              progress=progress), False
    else:
        rom, _ = cached_rom_runs(setup, points, directory / "rom_training.csv", damping=damping, variables=variables)
        fea, cached = cached_rom_runs(setup, points, directory / "fea_training.csv", damping=damping,
                                      variables=variables, model_factory=reference, progress=progress)
    return FeaCorrection.fit(variables, rom, fea), fea, cached


def model_run(d, setup, *, damping, model_factory, extra_outputs=None, variables=None, stress=None, progress=False):
    """Run ``model_factory`` at design ``d`` until the next object arrives and take its
    design outputs.

    Parameters
    ----------
    d : ccedi.design.optimise.Design
        The design (alpha and the second variable).
    setup : DrumSetup
        The base set-up.
    damping : {"relative", "global"}
        Damping kind of the run.
    model_factory : callable
        ``model_factory(setup) -> ccedi.models.ContactModel``.
    extra_outputs : dict, optional
        User-defined outputs (:func:`ccedi.design.outputs.design_outputs`).
    variables : tuple of ccedi.design.surrogate.Variable, optional
        The design's variables (default :func:`ccedi.design.surrogate.design_space`).
    stress : ObjectStress, optional
        The object's static solver (built here when not given).
    progress : bool, optional
        Show the model's progress bar (the full FEA's; the ROM shows none).

    Returns
    -------
    dict
        ``outputs`` (:func:`ccedi.design.outputs.design_outputs`), ``warnings`` (the
        model's validity warnings), ``wall_time_s`` [s].
    """
    variables = tuple(variables or design_space())
    s = setup_at(setup, [v.name for v in variables], (d.alpha_per_s, d.x))
    t_end = run_time_s(s)
    res = model_factory(s).run(d.alpha_per_s, damping=damping, t_end_s=t_end, n_outputs=output_count(t_end),
                               progress=progress)
    return {"outputs": design_outputs(s, res.history, stress or ObjectStress(setup), extra=extra_outputs),
            "warnings": list(res.summary["warnings"]), "wall_time_s": res.summary["wall_time_s"]}


def _check_one(d, setup, damping, limits, model_factory, extra_outputs, variables, done):
    """The full-model row of :func:`fea_check` for design ``d``: a run of ``done`` at the
    same design, else a new one (the object stress solver is built in the worker: its
    factorisation cannot be sent to it). A run the solver stops (an element inverted, an
    unstable step) gives a row with ``failed``, its outputs None and every requirement
    unmet, so that the other designs' rows and the result are kept."""
    keys = [k for k in (*OUTPUTS, *(extra_outputs or {})) if k in d.outputs]
    row = {"alpha_per_s": d.alpha_per_s, variables[1].key: float(variables[1].shown(d.x)), "damping": damping,
           "surrogate": {k: d.outputs[k] for k in keys}, "failed": None}
    t0 = time.perf_counter()
    try:
        run = next((r for r in done if r["alpha_per_s"] == d.alpha_per_s and r["x"] == d.x), None) or model_run(
            d, setup, damping=damping, model_factory=model_factory, extra_outputs=extra_outputs, variables=variables)
    except SolverError as err:
        return {**row, "failed": str(err), "fea": dict.fromkeys(keys), "relative_error": dict.fromkeys(keys),
                "requirements": {lim.describe(): {"value": None, "margin": None, "met": False} for lim in limits},
                "meets_requirements": False, "warnings": [str(err)], "wall_time_s": time.perf_counter() - t0}
    full = run["outputs"]
    return {**row, "fea": full,
            "relative_error": {k: output_error(k, d.outputs[k], full[k]) for k in keys},
            "requirements": {name: {"value": v, "margin": m, "met": ok} for name, (v, m, ok) in met(limits, full).items()},
            "meets_requirements": all(ok for _, _, ok in met(limits, full).values()),
            "warnings": run["warnings"], "wall_time_s": run["wall_time_s"]}


def fea_check(setup: DrumSetup, designs, *, damping="relative", limits=(), model_factory=full_fea_factory,
              progress=print, scheduler="serial", extra_outputs=None, variables=None, done=()):
    """Re-run designs with a (full) contact model and compare with the surrogate.

    For each design: run ``model_factory(setup at its length)`` at its alpha until the
    next object arrives (:func:`ccedi.design.outputs.run_time_s`); the designs are mapped
    through :func:`ccedi.distributed.map_runs` (``scheduler``). A finger mesh
    (``setup.finger``) is re-checked as it is, at its own length.

    Parameters
    ----------
    setup : DrumSetup
        The base set-up.
    designs : list of ccedi.design.optimise.Design
        Designs with the surrogate's ``outputs``.
    damping : {"relative", "global"}, optional
        Damping kind of the runs (the surrogate's).
    limits : sequence of ccedi.design.requirements.Limit, optional
        Requirements checked on the full model's outputs (with their own bounds, no
        model-error margin).
    model_factory : callable, optional
        ``model_factory(setup) -> ccedi.models.ContactModel`` (default
        :func:`full_fea_factory`; any contact model works, e.g. the ROM).
    progress : callable or None, optional
        Called with one line per design.
    scheduler : str, optional
        :func:`ccedi.distributed.map_runs` scheduler.
    extra_outputs : dict, optional
        User-defined outputs (:func:`ccedi.design.outputs.design_outputs`); module-level
        functions when the scheduler is not serial.
    variables : tuple of ccedi.design.surrogate.Variable, optional
        The designs' variables (default: alpha and the finger length,
        :func:`ccedi.design.surrogate.design_space`).
    done : sequence of dict, optional
        Runs of the same model already made (:func:`model_run` results with the design's
        ``alpha_per_s`` and ``x``, as :func:`verified_optimum` keeps them in its steps'
        ``run``): a design among them is not run again.

    Returns
    -------
    list of dict
        ``alpha_per_s`` [1/s], the second variable (``length_in`` [in] or
        ``drum_speed_rpm`` [rpm]), ``damping``, ``surrogate`` and ``fea``
        (the full model's outputs), ``relative_error`` of the surrogate per output
        (:func:`ccedi.design.model_error.output_error`), ``requirements`` ({requirement: value, margin, met} on the full model),
        ``meets_requirements``, ``warnings``, ``wall_time_s`` [s], ``failed`` (None, or the
        solver's message when it stopped the run: the outputs are then None).

    Raises
    ------
    InputError
        A design's length is not that of a finger mesh.
    """
    variables = tuple(variables or design_space())
    for d in designs:                       # every length before the first run (a finger mesh has one)
        setup_at(setup, [v.name for v in variables], (d.alpha_per_s, d.x))
    check = partial(_check_one, setup=setup, damping=damping, limits=tuple(limits), model_factory=model_factory,
                    extra_outputs=extra_outputs, variables=variables, done=tuple(done))
    rows = map_runs(check, designs, scheduler=scheduler, label="FEA re-check")
    for r in rows if progress else ():
        missed = [name for name, q in r["requirements"].items() if not q["met"]]
        head = (f"FEA check alpha = {r['alpha_per_s']:.4g} 1/s, {variables[1].label} = "
                f"{r[variables[1].key]:.4g} {variables[1].unit} ({r['wall_time_s']:.0f} s): ")
        progress(head + (f"the FE run failed: {r['failed']}" if r["failed"] else (
            "meets every requirement" if not missed else "misses " + "; ".join(missed)) + "; surrogate error "
            + ", ".join(f"{k} {v:+.1%}" for k, v in r["relative_error"].items() if v is not None)))
    return rows


def verified_optimum(problem, setup: DrumSetup, *, damping="relative", model_factory=None, iterations=4,
                     n_starts=8, extra_outputs=None, start=None):
    """The optimum re-solved until the surrogate's own model, run at it, meets every
    requirement: where the model misses a requirement at the optimum, the requirement's
    bound is shifted by the surrogate's error there, b' = b + (s - m) (s the surrogate's
    value, m the model's), and the problem solved again; at most ``iterations`` times. The
    surrogate interpolates between grid runs and a requirement that binds lands where it
    errs: this puts the binding requirement where the model itself meets it.

    Parameters
    ----------
    problem : ccedi.design.optimise.DesignProblem
        The problem on the surrogate.
    setup : DrumSetup
        The base set-up the surrogate was built on.
    damping : {"relative", "global"}, optional
        Damping kind of the surrogate's runs.
    model_factory : callable, optional
        The surrogate's model, ``model_factory(setup) -> ContactModel`` (default: the
        design ROM, :func:`ccedi.design.surrogate.rom_factory`).
    iterations : int, optional
        Re-solves at most.
    n_starts : int, optional
        IPOPT starts per solve.
    extra_outputs : dict, optional
        The user-defined outputs of the surrogate (:func:`ccedi.design.surrogate.run_rom`).
    start : ccedi.design.optimise.Design, optional
        The optimum of ``problem`` when already solved (else it is solved here).

    Returns
    -------
    design : ccedi.design.optimise.Design
        The last optimum (its ``outputs`` the surrogate's).
    problem : ccedi.design.optimise.DesignProblem
        The problem with the offsets (its requirements read as stated).
    steps : list of dict
        Per solve: alpha [1/s], the second variable in its shown unit, the model's
        outputs, the requirements it missed, and ``run`` (the :func:`model_run`, for
        :func:`fea_check`'s ``done``). A run the model's solver stops ends the
        verification: its step has ``model`` None and ``failed`` (the solver's message),
        and the design returned is the one it was run at, not verified.

    Raises
    ------
    ccedi.errors.RequirementsUnmet
        No design meets the (shifted) requirements; when shifted, its ``problem`` and
        ``steps`` attributes are the shifted problem and the runs that led to it.
    """
    factory = model_factory or rom_factory
    stress = ObjectStress(setup)
    variables = problem.surrogate.variables
    steps = []
    design = start if start is not None else solve(problem, n_starts=n_starts)[0]
    for _ in range(iterations):
        try:
            run = model_run(design, setup, damping=damping, model_factory=factory, extra_outputs=extra_outputs,
                            variables=variables, stress=stress, progress=True)
        except SolverError as err:
            steps.append({"alpha_per_s": design.alpha_per_s, variables[1].key: float(variables[1].shown(design.x)),
                          "model": None, "missed": [], "failed": str(err)})
            break
        model = run["outputs"]
        missed = [lim for lim in problem.limits if model.get(lim.output) is None
                  or lim.margin(model[lim.output], problem.bound(lim, design.alpha_per_s, design.x)) < 0.0]
        steps.append({"alpha_per_s": design.alpha_per_s, variables[1].key: float(variables[1].shown(design.x)),
                      "model": {k: model[k] for k in (*OUTPUTS, *(extra_outputs or {}))},
                      "missed": [lim.describe() for lim in missed],
                      "run": {"alpha_per_s": design.alpha_per_s, "x": design.x, **run}})
        if not missed:
            break
        shifted = [replace(lim, offset=lim.offset + design.outputs[lim.output] - model[lim.output])
                   if lim in missed and model.get(lim.output) is not None else lim for lim in problem.limits]
        problem = replace(problem, requirements=Requirements.from_limits(shifted))
        try:
            design, _ = solve(problem, n_starts=n_starts)
        except RequirementsUnmet as err:
            err.problem, err.steps = problem, steps
            raise
    return design, problem, steps
