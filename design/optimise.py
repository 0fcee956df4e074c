"""The design problem on the surrogate, solved with casadi/IPOPT (multi-start) and by
brute force on a grid (the check of the former).

Design variables: alpha [1/s] and L [m] (:func:`ccedi.design.surrogate.design_space`), worked
in their unit coordinates u in [-1, 1]^2 (ln alpha and L scaled). Objectives (surrogate
values, SI units):

    f_s = peak reaction force on the object [N] (``stress_measure="reaction_force"``)
          or peak object von Mises stress [Pa] (``"object_stress"``),
    f_d = contact duration [s],
    f_o = residual oscillation, RMS tip velocity over 0.5 s after breakaway [m/s],

each normalised by its range over the brute-force grid of the bounds,
f~_i = (f_i - min_grid f_i) / (max_grid f_i - min_grid f_i), and combined as

    J = sum_i w_i f~_i,   w = weights / sum(weights)   (dimensionless).

Constraints: contact duration >= ``min_contact_duration_s`` (the finger touches the
object), max finger von Mises stress <= ``allowable_finger_stress_Pa``, optionally
contact start in ``contact_start_bounds_s`` [s], and for "this rubber only" designs
alpha = alpha(L) (:func:`ccedi.design.objectives.alpha_of_length`), imposed as
ln alpha - ln alpha(L) = 0.
"""
import time
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from ccedi.errors import InputError, SolverError, require_finite_positive
from ccedi.fea.units import m_to_inch

from .objectives import alpha_of_length
from .surrogate import Surrogate

STRESS_MEASURES = {"reaction_force": "peak_reaction_force_N", "object_stress": "max_object_stress_Pa"}
"""Selectable stress objective -> surrogate output."""

OBJECTIVE_KEYS = ("stress", "duration", "oscillation")
"""Order of the weights."""

_OK = ("Solve_Succeeded", "Solved_To_Acceptable_Level")


def normalised_weights(weights):
    """The design weights normalised to sum 1 (check them before building anything).

    Parameters
    ----------
    weights : sequence of float
        w_stress, w_duration, w_oscillation: finite, >= 0, not all zero.

    Returns
    -------
    tuple of float
        ``weights / sum(weights)``.

    Raises
    ------
    InputError
        Not three finite numbers >= 0 with a positive sum.
    """
    try:
        w = np.asarray(weights, dtype=float)
    except (TypeError, ValueError):
        w = np.array([np.nan])
    if w.shape != (3,) or not np.all(np.isfinite(w)) or np.any(w < 0) or w.sum() <= 0:
        raise InputError(f"weights must be three numbers >= 0 (stress, duration, oscillation), "
                         f"not all zero, got {tuple(weights) if np.iterable(weights) else weights!r}")
    return tuple(w / w.sum())


@dataclass
class Design:
    """One design: its variables, the surrogate's outputs there and the weighted objective.

    Parameters
    ----------
    alpha_per_s : float
        Mass-proportional damping [1/s].
    length_m : float
        Finger length [m].
    outputs : dict
        Surrogate outputs at the design, by name (SI units, :data:`ccedi.design.objectives.OUTPUTS`).
    J : float
        Weighted normalised objective (dimensionless, module docstring).
    """

    alpha_per_s: float
    length_m: float
    outputs: dict
    J: float

    def as_dict(self, problem):
        """JSON form: ``alpha_per_s``, ``length_in``, the three objectives by name, J.

        Parameters
        ----------
        problem : DesignProblem

        Returns
        -------
        dict
        """
        d = {"alpha_per_s": self.alpha_per_s, "length_in": m_to_inch(self.length_m), "J": self.J}
        d.update({name: self.outputs[name] for name in problem.objective_outputs})
        d.update({k: self.outputs[k] for k in ("contact_start_s", "max_finger_stress_Pa")})
        return d


@dataclass
class DesignProblem:
    """Weighted design problem on ``surrogate`` (see the module docstring).

    Parameters
    ----------
    surrogate : ccedi.design.surrogate.Surrogate
        Interpolants of the design outputs over (alpha, L).
    weights : tuple of float, optional
        w_stress, w_duration, w_oscillation, >= 0 and not all zero (normalised to sum 1).
    stress_measure : {"reaction_force", "object_stress"}, optional
        The stress objective f_s: peak reaction force [N] or peak object stress [Pa].
    alpha_of_length : {"free", "paper", "fit"}, optional
        alpha free, or tied to the length by the paper's Eq. (7) or our fit.
    allowable_finger_stress_Pa : float, optional
        Largest finger von Mises stress allowed [Pa] (no limit when None).
    contact_start_bounds_s : tuple of float, optional
        Allowed first-contact window (lo, hi) [s], 0 <= lo < hi.
    min_contact_duration_s : float, optional
        Shortest contact that counts as touching the object [s].
    n_check : int, optional
        Points per axis of the brute-force grid (normalisation and check).

    Attributes
    ----------
    scale : dict
        ``{objective: (min over the grid, range over the grid)}``, the normalisation.

    Raises
    ------
    InputError
        Weights, stress measure, alpha-of-length mode, stress limit or contact window out
        of range.
    """

    surrogate: Surrogate
    weights: tuple = (1.0, 1.0, 1.0)
    stress_measure: str = "reaction_force"
    alpha_of_length: str = "free"
    allowable_finger_stress_Pa: float | None = None
    contact_start_bounds_s: tuple | None = None
    min_contact_duration_s: float = 0.01
    n_check: int = 100
    scale: dict = field(init=False)

    def __post_init__(self):
        self.weights = normalised_weights(self.weights)
        if self.stress_measure not in STRESS_MEASURES:
            raise InputError(f"stress objective must be one of {sorted(STRESS_MEASURES)}, got {self.stress_measure!r}")
        if self.alpha_of_length != "free":
            alpha_of_length(self.alpha_of_length, 6.0)            # validates the mode
        if self.allowable_finger_stress_Pa is not None:
            require_finite_positive("allowable finger stress (Pa)", self.allowable_finger_stress_Pa)
        if self.contact_start_bounds_s is not None:
            lo, hi = (float(b) for b in self.contact_start_bounds_s)
            if not (np.isfinite(lo) and np.isfinite(hi) and 0.0 <= lo < hi):
                raise InputError(f"contact start bounds must satisfy 0 <= lo < hi [s], got {self.contact_start_bounds_s}")
        grid = self.candidates(self.n_check)
        values = self.surrogate.evaluate(grid)
        self.scale = {k: (float(values[k].min()), float(np.ptp(values[k])) or 1.0) for k in self.objective_outputs}

    @property
    def objective_outputs(self):
        """Surrogate outputs of (stress, duration, oscillation)."""
        return (STRESS_MEASURES[self.stress_measure], "contact_duration_s", "residual_oscillation_m_s")

    def J(self, outputs, weights=None):
        """Weighted sum of normalised objectives (numpy or casadi).

        Parameters
        ----------
        outputs : dict
            Surrogate outputs (numpy or casadi).
        weights : tuple, optional
            Objective weights (default: the problem's).

        Returns
        -------
        float or casadi expression
        """
        w = self.weights if weights is None else weights
        return sum(wi * (outputs[k] - self.scale[k][0]) / self.scale[k][1] for wi, k in zip(w, self.objective_outputs))

    def candidates(self, n):
        """Brute-force points (m, 2) of (alpha [1/s], L [m]): an n x n grid (uniform in the
        unit coordinates), or n^2 lengths on alpha = alpha(L) for "this rubber only".

        Parameters
        ----------
        n : int
            Points per variable.

        Returns
        -------
        numpy.ndarray
            (m, 2) points (alpha [1/s], L [m]).
        """
        va, vl = self.surrogate.variables
        if self.alpha_of_length == "free":
            A, L = np.meshgrid(va.grid(n), vl.grid(n), indexing="ij")
            return np.column_stack([A.ravel(), L.ravel()])
        L = vl.grid(n * n)
        return np.column_stack([alpha_of_length(self.alpha_of_length, m_to_inch(L)), L])

    def constraint_margins(self, outputs, alpha_per_s=None):
        """{name: margin} with margin >= 0 when satisfied (numpy or casadi).

        Parameters
        ----------
        outputs : dict
            Surrogate outputs.
        alpha_per_s : float, optional
            alpha [1/s] (for the alpha-of-length constraint).

        Returns
        -------
        dict
        """
        g = {"touches the object (contact duration >= "
             f"{self.min_contact_duration_s:g} s)": outputs["contact_duration_s"] - self.min_contact_duration_s}
        if self.allowable_finger_stress_Pa is not None:
            g[f"max finger stress <= {self.allowable_finger_stress_Pa:g} Pa"] = \
                (self.allowable_finger_stress_Pa - outputs["max_finger_stress_Pa"]) / self.allowable_finger_stress_Pa
        if self.contact_start_bounds_s is not None:
            lo, hi = self.contact_start_bounds_s
            g[f"contact start >= {lo:g} s"] = outputs["contact_start_s"] - lo
            g[f"contact start <= {hi:g} s"] = hi - outputs["contact_start_s"]
        if alpha_per_s is not None:
            va = self.surrogate.variables[0]
            g[f"alpha within [{va.lo:g}, {va.hi:g}] 1/s"] = np.minimum(alpha_per_s - va.lo, va.hi - alpha_per_s)
        return g


def brute_force(problem: DesignProblem, n=None):
    """Best feasible point of :meth:`DesignProblem.candidates` (n x n, default
    ``problem.n_check``). Raises :class:`InputError` naming the constraint(s) no point
    satisfies.

    Parameters
    ----------
    problem : DesignProblem
    n : int, optional
        Points per variable.

    Returns
    -------
    Design

    Raises
    ------
    InputError
        No candidate is feasible.
    """
    X = problem.candidates(n or problem.n_check)
    out = problem.surrogate.evaluate(X)
    margins = problem.constraint_margins(out, X[:, 0])
    feasible = np.logical_and.reduce([m >= 0 for m in margins.values()])
    if not feasible.any():
        raise InputError(_infeasible_message(problem, out, margins))
    J = problem.J(out)
    k = int(np.flatnonzero(feasible)[np.argmin(J[feasible])])
    return Design(float(X[k, 0]), float(X[k, 1]), {name: float(v[k]) for name, v in out.items()}, float(J[k]))


def _infeasible_message(problem, out, margins):
    va, vl = problem.surrogate.variables
    where = (f"alpha in [{va.lo:g}, {va.hi:g}] 1/s, L in [{m_to_inch(vl.lo):g}, {m_to_inch(vl.hi):g}] in"
             + ("" if problem.alpha_of_length == "free" else f", alpha = alpha(L) ({problem.alpha_of_length})"))
    never = [name for name, m in margins.items() if not np.any(m >= 0)]
    if never:
        detail = "; ".join(never)
        hints = {"contact_start_s": "contact start", "max_finger_stress_Pa": "max finger stress",
                 "contact_duration_s": "contact duration"}
        ranges = ", ".join(f"{label} {out[k].min():.4g} to {out[k].max():.4g}" for k, label in hints.items())
        return f"no design satisfies: {detail} (for {where}; the surrogate predicts {ranges})"
    return f"no design satisfies all constraints together (for {where}): relax one of {', '.join(margins)}"


def _nlp(problem: DesignProblem, extra=None):
    """casadi NLP in the unit coordinates; ``extra(outputs)`` adds constraints g >= 0.
    Returns (solver, lbg, ubg)."""
    va, vl = problem.surrogate.variables
    u = ca.SX.sym("u", 2)
    out = problem.surrogate.unit_expressions([u[0], u[1]])
    g = list(problem.constraint_margins(out).values())
    lbg, ubg = [0.0] * len(g), [np.inf] * len(g)
    if problem.alpha_of_length != "free":
        g.append(u[0] - va.to_unit(alpha_of_length(problem.alpha_of_length, m_to_inch(vl.from_unit(u[1])))))
        lbg.append(0.0)
        ubg.append(0.0)
    if extra is not None:
        for e in extra(out):
            g.append(e)
            lbg.append(0.0)
            ubg.append(np.inf)
    nlp = {"x": u, "f": problem.J(out), "g": ca.vertcat(*g)}
    opts = {"ipopt.print_level": 0, "print_time": False, "ipopt.sb": "yes", "ipopt.tol": 1e-10, "ipopt.mu_init": 1e-5,
            "ipopt.max_iter": 200}
    return ca.nlpsol("design", "ipopt", nlp, opts), lbg, ubg


def _starts(problem, n_starts, seed=6):
    """Unit-coordinate starts: the best feasible points of a coarse grid, then random."""
    va, vl = problem.surrogate.variables
    X = problem.candidates(12)
    out = problem.surrogate.evaluate(X)
    ok = np.logical_and.reduce([m >= 0 for m in problem.constraint_margins(out, X[:, 0]).values()])
    order = np.argsort(np.where(ok, problem.J(out), np.inf))[: max(1, n_starts // 2)]
    U = np.column_stack([va.to_unit(X[order, 0]), vl.to_unit(X[order, 1])])
    rand = np.random.default_rng(seed).uniform(-1, 1, size=(n_starts - len(U), 2))
    return np.vstack([U, rand])


def solve(problem: DesignProblem, n_starts=8, extra=None, starts=None):
    """Minimise J with IPOPT from several starts and keep the best converged one.

    Parameters
    ----------
    problem : DesignProblem
        The problem on the surrogate.
    n_starts : int, optional
        Starts spread over the unit square (when ``starts`` is not given).
    extra : callable, optional
        ``extra(outputs) -> [g]``: more constraints g >= 0 on the casadi outputs (the
        epsilon constraints of the Pareto front); without it the request is first checked
        for feasibility on the brute-force grid.
    starts : sequence of array_like, optional
        Start points in unit coordinates instead of ``n_starts``.

    Returns
    -------
    design : Design
        The best converged start.
    info : dict
        Solver status, iterations of the best start and in total, starts converged,
        wall time [s].

    Raises
    ------
    InputError
        The request is infeasible (on the grid, or by IPOPT from every start).
    SolverError
        No start converged for another reason.
    """
    if extra is None:
        brute_force(problem)                                    # raises on an infeasible request
    t0 = time.perf_counter()
    solver, lbg, ubg = _nlp(problem, extra)
    best, total_iter, n_ok, statuses = None, 0, 0, []
    for u0 in (_starts(problem, n_starts) if starts is None else starts):
        sol = solver(x0=u0, lbx=-1.0, ubx=1.0, lbg=lbg, ubg=ubg)
        stats = solver.stats()
        statuses.append(stats["return_status"])
        total_iter += stats["iter_count"]
        if stats["return_status"] not in _OK:
            continue
        n_ok += 1
        f = float(sol["f"])
        if best is None or f < best[0]:
            best = (f, np.clip(np.array(sol["x"]).ravel(), -1.0, 1.0), stats)
    wall = time.perf_counter() - t0
    if best is None:
        if all(s == "Infeasible_Problem_Detected" for s in statuses):
            raise InputError("IPOPT found the constraints infeasible from every start: relax the bounds, "
                             "the allowable finger stress or the contact start bounds")
        raise SolverError(f"IPOPT did not converge from any of {len(statuses)} starts (statuses: "
                          f"{', '.join(sorted(set(statuses)))})")
    va, vl = problem.surrogate.variables
    alpha, L = float(va.from_unit(best[1][0])), float(vl.from_unit(best[1][1]))
    out = {k: float(v[0]) for k, v in problem.surrogate.evaluate([[alpha, L]]).items()}
    info = {"status": best[2]["return_status"], "iterations": int(best[2]["iter_count"]),
            "iterations_all_starts": int(total_iter), "starts": len(statuses), "starts_converged": n_ok,
            "wall_time_s": wall}
    return Design(alpha, L, out, float(problem.J(out))), info
