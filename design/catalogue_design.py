"""The compound as a design variable: every compound of a catalogue
(:func:`ccedi.design.compounds.load_compounds`) designed over the finger length with its
own modulus, density and damping, and the compounds ranked by the objective at their best
design.

A compound fixes three of the finger's inputs: its nominal Young's modulus E (the middle
of its range, :attr:`ccedi.design.compounds.Compound.E_nominal_Pa`), its density rho and its
damping, alpha = tan delta x omega_1(L) at its nominal loss factor
(:attr:`~ccedi.design.compounds.Compound.tan_delta_nominal`, for a row CCEDI identified the
identified alpha over its finger's first mode, so the identified alpha scaled to the
finger as :mod:`ccedi.design.compounds` says). alpha is therefore not free: each
compound's design varies the length alone, on alpha = alpha_c(L) (:class:`CompoundTie`),
the constraint the "this rubber" designs use (:class:`ccedi.design.optimise.DesignProblem`,
``alpha_of_length``).

One surrogate serves the whole catalogue. Scaling E and rho by one factor k leaves the
finger's motion unchanged and scales every force and stress by k
(:data:`ccedi.design.outputs.DENSITY_SCALED`), so a compound (E, rho) runs as the finger of
the set-up's density rho_0 with E' = E rho_0 / rho, its force outputs times rho / rho_0.
The contact ROM is run on a tensor grid over (alpha, L, E') at rho_0
(:func:`catalogue_surrogate`, :func:`ccedi.design.surrogate.material_space`); a compound
sees it at its E' (:class:`CompoundSurrogate`). Its first mode follows the same rule:
omega_1(L) is solved at rho_0 and the set-up's E and scaled by sqrt((E / rho) / (E_0 / rho_0))
(:class:`FirstMode`).

The ranking (:func:`design_compounds`): each compound's optimum is solved on its surrogate
(IPOPT and the brute-force grid, :func:`ccedi.design.optimise.solve`) and, by default,
verified by the ROM built at the compound's own E and rho
(:func:`ccedi.design.recheck.verified_optimum`); the compounds that meet the requirements
rank by the objective, the others after them by their largest shortfall
(:func:`ccedi.design.optimise.closest_design`). The robust margin of a design is its
smallest requirement margin over the compound's loss-factor range at the chosen length
(the loss factor moves with temperature, frequency and grade; E's range is a choice of
hardness, held at its middle here).
"""
from dataclasses import dataclass, field, replace

import casadi as ca
import numpy as np
import pandas as pd

from ccedi.errors import InputError, RequirementsUnmet
from ccedi.fea.material import NeoHookean
from ccedi.rom.finger_identification import finger_omega1
from ccedi.units import m_to_inch

from .compounds import Compound, alpha_from_loss_factor
from .optimise import OBJECTIVES, DesignProblem, binding, closest_design, on_bounds, solve
from .outputs import UNITS, density_scaled
from .recheck import verified_optimum
from .requirements import Requirements
from .surrogate import Surrogate, cached_rom_runs, grid_points, material_space, run_rom

CATALOGUE_GRID = (15, 11, 6)
"""Default ROM grid of the catalogue surrogate: points along alpha, L and E."""

RANGE_PAD = 1.05
"""Factor the catalogue's alpha and E ranges are widened by on each side."""

FIRST_MODE_LENGTHS = 5
"""FE eigen solves of the first mode over the length range (:class:`FirstMode`)."""


@dataclass(frozen=True)
class FirstMode:
    """omega_1(L) of the clamped generated finger [rad/s], any E and rho: ln omega_1 quadratic
    in ln L through FE eigen solves at a reference material
    (:func:`ccedi.rom.finger_identification.finger_omega1`), scaled by sqrt(E / rho) (the
    linearised stiffness is proportional to E, the mass to rho).

    Parameters
    ----------
    coefficients : tuple of float
        (c2, c1, c0) of ln omega_1 = c2 (ln L)^2 + c1 ln L + c0, L in inches, at the
        reference material.
    E_Pa : float
        Reference Young's modulus [Pa].
    rho_kg_m3 : float
        Reference density [kg/m^3].
    length_bounds_in : tuple of float
        The lengths the fit spans [in].
    fit_error : float
        Largest relative error of the fit at the solved lengths [-].
    """

    coefficients: tuple
    E_Pa: float
    rho_kg_m3: float
    length_bounds_in: tuple
    fit_error: float

    @classmethod
    def of(cls, setup, length_bounds_in, n=FIRST_MODE_LENGTHS):
        """The first mode of ``setup``'s generated finger (its material and section) over
        ``length_bounds_in`` [in], from ``n`` FE eigen solves.

        Parameters
        ----------
        setup : ccedi.fea.contact.drum.DrumSetup
            The set-up (``finger_material``, ``finger_semi_axes_m``).
        length_bounds_in : tuple of float
            (lo, hi) [in].
        n : int, optional
            Lengths solved, >= 3.

        Returns
        -------
        FirstMode

        Raises
        ------
        InputError
            A finger given as a mesh (its length is fixed), or fewer than 3 lengths.
        """
        if setup.finger is not None:
            raise InputError(f"the compound design varies the finger length; the finger is a given "
                             f"{setup.finger.element_type} mesh of fixed length: design it with ccedi design "
                             "--vary drum_speed")
        if n < 3:
            raise InputError(f"first-mode lengths must be >= 3, got {n}")
        m = setup.finger_material
        lengths = np.linspace(*length_bounds_in, n)
        omega = np.array([finger_omega1(x, material=m, semi_axes_m=tuple(setup.finger_semi_axes_m)) for x in lengths])
        c = np.polyfit(np.log(lengths), np.log(omega), 2)
        err = float(np.max(np.abs(np.exp(np.polyval(c, np.log(lengths))) / omega - 1.0)))
        return cls(tuple(float(v) for v in c), float(m.E), float(m.rho), tuple(map(float, length_bounds_in)), err)

    def __call__(self, length_in, *, E_Pa, rho_kg_m3):
        """omega_1 [rad/s] of the finger of ``length_in`` [in] (numpy or casadi) of E and rho.

        Parameters
        ----------
        length_in : float, numpy.ndarray or casadi expression
            Finger length [in].
        E_Pa : float
            Young's modulus [Pa].
        rho_kg_m3 : float
            Density [kg/m^3].

        Returns
        -------
        Same type as ``length_in``.
        """
        symbolic = isinstance(length_in, (ca.SX, ca.MX))
        x = ca.log(length_in) if symbolic else np.log(length_in)
        c2, c1, c0 = self.coefficients
        w = (ca.exp if symbolic else np.exp)(c2 * x * x + c1 * x + c0)
        return w * np.sqrt((E_Pa / rho_kg_m3) / (self.E_Pa / self.rho_kg_m3))


@dataclass(frozen=True)
class CompoundTie:
    """A compound's damping on a finger of any length: alpha = tan delta x omega_1(L)
    (:func:`ccedi.design.compounds.alpha_from_loss_factor`), the tie of a compound design
    (``alpha_of_length`` of :class:`ccedi.design.optimise.DesignProblem`).

    Parameters
    ----------
    compound : Compound
        The compound (its nominal E, its density).
    first_mode : FirstMode
        omega_1(L).
    tan_delta : float or None, optional
        Loss factor [-] (default: the compound's nominal one).
    """

    compound: Compound
    first_mode: FirstMode
    tan_delta: float | None = None

    @property
    def loss_factor(self):
        """The loss factor of the tie [-]."""
        return self.compound.tan_delta_nominal if self.tan_delta is None else self.tan_delta

    def __call__(self, length_in):
        """alpha [1/s] at ``length_in`` [in] (numpy or casadi).

        Parameters
        ----------
        length_in : float, numpy.ndarray or casadi expression

        Returns
        -------
        Same type as ``length_in``.
        """
        c = self.compound
        return alpha_from_loss_factor(self.loss_factor, self.first_mode(length_in, E_Pa=c.E_nominal_Pa,
                                                                        rho_kg_m3=c.rho_kg_m3))

    def __str__(self):
        return f"{self.compound.name}: tan delta {self.loss_factor:.4g} x omega_1(L)"


class CompoundSurrogate(Surrogate):
    """A catalogue surrogate over (alpha, L, E) at density rho_0 (:func:`catalogue_surrogate`)
    seen by a finger of Young's modulus ``E_Pa`` and density ``rho_kg_m3``: a surrogate over
    (alpha, L) at E' = E rho_0 / rho, its :data:`ccedi.design.outputs.DENSITY_SCALED` outputs
    times rho / rho_0 (module docstring).

    Parameters
    ----------
    surrogate : Surrogate
        Over (alpha_per_s, length_m, youngs_modulus_Pa), built at density ``reference_rho_kg_m3``.
    E_Pa : float
        The finger's Young's modulus [Pa].
    rho_kg_m3 : float
        Its density [kg/m^3].
    reference_rho_kg_m3 : float
        The density the surrogate was built at [kg/m^3].

    Raises
    ------
    InputError
        ``surrogate`` not over (alpha, L, E), or E' outside its E range.
    """

    def __init__(self, surrogate, *, E_Pa, rho_kg_m3, reference_rho_kg_m3):
        names = tuple(v.name for v in surrogate.variables)
        if names != ("alpha_per_s", "length_m", "youngs_modulus_Pa"):
            raise InputError(f"a compound surrogate needs a surrogate over (alpha_per_s, length_m, youngs_modulus_Pa), "
                             f"got {names}")
        var_E = surrogate.variables[2]
        self.base = surrogate
        self.density_ratio = float(rho_kg_m3 / reference_rho_kg_m3)
        self.E_equivalent_Pa = float(E_Pa / self.density_ratio)
        if not var_E.lo * (1 - 1e-9) <= self.E_equivalent_Pa <= var_E.hi * (1 + 1e-9):
            raise InputError(f"E = {E_Pa / 1e6:.4g} MPa at rho = {rho_kg_m3:.4g} kg/m^3 is E' = "
                             f"{self.E_equivalent_Pa / 1e6:.4g} MPa at the surrogate's density "
                             f"{reference_rho_kg_m3:.4g} kg/m^3, outside its E range {var_E.lo / 1e6:.4g}-"
                             f"{var_E.hi / 1e6:.4g} MPa: build the surrogate over the catalogue (catalogue_surrogate)")
        self.u_E = float(var_E.to_unit(self.E_equivalent_Pa))
        self.variables = surrogate.variables[:2]
        self.axes = surrogate.axes[:2]
        self.values = {}
        self.outputs = surrogate.outputs
        self.nonnegative = surrogate.nonnegative
        self._compile()

    def unit_expressions(self, us):
        """{output: expression} at the unit coordinates ``us`` of (alpha, L), at this
        finger's E and rho.

        Parameters
        ----------
        us : sequence
            Unit coordinates of alpha and L.

        Returns
        -------
        dict
        """
        out = self.base.unit_expressions([*us, self.u_E])
        return density_scaled(out, self.density_ratio)


def catalogue_space(compounds, first_mode, length_bounds_in, *, spread=None):
    """The (alpha, L, E') variables that hold every compound of ``compounds``: alpha over
    their loss-factor ranges at every length, E' their nominal moduli at the first mode's
    reference density, both widened by :data:`RANGE_PAD` (and rounded to 4 digits), and
    by a spread of E and the loss factor about their nominal values when one is given (a
    robust design's samples, :class:`ccedi.design.robust.Spread`).

    Parameters
    ----------
    compounds : sequence of Compound
    first_mode : FirstMode
        omega_1(L) (its reference density is the surrogate's).
    length_bounds_in : tuple of float
        (lo, hi) [in].
    spread : ccedi.design.robust.Spread, optional
        Relative half-widths of E and tan delta to cover besides. Default None.

    Returns
    -------
    tuple of ccedi.design.surrogate.Variable

    Raises
    ------
    InputError
        No compound, or bounds not 0 < lo < hi.
    """
    compounds = list(compounds)
    if not compounds:
        raise InputError("the compound design needs at least one compound, got an empty catalogue")
    lengths = np.asarray(length_bounds_in, dtype=float)
    alphas, moduli = [], []
    e, t = (0.0, 0.0) if spread is None else (spread.E_relative, spread.tan_delta_relative)
    for c in compounds:
        w = first_mode(lengths, E_Pa=c.E_nominal_Pa, rho_kg_m3=c.rho_kg_m3)
        alphas += [min(c.tan_delta_min, c.tan_delta_nominal * (1 - t)) * w.min() * np.sqrt(1 - e),
                   max(c.tan_delta_max, c.tan_delta_nominal * (1 + t)) * w.max() * np.sqrt(1 + e)]
        moduli += [c.E_nominal_Pa * (1 - e) * first_mode.rho_kg_m3 / c.rho_kg_m3,
                   c.E_nominal_Pa * (1 + e) * first_mode.rho_kg_m3 / c.rho_kg_m3]
    bounds = [_rounded(f(v) * RANGE_PAD ** k) for v in (alphas, moduli) for f, k in ((min, -1), (max, 1))]
    return material_space(tuple(bounds[:2]), tuple(length_bounds_in), tuple(bounds[2:]))


def _rounded(x):
    """``x`` to 4 significant digits: the bounds, and with them the grid a ROM cache is
    keyed on, do not move with the eigen solver's last digits."""
    return float(f"{x:.4g}")


def catalogue_surrogate(setup, compounds, *, length_bounds_in=(3.0, 8.0), shape=CATALOGUE_GRID, damping="relative",
                        path=None, progress=None, first_mode=None, spread=None):
    """The ROM surrogate over (alpha, L, E') that serves every compound of ``compounds``
    (:func:`catalogue_space`), at ``setup``'s density.

    Parameters
    ----------
    setup : ccedi.fea.contact.drum.DrumSetup
        The drum test (its finger material's density and Poisson's ratio are the
        surrogate's).
    compounds : sequence of Compound
        The catalogue.
    length_bounds_in : tuple of float, optional
        (lo, hi) [in].
    shape : tuple of int, optional
        ROM runs along alpha, L and E' (each >= 4).
    damping : {"relative", "global"}, optional
        Damping kind of every run.
    path : pathlib.Path, optional
        CSV cache of the runs (:func:`ccedi.design.surrogate.cached_rom_runs`); None: no cache.
    progress : callable, optional
        ``progress(done, total)`` after every run.
    first_mode : FirstMode, optional
        omega_1(L) of ``setup``'s finger (solved here when not given).
    spread : ccedi.design.robust.Spread, optional
        A spread of E and tan delta the surrogate must cover besides (:func:`catalogue_space`).

    Returns
    -------
    surrogate : Surrogate
        Over (alpha_per_s, length_m, youngs_modulus_Pa).
    first_mode : FirstMode
        omega_1(L).
    runs : pandas.DataFrame
        The ROM runs (:func:`ccedi.design.surrogate.run_rom`).
    cached : bool
        True when the runs were read from ``path``.

    Raises
    ------
    InputError
        A finger mesh, no compound, or a grid with fewer than 4 points along a variable.
    """
    first_mode = first_mode or FirstMode.of(setup, length_bounds_in)
    space = catalogue_space(compounds, first_mode, length_bounds_in, spread=spread)
    if len(shape) != 3 or min(shape) < 4:
        raise InputError(f"the catalogue grid needs 3 sizes >= 4 (alpha, L, E), got {tuple(shape)}")
    points = grid_points(space, shape)
    if path is None:
        runs, cached = run_rom(setup, points, damping=damping, progress=progress, variables=space), False
    else:
        runs, cached = cached_rom_runs(setup, points, path, damping=damping, progress=progress, variables=space)
    return Surrogate.fit(space, runs), first_mode, runs, cached


@dataclass
class CompoundDesign:
    """One compound's best design (:func:`design_compounds`).

    Parameters
    ----------
    compound : Compound
        The compound.
    tie : CompoundTie
        Its alpha over the length.
    problem : ccedi.design.optimise.DesignProblem
        Its problem (requirements shifted by the verification runs, when there were some).
    design : ccedi.design.optimise.Design
        The optimum, or the closest design when none meets the requirements.
    feasible : bool
        Whether a design meets the requirements.
    margins : dict
        {requirement: normalised margin} at ``design`` (>= 0: met).
    binding : list of str
        The requirements that bind (feasible) or are missed (infeasible).
    shortfall : float
        The largest normalised shortfall (0 when feasible).
    robust_margin : float
        The smallest margin over the loss-factor range at the design's length (NaN when
        that range leaves the surrogate's alpha range).
    robust_limit : str
        The requirement and loss factor of ``robust_margin``.
    verification : list of dict
        The ROM runs at the compound's own E and rho that verified the optimum.
    flags : list of str
        A variable on its bound (:func:`ccedi.design.optimise.on_bounds`).
    drum : ccedi.design.drum_speed.DrumSpeedCheck or None
        The fastest drum the design's finger allows (:func:`ccedi.design.drum_speed.with_drum_speeds`;
        None: not searched, or the design misses the requirements).
    """

    compound: Compound
    tie: CompoundTie
    problem: DesignProblem
    design: object
    feasible: bool
    margins: dict
    binding: list
    shortfall: float
    robust_margin: float
    robust_limit: str
    verification: list = field(default_factory=list)
    flags: list = field(default_factory=list)
    drum: object = None

    @property
    def objective_value(self):
        """The objective in its own unit at :attr:`design`."""
        return self.problem.objective_value(self.design.outputs)


def _robust(problem, tie, design, length_in):
    """(smallest margin, where) over the compound's loss-factor range at ``length_in``."""
    c = tie.compound
    va = problem.surrogate.variables[0]
    taus = np.unique(np.geomspace(c.tan_delta_min, c.tan_delta_max, 5)) if c.tan_delta_min > 0 else \
        np.unique(np.linspace(c.tan_delta_min, c.tan_delta_max, 5))
    alphas = np.array([CompoundTie(c, tie.first_mode, float(t))(length_in) for t in taus])
    if alphas.min() < va.lo * (1 - 1e-9) or alphas.max() > va.hi * (1 + 1e-9):
        return float("nan"), "loss-factor range outside the surrogate's alpha range"
    X = np.column_stack([alphas, np.full(len(alphas), design.x)])
    margins = problem.constraint_margins(problem.surrogate.evaluate(X), X[:, 0], X[:, 1])
    name, k = min(((n, int(np.argmin(m))) for n, m in margins.items()), key=lambda p: margins[p[0]][p[1]])
    return float(margins[name][k]), f"{name} at tan delta {taus[k]:.3g}"


def compound_setup(setup, compound: Compound):
    """``setup`` with the compound's nominal E and its density on the finger (its Poisson's
    ratio kept): the drum test a compound's ROM and FEA runs use.

    Parameters
    ----------
    setup : ccedi.fea.contact.drum.DrumSetup
        The drum test.
    compound : Compound
        The compound.

    Returns
    -------
    ccedi.fea.contact.drum.DrumSetup
    """
    return replace(setup, finger_material=NeoHookean(E=compound.E_nominal_Pa, nu=setup.finger_material.nu,
                                                     rho=compound.rho_kg_m3))


def _one(surrogate, compound, *, setup, first_mode, requirements, objective, model_error, verify, damping, n_starts):
    """The :class:`CompoundDesign` of ``compound``."""
    tie = CompoundTie(compound, first_mode)
    sliced = CompoundSurrogate(surrogate, E_Pa=compound.E_nominal_Pa, rho_kg_m3=compound.rho_kg_m3,
                               reference_rho_kg_m3=first_mode.rho_kg_m3)
    problem = DesignProblem(sliced, requirements=requirements or Requirements(), objective=objective, alpha_of_length=tie,
                            model_error=model_error or {})
    own = compound_setup(setup, compound)
    steps = []
    try:
        design, _ = solve(problem, n_starts=n_starts)
        if verify:
            design, problem, steps = verified_optimum(problem, own, damping=damping, n_starts=n_starts, start=design)
        feasible = True
    except RequirementsUnmet as err:
        problem = getattr(err, "problem", problem)
        steps = getattr(err, "steps", [])
        design, _ = closest_design(problem)
        feasible = False
    margins = {k: float(v) for k, v in problem.constraint_margins(design.outputs, design.alpha_per_s,
                                                                   design.x).items()}
    length_in = m_to_inch(design.x)
    robust, where = _robust(problem, tie, design, length_in)
    return CompoundDesign(
        compound=compound, tie=tie, problem=problem, design=design, feasible=feasible, margins=margins,
        binding=binding(problem, design) if feasible else [k for k, m in margins.items() if m < 0.0],
        shortfall=0.0 if feasible else float(max(-m for m in margins.values())),
        robust_margin=robust, robust_limit=where,
        verification=[{k: v for k, v in s.items() if k != "run"} for s in steps], flags=on_bounds(problem, design))


@dataclass
class CatalogueDesign:
    """The compounds ranked (:func:`design_compounds`).

    Parameters
    ----------
    designs : list of CompoundDesign
        In rank order: those that meet the requirements by the objective, then the others
        by their largest shortfall.
    objective : str
        The objective's name (:data:`ccedi.design.optimise.OBJECTIVES`).
    rank_by : {"objective", "fastest_drum"}, optional
        What orders the compounds that meet the requirements: their objective, or their
        fastest drum, fastest first (:func:`ccedi.design.drum_speed.with_drum_speeds`).
    """

    designs: list
    objective: str
    rank_by: str = "objective"

    @property
    def winner(self):
        """The first-ranked compound's design when it meets the requirements, else None."""
        return self.designs[0] if self.designs and self.designs[0].feasible else None

    @property
    def table(self):
        """The ranked table (pandas.DataFrame): rank, compound, feasible, E [Pa], rho
        [kg/m^3], tan delta, alpha [1/s], L [in], the objective and its unit, the binding
        (or missed) requirements, the largest shortfall, the robust margin, the margin
        of every requirement (``margin: <requirement>``), and, when the drum speeds were
        searched, each design's fastest drum [rpm] and the requirement that stops a faster
        one (``drum_binding``; "" when the fastest speed run holds)."""
        output = OBJECTIVES[self.objective]
        searched = any(d.drum is not None for d in self.designs)
        rows = []
        for rank, d in enumerate(self.designs, start=1):
            c = d.compound
            row = {"rank": rank, "compound": c.name, "feasible": d.feasible, "E_Pa": c.E_nominal_Pa,
                   "rho_kg_m3": c.rho_kg_m3, "tan_delta": d.tie.loss_factor, "alpha_per_s": d.design.alpha_per_s,
                   "length_in": float(m_to_inch(d.design.x)), "objective": d.objective_value,
                   "objective_unit": UNITS[output], "binding": "; ".join(d.binding),
                   "largest_shortfall": d.shortfall, "robust_margin": d.robust_margin}
            row.update({f"margin: {k}": v for k, v in d.margins.items()})
            if searched:
                row.update({"fastest_drum_rpm": None if d.drum is None else d.drum.fastest_rpm,
                            "drum_binding": None if d.drum is None else d.drum.binding})
            rows.append(row)
        return pd.DataFrame(rows)

    def as_dict(self):
        """JSON form: the objective, what ranks, the table's rows, and per compound its design
        (:meth:`ccedi.design.optimise.Design.as_dict`), the robust margin's requirement, its
        verification runs, flags and fastest drum (``drum_speed``, None when not searched).

        Returns
        -------
        dict
        """
        return {"objective": self.objective, "objective_output": OBJECTIVES[self.objective], "rank_by": self.rank_by,
                "table": self.table.to_dict(orient="records"),
                "designs": {d.compound.name: {"feasible": d.feasible, "tie": str(d.tie),
                                              "design": d.design.as_dict(d.problem), "robust_limit": d.robust_limit,
                                              "verification": d.verification, "flags": d.flags,
                                              "drum_speed": None if d.drum is None else d.drum.as_dict(),
                                              "requirements": [lim.describe() for lim in d.problem.limits]}
                            for d in self.designs},
                "winner": None if self.winner is None else self.winner.compound.name}


def design_compounds(surrogate, compounds, *, setup, first_mode, requirements=None, objective="object_force",
                     model_error=None, verify=True, damping="relative", n_starts=4):
    """Every compound's best design over the finger length, ranked (module docstring).

    Parameters
    ----------
    surrogate : Surrogate
        Over (alpha, L, E') at ``first_mode``'s reference density (:func:`catalogue_surrogate`).
    compounds : sequence of Compound
        The compounds (e.g. ``load_compounds().values()``).
    setup : ccedi.fea.contact.drum.DrumSetup
        The drum test the surrogate was built on (the verification runs put each
        compound's E and rho on its finger).
    first_mode : FirstMode
        omega_1(L) of the set-up's finger.
    requirements : ccedi.design.requirements.Requirements, optional
        The requirements (default: their documented defaults).
    objective : str, optional
        One of :data:`ccedi.design.optimise.OBJECTIVES` but "throughput" (the length is
        the variable).
    model_error : dict, optional
        ``{output: ModelError}`` over (alpha, L) carried on every compound's requirements.
    verify : bool, optional
        Verify each optimum with the ROM at the compound's own E and rho
        (:func:`ccedi.design.recheck.verified_optimum`).
    damping : {"relative", "global"}, optional
        The surrogate's damping kind.
    n_starts : int, optional
        IPOPT starts per compound.

    Returns
    -------
    CatalogueDesign

    Raises
    ------
    InputError
        No compound, two compounds of one name, a weighted objective (the ranking needs an
        objective in a unit) or another the problem refuses, or a compound outside the
        surrogate's range.
    """
    compounds = list(compounds)
    if not compounds:
        raise InputError("the compound design needs at least one compound, got none")
    names = [c.name for c in compounds]
    if len(set(names)) != len(names):
        raise InputError(f"compound names must be unique, got {names}")
    if objective not in OBJECTIVES:
        raise InputError(f"the compound ranking compares an objective with a unit: one of {', '.join(OBJECTIVES)}, "
                         f"got {objective!r}")
    designs = [_one(surrogate, c, setup=setup, first_mode=first_mode, requirements=requirements,
                    objective=objective, model_error=model_error, verify=verify, damping=damping, n_starts=n_starts)
               for c in compounds]
    designs.sort(key=lambda d: (not d.feasible, d.objective_value if d.feasible else d.shortfall))
    return CatalogueDesign(designs, objective)
