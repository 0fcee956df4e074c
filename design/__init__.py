"""Design of a compliant finger: damping and length (or drum speed) that meet a designer's
requirements.

What a design script needs (``examples/design_script.py``)::

    from ccedi.design import (Requirements, Limit, DesignProblem, Surrogate, design_space,
                              grid_points, run_rom, solve, pareto_front, fea_check)

* :mod:`ccedi.design.outputs`: what a run is judged on (:data:`OUTPUTS`, :func:`design_outputs`);
* :mod:`ccedi.design.requirements`: the designer's limits (:class:`Requirements`, :class:`Limit`);
* :mod:`ccedi.design.surrogate`: B-spline surrogate of the contact ROM over (alpha, L)
  (:func:`design_space`), (alpha, drum speed) (:func:`speed_space`), (alpha, a section
  semi-axis) (:func:`section_space`), (alpha, taper ratio) (:func:`taper_space`) or
  (alpha, L, E) (:func:`material_space`);
* :mod:`ccedi.design.optimise`: the problem, IPOPT, brute force, infeasibility, sensitivities;
* :mod:`ccedi.design.pareto`: the front of the objective against a second output;
* :mod:`ccedi.design.recheck`: the full FEA re-check (:func:`fea_check`) and the optimum
  verified by a model run (:func:`verified_optimum`);
* :mod:`ccedi.design.model_error`: the model against the full FEA: margins where it errs,
  or the surrogate corrected by full-FEA runs at training designs (:class:`FeaCorrection`);
* :mod:`ccedi.design.rubber`: the paper's rubber, alpha over length.
* :mod:`ccedi.design.compounds`: the compound catalogue (:func:`load_compounds`) and a
  loss factor as alpha at a finger's first mode (:func:`alpha_from_loss_factor`,
  :func:`finger_damping`).
* :mod:`ccedi.design.catalogue_design`: the compound as a design variable: every compound
  of a catalogue designed over the length on one surrogate over (alpha, L, E)
  (:func:`catalogue_surrogate`), ranked (:func:`design_compounds`).
* :mod:`ccedi.design.robust`: a compound's robust design over its batch spread of E and
  tan delta or a calibration's E-alpha covariance (:class:`Spread`,
  :class:`CalibratedSpread`, :func:`robust_design`, :func:`violation_probabilities`), and the
  catalogue ranked by robust designs (:func:`robust_catalogue`).
* :mod:`ccedi.design.drum_speed`: the fastest drum a chosen finger allows
  (:func:`fastest_drum_speed`), and every feasible compound's in a ranking
  (:func:`with_drum_speeds`).

User-defined outputs plug into :func:`run_rom` (``extra_outputs``) and get limits as
:class:`Limit` objects in ``Requirements(extra=...)``.
"""
import importlib

_EXPORTS = {
    "fea_check": "recheck", "verified_optimum": "recheck",
    "OBJECTIVES": "optimise", "Design": "optimise", "DesignProblem": "optimise", "ModelError": "optimise",
    "binding": "optimise", "brute_force": "optimise", "closest_design": "optimise", "on_bounds": "optimise",
    "sensitivities": "optimise", "solve": "optimise",
    "OUTPUTS": "outputs", "design_outputs": "outputs", "setup_at": "outputs",
    "pareto_front": "pareto", "recommended": "pareto",
    "Limit": "requirements", "Requirements": "requirements", "met": "requirements",
    "Surrogate": "surrogate", "design_space": "surrogate", "grid_points": "surrogate", "run_rom": "surrogate",
    "speed_space": "surrogate", "material_space": "surrogate", "section_space": "surrogate",
    "taper_space": "surrogate",
    "CompoundSurrogate": "catalogue_design", "CompoundTie": "catalogue_design", "FirstMode": "catalogue_design",
    "catalogue_space": "catalogue_design", "catalogue_surrogate": "catalogue_design",
    "design_compounds": "catalogue_design", "Spread": "robust", "RobustDesign": "robust",
    "robust_design": "robust", "violation_probabilities": "robust", "CalibratedSpread": "robust",
    "robust_catalogue": "robust", "RobustCatalogue": "robust", "spread_check": "robust",
    "fastest_drum_speed": "drum_speed", "DrumSpeedCheck": "drum_speed", "with_drum_speeds": "drum_speed",
    "Compound": "compounds", "alpha_from_loss_factor": "compounds", "finger_damping": "compounds",
    "load_compounds": "compounds", "loss_factor_from_alpha": "compounds", "FeaCorrection": "model_error",
}
"""Name -> the module of :mod:`ccedi.design` that defines it. Loaded on first use (PEP 562):
importing a ccedi package imports no third-party library, so that ``import ccedi.design``
stays light and a wheel's imports can be checked without its dependencies."""

__all__ = sorted(_EXPORTS)


def __getattr__(name):
    if name not in _EXPORTS:
        raise AttributeError(f"module 'ccedi.design' has no attribute {name!r}")
    return getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
