"""Small statistics shared by the validation studies and the design's reliability checks."""
import numpy as np
from scipy.stats import norm

from .errors import InputError


def wilson_interval(successes, n, confidence=0.95):
    """Wilson score interval of a binomial proportion: the p whose normal test does not
    reject ``successes`` out of ``n`` at the given confidence, the roots of
    (k/n - p)^2 = z^2 p (1 - p) / n. Unlike p +- z sqrt(p (1 - p) / n) it stays in [0, 1]
    and is not empty at 0 or n successes.

    Parameters
    ----------
    successes : int
        Number of successes k, 0 <= k <= n.
    n : int
        Number of trials, >= 1.
    confidence : float, optional
        Two-sided confidence level in (0, 1). Default 0.95.

    Returns
    -------
    tuple of float
        (lower, upper) bounds of the proportion, in [0, 1].

    Raises
    ------
    InputError
        n < 1, k outside 0..n, or a confidence outside (0, 1).
    """
    if not (isinstance(n, (int, np.integer)) and n >= 1):
        raise InputError(f"wilson_interval: n = {n!r} trials; must be an integer >= 1")
    if not 0 <= successes <= n:
        raise InputError(f"wilson_interval: {successes!r} successes of {n} trials; must be in 0..{n}")
    if not 0.0 < confidence < 1.0:
        raise InputError(f"wilson_interval: confidence = {confidence!r}; must be in (0, 1)")
    z = float(norm.ppf(0.5 + confidence / 2.0))
    p = successes / n
    centre = (p + z**2 / (2 * n)) / (1 + z**2 / n)
    half = z * np.sqrt(p * (1 - p) / n + z**2 / (4 * n**2)) / (1 + z**2 / n)
    low = 0.0 if successes == 0 else max(centre - half, 0.0)          # exact at the ends (rounding)
    high = 1.0 if successes == n else min(centre + half, 1.0)
    return float(low), float(high)
