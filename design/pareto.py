"""Trade-off between the contact objectives and the residual oscillation
(epsilon-constraint on the surrogate).

With f_c = sum_{i in {stress, duration}} w_i f~_i / (w_s + w_d) (normalised as in
:mod:`ccedi.design.optimise`; equal weights when both are zero) and f_o the residual
oscillation [m/s], the k-th front point solves

    min f_c  subject to  f_o <= eps_k  (and the problem's constraints),

for eps_k evenly spaced between the oscillation of the min-f_o design and that of the
min-f_c design. Every point is Pareto-optimal in (f_c, f_o), and the weighted optimum
of the full problem lies on the same front (it minimises a positive combination of
f_c and f~_o).
"""
from dataclasses import replace

import numpy as np

from ccedi.fea.units import m_to_inch

from .optimise import DesignProblem, solve

OSC = "residual_oscillation_m_s"


def pareto_front(problem: DesignProblem, n_points=24, n_starts=4):
    """``n_points`` designs along the (f_c, f_o) front, non-dominated and de-duplicated
    (as :class:`ccedi.design.optimise.Design`), sorted by f_o.

    Parameters
    ----------
    problem : DesignProblem
    n_points : int, optional
        Weightings along the front.
    n_starts : int, optional
        IPOPT starts per weighting.

    Returns
    -------
    list of Design
    """
    w_s, w_d, _ = problem.weights
    contact = replace(problem, weights=(w_s, w_d, 0.0) if w_s + w_d > 0 else (1.0, 1.0, 0.0))
    quiet = replace(problem, weights=(0.0, 0.0, 1.0))
    best_c, _ = solve(contact, n_starts=n_starts)
    best_o, _ = solve(quiet, n_starts=n_starts)
    lo, hi = best_o.outputs[OSC], best_c.outputs[OSC]
    designs = [best_o, best_c]
    for eps in np.linspace(lo, hi, n_points)[1:-1]:
        def cap(out, eps=eps):
            return [(eps - out[OSC]) / max(hi - lo, 1e-12)]
        d, _ = solve(contact, n_starts=n_starts, extra=cap)
        designs.append(d)
    return _non_dominated(contact, designs)


def _non_dominated(contact, designs):
    """Designs not dominated in (f_c, f_o), duplicates (same f_c and f_o to 1e-9) removed."""
    pts = np.array([[contact.J(d.outputs), d.outputs[OSC]] for d in designs])
    keep = []
    for i, p in enumerate(pts):
        dominated = np.any(np.all(pts <= p + 1e-9, axis=1) & np.any(pts < p - 1e-9, axis=1))
        duplicate = any(np.allclose(p, pts[j], rtol=0, atol=1e-9) for j in keep)
        if not dominated and not duplicate:
            keep.append(i)
    return sorted((designs[i] for i in keep), key=lambda d: d.outputs[OSC])


def recommended(front, optimum):
    """Three designs to re-check with full FEA: the weighted optimum and the front points
    nearest to 1/4 and 3/4 of the front's oscillation range (other than the optimum).

    Parameters
    ----------
    front : list of Design
    optimum : Design

    Returns
    -------
    list of Design
    """
    osc = np.array([d.outputs[OSC] for d in front])
    picks = [optimum]
    for frac in (0.25, 0.75):
        target = osc.min() + frac * np.ptp(osc)
        for k in np.argsort(np.abs(osc - target)):
            d = front[k]
            if all(abs(d.alpha_per_s - p.alpha_per_s) > 1e-6 * p.alpha_per_s or abs(d.length_m - p.length_m) > 1e-9
                   for p in picks):
                picks.append(d)
                break
    return picks


def plot_front(problem: DesignProblem, front, optimum, checked=()):
    """Left: the front, stress objective against residual oscillation [m/s], coloured by
    contact duration [s]; right: the same designs in (alpha [1/s], L [in]). The chosen
    design is starred, the FEA-checked ones ringed.

    Parameters
    ----------
    problem : DesignProblem
    front : list of Design
    optimum : Design
    checked : sequence of Design, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s_key, d_key, o_key = problem.objective_outputs
    label = {"peak_reaction_force_N": "peak reaction force (25 ms average) [N]",
             "max_object_stress_Pa": "peak object von Mises stress [Pa]"}[s_key]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.5))
    x = [d.outputs[o_key] for d in front]
    y = [d.outputs[s_key] for d in front]
    c = [d.outputs[d_key] for d in front]
    sc = a1.scatter(x, y, c=c, cmap="viridis", s=30)
    fig.colorbar(sc, ax=a1, label="contact duration [s]")
    a2.scatter([d.alpha_per_s for d in front], [m_to_inch(d.length_m) for d in front], c=c, cmap="viridis", s=30)
    for d in checked:
        a1.plot(d.outputs[o_key], d.outputs[s_key], "o", mfc="none", mec="k", ms=11)
        a2.plot(d.alpha_per_s, m_to_inch(d.length_m), "o", mfc="none", mec="k", ms=11)
    a1.plot(optimum.outputs[o_key], optimum.outputs[s_key], "r*", ms=16, label="chosen design")
    a2.plot(optimum.alpha_per_s, m_to_inch(optimum.length_m), "r*", ms=16, label="chosen design")
    a1.set_xlabel("residual oscillation, RMS tip velocity 0.5 s after breakaway [m/s]")
    a1.set_ylabel(label)
    a1.legend(fontsize=8)
    a2.set_xscale("log")
    va, vl = problem.surrogate.variables
    a2.set_xlim(va.lo, va.hi)
    a2.set_ylim(m_to_inch(vl.lo), m_to_inch(vl.hi))
    a2.set_xlabel("mass-proportional damping alpha [1/s]")
    a2.set_ylabel("finger length L [in]")
    a2.set_title("Pareto designs (rings: re-checked with full FEA)", fontsize=9)
    fig.tight_layout()
    return fig
