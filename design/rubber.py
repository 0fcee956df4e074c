"""The damping of "this rubber" over finger length: the paper's fingers and our fit.

The paper matched alpha to its measured over-damped 3 and 4.5-in fingers
(:data:`PAPER_MATCHED_ALPHA`) and measured the damping ratios of its under-damped 6 and
8-in fingers (:data:`PAPER_ZETA`); its Eq. (7) draws alpha(x) through them. A design that
keeps the paper's rubber ties alpha to the length by :func:`alpha_of_length` ("paper":
Eq. 7; "fit": the same form through our alpha_cr). Lengths here are in inches, as in the
paper; alpha in 1/s.
"""
import casadi as ca
import numpy as np

from ccedi.errors import InputError
from ccedi.rom.ccedi import piecewise_alpha_fit

PAPER_MATCHED_ALPHA = {3.0: 600.0, 4.5: 180.0}
"""The paper's alpha [1/s] matched to its measured over-damped 3 and 4.5-in fingers."""

PAPER_ZETA = {6.0: 0.17, 8.0: 0.15}
"""The paper's measured damping ratios of the 6 and 8-in fingers (log-decrement)."""

FIT_ALPHA_CR = (3525.0, -1.997)
"""Our alpha_cr(x) = c x^p [1/s], x in inches (docs/validation.md, "Damping identification")."""


def alpha_cr_of_length(length_in):
    """Critical mass-proportional damping alpha_cr [1/s] of the generated finger of length
    ``length_in`` [in] from our power-law fit :data:`FIT_ALPHA_CR` (numpy or casadi).

    Parameters
    ----------
    length_in : float or array_like
        Finger length [in].

    Returns
    -------
    float or numpy.ndarray
        alpha_cr [1/s].
    """
    return FIT_ALPHA_CR[0] * length_in ** FIT_ALPHA_CR[1]


def _piecewise(x, quad, line):
    """quad(x) for x <= 6 in, line(x) above (the form of the paper's Eq. 7); numpy or casadi."""
    q = quad[0] * x**2 + quad[1] * x + quad[2]
    l_ = line[0] * x + line[1]
    if isinstance(x, (ca.SX, ca.MX)):
        return ca.if_else(x <= 6.0, q, l_)
    return np.where(np.asarray(x) <= 6.0, q, l_)


ALPHA_OF_LENGTH = {
    "paper": ((56.667, -705.0, 2205.0), (-3.75, 37.5)),
    "fit": piecewise_alpha_fit([3.0, 4.5, 6.0, 8.0], [
        PAPER_MATCHED_ALPHA[3.0], PAPER_MATCHED_ALPHA[4.5],
        PAPER_ZETA[6.0] * alpha_cr_of_length(6.0), PAPER_ZETA[8.0] * alpha_cr_of_length(8.0)]),
}
"""Coefficients (quadratic 3-6 in, line 6-8 in) of alpha(x) [1/s], x in inches: "paper"
is Eq. (7); "fit" the same form through the paper's matched alpha at 3 and 4.5 in and
its measured zeta times our alpha_cr at 6 and 8 in (as ``ccedi damping-fits``)."""


def alpha_of_length(mode, length_in):
    """alpha(x) [1/s] of "this rubber" at finger length ``length_in`` [in] (numpy or
    casadi expression); ``mode`` is "paper" or "fit" (see :data:`ALPHA_OF_LENGTH`).

    Parameters
    ----------
    mode : str
        "paper" or "fit".
    length_in : float or casadi expression
        Finger length [in].

    Returns
    -------
    float or casadi expression
        alpha [1/s].

    Raises
    ------
    InputError
        Unknown ``mode``.
    """
    if mode not in ALPHA_OF_LENGTH:
        raise InputError(f"alpha-of-length must be one of {sorted(ALPHA_OF_LENGTH)} or 'free', got {mode!r}")
    return _piecewise(length_in, *ALPHA_OF_LENGTH[mode])
