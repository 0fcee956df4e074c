"""Trade-off between the objective and a second output (epsilon-constraint on the
surrogate): what the designer pays in one for less of the other.

With f the problem's objective and h the second output (default the ringing amplitude
after breakaway, the paper's "suppression of oscillatory responses"), the problem without
the requirements on h gives the two ends: the design of least f (h_f there) and the
design of least h (h_min). The k-th front point solves

    min f  subject to  h <= eps_k  (and every other requirement),

for eps_k evenly spaced between h_min and h_f (the least-h design itself is rarely unique,
e.g. every over-damped finger rings 0 mm, so eps = h_min is solved too and the dominated
ones dropped). Every point is Pareto-optimal in (f, h);
the designer's own limit on h is one vertical line across the front.
"""
from dataclasses import replace

import numpy as np

from ccedi.errors import RequirementsUnmet, SolverError

from .optimise import DesignProblem, solve

DEFAULT_SECOND = "ringing_amplitude_m"
"""The default second output of the front."""


def pareto_front(problem: DesignProblem, *, second=DEFAULT_SECOND, n_points=24, n_starts=4):
    """Designs along the (objective, ``second``) front, non-dominated and de-duplicated,
    sorted by ``second``.

    Parameters
    ----------
    problem : DesignProblem
    second : str, optional
        The second output (a surrogate output).
    n_points : int, optional
        Epsilon levels along the front.
    n_starts : int, optional
        IPOPT starts per level.

    Returns
    -------
    list of ccedi.design.optimise.Design
        Empty when no design meets the other requirements.
    """
    free = problem.without(second)
    quiet = replace(free, objective="weighted", weights={second: 1.0})
    try:
        best_f, _ = solve(free, n_starts=n_starts)
        best_h, _ = solve(quiet, n_starts=n_starts)
    except (RequirementsUnmet, SolverError):
        return []
    lo, hi = best_h.outputs[second], best_f.outputs[second]
    designs = [best_h, best_f]
    for eps in np.linspace(lo, hi, n_points)[:-1]:      # from lo: the least-h design is rarely unique
        def cap(out, eps=eps):
            return [(eps - out[second]) / max(hi - lo, 1e-12)]
        try:
            designs.append(solve(free, n_starts=n_starts, extra=cap)[0])
        except SolverError:
            continue
    return non_dominated(free, designs, second)


def non_dominated(problem, designs, second):
    """Designs not dominated in (J, ``second``), duplicates (both to 1e-9) removed,
    sorted by ``second``.

    Parameters
    ----------
    problem : DesignProblem
    designs : list of ccedi.design.optimise.Design
    second : str

    Returns
    -------
    list of ccedi.design.optimise.Design
    """
    pts = np.array([[problem.J(d.outputs), d.outputs[second]] for d in designs])
    keep = []
    for i, p in enumerate(pts):
        dominated = np.any(np.all(pts <= p + 1e-9, axis=1) & np.any(pts < p - 1e-9, axis=1))
        duplicate = any(np.allclose(p, pts[j], rtol=0, atol=1e-9) for j in keep)
        if not dominated and not duplicate:
            keep.append(i)
    return sorted((designs[i] for i in keep), key=lambda d: d.outputs[second])


def recommended(front, optimum, second=DEFAULT_SECOND):
    """Three designs to re-check with full FEA: the optimum and the front points nearest
    to 1/4 and 3/4 of the front's range of ``second`` (other than the optimum).

    Parameters
    ----------
    front : list of Design
    optimum : Design
    second : str, optional

    Returns
    -------
    list of Design
    """
    picks = [optimum]
    if not front:
        return picks
    h = np.array([d.outputs[second] for d in front])
    for frac in (0.25, 0.75):
        target = h.min() + frac * np.ptp(h)
        for k in np.argsort(np.abs(h - target)):
            d = front[k]
            if all(abs(d.alpha_per_s - p.alpha_per_s) > 1e-3 * p.alpha_per_s or abs(d.x - p.x) > 1e-4 * abs(p.x)
                   for p in picks):
                picks.append(d)
                break
    return picks
