"""Re-check of designs with a full model run (by default the explicit FEA,
:class:`ccedi.fea.drum.FullContactModel`): the same design outputs
(:func:`ccedi.design.outputs.design_outputs`) from the full model beside the surrogate's,
output by output, with the error (surrogate - full) / |full| and whether the full model
meets each requirement.

Any finger: a set-up whose finger is a given mesh (``DrumSetup(finger=mesh)``, hexahedra or
tetrahedra) is re-checked with that mesh on the drum, at its own length; a design of
another length is refused in one line (:func:`ccedi.design.outputs.setup_for_length`)."""
from functools import partial

from ccedi.fea.distributed import map_runs
from ccedi.fea.drum import DrumSetup, FullContactModel, ObjectStress
from ccedi.fea.units import m_to_inch

from .outputs import OUTPUTS, design_outputs, output_count, run_time_s, setup_for_length
from .requirements import met


def full_fea_factory(setup: DrumSetup):
    """The re-check's default contact model: the full FEA without the per-output object
    stress (the design outputs compute their own, :class:`ccedi.fea.drum.ObjectStress`).

    Parameters
    ----------
    setup : DrumSetup
        The set-up at the design's finger length.

    Returns
    -------
    ccedi.fea.drum.FullContactModel
    """
    return FullContactModel(setup, object_stress=False)


def relative_error(model, full):
    """(model - full) / |full|, None where either is undefined or full is zero.

    Parameters
    ----------
    model, full : float or None

    Returns
    -------
    float or None
    """
    if model is None or full is None or full == 0.0:
        return None
    return (model - full) / abs(full)


def _check_one(d, setup, damping, limits, model_factory):
    """The full-model row of :func:`fea_check` for design ``d`` (the object stress solver
    is built here: its factorisation cannot be sent to a worker)."""
    stress = ObjectStress(setup)
    s = setup_for_length(setup, d.length_m)
    t_end = run_time_s(s)
    res = model_factory(s).run(d.alpha_per_s, damping=damping, t_end_s=t_end, n_outputs=output_count(t_end))
    full = design_outputs(s, res.history, stress)
    keys = [k for k in OUTPUTS if k in d.outputs]
    return {"alpha_per_s": d.alpha_per_s, "length_in": m_to_inch(d.length_m), "damping": damping,
            "surrogate": {k: d.outputs[k] for k in keys}, "fea": full,
            "relative_error": {k: relative_error(d.outputs[k], full[k]) for k in keys},
            "requirements": {name: {"value": v, "margin": m, "met": ok} for name, (v, m, ok) in met(limits, full).items()},
            "meets_requirements": all(ok for _, _, ok in met(limits, full).values()),
            "warnings": list(res.summary["warnings"]), "wall_time_s": res.summary["wall_time_s"]}


def fea_check(setup: DrumSetup, designs, *, damping="relative", limits=(), model_factory=full_fea_factory,
              progress=print, scheduler="serial"):
    """Re-run designs with a (full) contact model and compare with the surrogate.

    For each design: run ``model_factory(setup at its length)`` at its alpha until the
    next object arrives (:func:`ccedi.design.outputs.run_time_s`); the designs are mapped
    through :func:`ccedi.fea.distributed.map_runs` (``scheduler``). A finger mesh
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
        :func:`ccedi.fea.distributed.map_runs` scheduler.

    Returns
    -------
    list of dict
        ``alpha_per_s`` [1/s], ``length_in`` [in], ``damping``, ``surrogate`` and ``fea``
        (the full model's outputs), ``relative_error`` (surrogate - full) / |full| per
        output, ``requirements`` ({requirement: value, margin, met} on the full model),
        ``meets_requirements``, ``warnings``, ``wall_time_s`` [s].

    Raises
    ------
    InputError
        A design's length is not that of a finger mesh.
    """
    for d in designs:                       # every length before the first run (a finger mesh has one)
        setup_for_length(setup, d.length_m)
    check = partial(_check_one, setup=setup, damping=damping, limits=tuple(limits), model_factory=model_factory)
    rows = map_runs(check, designs, scheduler, label="FEA re-check")
    for r in rows if progress else ():
        missed = [name for name, q in r["requirements"].items() if not q["met"]]
        progress(f"FEA check alpha = {r['alpha_per_s']:.4g} 1/s, L = {r['length_in']:.3g} in "
                 f"({r['wall_time_s']:.0f} s): " + ("meets every requirement" if not missed
                                                    else "misses " + "; ".join(missed)) + "; surrogate error "
                 + ", ".join(f"{k} {v:+.1%}" for k, v in r["relative_error"].items() if v is not None))
    return rows
