"""Robust design over a compound's batch spread: the finger length whose design meets every
requirement with a chosen probability when the compound's Young's modulus and loss factor
are only known within their spread.

The uncertain inputs (:class:`Spread`): E uniform within E_nominal (1 +- ``E_relative``)
and tan delta uniform within tan_delta_nominal (1 +- ``tan_delta_relative``) (defaults
+-15 % and +-30 %, the batch-to-batch spread of a compound), independent. A sample of the
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

The surrogate's probabilities are estimates; a full-FEA Monte Carlo at the robust and the
nominal optimum is the check (benchmarks/).
"""
from dataclasses import dataclass

import numpy as np

from ccedi.errors import InputError
from ccedi.units import m_to_inch

from .catalogue_design import CompoundDesign
from .compounds import alpha_from_loss_factor
from .optimise import OBJECTIVES
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


@dataclass(frozen=True)
class RobustDesign:
    """A compound's robust design (:func:`robust_design`).

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
    violation : dict
        {requirement: violation probability} at ``length_m`` over the samples.
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
    violation: dict
    allowed: float
    feasible: bool
    n_samples: int


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
    E, tan_delta = (np.asarray(s, dtype=float) for s in samples)
    c, first_mode = design.compound, design.tie.first_mode
    omega = first_mode(m_to_inch(length_m), E_Pa=E, rho_kg_m3=c.rho_kg_m3)
    alpha = alpha_from_loss_factor(tan_delta, omega)
    ratio = c.rho_kg_m3 / first_mode.rho_kg_m3
    E_equivalent = E / ratio
    for var, values in ((surrogate.variables[0], alpha), (surrogate.variables[2], E_equivalent)):
        if values.min() < var.lo * (1 - 1e-9) or values.max() > var.hi * (1 + 1e-9):
            raise InputError(f"{c.name}: the spread's {var.name} {values.min():.4g}-{values.max():.4g} leaves the "
                             f"surrogate's range {var.lo:.4g}-{var.hi:.4g}: build the catalogue surrogate with "
                             f"catalogue_space(..., spread=) at least as wide")
    X = np.column_stack([alpha, np.full(len(alpha), length_m), E_equivalent])
    outputs = density_scaled(surrogate.evaluate(X), ratio)
    margins = design.problem.constraint_margins(outputs, alpha, length_m)
    return {k: float(np.mean(np.asarray(m) < 0.0)) for k, m in margins.items()}


def robust_design(design: CompoundDesign, surrogate, *, spread=Spread(), probability=0.95, n_samples=N_SAMPLES,
                  n_lengths=N_LENGTHS, seed=0):
    """The compound's robust design over its spread (module docstring).

    Parameters
    ----------
    design : CompoundDesign
        The compound's nominal design (:func:`ccedi.design.catalogue_design.design_compounds`).
    surrogate : ccedi.design.surrogate.Surrogate
        The catalogue surrogate it was solved on.
    spread : Spread, optional
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
        violation probability.

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
    return RobustDesign(compound=design.compound.name, length_m=float(lengths[k]), alpha_per_s=float(alpha[k]),
                        objective=float(objective[k]), violation=violations[k], allowed=allowed,
                        feasible=bool(ok.any()), n_samples=int(n_samples))
