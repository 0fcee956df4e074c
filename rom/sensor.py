"""The force transducer between the object and the ground: what a reaction-force record
shows of the force the finger puts on the object.

The transducer, with its acquisition, is a second-order low-pass from the true force F
[N] to the reading y [N]::

    y'' + 2 zeta omega_n y' + omega_n^2 y = omega_n^2 F,   H(s) = omega_n^2 / (s^2 + 2 zeta omega_n s + omega_n^2)

omega_n = 2 pi f_n the natural frequency [rad/s], zeta the damping ratio [-]; unit static
gain. :meth:`Transducer.measured` integrates it exactly for a force linearly interpolated
between samples (first-order hold, on a uniform resampling of the record), starting at
rest at the first sample's value: the discretisation of :func:`scipy.signal.lsim`
(:meth:`Transducer.digital_filter`) run as a digital filter (:func:`scipy.signal.lfilter`,
~20 x faster than lsim's Python loop; the two agree to 1e-14, tested).

Default (:data:`DEFAULT_NATURAL_FREQUENCY_HZ`, :data:`DEFAULT_DAMPING_RATIO`): a 100 Hz
Butterworth (zeta = 1/sqrt(2), maximally flat) acquisition low-pass. Why the acquisition
filter and not the transducer's structure: the paper (Liu & Lee 2012, Table 2) models the
"F/T sensor" as an AL6061 pad 20 mm across and 12.25 mm high under the 0.0991 x 0.067 x
0.025 m aluminium object (1.41 kg). That pad's lateral stiffness, shear G A / h = 6.6e8 N/m
in series with bending 3 E I / h^3 = 8.8e8 N/m, is 3.8e8 N/m, so the object rings on it
at sqrt(k / m) / 2 pi = 2.6 kHz; small 6-axis F/T transducers are made stiff for the same
reason (kHz resonances). A structure resonating in the kHz passes the FE finger's 400 Hz
friction chatter unchanged (docs/validation.md, rom.check): what a record shows of the chatter is set
by the acquisition's low-pass. The paper names neither the transducer model nor its
filter, so the 100 Hz is a declared choice, not a published figure: it keeps the contact
load (rise over ~0.1 s, content below ~20 Hz: |H| >= 0.9994 there) and attenuates 400 Hz
to |H| = 0.062. ``ccedi rom-check --sensor-hz`` and the calibration's ``sensor_bandwidth``
effect take other values.
"""
from dataclasses import dataclass

import numpy as np
from scipy import linalg, signal

from ccedi.errors import InputError, require_finite_positive

DEFAULT_NATURAL_FREQUENCY_HZ = 100.0
"""Natural frequency of the default transducer-plus-acquisition low-pass [Hz] (module docstring)."""
DEFAULT_DAMPING_RATIO = 1.0 / np.sqrt(2.0)
"""Damping ratio of the default low-pass [-] (Butterworth, maximally flat)."""
UNIFORM_RTOL = 1e-6
"""Relative spread of the sample steps below which a record counts as uniformly sampled."""


@dataclass(frozen=True)
class Transducer:
    """A force transducer with its acquisition: a second-order low-pass (module docstring).

    Parameters
    ----------
    natural_frequency_hz : float, optional
        f_n [Hz], > 0. Default :data:`DEFAULT_NATURAL_FREQUENCY_HZ`.
    damping_ratio : float, optional
        zeta [-], > 0. Default :data:`DEFAULT_DAMPING_RATIO`.

    Raises
    ------
    InputError
        A non-positive or non-finite parameter.
    """

    natural_frequency_hz: float = DEFAULT_NATURAL_FREQUENCY_HZ
    damping_ratio: float = DEFAULT_DAMPING_RATIO

    def __post_init__(self):
        require_finite_positive("natural_frequency_hz", self.natural_frequency_hz)
        require_finite_positive("damping_ratio", self.damping_ratio)

    @property
    def omega_n_rad_s(self):
        """Natural angular frequency omega_n = 2 pi f_n [rad/s]."""
        return 2.0 * np.pi * float(self.natural_frequency_hz)

    def system(self):
        """The low-pass as a continuous state-space system.

        Returns
        -------
        scipy.signal.StateSpace
            H(s) = omega_n^2 / (s^2 + 2 zeta omega_n s + omega_n^2), input F [N], output y [N].
        """
        w, z = self.omega_n_rad_s, float(self.damping_ratio)
        return signal.lti([w * w], [1.0, 2.0 * z * w, w * w]).to_ss()

    def frequency_response(self, frequency_hz):
        """H(i 2 pi f) at the given frequencies.

        Parameters
        ----------
        frequency_hz : array_like
            Frequencies [Hz].

        Returns
        -------
        numpy.ndarray
            Complex gain [-] (reading over true force).
        """
        r = np.asarray(frequency_hz, dtype=float) / float(self.natural_frequency_hz)
        return 1.0 / (1.0 - r * r + 2j * float(self.damping_ratio) * r)

    def digital_filter(self, step_s):
        """The transducer for a force sampled every ``step_s`` and linear between samples
        (first-order hold, exact), as a digital filter.

        With the state-space (A, B, C, D) of :meth:`system`, the hold's discretisation
        x[k+1] = Ad x[k] + B0 u[k] + B1 u[k+1] (the block exponential :func:`scipy.signal.lsim`
        uses) becomes, with w = x - B1 u, the plain recursion
        w[k+1] = Ad w[k] + (B0 + Ad B1) u[k], y = C w + (D + C B1) u, whose transfer
        function is returned.

        Parameters
        ----------
        step_s : float
            Sample step [s], > 0.

        Returns
        -------
        tuple of numpy.ndarray
            (b, a): numerator and denominator for :func:`scipy.signal.lfilter`.
        """
        sys = self.system()
        A, B, C, D = sys.A, sys.B, sys.C, sys.D
        n, m = A.shape[0], B.shape[1]
        M = np.zeros((n + 2 * m, n + 2 * m))
        M[:n, :n], M[:n, n:n + m], M[n:n + m, n + m:] = A * step_s, B * step_s, np.eye(m)
        E = linalg.expm(M)
        Ad, B1 = E[:n, :n], E[:n, n + m:]
        B0 = E[:n, n:n + m] - B1
        b, a = signal.ss2tf(Ad, B0 + Ad @ B1, C, D + C @ B1)
        return b[0], a

    def measured(self, time_s, force_N):
        """The reading of the transducer under a sampled force.

        The force is taken as linear between samples; a non-uniformly sampled record is
        first resampled linearly at its median step (the reading is returned at the
        given times). The transducer starts at rest, reading the first sample's force.

        Parameters
        ----------
        time_s : array_like
            Sample times, strictly increasing, (n,) [s].
        force_N : array_like
            True force at those times, (n,) [N].

        Returns
        -------
        numpy.ndarray
            The reading y at ``time_s``, (n,) [N].

        Raises
        ------
        InputError
            Times not strictly increasing, fewer than 2 samples, lengths that differ or
            non-finite values.
        """
        t = np.asarray(time_s, dtype=float)
        f = np.asarray(force_N, dtype=float)
        if t.ndim != 1 or f.shape != t.shape or len(t) < 2:
            raise InputError(f"time_s and force_N must be 1-D of the same length >= 2, got shapes {t.shape} "
                             f"and {f.shape}")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(f))):
            raise InputError("time_s and force_N must be finite")
        dt = np.diff(t)
        if np.any(dt <= 0.0):
            raise InputError("time_s must be strictly increasing")
        step = float(np.median(dt))
        uniform = np.ptp(dt) <= UNIFORM_RTOL * step
        tu = t if uniform else t[0] + step * np.arange(int(np.floor((t[-1] - t[0]) / step)) + 2)
        fu = f if uniform else np.interp(tu, t, f)
        b, a = self.digital_filter(step)
        y, _ = signal.lfilter(b, a, fu, zi=signal.lfilter_zi(b, a) * fu[0])    # at rest, reading F(t0)
        return y if uniform else np.interp(t, tu, y)


def peak(time_s, force_N, transducer=None):
    """Largest transducer reading of a sampled force.

    Parameters
    ----------
    time_s, force_N : array_like
        Samples (:meth:`Transducer.measured`) [s], [N].
    transducer : Transducer, optional
        The transducer (default ``Transducer()``).

    Returns
    -------
    float
        max_t y(t) [N].
    """
    return float(np.max((transducer or Transducer()).measured(time_s, force_N)))
