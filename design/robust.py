"""Robust design over a compound's batch spread: the finger length whose design meets every
requirement with a chosen probability when the compound's Young's modulus and loss factor
are only known within their spread.

The uncertain inputs come in one of two forms. :class:`Spread`: E uniform within
E_nominal (1 +- ``E_relative``) and tan delta uniform within tan_delta_nominal
(1 +- ``tan_delta_relative``) (defaults +-15 % and +-30 %, the batch-to-batch spread of a
compound), independent. :class:`CalibratedSpread`: E and alpha jointly normal with the
relative standard errors and the correlation a CCEDI calibration reports
(:meth:`CalibratedSpread.from_calibration`), truncated at ``truncation`` standard
deviations; a sample's loss factor is its alpha over the calibrated finger's first mode at
the sample's E (omega_1 ~ sqrt(E)), so tan delta = tan_delta_nominal (alpha / alpha_0) /
sqrt(E / E_0). Either is applied about the compound's nominal values. A sample of the
finger has alpha = tan delta x omega_1(L; E, rho) (the compound's tie at its own E) and is
evaluated on the catalogue surrogate (:func:`ccedi.design.catalogue_design.catalogue_surrogate`,
built wide enough: ``catalogue_space(..., spread=)``) at E' = E rho_0 / rho, its force
and stress outputs scaled by rho / rho_0, as a compound's nominal design is.

A requirement's violation probability at a length is the fraction of ``n_samples`` samples
whose margin (:meth:`ccedi.design.optimise.DesignProblem.constraint_margins`, with the
problem's model-error tightening) is negative; the same samples at every length (common
random numbers), so the fractions are smooth in L. The robust design is the length of
least objective, at the compound's nominal E and tan delta, among those where every
requirement's violation probability is at most 1 - ``probability`` (default 95 %: at most
5 %), searched on a grid over the surrogate's length range.

The margin a requirement keeps (:class:`SpreadCheck`) is the (1 - probability) quantile of
its normalised margin over the samples: with the chosen probability the requirement is met
with at least that margin (negative: missed that often). Over a catalogue
(:func:`robust_catalogue`) every compound's robust design is found and the compounds rank
by their robust objective, those with no robust length after them by their largest
violation probability; each keeps the check of its nominal optimum beside, so that the
nominal and the robust design are shown side by side.

When the compound design varies the section's semi-thickness b too
(:func:`ccedi.design.catalogue_design.catalogue_surrogate` with ``semi_thickness_bounds_mm``),
the robust design holds b at the compound's nominal optimum and searches the length alone
(its samples' first mode and the surrogate taken at that b): a robust search over (L, b)
would cost the scan over b of the nominal design times the samples, and the spread of E
and tan delta moves the finger's stiffness and damping, which a change of length answers
as well as one of thickness.

The surrogate's probabilities are estimates; a full-FEA Monte Carlo at the robust and the
nominal optimum is the check (benchmarks/robust_design_monte_carlo.py).
"""
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ccedi.errors import InputError
from ccedi.units import m_to_inch

from .catalogue_design import CatalogueDesign, CompoundDesign
from .compounds import alpha_from_loss_factor
from .optimise import OBJECTIVES, Design
from .outputs import density_scaled

N_SAMPLES = 400
"""Samples of the uncertain inputs (a 5 % probability then has a binomial std of 1.1 %)."""
N_LENGTHS = 81
"""Lengths searched over the surrogate's length range."""


@dataclass(frozen=True)
class Spread:
    """How far a compound's inputs may lie from their nominal values (uniform, independent).

    Parameters
    ----------
    E_relative : float, optional
        Half-width of Young's modulus, a fraction of the nominal [-], in [0, 0.9). Default 0.15.
    tan_delta_relative : float, optional
        Half-width of the loss factor, a fraction of the nominal [-], in [0, 0.9). Default 0.30.

    Raises
    ------
    InputError
        A half-width outside [0, 0.9).
    """

    E_relative: float = 0.15
    tan_delta_relative: float = 0.30

    def __post_init__(self):
        for name in ("E_relative", "tan_delta_relative"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and 0.0 <= value < 0.9):
                raise InputError(f"Spread {name} = {value!r}: must be a fraction in [0, 0.9)")

    def samples(self, compound, n, seed=0):
        """Samples of a compound's E and loss factor.

        Parameters
        ----------
        compound : ccedi.design.compounds.Compound
            The compound (its nominal E and tan delta).
        n : int
            Number of samples, >= 1.
        seed : int, optional
            Random seed. Default 0.

        Returns
        -------
        E_Pa : numpy.ndarray
            (n,) Young's moduli [Pa].
        tan_delta : numpy.ndarray
            (n,) loss factors [-].
        """
        u = np.random.default_rng(seed).uniform(-1.0, 1.0, (2, int(n)))
        return (compound.E_nominal_Pa * (1.0 + self.E_relative * u[0]),
                compound.tan_delta_nominal * (1.0 + self.tan_delta_relative * u[1]))

    def describe(self):
        """The spread in words, for the report.

        Returns
        -------
        str
        """
        return f"E +-{self.E_relative:.0%} and tan delta +-{self.tan_delta_relative:.0%} (uniform, independent)"


@dataclass(frozen=True)
class CalibratedSpread:
    """E and alpha jointly normal with the relative standard errors and the correlation a
    calibration reports, truncated at ``truncation`` standard deviations (module docstring).

    Parameters
    ----------
    E_relative_std : float
        Standard error of E over E [-], in [0, 0.3].
    alpha_relative_std : float
        Standard error of alpha over alpha [-], in [0, 0.3].
    correlation : float
        Correlation of E and alpha [-], in [-1, 1].
    truncation : float, optional
        Samples are drawn within this many standard deviations [-], in [1, 5]. Default 3.
    source : str, optional
        Where the figures come from (the calibration's result file).

    Raises
    ------
    InputError
        A figure outside its range, or a truncation that reaches 90 % of E or alpha.
    """

    E_relative_std: float
    alpha_relative_std: float
    correlation: float
    truncation: float = 3.0
    source: str = ""

    def __post_init__(self):
        for name, lo, hi in (("E_relative_std", 0.0, 0.3), ("alpha_relative_std", 0.0, 0.3),
                             ("correlation", -1.0, 1.0), ("truncation", 1.0, 5.0)):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and np.isfinite(value) and lo <= value <= hi):
                raise InputError(f"CalibratedSpread {name} = {value!r}: must be in [{lo:g}, {hi:g}]")
        if self.truncation * max(self.E_relative_std, self.alpha_relative_std) >= 0.9:
            raise InputError(f"CalibratedSpread: {self.truncation:g} standard errors of E ({self.E_relative_std:.3g}) "
                             f"or alpha ({self.alpha_relative_std:.3g}) reach 90 % of the value: a calibration this "
                             "uncertain does not bound the design")

    @classmethod
    def from_calibration(cls, result, *, truncation=3.0):
        """The spread of a calibration's E and alpha (the ``final_params``, ``final_stderr``
        and ``final_correlation`` of ``ccedi calibrate``'s result JSON: E as ``E_factor``
        times the declared E, alpha as ``alpha_per_s``).

        Parameters
        ----------
        result : dict, str or pathlib.Path
            The calibration result, or the path of its JSON.
        truncation : float, optional
            Standard deviations the samples are drawn within. Default 3.

        Returns
        -------
        CalibratedSpread

        Raises
        ------
        InputError
            A file that does not read as a calibration result with E and alpha fitted.
        """
        source = ""
        if not isinstance(result, dict):
            source = str(result)
            try:
                result = json.loads(Path(result).read_text())
            except (OSError, ValueError) as err:
                raise InputError(f"calibration result {source!r} does not read as JSON: {err}") from None
        try:
            values, stderr = result["final_params"], result["final_stderr"]
            pairs = result.get("final_correlation", {})
            r = float(pairs.get("alpha_per_s,E_factor", pairs.get("E_factor,alpha_per_s", 0.0)))
            e = float(stderr["E_factor"]) / abs(float(values["E_factor"]))
            a = float(stderr["alpha_per_s"]) / abs(float(values["alpha_per_s"]))
        except (KeyError, TypeError, ValueError, ZeroDivisionError):
            raise InputError(f"calibration result {source or 'given'}: expected final_params and final_stderr with "
                             "alpha_per_s and E_factor (the JSON ccedi calibrate writes)") from None
        return cls(E_relative_std=e, alpha_relative_std=a, correlation=r, truncation=truncation, source=source)

    @property
    def E_relative(self):
        """Largest relative departure of E from its nominal value in a sample [-]."""
        return self.truncation * self.E_relative_std

    @property
    def tan_delta_relative(self):
        """Largest relative departure of tan delta = tan_delta_0 (alpha / alpha_0) / sqrt(E / E_0)
        in a sample [-]: at a corner of the truncation box."""
        a, e = self.truncation * self.alpha_relative_std, self.E_relative_std * self.truncation
        return max((1.0 + a) / np.sqrt(1.0 - e) - 1.0, 1.0 - (1.0 - a) / np.sqrt(1.0 + e))

    def samples(self, compound, n, seed=0):
        """Samples of a compound's E and loss factor (:meth:`Spread.samples`).

        Parameters
        ----------
        compound : ccedi.design.compounds.Compound
            The compound (its nominal E and tan delta).
        n : int
            Number of samples, >= 1.
        seed : int, optional
            Random seed. Default 0.

        Returns
        -------
        E_Pa : numpy.ndarray
            (n,) Young's moduli [Pa].
        tan_delta : numpy.ndarray
            (n,) loss factors [-].
        """
        rng = np.random.default_rng(seed)
        r = self.correlation
        root = np.linalg.cholesky(np.array([[1.0, r], [r, 1.0]]) + 1e-12 * np.eye(2))
        z = np.empty((0, 2))
        while len(z) < int(n):
            draw = rng.standard_normal((2 * int(n), 2)) @ root.T
            z = np.vstack([z, draw[np.all(np.abs(draw) <= self.truncation, axis=1)]])
        E_factor = 1.0 + self.E_relative_std * z[: int(n), 0]
        alpha_factor = 1.0 + self.alpha_relative_std * z[: int(n), 1]
        return (compound.E_nominal_Pa * E_factor,
                compound.tan_delta_nominal * alpha_factor / np.sqrt(E_factor))

    def describe(self):
        """The spread in words, for the report.

        Returns
        -------
        str
        """
        return (f"E and alpha normal as calibrated{f' ({self.source})' if self.source else ''}: std "
                f"{self.E_relative_std:.2%} and {self.alpha_relative_std:.2%}, correlation {self.correlation:+.2f}, "
                f"within {self.truncation:g} std")


@dataclass(frozen=True)
class SpreadCheck:
    """A finger length's requirements over the samples of the uncertain inputs.

    Parameters
    ----------
    length_m : float
        The length [m].
    violation : dict
        {requirement: fraction of the samples that miss it}.
    margin_kept : dict
        {requirement: the normalised margin met with the chosen probability, the
        (1 - probability) quantile over the samples} (negative: missed that often).
    nominal_margin : dict
        {requirement: the normalised margin at the nominal E and tan delta}.
    """

    length_m: float
    violation: dict
    margin_kept: dict
    nominal_margin: dict

    @property
    def worst(self):
        """The largest violation probability over the requirements [-]."""
        return max(self.violation.values(), default=0.0)


@dataclass(frozen=True)
class RobustDesign:
    """A compound's robust design (:func:`robust_design`) and its nominal optimum's check.

    Parameters
    ----------
    compound : str
        The compound's name.
    length_m : float
        The robust length [m] (or, when ``feasible`` is False, the length of least
        largest violation probability).
    alpha_per_s : float
        alpha at the nominal E and tan delta there [1/s].
    objective : float
        The objective at the nominal inputs there, in its unit.
    design : ccedi.design.optimise.Design
        The robust design at the nominal inputs (the surrogate's outputs there), for the
        full-FEA re-check.
    check : SpreadCheck
        The requirements over the samples at ``length_m``.
    nominal : SpreadCheck
        The same at the compound's nominal optimum (the same samples).
    nominal_objective : float
        The objective at the nominal optimum, in its unit.
    allowed : float
        The violation probability allowed per requirement, 1 - probability.
    feasible : bool
        Whether some length keeps every requirement within ``allowed``.
    n_samples : int
        Samples per length.
    """

    compound: str
    length_m: float
    alpha_per_s: float
    objective: float
    design: Design
    check: SpreadCheck
    nominal: SpreadCheck
    nominal_objective: float
    allowed: float
    feasible: bool
    n_samples: int

    @property
    def violation(self):
        """{requirement: violation probability} at the robust length."""
        return self.check.violation

    def as_dict(self):
        """JSON form (lengths also in inches).

        Returns
        -------
        dict
        """
        def shown(c):
            return {"length_in": float(m_to_inch(c.length_m)), "violation": c.violation,
                    "margin_kept": c.margin_kept, "nominal_margin": c.nominal_margin}

        return {"compound": self.compound, "feasible": self.feasible, "allowed": self.allowed,
                "n_samples": self.n_samples, "alpha_per_s": self.alpha_per_s, "objective": self.objective,
                "nominal_objective": self.nominal_objective, "robust": shown(self.check),
                "nominal": shown(self.nominal)}


def requirement_margins(design: CompoundDesign, surrogate, *, length_m, samples):
    """Each requirement's normalised margin at a finger length for every sample of the
    compound's E and loss factor (module docstring).

    Parameters
    ----------
    design : CompoundDesign
        The compound's nominal design (its problem, tie and compound).
    surrogate : ccedi.design.surrogate.Surrogate
        The catalogue surrogate over (alpha, L, E'), or (alpha, L, E', b), it was solved on
        (the design's semi-thickness held).
    length_m : float
        Finger length [m].
    samples : tuple of numpy.ndarray
        (E_Pa, tan_delta) samples (:meth:`Spread.samples`).

    Returns
    -------
    dict
        {requirement: (n,) margins, >= 0 where met}.

    Raises
    ------
    InputError
        Samples outside the surrogate's alpha or E range.
    """
    E, tan_delta = (np.asarray(s, dtype=float) for s in samples)
    c, first_mode, b = design.compound, design.tie.first_mode, design.semi_thickness_m
    omega = first_mode(m_to_inch(length_m), E_Pa=E, rho_kg_m3=c.rho_kg_m3, semi_thickness_m=b)
    alpha = alpha_from_loss_factor(tan_delta, omega)
    ratio = c.rho_kg_m3 / first_mode.rho_kg_m3
    E_equivalent = E / ratio
    for var, values in ((surrogate.variables[0], alpha), (surrogate.variables[2], E_equivalent)):
        if values.min() < var.lo * (1 - 1e-9) or values.max() > var.hi * (1 + 1e-9):
            raise InputError(f"{c.name}: the spread's {var.name} {values.min():.4g}-{values.max():.4g} leaves the "
                             f"surrogate's range {var.lo:.4g}-{var.hi:.4g}: build the catalogue surrogate with "
                             f"catalogue_space(..., spread=) at least as wide")
    X = np.column_stack([alpha, np.full(len(alpha), length_m), E_equivalent] + ([] if b is None else
                                                                                [np.full(len(alpha), b)]))
    outputs = density_scaled(surrogate.evaluate(X), ratio)
    margins = design.problem.constraint_margins(outputs, alpha, length_m)
    return {k: np.asarray(m, dtype=float).ravel() for k, m in margins.items()}


def violation_probabilities(design: CompoundDesign, surrogate, *, length_m, samples):
    """Each requirement's violation probability at a finger length over samples of the
    compound's E and loss factor (module docstring).

    Parameters
    ----------
    design : CompoundDesign
        The compound's nominal design (its problem, tie and compound).
    surrogate : ccedi.design.surrogate.Surrogate
        The catalogue surrogate over (alpha, L, E') it was solved on.
    length_m : float
        Finger length [m].
    samples : tuple of numpy.ndarray
        (E_Pa, tan_delta) samples (:meth:`Spread.samples`).

    Returns
    -------
    dict
        {requirement: fraction of the samples that violate it}.

    Raises
    ------
    InputError
        Samples outside the surrogate's alpha or E range.
    """
    margins = requirement_margins(design, surrogate, length_m=length_m, samples=samples)
    return {k: float(np.mean(m < 0.0)) for k, m in margins.items()}


def spread_check(design: CompoundDesign, surrogate, *, length_m, samples, probability=0.95):
    """A finger length's requirements over the samples: violation probabilities, the
    margin each keeps with ``probability``, and the margins at the nominal inputs.

    Parameters
    ----------
    design : CompoundDesign
        The compound's nominal design.
    surrogate : ccedi.design.surrogate.Surrogate
        The catalogue surrogate it was solved on.
    length_m : float
        Finger length [m].
    samples : tuple of numpy.ndarray
        (E_Pa, tan_delta) samples.
    probability : float, optional
        The probability the kept margin is met with. Default 0.95.

    Returns
    -------
    SpreadCheck

    Raises
    ------
    InputError
        Samples outside the surrogate's alpha or E range.
    """
    margins = requirement_margins(design, surrogate, length_m=length_m, samples=samples)
    c = design.compound
    nominal = requirement_margins(design, surrogate, length_m=length_m,
                                  samples=(np.array([c.E_nominal_Pa]), np.array([design.tie.loss_factor])))
    return SpreadCheck(length_m=float(length_m), violation={k: float(np.mean(m < 0.0)) for k, m in margins.items()},
                       margin_kept={k: float(np.quantile(m, 1.0 - probability)) for k, m in margins.items()},
                       nominal_margin={k: float(m[0]) for k, m in nominal.items()})


def robust_design(design: CompoundDesign, surrogate, *, spread=Spread(), probability=0.95, n_samples=N_SAMPLES,
                  n_lengths=N_LENGTHS, seed=0):
    """The compound's robust design over its spread (module docstring).

    Parameters
    ----------
    design : CompoundDesign
        The compound's nominal design (:func:`ccedi.design.catalogue_design.design_compounds`).
    surrogate : ccedi.design.surrogate.Surrogate
        The catalogue surrogate it was solved on.
    spread : Spread or CalibratedSpread, optional
        The inputs' spread. Default E +-15 %, tan delta +-30 %.
    probability : float, optional
        Probability with which every requirement must be met, in (0.5, 1). Default 0.95.
    n_samples : int, optional
        Samples per length. Default :data:`N_SAMPLES`.
    n_lengths : int, optional
        Lengths searched. Default :data:`N_LENGTHS`.
    seed : int, optional
        Random seed of the samples. Default 0.

    Returns
    -------
    RobustDesign
        The robust design, or (``feasible`` False) the length of least largest
        violation probability; with the check of the nominal optimum on the same samples.

    Raises
    ------
    InputError
        A probability outside (0.5, 1), fewer than 20 samples or 2 lengths, or a spread
        the surrogate does not cover.
    """
    if not 0.5 < probability < 1.0:
        raise InputError(f"robust design probability = {probability!r}: must be in (0.5, 1), e.g. 0.95")
    if int(n_samples) < 20 or int(n_lengths) < 2:
        raise InputError(f"robust design: {n_samples!r} samples and {n_lengths!r} lengths; at least 20 and 2 needed")
    samples = spread.samples(design.compound, n_samples, seed)
    var_L = surrogate.variables[1]
    lengths = np.linspace(var_L.lo, var_L.hi, int(n_lengths))
    violations = [violation_probabilities(design, surrogate, length_m=float(L), samples=samples) for L in lengths]
    worst = np.array([max(v.values(), default=0.0) for v in violations])
    alpha = np.array([float(design.tie(m_to_inch(L))) for L in lengths])
    nominal = design.problem.surrogate.evaluate(np.column_stack([alpha, lengths]))
    objective = np.asarray(nominal[OBJECTIVES[design.problem.objective]], dtype=float)
    allowed = 1.0 - probability
    ok = worst <= allowed + 1e-12
    k = int(np.argmin(np.where(ok, objective, np.inf))) if ok.any() else int(np.argmin(worst))
    at = {name: float(np.ravel(v)[k]) for name, v in nominal.items()}
    return RobustDesign(
        compound=design.compound.name, length_m=float(lengths[k]), alpha_per_s=float(alpha[k]),
        objective=float(objective[k]),
        design=Design(float(alpha[k]), float(lengths[k]), at, float(design.problem.J(at))),
        check=spread_check(design, surrogate, length_m=float(lengths[k]), samples=samples, probability=probability),
        nominal=spread_check(design, surrogate, length_m=design.design.x, samples=samples, probability=probability),
        nominal_objective=float(design.objective_value), allowed=allowed, feasible=bool(ok.any()),
        n_samples=int(n_samples))


@dataclass(frozen=True)
class RobustCatalogue:
    """The compounds ranked by their robust designs (:func:`robust_catalogue`).

    Parameters
    ----------
    designs : list of RobustDesign
        In rank order: those with a robust length by the objective there, then the others
        by their largest violation probability.
    nominal : CatalogueDesign
        The nominal ranking the robust designs start from.
    spread : Spread or CalibratedSpread
        The inputs' spread.
    probability : float
        The probability every requirement is met with.
    """

    designs: list
    nominal: CatalogueDesign
    spread: object
    probability: float

    @property
    def winner(self):
        """The first-ranked robust design when it is feasible, else None."""
        return self.designs[0] if self.designs and self.designs[0].feasible else None

    def as_dict(self):
        """JSON form: the spread, the probability, the winner and every compound's robust
        design in rank order.

        Returns
        -------
        dict
        """
        return {"spread": self.spread.describe(), "probability": self.probability,
                "winner": None if self.winner is None else self.winner.compound,
                "designs": [d.as_dict() for d in self.designs]}


def robust_catalogue(ranking: CatalogueDesign, surrogate, *, spread=Spread(), probability=0.95, n_samples=N_SAMPLES,
                     n_lengths=N_LENGTHS, seed=0):
    """Every compound's robust design, ranked (module docstring).

    Parameters
    ----------
    ranking : CatalogueDesign
        The nominal ranking (:func:`ccedi.design.catalogue_design.design_compounds`).
    surrogate : ccedi.design.surrogate.Surrogate
        The catalogue surrogate it was solved on, wide enough for the spread.
    spread : Spread or CalibratedSpread, optional
        The inputs' spread. Default E +-15 %, tan delta +-30 %.
    probability : float, optional
        Probability with which every requirement must be met, in (0.5, 1). Default 0.95.
    n_samples : int, optional
        Samples per length. Default :data:`N_SAMPLES`.
    n_lengths : int, optional
        Lengths searched. Default :data:`N_LENGTHS`.
    seed : int, optional
        Random seed of the samples. Default 0.

    Returns
    -------
    RobustCatalogue

    Raises
    ------
    InputError
        As :func:`robust_design`.
    """
    designs = [robust_design(d, surrogate, spread=spread, probability=probability, n_samples=n_samples,
                             n_lengths=n_lengths, seed=seed) for d in ranking.designs]
    designs.sort(key=lambda r: (not r.feasible, r.objective if r.feasible else r.check.worst))
    return RobustCatalogue(designs=designs, nominal=ranking, spread=spread, probability=probability)
