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

The section's semi-thickness b (along the bending direction) may be a design variable too
(:func:`catalogue_surrogate` with ``semi_thickness_bounds_mm``): the ROM runs on a grid over
(alpha, L, E', b), the first mode is fitted over (L, b) (:class:`FirstMode`), and each
compound's design varies (L, b) on alpha = tan delta x omega_1(L, b). Its optimum is found
as a profile: the design over the length (IPOPT and the brute-force grid, as above) is
solved at :data:`THICKNESS_SCAN` semi-thicknesses, evenly over the range and then across
the best one's neighbouring intervals (so b is resolved to a 48th of its range by default),
the best of them kept (the least objective among those that meet the requirements, else the
least largest shortfall) and verified by the ROM built at that section. The semi-width a
stays the set-up's.
"""
from dataclasses import dataclass, field, replace

import casadi as ca
import numpy as np
import pandas as pd

from ccedi.errors import InputError, RequirementsUnmet
from ccedi.fea.contact.drum import finger_mesh
from ccedi.fea.material import NeoHookean
from ccedi.rom.finger_identification import finger_omega1
from ccedi.units import inch_to_m, m_to_inch

from .compounds import Compound, alpha_from_loss_factor
from .optimise import OBJECTIVES, DesignProblem, binding, bound_flag, closest_design, on_bounds, solve
from .outputs import UNITS, density_scaled, setup_for_section
from .recheck import verified_optimum
from .requirements import Requirements
from .surrogate import Surrogate, cached_rom_runs, grid_points, material_space, run_rom, section_space

CATALOGUE_GRID = (15, 11, 6)
"""Default ROM grid of the catalogue surrogate: points along alpha, L and E."""

MATERIAL_NAMES = ("alpha_per_s", "length_m", "youngs_modulus_Pa")
"""The catalogue surrogate's variables (:func:`ccedi.design.surrogate.material_space`);
the semi-thickness follows them when the section is designed too."""

RANGE_PAD = 1.05
"""Factor the catalogue's alpha and E ranges are widened by on each side."""

FIRST_MODE_LENGTHS = 5
"""FE eigen solves of the first mode over the length range (:class:`FirstMode`)."""

FIRST_MODE_THICKNESSES = 4
"""FE eigen solves of the first mode over the semi-thickness range, at each length."""

COMPOUND_THICKNESS_MM = (4.0, 12.0)
"""Default semi-thickness range of the compound design over the section [mm]: from the
section design's lower bound (:data:`ccedi.design.surrogate.SECTION_BOUNDS_MM`) up to the
paper's semi-width a = 12 mm. A finger thicker than it is wide has its first mode bending
across (along a), while the tie alpha = tan delta x omega_1 and the drum load follow the
bending along b (:meth:`FirstMode.of` refuses b above a)."""

CATALOGUE_SECTION_GRID = (9, 7, 4, 4)
"""Default ROM grid of the catalogue surrogate over the section too: points along alpha,
L, E and the semi-thickness b (one model build per (L, E, b))."""

THICKNESS_SCAN = (13, 9)
"""Semi-thicknesses a compound's design is solved at over the section (:func:`design_compounds`):
evenly over the range, then across the best one's two neighbouring intervals."""


@dataclass(frozen=True)
class FirstMode:
    """omega_1(L) of the clamped generated finger [rad/s], any E and rho: ln omega_1 quadratic
    in ln L through FE eigen solves at a reference material
    (:func:`ccedi.rom.finger_identification.finger_omega1`), scaled by sqrt(E / rho) (the
    linearised stiffness is proportional to E, the mass to rho). Fitted over the section's
    semi-thickness b as well (``semi_thickness_bounds_mm``), omega_1(L, b): ln omega_1
    quadratic in (ln L, ln b), its cross term included (a slender cantilever's
    omega_1 ~ b / L^2; the fit carries the departures of a stubby one).

    Parameters
    ----------
    coefficients : tuple of float
        (c2, c1, c0) of ln omega_1 = c2 (ln L)^2 + c1 ln L + c0, L in inches, at the
        reference material; over the section too, (c2, c1, c0, d1, d2, e) of
        ln omega_1 = c2 x^2 + c1 x + c0 + d1 y + d2 y^2 + e x y, x = ln L [in],
        y = ln b [mm].
    E_Pa : float
        Reference Young's modulus [Pa].
    rho_kg_m3 : float
        Reference density [kg/m^3].
    length_bounds_in : tuple of float
        The lengths the fit spans [in].
    fit_error : float
        Largest relative error of the fit at the solved points [-].
    semi_thickness_bounds_mm : tuple of float or None, optional
        The semi-thicknesses the fit spans [mm]; None: fitted at the set-up's section.
    """

    coefficients: tuple
    E_Pa: float
    rho_kg_m3: float
    length_bounds_in: tuple
    fit_error: float
    semi_thickness_bounds_mm: tuple | None = None

    @classmethod
    def of(cls, setup, length_bounds_in, n=FIRST_MODE_LENGTHS, *, semi_thickness_bounds_mm=None,
           n_thickness=FIRST_MODE_THICKNESSES):
        """The first mode of ``setup``'s generated finger (its material, section and taper,
        :func:`ccedi.fea.contact.drum.finger_mesh`) over
        ``length_bounds_in`` [in], from ``n`` FE eigen solves; over the semi-thickness too
        when ``semi_thickness_bounds_mm`` is given, from an ``n`` x ``n_thickness`` grid.

        Parameters
        ----------
        setup : ccedi.fea.contact.drum.DrumSetup
            The set-up (``finger_material``, ``finger_semi_axes_m``: its semi-width a is
            kept when b varies).
        length_bounds_in : tuple of float
            (lo, hi) [in].
        n : int, optional
            Lengths solved, >= 3.
        semi_thickness_bounds_mm : tuple of float, optional
            (lo, hi) of the semi-thickness b [mm], 0 < lo < hi.
        n_thickness : int, optional
            Semi-thicknesses solved, >= 3.

        Returns
        -------
        FirstMode

        Raises
        ------
        InputError
            A finger given as a mesh (its length is fixed), fewer than 3 lengths or
            semi-thicknesses, or semi-thickness bounds not 0 < lo < hi <= the set-up's
            semi-width a (:data:`COMPOUND_THICKNESS_MM`).
        """
        if setup.finger is not None:
            raise InputError(f"the compound design varies the finger length; the finger is a given "
                             f"{setup.finger.element_type} mesh of fixed length: design it with ccedi design "
                             "--vary drum_speed")
        if n < 3 or n_thickness < 3:
            raise InputError(f"first-mode lengths and semi-thicknesses must be >= 3, got {n} and {n_thickness}")
        m = setup.finger_material
        a, b0 = setup.finger_semi_axes_m
        lengths = np.linspace(*length_bounds_in, n)
        if semi_thickness_bounds_mm is None:
            points = [(x, 1e3 * b0) for x in lengths]
        else:
            lo, hi = semi_thickness_bounds_mm
            if not 0.0 < lo < hi <= 1e3 * a * (1 + 1e-9):
                raise InputError(f"semi-thickness bounds {lo!r}-{hi!r} mm: must be 0 < lo < hi <= the semi-width "
                                 f"a = {1e3 * a:.4g} mm (a thicker finger's first mode bends across, along a)")
            points = [(x, y) for x in lengths for y in np.linspace(lo, hi, n_thickness)]
        omega = np.array([finger_omega1(mesh=finger_mesh(replace(setup, finger_length_m=inch_to_m(x),
                                                                 finger_semi_axes_m=(a, 1e-3 * y))), material=m)
                          for x, y in points])
        x, y = np.log(np.array(points)).T
        terms = _terms(x, y)[: 3 if semi_thickness_bounds_mm is None else 6]
        c = np.linalg.lstsq(np.column_stack(terms), np.log(omega), rcond=None)[0]
        mode = cls(tuple(float(v) for v in c), float(m.E), float(m.rho), tuple(map(float, length_bounds_in)), 0.0,
                   None if semi_thickness_bounds_mm is None else tuple(map(float, semi_thickness_bounds_mm)))
        b = None if semi_thickness_bounds_mm is None else 1e-3 * np.exp(y)
        fit = mode(np.exp(x), E_Pa=m.E, rho_kg_m3=m.rho, semi_thickness_m=b)
        return replace(mode, fit_error=float(np.max(np.abs(fit / omega - 1.0))))

    def __call__(self, length_in, *, E_Pa, rho_kg_m3, semi_thickness_m=None):
        """omega_1 [rad/s] of the finger of ``length_in`` [in] (numpy or casadi) of E and rho
        (and, for a mode fitted over the section, of semi-thickness ``semi_thickness_m``).

        Parameters
        ----------
        length_in : float, numpy.ndarray or casadi expression
            Finger length [in].
        E_Pa : float
            Young's modulus [Pa].
        rho_kg_m3 : float
            Density [kg/m^3].
        semi_thickness_m : float or numpy.ndarray, optional
            Semi-thickness b [m]: required by a mode fitted over the section, refused by
            one fitted at a single section.

        Returns
        -------
        Same type as ``length_in``.

        Raises
        ------
        InputError
            ``semi_thickness_m`` given to a mode of one section, or missing for one over
            the section.
        """
        over_section = self.semi_thickness_bounds_mm is not None
        if over_section != (semi_thickness_m is not None):
            raise InputError("this first mode was fitted " + ("over the semi-thickness: give semi_thickness_m"
                                                              if over_section else
                                                              "at one section: it takes no semi_thickness_m"))
        symbolic = isinstance(length_in, (ca.SX, ca.MX))
        x = ca.log(length_in) if symbolic else np.log(length_in)
        y = 0.0 if semi_thickness_m is None else np.log(1e3 * np.asarray(semi_thickness_m, dtype=float))
        y = float(y) if np.ndim(y) == 0 else y                 # a plain number beside a casadi length
        ln_w = sum(c * t for c, t in zip(self.coefficients, _terms(x, y)))
        return (ca.exp if symbolic else np.exp)(ln_w) * np.sqrt((E_Pa / rho_kg_m3) / (self.E_Pa / self.rho_kg_m3))


def _terms(x, y):
    """The terms of :class:`FirstMode`'s fit in x = ln L and y = ln b, in coefficient order."""
    return [x * x, x, 1.0 + 0.0 * x, y, y * y, x * y]


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
    semi_thickness_m : float or None, optional
        The section's semi-thickness b [m] when ``first_mode`` is fitted over it (None: the
        set-up's section, a mode of one section).
    """

    compound: Compound
    first_mode: FirstMode
    tan_delta: float | None = None
    semi_thickness_m: float | None = None

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
                                                                        rho_kg_m3=c.rho_kg_m3,
                                                                        semi_thickness_m=self.semi_thickness_m))

    def __str__(self):
        at = "" if self.semi_thickness_m is None else f" at b = {1e3 * self.semi_thickness_m:.4g} mm"
        return f"{self.compound.name}: tan delta {self.loss_factor:.4g} x omega_1(L){at}"


class CompoundSurrogate(Surrogate):
    """A catalogue surrogate over (alpha, L, E) at density rho_0 (:func:`catalogue_surrogate`)
    seen by a finger of Young's modulus ``E_Pa`` and density ``rho_kg_m3``: a surrogate over
    (alpha, L) at E' = E rho_0 / rho, its :data:`ccedi.design.outputs.DENSITY_SCALED` outputs
    times rho / rho_0 (module docstring); over (alpha, L, E, b), at the semi-thickness
    ``semi_thickness_m`` as well.

    Parameters
    ----------
    surrogate : Surrogate
        Over (alpha_per_s, length_m, youngs_modulus_Pa[, semi_thickness_m]), built at density
        ``reference_rho_kg_m3``.
    E_Pa : float
        The finger's Young's modulus [Pa].
    rho_kg_m3 : float
        Its density [kg/m^3].
    reference_rho_kg_m3 : float
        The density the surrogate was built at [kg/m^3].
    semi_thickness_m : float, optional
        The section's semi-thickness b [m]: required by a surrogate over b, refused otherwise.

    Raises
    ------
    InputError
        ``surrogate`` not over (alpha, L, E[, b]), E' or b outside its range, or b given to
        (or missing for) the surrogate.
    """

    def __init__(self, surrogate, *, E_Pa, rho_kg_m3, reference_rho_kg_m3, semi_thickness_m=None):
        names = tuple(v.name for v in surrogate.variables)
        if names not in (MATERIAL_NAMES, (*MATERIAL_NAMES, "semi_thickness_m")):
            raise InputError(f"a compound surrogate needs a surrogate over (alpha_per_s, length_m, youngs_modulus_Pa"
                             f"[, semi_thickness_m]), got {names}")
        if (len(names) == 4) != (semi_thickness_m is not None):
            raise InputError("a compound surrogate over the semi-thickness needs semi_thickness_m, and one without it "
                             f"takes none; got {semi_thickness_m!r} for a surrogate over {names}")
        var_E = surrogate.variables[2]
        self.base = surrogate
        self.density_ratio = float(rho_kg_m3 / reference_rho_kg_m3)
        self.E_equivalent_Pa = float(E_Pa / self.density_ratio)
        if not var_E.lo * (1 - 1e-9) <= self.E_equivalent_Pa <= var_E.hi * (1 + 1e-9):
            raise InputError(f"E = {E_Pa / 1e6:.4g} MPa at rho = {rho_kg_m3:.4g} kg/m^3 is E' = "
                             f"{self.E_equivalent_Pa / 1e6:.4g} MPa at the surrogate's density "
                             f"{reference_rho_kg_m3:.4g} kg/m^3, outside its E range {var_E.lo / 1e6:.4g}-"
                             f"{var_E.hi / 1e6:.4g} MPa: build the surrogate over the catalogue (catalogue_surrogate)")
        self.u_fixed = [float(var_E.to_unit(self.E_equivalent_Pa))]
        if semi_thickness_m is not None:
            var_b = surrogate.variables[3]
            if not var_b.lo * (1 - 1e-9) <= semi_thickness_m <= var_b.hi * (1 + 1e-9):
                raise InputError(f"semi-thickness b = {1e3 * semi_thickness_m:.4g} mm: outside the surrogate's range "
                                 f"{1e3 * var_b.lo:.4g}-{1e3 * var_b.hi:.4g} mm")
            self.u_fixed.append(float(var_b.to_unit(semi_thickness_m)))
        self.variables = surrogate.variables[:2]
        self.axes = surrogate.axes[:2]
        self.values = {}
        self.outputs = surrogate.outputs
        self.nonnegative = surrogate.nonnegative
        self._compile()

    def unit_expressions(self, us):
        """{output: expression} at the unit coordinates ``us`` of (alpha, L), at this
        finger's E and rho (and semi-thickness).

        Parameters
        ----------
        us : sequence
            Unit coordinates of alpha and L.

        Returns
        -------
        dict
        """
        out = self.base.unit_expressions([*us, *self.u_fixed])
        return density_scaled(out, self.density_ratio)


def catalogue_space(compounds, first_mode, length_bounds_in, *, spread=None):
    """The (alpha, L, E') variables that hold every compound of ``compounds``: alpha over
    their loss-factor ranges at every length, E' their nominal moduli at the first mode's
    reference density, both widened by :data:`RANGE_PAD` (and rounded to 4 digits), and
    by a spread of E and the loss factor about their nominal values when one is given (a
    robust design's samples, :class:`ccedi.design.robust.Spread`). With a first mode
    fitted over the semi-thickness b, the variables are (alpha, L, E', b), alpha over every
    length and b of its range.

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
    section = first_mode.semi_thickness_bounds_mm
    lengths, thicknesses = np.meshgrid(np.asarray(length_bounds_in, dtype=float),
                                       [None] if section is None else 1e-3 * np.asarray(section), indexing="ij")
    alphas, moduli = [], []
    e, t = (0.0, 0.0) if spread is None else (spread.E_relative, spread.tan_delta_relative)
    for c in compounds:
        w = np.array([first_mode(x, E_Pa=c.E_nominal_Pa, rho_kg_m3=c.rho_kg_m3, semi_thickness_m=b)
                      for x, b in zip(lengths.ravel(), thicknesses.ravel())])
        alphas += [min(c.tan_delta_min, c.tan_delta_nominal * (1 - t)) * w.min() * np.sqrt(1 - e),
                   max(c.tan_delta_max, c.tan_delta_nominal * (1 + t)) * w.max() * np.sqrt(1 + e)]
        moduli += [c.E_nominal_Pa * (1 - e) * first_mode.rho_kg_m3 / c.rho_kg_m3,
                   c.E_nominal_Pa * (1 + e) * first_mode.rho_kg_m3 / c.rho_kg_m3]
    bounds = [_rounded(f(v) * RANGE_PAD ** k) for v in (alphas, moduli) for f, k in ((min, -1), (max, 1))]
    space = material_space(tuple(bounds[:2]), tuple(length_bounds_in), tuple(bounds[2:]))
    return space if section is None else (*space, section_space(semi_axis="semi_thickness_m", bounds_mm=section)[1])


def _rounded(x):
    """``x`` to 4 significant digits: the bounds, and with them the grid a ROM cache is
    keyed on, do not move with the eigen solver's last digits."""
    return float(f"{x:.4g}")


def catalogue_surrogate(setup, compounds, *, length_bounds_in=(3.0, 8.0), shape=None, damping="relative",
                        path=None, progress=None, first_mode=None, spread=None, semi_thickness_bounds_mm=None):
    """The ROM surrogate over (alpha, L, E') that serves every compound of ``compounds``
    (:func:`catalogue_space`), at ``setup``'s density; over (alpha, L, E', b) with
    ``semi_thickness_bounds_mm``, the section's semi-thickness b a design variable too (the
    ROM built at every (L, E', b) of the grid; the semi-width a stays the set-up's).

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
        ROM runs along alpha, L and E' (and b), each >= 4 (default :data:`CATALOGUE_GRID`,
        over the section :data:`CATALOGUE_SECTION_GRID`).
    damping : {"relative", "global"}, optional
        Damping kind of every run.
    path : pathlib.Path, optional
        CSV cache of the runs (:func:`ccedi.design.surrogate.cached_rom_runs`); None: no cache.
    progress : callable, optional
        ``progress(done, total)`` after every run.
    first_mode : FirstMode, optional
        omega_1(L) (or omega_1(L, b)) of ``setup``'s finger (solved here when not given).
    spread : ccedi.design.robust.Spread, optional
        A spread of E and tan delta the surrogate must cover besides (:func:`catalogue_space`).
    semi_thickness_bounds_mm : tuple of float, optional
        (lo, hi) of the semi-thickness b [mm], hi at most the set-up's semi-width (e.g.
        :data:`COMPOUND_THICKNESS_MM`); None: the set-up's section.

    Returns
    -------
    surrogate : Surrogate
        Over (alpha_per_s, length_m, youngs_modulus_Pa[, semi_thickness_m]).
    first_mode : FirstMode
        omega_1(L) (or omega_1(L, b)).
    runs : pandas.DataFrame
        The ROM runs (:func:`ccedi.design.surrogate.run_rom`).
    cached : bool
        True when the runs were read from ``path``.

    Raises
    ------
    InputError
        A finger mesh, no compound, a grid with fewer than 4 points along a variable, bad
        semi-thickness bounds, or a first mode fitted over other semi-thicknesses.
    """
    first_mode = first_mode or FirstMode.of(setup, length_bounds_in, semi_thickness_bounds_mm=semi_thickness_bounds_mm)
    section = None if semi_thickness_bounds_mm is None else tuple(map(float, semi_thickness_bounds_mm))
    if first_mode.semi_thickness_bounds_mm != section:
        raise InputError(f"the first mode was fitted over semi-thicknesses {first_mode.semi_thickness_bounds_mm} mm, "
                         f"the surrogate asked over {section} mm: fit it over the same (FirstMode.of)")
    space = catalogue_space(compounds, first_mode, length_bounds_in, spread=spread)
    shape = tuple(shape or (CATALOGUE_GRID if section is None else CATALOGUE_SECTION_GRID))
    if len(shape) != len(space) or min(shape) < 4:
        raise InputError(f"the catalogue grid needs {len(space)} sizes >= 4 "
                         f"({', '.join(v.label for v in space)}), got {shape}")
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

    @property
    def semi_thickness_m(self):
        """The section's semi-thickness b of the design [m] (None: the set-up's section)."""
        return self.tie.semi_thickness_m


def _robust(problem, tie, design, length_in):
    """(smallest margin, where) over the compound's loss-factor range at ``length_in``."""
    c = tie.compound
    va = problem.surrogate.variables[0]
    taus = np.unique(np.geomspace(c.tan_delta_min, c.tan_delta_max, 5)) if c.tan_delta_min > 0 else \
        np.unique(np.linspace(c.tan_delta_min, c.tan_delta_max, 5))
    alphas = np.array([CompoundTie(c, tie.first_mode, float(t), tie.semi_thickness_m)(length_in) for t in taus])
    if alphas.min() < va.lo * (1 - 1e-9) or alphas.max() > va.hi * (1 + 1e-9):
        return float("nan"), "loss-factor range outside the surrogate's alpha range"
    X = np.column_stack([alphas, np.full(len(alphas), design.x)])
    margins = problem.constraint_margins(problem.surrogate.evaluate(X), X[:, 0], X[:, 1])
    name, k = min(((n, int(np.argmin(m))) for n, m in margins.items()), key=lambda p: margins[p[0]][p[1]])
    return float(margins[name][k]), f"{name} at tan delta {taus[k]:.3g}"


def compound_setup(setup, compound: Compound, semi_thickness_m=None):
    """``setup`` with the compound's nominal E and its density on the finger (its Poisson's
    ratio kept), and the section's semi-thickness when one is given: the drum test a
    compound's ROM and FEA runs use.

    Parameters
    ----------
    setup : ccedi.fea.contact.drum.DrumSetup
        The drum test.
    compound : Compound
        The compound.
    semi_thickness_m : float, optional
        The section's semi-thickness b [m] (default: the set-up's).

    Returns
    -------
    ccedi.fea.contact.drum.DrumSetup
    """
    own = replace(setup, finger_material=NeoHookean(E=compound.E_nominal_Pa, nu=setup.finger_material.nu,
                                                    rho=compound.rho_kg_m3))
    return own if semi_thickness_m is None else setup_for_section(own, semi_thickness_m=semi_thickness_m)


def _problem(surrogate, compound, *, first_mode, semi_thickness_m, requirements, objective, model_error):
    """The compound's tie and design problem over the length (at ``semi_thickness_m`` on a
    surrogate over the section)."""
    tie = CompoundTie(compound, first_mode, semi_thickness_m=semi_thickness_m)
    sliced = CompoundSurrogate(surrogate, E_Pa=compound.E_nominal_Pa, rho_kg_m3=compound.rho_kg_m3,
                               reference_rho_kg_m3=first_mode.rho_kg_m3, semi_thickness_m=semi_thickness_m)
    return tie, DesignProblem(sliced, requirements=requirements or Requirements(), objective=objective,
                              alpha_of_length=tie, model_error=model_error or {})


def _rank_key(problem, n_starts):
    """(missed, objective or largest shortfall) of the problem's optimum on its surrogate:
    the smaller, the better."""
    try:
        design, _ = solve(problem, n_starts=n_starts)
        return False, problem.objective_value(design.outputs)
    except RequirementsUnmet:
        design, _ = closest_design(problem)
        margins = problem.constraint_margins(design.outputs, design.alpha_per_s, design.x)
        return True, float(max(-m for m in margins.values()))


def _best_thickness(surrogate, compound, n_starts, **kwargs):
    """The semi-thickness [m] of the compound's best design over (L, b): the design over
    the length solved at :data:`THICKNESS_SCAN` semi-thicknesses, evenly over the range, then
    across the best one's neighbouring intervals; the best feasible by the objective, else
    the least largest shortfall."""
    var_b = surrogate.variables[3]
    n_even, n_fine = THICKNESS_SCAN
    tried = {}

    def scan(values):
        for b in values:
            b = float(np.clip(b, var_b.lo, var_b.hi))
            if b not in tried:
                tried[b] = _rank_key(_problem(surrogate, compound, semi_thickness_m=b, **kwargs)[1], n_starts)
        return min(tried, key=tried.get)

    step = (var_b.hi - var_b.lo) / (n_even - 1)
    best = scan(np.linspace(var_b.lo, var_b.hi, n_even))
    return scan(np.linspace(best - step, best + step, n_fine))


def _one(surrogate, compound, *, setup, first_mode, requirements, objective, model_error, verify, damping, n_starts):
    """The :class:`CompoundDesign` of ``compound`` (over the section too on a surrogate over it)."""
    kwargs = {"first_mode": first_mode, "requirements": requirements, "objective": objective,
              "model_error": model_error}
    b = _best_thickness(surrogate, compound, n_starts, **kwargs) if len(surrogate.variables) == 4 else None
    tie, problem = _problem(surrogate, compound, semi_thickness_m=b, **kwargs)
    own = compound_setup(setup, compound, semi_thickness_m=b)
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
        verification=[{k: v for k, v in s.items() if k != "run"} for s in steps],
        flags=on_bounds(problem, design) + _thickness_on_bounds(surrogate, b))


def _thickness_on_bounds(surrogate, semi_thickness_m):
    """["b at its lower bound 4 mm"] when the chosen semi-thickness sits on a bound of the
    surrogate's (:func:`ccedi.design.optimise.bound_flag`), else []."""
    flag = None if semi_thickness_m is None else bound_flag(surrogate.variables[3], semi_thickness_m)
    return [flag] if flag else []


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
        [kg/m^3], tan delta, alpha [1/s], L [in], the semi-thickness b [mm] when the
        section is designed too, the objective and its unit, the binding
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
            if d.semi_thickness_m is not None:
                row["semi_thickness_mm"] = 1e3 * d.semi_thickness_m
            row.update({f"margin: {k}": v for k, v in d.margins.items()})
            if searched:
                row.update({"fastest_drum_rpm": None if d.drum is None else d.drum.fastest_rpm,
                            "drum_binding": None if d.drum is None else d.drum.binding})
            rows.append(row)
        return pd.DataFrame(rows)

    def as_dict(self):
        """JSON form: the objective, what ranks, the table's rows, and per compound its design
        (:meth:`ccedi.design.optimise.Design.as_dict`), the robust margin's requirement, its
        verification runs, flags, fastest drum (``drum_speed``, None when not searched) and
        semi-thickness (``semi_thickness_mm``, None when the section is the set-up's).

        Returns
        -------
        dict
        """
        return {"objective": self.objective, "objective_output": OBJECTIVES[self.objective], "rank_by": self.rank_by,
                "table": self.table.to_dict(orient="records"),
                "designs": {d.compound.name: {"feasible": d.feasible, "tie": str(d.tie),
                                              "design": d.design.as_dict(d.problem),
                                              "semi_thickness_mm": None if d.semi_thickness_m is None
                                              else 1e3 * d.semi_thickness_m, "robust_limit": d.robust_limit,
                                              "verification": d.verification, "flags": d.flags,
                                              "drum_speed": None if d.drum is None else d.drum.as_dict(),
                                              "requirements": [lim.describe() for lim in d.problem.limits]}
                            for d in self.designs},
                "winner": None if self.winner is None else self.winner.compound.name}


def design_compounds(surrogate, compounds, *, setup, first_mode, requirements=None, objective="object_force",
                     model_error=None, verify=True, damping="relative", n_starts=4):
    """Every compound's best design over the finger length (and the section's semi-thickness
    on a surrogate over it), ranked (module docstring).

    Parameters
    ----------
    surrogate : Surrogate
        Over (alpha, L, E') or (alpha, L, E', b) at ``first_mode``'s reference density
        (:func:`catalogue_surrogate`).
    compounds : sequence of Compound
        The compounds (e.g. ``load_compounds().values()``).
    setup : ccedi.fea.contact.drum.DrumSetup
        The drum test the surrogate was built on (the verification runs put each
        compound's E and rho on its finger).
    first_mode : FirstMode
        omega_1(L) (or omega_1(L, b), with a surrogate over b) of the set-up's finger.
    requirements : ccedi.design.requirements.Requirements, optional
        The requirements (default: their documented defaults).
    objective : str, optional
        One of :data:`ccedi.design.optimise.OBJECTIVES` but "throughput" (the length is
        the variable).
    model_error : dict, optional
        ``{output: ModelError}`` over (alpha, L) carried on every compound's requirements.
    verify : bool, optional
        Verify each optimum with the ROM at the compound's own E and rho (and chosen b)
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
