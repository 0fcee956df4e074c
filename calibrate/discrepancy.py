"""The contact chain's model error against the full FEA, as a Gaussian process in time.

The chain (:class:`ccedi.rom.contact_rom.ReducedContactModel`) read through the transducer
differs from the full explicit FEA's reading at the *true* parameters by a deterministic
discrepancy d(t): measured on the bundled FE runs (benchmarks/contact_discrepancy.py) it is
zero before and after contact and, during contact, 0.2-0.7 N RMS in 0.1 s windows (1-5 %
of the peak reading), correlated over a few milliseconds (the friction chatter the chain
does not have, through the transducer) and over a tenth of a second and more (the chain's
smooth bias: the impulse, the peak and the rise). Fitted as if it were noise, it pulls
alpha and E and lets effects that mimic it in (a sensor bandwidth, a timing offset). It is
carried in the likelihood as a Gaussian process::

    d(t) ~ GP(0, e(t) e(t') peak^2 sum_i a_i^2 k(|t - t'| / l_i)
                 + s_tau^2 y'(t) y'(t') k(|t - t'| / l_tau))

k the Matern-3/2 correlation (1 + sqrt(3) x) exp(-sqrt(3) x), e(t) the contact envelope
of the model's reading y (1 where it exceeds ``CONTACT_LEVEL`` of its peak, widened by
``ENVELOPE_WIDENING_S`` on either side, 0 elsewhere), peak the record's peak reading. The
second term is a local timing error tau(t) of std s_tau, d = y' tau: the chain's contact
starts and ends a few milliseconds off the FEA's, where the reading changes fastest. The
amplitudes a_i [-], length scales l_i [s], s_tau and l_tau [s] are the maximum-likelihood
values over the bundled FE runs (:data:`CHAIN_DISCREPANCY`), checked on runs left out.
"""
from dataclasses import dataclass

import numpy as np
from scipy.linalg import cho_factor, cho_solve, toeplitz
from scipy.ndimage import maximum_filter1d

CONTACT_LEVEL = 0.05
"""Fraction of the peak reading above which the envelope is 1 [-]."""
ENVELOPE_WIDENING_S = 0.02
"""Widening of the envelope on either side of the contact [s] (the contact start's timing
uncertainty)."""
NUGGET = 1e-6
"""Variance added on the diagonal, over the peak reading squared, to keep the covariance
positive definite where the envelope is 0 (a std of 0.1 % of the peak) [-]."""


@dataclass(frozen=True)
class DiscrepancyKernel:
    """The discrepancy's Gaussian process (module docstring).

    Parameters
    ----------
    amplitudes : tuple of float
        a_i, standard deviations as fractions of the peak reading [-].
    length_scales_s : tuple of float
        l_i [s].
    timing_std_s : float, optional
        s_tau, the std of the chain's local timing error [s] (module docstring). Default 0.
    timing_length_s : float, optional
        l_tau, its correlation length [s]. Default 0.1.
    """

    amplitudes: tuple
    length_scales_s: tuple
    timing_std_s: float = 0.0
    timing_length_s: float = 0.1

    def covariance(self, time_s, reading):
        """The discrepancy's covariance at the samples of a record.

        Parameters
        ----------
        time_s : numpy.ndarray
            Uniform sample times [s], shape (n,).
        reading : numpy.ndarray
            The model's reading at them (its envelope and peak), shape (n,), [N].

        Returns
        -------
        numpy.ndarray
            Covariance [N^2], shape (n, n).
        """
        t = np.asarray(time_s, dtype=float)
        env = contact_envelope(t, reading)
        dt = float(t[1] - t[0])
        lag = np.arange(len(t)) * dt                        # uniform samples: a Toeplitz correlation
        corr = sum(a**2 * matern32(lag / ell) for a, ell in zip(self.amplitudes, self.length_scales_s))
        peak = float(np.max(reading))
        cov = peak**2 * np.outer(env, env) * toeplitz(corr)
        if self.timing_std_s > 0.0:
            rate = np.gradient(np.asarray(reading, dtype=float), dt)
            cov += self.timing_std_s**2 * np.outer(rate, rate) * toeplitz(matern32(lag / self.timing_length_s))
        return cov

    def scaled(self, factor):
        """The kernel with every amplitude and the timing std times ``factor``.

        Parameters
        ----------
        factor : float
            Scale of the standard deviations [-].

        Returns
        -------
        DiscrepancyKernel
            The scaled kernel.
        """
        return DiscrepancyKernel(tuple(factor * a for a in self.amplitudes), self.length_scales_s,
                                 factor * self.timing_std_s, self.timing_length_s)

    def summary(self):
        """The kernel, JSON-ready.

        Returns
        -------
        dict
            ``amplitudes_of_peak`` [-], ``length_scales_s``, ``timing_std_s`` and
            ``timing_length_s`` [s].
        """
        return {"amplitudes_of_peak": list(self.amplitudes), "length_scales_s": list(self.length_scales_s),
                "timing_std_s": self.timing_std_s, "timing_length_s": self.timing_length_s}


def matern32(x):
    """The Matern-3/2 correlation (1 + sqrt(3) x) exp(-sqrt(3) x) of scaled distances x >= 0.

    Parameters
    ----------
    x : numpy.ndarray
        |t - t'| / l [-].

    Returns
    -------
    numpy.ndarray
        The correlation [-].
    """
    s = np.sqrt(3.0) * x
    return (1.0 + s) * np.exp(-s)


def contact_envelope(time_s, reading):
    """1 where a reading is in contact (above CONTACT_LEVEL of its peak), widened by
    ENVELOPE_WIDENING_S on either side; 0 elsewhere.

    Parameters
    ----------
    time_s : numpy.ndarray
        Uniform sample times [s].
    reading : numpy.ndarray
        The reading [N].

    Returns
    -------
    numpy.ndarray
        The envelope, 0 or 1.
    """
    y = np.asarray(reading, dtype=float)
    dt = float(time_s[1] - time_s[0])
    contact = (y > CONTACT_LEVEL * float(np.max(y))).astype(float)
    return maximum_filter1d(contact, size=2 * int(round(ENVELOPE_WIDENING_S / dt)) + 1)


def log_likelihood(kernel: DiscrepancyKernel, *, time_s, reading, discrepancy):
    """Gaussian log-likelihood of a measured discrepancy under a kernel (with the NUGGET).

    Parameters
    ----------
    kernel : DiscrepancyKernel
        The kernel.
    time_s, reading, discrepancy : numpy.ndarray
        The run's sample times [s], the model's reading [N] and the discrepancy [N].

    Returns
    -------
    tuple of float
        (ln L, chi-square per sample d^T C^-1 d / n) [-].
    """
    C = kernel.covariance(time_s, reading)
    C[np.diag_indices_from(C)] += NUGGET * float(np.max(reading)) ** 2
    factor = cho_factor(C, lower=True)
    d = np.asarray(discrepancy, dtype=float)
    chi2 = float(d @ cho_solve(factor, d))
    logdet = 2.0 * float(np.sum(np.log(np.diag(factor[0]))))
    return -0.5 * (chi2 + logdet + len(d) * np.log(2.0 * np.pi)), chi2 / len(d)


CHAIN_DISCREPANCY = DiscrepancyKernel(amplitudes=(0.0167, 0.0138), length_scales_s=(0.0053, 0.282),
                                      timing_std_s=0.00149, timing_length_s=0.0037)
"""The chain's discrepancy from the full FEA, fitted to the ten bundled FE runs
(benchmarks/contact_discrepancy.json): 1.7 % of the peak over 5.3 ms (the chatter through
the transducer), 1.4 % over 0.28 s (the smooth bias), 2.2 % in all in contact (0.35 N on
the bundled records, whose noise std is 0.27-0.34 N), and a local timing error of 1.5 ms
over 3.7 ms where the reading rises and falls. Each run left out in turn, the kernel of the other nine gives
it the chi-square per sample of the kernel of all ten within 6 % (0.27-3.60; 3.60 at
alpha = 80 1/s, where the chatter is strongest)."""
