"""Design of a compliant finger: damping and length that meet a designer's requirements.

What a design script needs (``examples/design_script.py``)::

    from ccedi.design import (Requirements, Limit, DesignProblem, Surrogate, design_space,
                              grid_points, run_rom, solve, pareto_front, fea_check)

* :mod:`ccedi.design.outputs`: what a run is judged on (:data:`OUTPUTS`, :func:`design_outputs`);
* :mod:`ccedi.design.requirements`: the designer's limits (:class:`Requirements`, :class:`Limit`);
* :mod:`ccedi.design.surrogate`: B-spline surrogate of the contact ROM over (alpha, L);
* :mod:`ccedi.design.optimise`: the problem, IPOPT, brute force, infeasibility, sensitivities;
* :mod:`ccedi.design.pareto`: the front of the objective against a second output;
* :mod:`ccedi.design.fea_check`: the full FEA re-check;
* :mod:`ccedi.design.rubber`: the paper's rubber, alpha over length.

User-defined outputs plug into :func:`run_rom` (``extra_outputs``) and get limits as
:class:`Limit` objects in ``Requirements(extra=...)``.
"""
from .fea_check import fea_check
from .optimise import (
    OBJECTIVES,
    Design,
    DesignProblem,
    ModelError,
    binding,
    brute_force,
    closest_design,
    on_bounds,
    sensitivities,
    solve,
)
from .outputs import OUTPUTS, design_outputs
from .pareto import pareto_front, recommended
from .requirements import Limit, Requirements, met
from .surrogate import Surrogate, design_space, grid_points, run_rom

__all__ = ["OBJECTIVES", "OUTPUTS", "Design", "DesignProblem", "Limit", "ModelError", "Requirements", "Surrogate",
           "binding", "brute_force", "closest_design", "design_outputs", "design_space", "fea_check", "grid_points",
           "met", "on_bounds", "pareto_front", "recommended", "run_rom", "sensitivities", "solve"]
