"""The catalogues of physical effects the calibration can add to the declared finger:
each effect's physics, the residual signature that suggests it, and its parameters with
units, bounds and a starting value scaled to the record. :data:`CATALOGUE` holds the
effects of an impulse record (the finger's modal model), :data:`CONTACT_CATALOGUE` those
of a contact record (the finger on the drum, read by the force transducer). Light (numpy
only), so the command line can list the effects without building a model."""
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Parameter:
    """A fitted parameter with its bounds and the scale the optimiser works in.

    The optimiser's variable is z = log10(x) (``log``) or z = x / ``scale``.

    Parameters
    ----------
    name : str
        Parameter name, ending in its unit (e.g. ``"beta_s"``, ``"tip_mass_kg"``).
    lower : float
        Lower bound (in the parameter's unit).
    upper : float
        Upper bound.
    log : bool, optional
        Work in log10 (bounds must then be > 0). Default True.
    scale : float, optional
        Linear scale when not ``log``. Default 1.
    step : float or None, optional
        Finite-difference step of the Jacobian in the optimiser's variable z (absolute),
        for a model whose output is smooth only on that scale (the contact chain); None:
        the fit's relative default. Default None.
    absent : float or None, optional
        The value at which the effect vanishes, so that the model is the one the effect
        extends (0 for an added force or mass, inf for a root spring, the declared value
        for a declared quantity); a nested fit restarts from it, clipped into the bounds.
        None: unknown. Default None.
    """

    name: str
    lower: float
    upper: float
    log: bool = True
    scale: float = 1.0
    step: float | None = None
    absent: float | None = None

    def to_z(self, x):
        """The optimiser's variable of a parameter value.

        Parameters
        ----------
        x : float or numpy.ndarray
            Parameter value (its unit).

        Returns
        -------
        float or numpy.ndarray
            z = log10(x) or x / scale.
        """
        return np.log10(x) if self.log else x / self.scale

    def from_z(self, z):
        """The parameter value of an optimiser variable (inverse of :meth:`to_z`).

        Parameters
        ----------
        z : float or numpy.ndarray
            Optimiser variable.

        Returns
        -------
        float or numpy.ndarray
            x = 10^z or z scale (the parameter's unit).
        """
        return 10.0**z if self.log else z * self.scale

    def absent_z(self):
        """The optimiser's variable where the effect vanishes, clipped into the bounds
        (None when :attr:`absent` is unknown).

        Returns
        -------
        float or None
        """
        if self.absent is None:
            return None
        lo, hi = self.z_bounds()
        if self.log and self.absent <= 0.0:
            return lo
        return float(np.clip(self.to_z(self.absent) if np.isfinite(self.absent) else np.sign(self.absent) * np.inf,
                             lo, hi))

    def z_bounds(self):
        """The bounds in the optimiser's variable.

        Returns
        -------
        tuple of float
            (to_z(lower), to_z(upper)).
        """
        return self.to_z(self.lower), self.to_z(self.upper)


@dataclass(frozen=True)
class Effect:
    """A candidate physical effect of the calibration catalogue.

    Parameters
    ----------
    name : str
        Effect name (the catalogue key, e.g. ``"coulomb_friction"``).
    physics : str
        One line of physics, with its equation.
    signature : str
        The residual signature that suggests the effect.
    parameters : callable
        ``parameters(scales: Scales) -> [(Parameter, start value)]``: bounds and a
        starting value scaled to the record.
    """

    name: str
    physics: str
    signature: str
    parameters: object


@dataclass(frozen=True)
class Scales:
    """Scales of the record and finger, for parameter bounds and starting values.

    Parameters
    ----------
    mass_kg : float
        Finger mass [kg].
    stiffness_N_m : float
        Tip stiffness [N/m].
    ei_over_l : float
        E I / L [N m/rad].
    omega1 : float
        First angular frequency [rad/s].
    omega2 : float
        Second angular frequency [rad/s].
    amplitude_m : float
        Response amplitude [m].
    duration_s : float
        Record length [s].
    length_m : float
        Finger length [m].
    """

    mass_kg: float
    stiffness_N_m: float
    ei_over_l: float
    omega1: float
    omega2: float
    amplitude_m: float
    duration_s: float
    length_m: float


def _catalogue():
    P = Parameter
    return {e.name: e for e in [
        Effect("stiffness_damping", "Rayleigh C = alpha M + beta K: zeta_i = alpha/(2 w_i) + beta w_i/2",
               "higher modes decay faster than alpha alone allows (residual at mode 2 early on)",
               lambda s: [(P("beta_s", 1e-7, 10.0 / s.omega2, absent=0.0), 0.04 / s.omega2)]),
        Effect("viscoelastic", "standard linear solid: stiffness w^2 (q - g v), v' = (q - v)/tau",
               "slow creep/recovery tail and frequency-dependent damping",
               lambda s: [(P("prony_g", 1e-4, 0.9, absent=0.0), 0.05), (P("prony_tau_s", 0.05 / s.omega2, s.duration_s), 1.0 / s.omega1)]),
        Effect("quadratic_damping", "air drag -c_q |w'| w' per unit length along the finger [c_q in N s^2/m^3]",
               "decay per cycle grows with amplitude",
               lambda s: [(P("drag_N_s2_m3", 1e-6 * s.mass_kg / (s.amplitude_m * s.length_m),
                             10.0 * s.mass_kg / (s.amplitude_m * s.length_m), absent=0.0), 0.03 * s.mass_kg / (s.amplitude_m * s.length_m))]),
        Effect("coulomb_friction", "tip friction -F_c tanh(u'/1 mm/s)",
               "envelope decays linearly; residual correlates with sign(velocity)",
               lambda s: [(P("friction_N", 1e-7 * s.stiffness_N_m * s.amplitude_m, 0.5 * s.stiffness_N_m * s.amplitude_m, absent=0.0),
                           2.5e-3 * s.stiffness_N_m * s.amplitude_m)]),
        Effect("tip_mass", "point mass m_t at the tip (magnet, sensor target)",
               "frequency lower than E's tolerance allows, with a smaller response per impulse",
               lambda s: [(P("tip_mass_kg", 1e-5 * s.mass_kg, 2.0 * s.mass_kg, absent=0.0), 0.05 * s.mass_kg)]),
        Effect("root_compliance", "clamp as a rotational spring k_r at the root",
               "frequency lower than E's tolerance allows, with a larger static flexibility",
               lambda s: [(P("root_stiffness_N_m_rad", 0.1 * s.ei_over_l, 1e4 * s.ei_over_l, absent=np.inf), 30.0 * s.ei_over_l)]),
        Effect("gravity", "static sag under the transverse gravity component g_t",
               "constant offset of the residual",
               lambda s: [(P("gravity_m_s2", -9.81, 9.81, log=False, absent=0.0), 0.0)]),
        Effect("geometric_nonlinearity", "large-amplitude stiffening as a cubic tip spring -k_3 u^3",
               "frequency falls as the amplitude decays; residual correlates with u^3",
               lambda s: [(P("cubic_N_m3", -10 * s.stiffness_N_m / s.amplitude_m**2, 10 * s.stiffness_N_m / s.amplitude_m**2,
                             log=False, scale=0.01 * s.stiffness_N_m / s.amplitude_m**2, absent=0.0), 0.0)]),
        Effect("sensor_nonlinearity", "sensor reads u + s_2 u^2",
               "residual correlates with u^2 (asymmetric peaks)",
               lambda s: [(P("sensor_quadratic_per_m", -0.5 / s.amplitude_m, 0.5 / s.amplitude_m, log=False,
                             scale=0.01 / s.amplitude_m, absent=0.0), 0.0)]),
        Effect("sensor_offset_drift", "sensor reads u + y_0 + y_1 t",
               "constant offset plus a slow linear drift of the residual",
               lambda s: [(P("offset_m", -s.amplitude_m, s.amplitude_m, log=False, scale=0.01 * s.amplitude_m, absent=0.0), 0.0),
                          (P("drift_m_s", -s.amplitude_m / s.duration_s, s.amplitude_m / s.duration_s, log=False,
                             scale=0.01 * s.amplitude_m / s.duration_s, absent=0.0), 0.0)]),
        Effect("time_delay", "sensor reads u(t - tau)",
               "residual proportional to -velocity, uniform in time (phase lag at every frequency)",
               lambda s: [(P("delay_s", 0.0, 1.0 / s.omega1, log=False, scale=0.01 / s.omega1, absent=0.0), 0.01 / s.omega1)]),
    ]}


CATALOGUE = _catalogue()
"""Candidate effects by name (the catalogue the calibration searches)."""


@dataclass(frozen=True)
class ContactScales:
    """Scales of a contact record and its declared set-up, for parameter bounds and
    starting values.

    Parameters
    ----------
    peak_force_N : float
        Largest reading of the record [N].
    duration_s : float
        Record length [s].
    omega_rad_s : float
        Declared drum speed [rad/s].
    friction : float
        Declared friction coefficient [-].
    sensor_hz : float
        Natural frequency of the declared transducer [Hz].
    sensor_damping_ratio : float
        Damping ratio of the declared transducer [-].
    """

    peak_force_N: float
    duration_s: float
    omega_rad_s: float
    friction: float
    sensor_hz: float
    sensor_damping_ratio: float


def _contact_catalogue():
    P = Parameter
    return {e.name: e for e in [
        Effect("friction", "Coulomb friction finger-object f_t <= mu f_n with mu other than declared",
               "force level and shape change while the contact (start, end) keeps its timing; "
               "residual correlates with the force",
               lambda s: [(P("friction_mu", 0.0, 2.0, log=False, scale=0.01, step=2.0, absent=s.friction), s.friction)]),
        Effect("drum_speed", "drum turns at omega other than declared: contact window scales as 1 / omega",
               "contact starts and ends early (or late) by amounts growing with time; residual "
               "correlates with t F'",
               lambda s: [(P("omega_rad_s", 0.7 * s.omega_rad_s, 1.3 * s.omega_rad_s, log=False,
                             scale=0.002 * s.omega_rad_s, step=2.0, absent=s.omega_rad_s), s.omega_rad_s)]),
        Effect("timing_offset", "initial drum angle (or trigger) off by d_theta: the record shifted by "
               "d_theta / omega",
               "whole record shifted in time: residual correlates with -F', start and end errors equal",
               lambda s: [(P("theta0_offset_rad", -0.2, 0.2, log=False, scale=0.001, step=2.0, absent=0.0), 0.0)]),
        Effect("object_offset", "object centre displaced by d_r along the line from the drum axis through "
               "it: the finger's interference with the object changes (a displacement across that line is, "
               "to first order, met d / (R omega) earlier or later: a timing offset)",
               "force level and contact duration change together, contact starts earlier (closer) or later",
               lambda s: [(P("object_radial_offset_m", -0.01, 0.01, log=False, scale=1e-4, step=3.0, absent=0.0), 0.0)]),
        Effect("contact_damping", "a viscous normal contact force on the penetration rate, c d' with c = 2 zeta "
               "sqrt(k m_eff) of each contact spring (a lossy object surface)",
               "contact ringing and friction chatter die sooner; against a rigid object the filtered force "
               "barely changes (zeta 0.2 at alpha 80 1/s: chain 0.05, FEA 0.46 noise std of a 2 % record)",
               lambda s: [(P("contact_damping_ratio", 0.0, 0.2, log=False, scale=0.002, step=2.0, absent=0.0), 0.05)]),
        Effect("sensor_bandwidth", "transducer low-pass y'' + 2 zeta w_n y' + w_n^2 y = w_n^2 F with "
               "w_n, zeta other than declared",
               "rises and falls of the record lag and round off against the model; residual "
               "correlates with -F' and F''",
               lambda s: [(P("sensor_hz", 1.0, 2000.0, step=0.01, absent=s.sensor_hz), s.sensor_hz),
                          (P("sensor_damping_ratio", 0.05, 5.0, step=0.01, absent=s.sensor_damping_ratio), s.sensor_damping_ratio)]),
        Effect("sensor_offset_drift", "transducer reads F + F_0 + F_1 t (zero offset and its drift)",
               "non-zero reading out of contact: constant offset plus a slow linear drift of the residual",
               lambda s: [(P("offset_N", -0.2 * s.peak_force_N, 0.2 * s.peak_force_N, log=False,
                             scale=0.001 * s.peak_force_N, step=1.0, absent=0.0), 0.0),
                          (P("drift_N_s", -0.2 * s.peak_force_N / s.duration_s, 0.2 * s.peak_force_N / s.duration_s,
                             log=False, scale=0.001 * s.peak_force_N / s.duration_s, step=1.0, absent=0.0), 0.0)]),
    ]}


CONTACT_CATALOGUE = _contact_catalogue()
"""Candidate effects of a contact record by name."""
