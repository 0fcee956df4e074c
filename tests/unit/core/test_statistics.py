"""The Wilson score interval: its bounds solve the score test's equation, and it covers."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.stats import norm

from ccedi.errors import InputError
from ccedi.statistics import wilson_interval


@given(n=st.integers(1, 500), data=st.data(), confidence=st.sampled_from([0.8, 0.9, 0.95, 0.99]))
@settings(max_examples=200, deadline=None)
def test_bounds_are_the_roots_of_the_score_test(n, data, confidence):
    """Each bound p solves (k/n - p)^2 = z^2 p (1 - p) / n, and lower <= k/n <= upper."""
    k = data.draw(st.integers(0, n))
    z = norm.ppf(0.5 + confidence / 2)
    low, high = wilson_interval(k, n, confidence)
    assert 0.0 <= low <= k / n <= high <= 1.0
    for p in (low, high):
        assert (k / n - p) ** 2 == pytest.approx(z**2 * p * (1 - p) / n, abs=1e-12)


def test_coverage_near_nominal():
    """Over 20 000 binomial draws of n = 40, p = 0.3 the 95 % interval covers p in 93-97 %."""
    rng = np.random.default_rng(1)
    ks = rng.binomial(40, 0.3, 20_000)
    covered = np.mean([lo <= 0.3 <= hi for lo, hi in (wilson_interval(int(k), 40) for k in ks)])
    assert 0.93 <= covered <= 0.97


@pytest.mark.parametrize("k, n, c", [(3, 0, 0.95), (5, 4, 0.95), (-1, 4, 0.95), (1, 4, 1.0), (1, 4.0, 0.95)])
def test_bad_input_is_refused(k, n, c):
    with pytest.raises(InputError, match="wilson_interval"):
        wilson_interval(k, n, c)
