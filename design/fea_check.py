"""Re-check of recommended designs with a full model run (by default the explicit FEA,
:class:`ccedi.fea.drum.FullContactModel`): the same design outputs
(:func:`ccedi.design.objectives.design_outputs`) from the full model beside the surrogate's,
with relative errors (surrogate - full) / full.

Any finger: a set-up whose finger is a given mesh (``DrumSetup(finger=mesh)``, hexahedra or
tetrahedra) is re-checked with that mesh on the drum, at its own length; a design of
another length is refused in one line (:func:`ccedi.design.objectives.setup_for_length`)."""
import time

from ccedi.fea.drum import DrumSetup, FullContactModel, ObjectStress
from ccedi.fea.units import m_to_inch

from .objectives import OUTPUT_STEP_S, design_outputs, run_time_s, setup_for_length

BREAKAWAY_MARGIN_S = 0.05
"""Extra simulated time beyond the surrogate's predicted breakaway [s], in case the full
model lets go later."""


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


def _check_one(d, setup, objective_outputs, model_factory):
    """The full-model row of :func:`fea_check` for design ``d`` (the object stress solver,
    0.2 s to build, is built here: its factorisation cannot be sent to a worker)."""
    stress = ObjectStress(setup)
    s = setup_for_length(setup, d.length_m)
    end = d.outputs["contact_start_s"] + d.outputs["contact_duration_s"] + BREAKAWAY_MARGIN_S
    t_end = run_time_s(end)
    t0 = time.perf_counter()
    res = model_factory(s).run(d.alpha_per_s, t_end_s=t_end, n_outputs=int(round(t_end / OUTPUT_STEP_S)))
    full = design_outputs(s, res.history, stress)
    wall = time.perf_counter() - t0
    keys = tuple(objective_outputs) + ("contact_start_s", "max_finger_stress_Pa")
    rel = {k: (None if full[k] in (None, 0.0) else (d.outputs[k] - full[k]) / abs(full[k])) for k in keys}
    return {"alpha_per_s": d.alpha_per_s, "length_in": m_to_inch(d.length_m),
            "surrogate": {k: d.outputs[k] for k in keys}, "fea": {k: full[k] for k in keys},
            "relative_error": rel, "wall_time_s": wall}


def fea_check(setup: DrumSetup, designs, objective_outputs, model_factory=full_fea_factory, progress=print,
              scheduler="serial"):
    """Re-run recommended designs with a (full) contact model and compare with the surrogate.

    For each design: run ``model_factory(setup at its length)`` at its alpha up to the
    predicted breakaway + margin + 0.5 s; the designs are mapped through
    :func:`ccedi.fea.distributed.map_runs` (``scheduler``). A finger mesh
    (``setup.finger``) is re-checked as it is, at its own length.

    Parameters
    ----------
    setup : DrumSetup
        The base set-up.
    designs : list of ccedi.design.optimise.Design
        Designs with the surrogate's ``outputs``.
    objective_outputs : sequence of str
        Outputs compared (plus contact_start_s and max_finger_stress_Pa).
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
        ``alpha_per_s`` [1/s], ``length_in`` [in], ``surrogate``, ``fea`` (the model's
        outputs), ``relative_error`` (surrogate - full) / full per output, ``wall_time_s`` [s].

    Raises
    ------
    InputError
        A design's length is not that of a finger mesh.
    """
    from functools import partial

    from ccedi.fea.distributed import map_runs

    for d in designs:                       # every length before the first run (a finger mesh has one)
        setup_for_length(setup, d.length_m)
    check = partial(_check_one, setup=setup, objective_outputs=tuple(objective_outputs),
                    model_factory=model_factory)
    rows = map_runs(check, designs, scheduler, label="FEA re-check")
    for r in rows if progress else ():
        progress(f"FEA check alpha = {r['alpha_per_s']:.4g} 1/s, L = {r['length_in']:.3g} in "
                 f"({r['wall_time_s']:.0f} s): "
                 + ", ".join(f"{k} {v:+.1%}" for k, v in r["relative_error"].items() if v is not None))
    return rows
