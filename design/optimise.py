"""The design problem on the surrogate, solved with casadi/IPOPT (multi-start) and by
brute force on a grid (the check of the former).

Design variables: alpha [1/s] and L [m] (:func:`ccedi.design.surrogate.design_space`),
worked in their unit coordinates u in [-1, 1]^2 (ln alpha and L scaled). The objective is
one output with a meaning (:data:`OBJECTIVES`; default: the transducer-filtered peak force
on the object), normalised by its range over the brute-force grid,

    J = (f - min_grid f) / (max_grid f - min_grid f),

or a weighted sum of such terms (``objective="weighted"``, ``weights={output: w}``).
Constraints: every requirement's margin >= 0 (:mod:`ccedi.design.requirements`), its
bound tightened by the surrogate's measured model error where one is given
(:class:`ModelError`: a ROM that reads a force 12 % low against the full FEA has its
force limit lowered by 12 %), and for "this rubber only" designs alpha = alpha(L)
(:func:`ccedi.design.rubber.alpha_of_length`, or any function of the length such as a
compound's loss factor times the finger's first mode,
:class:`ccedi.design.catalogue_design.CompoundTie`), imposed as ln alpha - ln alpha(L) = 0.

When no design meets the requirements, :func:`closest_design` finds the grid point whose
largest shortfall is smallest and says by how much it misses each requirement;
:func:`solve` raises :class:`ccedi.errors.RequirementsUnmet` with it.
"""
import time
from dataclasses import dataclass, field, replace

import casadi as ca
import numpy as np

from ccedi.errors import InputError, RequirementsUnmet, SolverError
from ccedi.units import m_to_inch

from .requirements import Limit, Requirements
from .rubber import alpha_of_length
from .surrogate import Surrogate

OBJECTIVES = {"object_force": "sensor_peak_force_N", "object_stress": "max_object_stress_Pa",
              "root_stress": "max_finger_stress_Pa", "recovery": "recovery_deviation_m",
              "ringing": "ringing_amplitude_m", "throughput": "cycle_time_s"}
"""Objective name -> the output it minimises ("weighted": a weighted sum of outputs);
"throughput" minimises the time between objects, so it needs the drum speed as a variable."""

BINDING_MARGIN = 1e-3
"""A requirement whose margin at the optimum is below this (normalised) binds."""

ON_BOUND = 0.01
"""A variable within this fraction of its range (in unit coordinates) of a bound sits on it."""

_OK = ("Solve_Succeeded", "Solved_To_Acceptable_Level")


def tied_alpha(mode, length_in):
    """alpha [1/s] tied to the finger length ``length_in`` [in] by ``mode``: "paper" or
    "fit" (:func:`ccedi.design.rubber.alpha_of_length`), or a function of the length
    (numpy or casadi values, e.g. :class:`ccedi.design.catalogue_design.CompoundTie`).

    Parameters
    ----------
    mode : str or callable
        The tie.
    length_in : float, numpy.ndarray or casadi expression
        Finger length [in].

    Returns
    -------
    Same type as ``length_in``.

    Raises
    ------
    InputError
        An unknown mode.
    """
    return mode(length_in) if callable(mode) else alpha_of_length(mode, length_in)


class ModelError:
    """How far the surrogate's model strays from the full FEA on one output, as measured
    (``validation/design_rom_check.py``): its under- and over-prediction over the design
    variables, interpolated linearly in (ln alpha, L) between the checked points (held
    constant beyond them).

    Parameters
    ----------
    alphas_per_s : array_like
        Increasing alpha nodes [1/s] (one node: a constant error).
    lengths_m : array_like
        Increasing length nodes [m] (one node: constant along the length).
    under : array_like
        (len(alphas), len(lengths)) largest (FEA - model), >= 0: a fraction of the FEA's
        value when ``relative``, else in the output's unit.
    over : array_like
        The same for (model - FEA).
    relative : bool, optional
        The errors are fractions of the FEA's value.
    """

    def __init__(self, alphas_per_s, lengths_m, *, under, over, relative=True):
        self.alphas_per_s = np.atleast_1d(np.asarray(alphas_per_s, dtype=float))
        self.lengths_m = np.atleast_1d(np.asarray(lengths_m, dtype=float))
        shape = (len(self.alphas_per_s), len(self.lengths_m))
        self.under = np.maximum(np.asarray(under, dtype=float).reshape(shape), 0.0)
        self.over = np.maximum(np.asarray(over, dtype=float).reshape(shape), 0.0)
        self.relative = bool(relative)
        x = ca.SX.sym("x", 2)
        coords = [np.log(self.alphas_per_s), self.lengths_m]
        pieces = [ca.fmin(ca.fmax(ca.log(x[0]), coords[0][0]), coords[0][-1]),
                  ca.fmin(ca.fmax(x[1], coords[1][0]), coords[1][-1])]
        values = []
        for table in (self.under, self.over):
            axes = [c for c in coords if len(c) > 1]
            args = [p for p, c in zip(pieces, coords) if len(c) > 1]
            if not axes:
                values.append(ca.SX(float(table.ravel()[0])))
                continue
            f = ca.interpolant("model_error", "linear", axes, table.ravel(order="F"))
            values.append(f(ca.vertcat(*args)))
        self.function = ca.Function("model_error", [x], [ca.vertcat(*values)])

    @classmethod
    def constant(cls, under, over, relative=True):
        """The same error everywhere.

        Parameters
        ----------
        under, over : float
            Largest under- and over-prediction (module docstring of the class).
        relative : bool, optional

        Returns
        -------
        ModelError
        """
        return cls([1.0], [1.0], [[under]], [[over]], relative)

    def at(self, alpha_per_s, length_m):
        """(under, over) at the design(s) (numpy arrays or casadi expressions).

        Parameters
        ----------
        alpha_per_s, length_m : float, numpy.ndarray or casadi expression

        Returns
        -------
        tuple
        """
        if isinstance(alpha_per_s, (ca.SX, ca.MX)):
            y = self.function(ca.vertcat(alpha_per_s, length_m))
            return y[0], y[1]
        a, L = np.broadcast_arrays(np.asarray(alpha_per_s, dtype=float), np.asarray(length_m, dtype=float))
        y = np.array(self.function.map(a.size)(np.vstack([a.ravel(), L.ravel()]))).reshape(2, *a.shape)
        return y[0], y[1]

    def tightened(self, limit: Limit, alpha_per_s, length_m):
        """The bound of ``limit`` that the model's value must meet at the design so that
        the FEA's does: upper limit b (1 - under) or b - under; lower b (1 + over) or b + over.

        Parameters
        ----------
        limit : Limit
        alpha_per_s, length_m : float, numpy.ndarray or casadi expression
            The design(s) [1/s], [m].

        Returns
        -------
        Same type as ``alpha_per_s``.
        """
        under, over = self.at(alpha_per_s, length_m)
        b = limit.target
        if limit.upper:
            return b * (1.0 - under) if self.relative else b - under
        return b * (1.0 + over) if self.relative else b + over

    def largest(self):
        """The largest (under, over) anywhere.

        Returns
        -------
        tuple of float
        """
        return float(self.under.max()), float(self.over.max())


@dataclass
class Design:
    """One design: its variables, the surrogate's outputs there and the objective.

    Parameters
    ----------
    alpha_per_s : float
        Mass-proportional damping [1/s].
    x : float
        The second design variable (the problem's ``surrogate.variables[1]``) [SI]: the
        finger length [m] or the drum speed [rad/s].
    outputs : dict
        Surrogate outputs at the design, by name (SI units).
    J : float
        Normalised objective (dimensionless, module docstring).
    """

    alpha_per_s: float
    x: float
    outputs: dict
    J: float

    def describe(self, variables):
        """``"alpha = 234.9 1/s, L = 4.183 in"``.

        Parameters
        ----------
        variables : tuple of ccedi.design.surrogate.Variable
            The problem's variables.

        Returns
        -------
        str
        """
        return ", ".join(v.describe(x) for v, x in zip(variables, (self.alpha_per_s, self.x)))

    def as_dict(self, problem):
        """JSON form: ``alpha_per_s``, the second variable in its shown unit
        (``length_in`` or ``drum_speed_rpm``), J, every output, and each requirement's
        margin (``margins``, normalised, >= 0 when met by the surrogate with the
        model-error margin).

        Parameters
        ----------
        problem : DesignProblem

        Returns
        -------
        dict
        """
        v = problem.surrogate.variables[1]
        d = {"alpha_per_s": self.alpha_per_s, v.key: float(v.shown(self.x)), "J": self.J}
        d.update({k: float(v) for k, v in self.outputs.items()})
        d["margins"] = {k: float(v) for k, v in
                        problem.constraint_margins(self.outputs, self.alpha_per_s, self.x).items()}
        return d


@dataclass
class DesignProblem:
    """A design problem on ``surrogate`` (see the module docstring).

    Parameters
    ----------
    surrogate : ccedi.design.surrogate.Surrogate
        Interpolants of the design outputs over (alpha, L).
    requirements : Requirements, optional
        The designer's requirements (default: their documented defaults).
    objective : str, optional
        One of :data:`OBJECTIVES` or "weighted".
    weights : dict, optional
        ``{output: weight >= 0}`` of the weighted objective (not all zero).
    alpha_of_length : {"free", "paper", "fit"} or callable, optional
        alpha free, or tied to the length by the paper's Eq. (7), our fit, or a function
        ``f(length_in) -> alpha [1/s]`` of numpy and casadi values (:func:`tied_alpha`).
    model_error : dict, optional
        ``{output: ModelError}``: the surrogate's measured error against the full FEA,
        carried as a conservative margin on every requirement on that output.
    n_check : int, optional
        Points per axis of the brute-force grid (normalisation and check).

    Attributes
    ----------
    scale : dict
        ``{output: (min over the grid, range over the grid)}`` of the objective's outputs.

    Raises
    ------
    InputError
        Unknown objective, bad weights, a requirement on an output the surrogate lacks,
        an unknown alpha-of-length mode, a choice the problem's variables do not allow
        ("throughput" without the drum speed; alpha tied to the length or a model error
        without the length), or an objective whose output is the same everywhere.
    """

    surrogate: Surrogate
    requirements: Requirements = field(default_factory=Requirements)
    objective: str = "object_force"
    weights: dict | None = None
    alpha_of_length: object = "free"
    model_error: dict = field(default_factory=dict)
    n_check: int = 100
    scale: dict = field(init=False)

    def __post_init__(self):
        if self.objective not in (*OBJECTIVES, "weighted"):
            raise InputError(f"objective must be one of {', '.join((*OBJECTIVES, 'weighted'))}, got {self.objective!r}")
        self.weights = self._checked_weights()
        if self.alpha_of_length != "free":
            tied_alpha(self.alpha_of_length, 6.0)                 # validates the mode
        second = self.surrogate.variables[1]
        if self.objective == "throughput" and second.name != "drum_speed_rad_s":
            raise InputError(f"objective 'throughput' needs the drum speed as a design variable; this problem varies "
                             f"{second.label} (a finger mesh's design varies the drum speed)")
        if second.name != "length_m" and (self.alpha_of_length != "free" or self.model_error):
            raise InputError(f"alpha tied to the length and the ROM's model error (measured over alpha and length) "
                             f"need the length as a design variable; this problem varies {second.label}")
        missing = sorted({lim.output for lim in self.limits} - set(self.surrogate.outputs))
        if missing:
            raise InputError(f"requirements on outputs the surrogate lacks: {', '.join(missing)} "
                             f"(it has {', '.join(self.surrogate.outputs)})")
        values = self.surrogate.evaluate(self.candidates(self.n_check))
        if self.objective != "weighted" and np.ptp(values[OBJECTIVES[self.objective]]) == 0.0:
            output = OBJECTIVES[self.objective]
            raise InputError(f"objective {self.objective!r}: {output} is {float(values[output][0]):.4g} everywhere in "
                             f"the design space, nothing to minimise"
                             + (" (a fixed [drum] cycle_time_s does not follow the drum speed)"
                                if output == "cycle_time_s" else ""))
        self.scale = {k: (float(values[k].min()), float(np.ptp(values[k])) or 1.0) for k in self.weights}

    def _checked_weights(self):
        if self.objective != "weighted":
            return {OBJECTIVES[self.objective]: 1.0}
        w = self.weights or {}
        bad = [k for k in w if k not in self.surrogate.outputs]
        values = np.array([float(v) for v in w.values()]) if w else np.array([])
        if bad or not len(values) or not np.all(np.isfinite(values)) or np.any(values < 0) or values.sum() <= 0:
            raise InputError(f"weights must map surrogate outputs ({', '.join(self.surrogate.outputs)}) to numbers "
                             f">= 0, not all zero, got {w!r}")
        return {k: float(v) / values.sum() for k, v in w.items()}

    @property
    def limits(self):
        """The requirements as :class:`ccedi.design.requirements.Limit` objects."""
        return self.requirements.limits()

    def bound(self, limit, alpha_per_s, x):
        """The bound the surrogate must meet for ``limit`` at the design(s): tightened by
        the output's model error there when one is given.

        Parameters
        ----------
        limit : Limit
        alpha_per_s, x : float, numpy.ndarray or casadi expression
            The design(s): alpha [1/s] and the second variable [SI].

        Returns
        -------
        float, numpy.ndarray or casadi expression
        """
        err = self.model_error.get(limit.output)
        return limit.target if err is None else err.tightened(limit, alpha_per_s, x)

    def J(self, outputs):
        """Normalised objective (numpy or casadi).

        Parameters
        ----------
        outputs : dict
            Surrogate outputs (numpy or casadi).

        Returns
        -------
        float or casadi expression
        """
        return sum(w * (outputs[k] - self.scale[k][0]) / self.scale[k][1] for k, w in self.weights.items())

    def objective_value(self, outputs):
        """The objective in its own unit: the output minimised, or J for a weighted sum.

        Parameters
        ----------
        outputs : dict

        Returns
        -------
        float
        """
        return float(outputs[OBJECTIVES[self.objective]]) if self.objective != "weighted" else float(self.J(outputs))

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
        return np.column_stack([tied_alpha(self.alpha_of_length, m_to_inch(L)), L])

    def constraint_margins(self, outputs, alpha_per_s, x, *, alpha_bounds=False):
        """{requirement: normalised margin}, >= 0 when met (numpy or casadi); with
        ``alpha_bounds``, also the alpha bounds (for the alpha-of-length designs).

        Parameters
        ----------
        outputs : dict
            Surrogate outputs at the design(s).
        alpha_per_s, x : float, numpy.ndarray or casadi expression
            The design(s): alpha [1/s] and the second variable [SI].
        alpha_bounds : bool, optional
            Add the margin of alpha to its bounds.

        Returns
        -------
        dict
        """
        g = {lim.describe(): lim.margin(outputs[lim.output], self.bound(lim, alpha_per_s, x))
             for lim in self.limits}
        if alpha_bounds:
            va = self.surrogate.variables[0]
            g[f"alpha within [{va.lo:g}, {va.hi:g}] 1/s"] = np.minimum(alpha_per_s - va.lo, va.hi - alpha_per_s) / va.hi
        return g

    def without(self, output):
        """The same problem without the requirements on ``output``.

        Parameters
        ----------
        output : str

        Returns
        -------
        DesignProblem
        """
        kept = [lim for lim in self.limits if lim.output != output]
        return replace(self, requirements=Requirements.from_limits(kept))


def _design_at(problem, X, k, out):
    return Design(float(X[k, 0]), float(X[k, 1]), {name: float(v[k]) for name, v in out.items()},
                  float(problem.J({name: v[k] for name, v in out.items()})))


def brute_force(problem: DesignProblem, n=None):
    """Best feasible point of :meth:`DesignProblem.candidates` (n x n, default
    ``problem.n_check``).

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
    RequirementsUnmet
        No candidate is feasible (with :func:`closest_design`).
    """
    X = problem.candidates(n or problem.n_check)
    out = problem.surrogate.evaluate(X)
    margins = problem.constraint_margins(out, X[:, 0], X[:, 1], alpha_bounds=True)
    feasible = np.logical_and.reduce([m >= 0 for m in margins.values()])
    if not feasible.any():
        raise unmet(problem)
    J = problem.J(out)
    k = int(np.flatnonzero(feasible)[np.argmin(J[feasible])])
    return _design_at(problem, X, k, out)


def closest_design(problem: DesignProblem, n=None):
    """The candidate whose largest shortfall is smallest, and its shortfall per
    requirement.

    Parameters
    ----------
    problem : DesignProblem
    n : int, optional
        Points per variable (default ``problem.n_check``).

    Returns
    -------
    design : Design
        The closest design.
    misses : dict
        ``{requirement: {"value", "bound", "miss"}}`` for each requirement it misses:
        the surrogate's value, the bound it had to meet (with the model-error margin) and
        the shortfall in the requirement's own unit (SI).
    """
    X = problem.candidates(n or problem.n_check)
    out = problem.surrogate.evaluate(X)
    margins = problem.constraint_margins(out, X[:, 0], X[:, 1], alpha_bounds=True)
    worst = np.max(np.vstack([-m for m in margins.values()]), axis=0)
    k = int(np.argmin(worst))
    design = _design_at(problem, X, k, out)
    misses = {}
    for lim in problem.limits:
        value, b = design.outputs[lim.output], float(problem.bound(lim, design.alpha_per_s, design.x))
        if lim.margin(value, b) < 0:
            misses[lim.describe()] = {"value": value, "bound": b, "miss": abs(value - b)}
    return design, misses


def unmet(problem: DesignProblem):
    """:class:`ccedi.errors.RequirementsUnmet` naming what the closest design misses; its
    ``design`` and ``misses`` attributes are those of :func:`closest_design`.

    Parameters
    ----------
    problem : DesignProblem

    Returns
    -------
    RequirementsUnmet
    """
    design, misses = closest_design(problem)
    where = (", ".join(f"{v.label} {v.shown(v.lo):.4g}-{v.shown(v.hi):.4g} {v.unit}" for v in problem.surrogate.variables)
             + ("" if problem.alpha_of_length == "free" else f" on alpha = alpha(L) ({problem.alpha_of_length})"))
    said = "; ".join(f"{lim.describe()}: {lim.shown(misses[lim.describe()]['value'])} against "
                     f"{lim.shown(misses[lim.describe()]['bound'])}" for lim in problem.limits if lim.describe() in misses)
    err = RequirementsUnmet(f"no design meets the requirements ({where}); the closest, "
                            f"{design.describe(problem.surrogate.variables)}, misses {said}")
    err.design, err.misses = design, misses
    return err


def _nlp(problem: DesignProblem, extra=None):
    """casadi NLP in the unit coordinates; ``extra(outputs)`` adds constraints g >= 0.
    Returns (solver, lbg, ubg)."""
    va, vl = problem.surrogate.variables
    u = ca.SX.sym("u", 2)
    out = problem.surrogate.unit_expressions([u[0], u[1]])
    g = list(problem.constraint_margins(out, va.from_unit(u[0]), vl.from_unit(u[1])).values())
    lbg, ubg = [0.0] * len(g), [np.inf] * len(g)
    if problem.alpha_of_length != "free":
        g.append(u[0] - va.to_unit(tied_alpha(problem.alpha_of_length, m_to_inch(vl.from_unit(u[1])))))
        lbg.append(0.0)
        ubg.append(0.0)
    for e in extra(out) if extra is not None else ():
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
    ok = np.logical_and.reduce([m >= 0 for m in problem.constraint_margins(out, X[:, 0], X[:, 1],
                                                                            alpha_bounds=True).values()])
    order = np.argsort(np.where(ok, problem.J(out), np.inf))[: max(1, n_starts // 2)]
    U = np.column_stack([va.to_unit(X[order, 0]), vl.to_unit(X[order, 1])])
    rand = np.random.default_rng(seed).uniform(-1, 1, size=(n_starts - len(U), 2))
    return np.vstack([U, rand])


def solve(problem: DesignProblem, *, n_starts=8, extra=None, starts=None):
    """Minimise J with IPOPT from several starts and keep the best converged feasible one;
    the brute-force grid's best feasible point is a start too, and the answer when IPOPT
    converges nowhere better (the requirements' boundaries are kinked where an output is,
    e.g. the ringing amplitude where the finger stops overshooting).

    Parameters
    ----------
    problem : DesignProblem
        The problem on the surrogate.
    n_starts : int, optional
        Starts spread over the unit square (when ``starts`` is not given).
    extra : callable, optional
        ``extra(outputs) -> [g]``: more constraints g >= 0 on the casadi outputs (the
        epsilon constraints of the Pareto front).
    starts : sequence of array_like, optional
        Start points in unit coordinates instead of ``n_starts``.

    Returns
    -------
    design : Design
        The best design found.
    info : dict
        Solver status, iterations of the best start and in total, starts converged,
        wall time [s].

    Raises
    ------
    RequirementsUnmet
        No point of the brute-force grid meets the requirements (without ``extra``).
    SolverError
        No start converged to a feasible point and the grid has none either.
    """
    va, vl = problem.surrogate.variables
    grid_best = None
    if extra is None:
        grid_best = brute_force(problem)                        # raises RequirementsUnmet
    t0 = time.perf_counter()
    solver, lbg, ubg = _nlp(problem, extra)
    best, total_iter, n_ok, statuses = None, 0, 0, []
    u_starts = list(_starts(problem, n_starts) if starts is None else starts)
    if grid_best is not None:
        u_starts.append([va.to_unit(grid_best.alpha_per_s), vl.to_unit(grid_best.x)])
    for u0 in u_starts:
        sol = solver(x0=u0, lbx=-1.0, ubx=1.0, lbg=lbg, ubg=ubg)
        stats = solver.stats()
        statuses.append(stats["return_status"])
        total_iter += stats["iter_count"]
        if stats["return_status"] not in _OK:
            continue
        n_ok += 1
        f = float(sol["f"])
        if best is None or f < best[0]:
            best = (f, np.clip(np.array(sol["x"]).ravel(), -1.0, 1.0), stats["return_status"], stats["iter_count"])
    wall = time.perf_counter() - t0
    if best is None and grid_best is None:
        raise SolverError(f"IPOPT did not converge from any of {len(statuses)} starts (statuses: "
                          f"{', '.join(sorted(set(statuses)))})")
    if best is None or (grid_best is not None and grid_best.J < best[0] - 1e-9):
        design, status, iters = grid_best, "grid point (IPOPT converged nowhere better)", 0
    else:
        alpha, L = float(va.from_unit(best[1][0])), float(vl.from_unit(best[1][1]))
        out = {k: float(v[0]) for k, v in problem.surrogate.evaluate([[alpha, L]]).items()}
        design, status, iters = Design(alpha, L, out, float(problem.J(out))), best[2], int(best[3])
    info = {"status": status, "iterations": iters, "iterations_all_starts": int(total_iter),
            "starts": len(statuses), "starts_converged": n_ok, "wall_time_s": wall}
    return design, info


def on_bounds(problem: DesignProblem, design: Design):
    """The variables of ``design`` that sit on a bound (within :data:`ON_BOUND` of the
    range), e.g. ``["alpha at its upper bound 600 1/s"]``.

    Parameters
    ----------
    problem : DesignProblem
    design : Design

    Returns
    -------
    list of str
    """
    flags = (bound_flag(var, x) for var, x in zip(problem.surrogate.variables, (design.alpha_per_s, design.x)))
    return [f for f in flags if f]


def bound_flag(var, x):
    """``"alpha at its upper bound 600 1/s"`` when the value ``x`` [SI] of the variable
    ``var`` sits on a bound (within :data:`ON_BOUND` of its range), else None.

    Parameters
    ----------
    var : ccedi.design.surrogate.Variable
    x : float

    Returns
    -------
    str or None
    """
    u = float(var.to_unit(x))
    if u <= -1.0 + 2.0 * ON_BOUND:
        return f"{var.label} at its lower bound {var.shown(var.lo):.4g} {var.unit}"
    if u >= 1.0 - 2.0 * ON_BOUND:
        return f"{var.label} at its upper bound {var.shown(var.hi):.4g} {var.unit}"
    return None


def binding(problem: DesignProblem, design: Design):
    """The requirements that bind at ``design`` (margin below :data:`BINDING_MARGIN`).

    Parameters
    ----------
    problem : DesignProblem
    design : Design

    Returns
    -------
    list of str
    """
    margins = problem.constraint_margins(design.outputs, design.alpha_per_s, design.x)
    return [name for name, m in margins.items() if m < BINDING_MARGIN]


def sensitivities(problem: DesignProblem, design: Design, *, relax=0.1, n_starts=4):
    """What relaxing each requirement buys: the problem re-solved with that one bound
    moved by ``relax`` of its scale (an upper limit up, a lower one down).

    Parameters
    ----------
    problem : DesignProblem
    design : Design
        The optimum of ``problem``.
    relax : float, optional
        Relaxation, a fraction of each requirement's scale.
    n_starts : int, optional
        IPOPT starts per re-solve.

    Returns
    -------
    dict
        ``{requirement: {"binding", "relaxed_to", "objective", "objective_change",
        "alpha_per_s", and the second variable's key}}``: the relaxed bound (SI), the
        objective there (its own unit) and its change from the optimum's (negative:
        better).
    """
    base = problem.objective_value(design.outputs)
    bind = set(binding(problem, design))
    out = {}
    limits = problem.limits
    for i, lim in enumerate(limits):
        moved = lim.bound + (relax if lim.upper else -relax) * lim.norm
        relaxed = replace(lim, bound=moved)
        others = limits[:i] + limits[i + 1:]
        try:
            d, _ = solve(replace(problem, requirements=Requirements.from_limits(others + [relaxed])), n_starts=n_starts)
        except (RequirementsUnmet, SolverError):
            continue
        value = problem.objective_value(d.outputs)
        v = problem.surrogate.variables[1]
        out[lim.describe()] = {"binding": lim.describe() in bind, "relaxed_to": moved, "objective": value,
                               "objective_change": value - base, "alpha_per_s": d.alpha_per_s,
                               v.key: float(v.shown(d.x))}
    return out
