"""Model adequacy: can the declared finger explain the record at all? Checked on the
baseline fit, before any effect is added, so that effects are never added to cover a
wrong declaration (a wrong length, an E off by a factor of two, a record too short to
show the finger's first mode).

The record's own first mode, independent of the finger model: the free decay after the
pulse (t >= start + duration, tau = t - t_free) is fitted by a damped sinusoid on a
straight line::

    y(tau) = c_0 + c_1 tau + exp(-sigma tau) (a cos(omega_d tau) + b sin(omega_d tau))

by variable projection (c_0, c_1, a, b linear; omega_d and sigma by bounded least
squares, started from the largest peak of the zero-padded spectrum of the detrended
decay, refined by a parabola through the log-magnitudes, and from several damping
ratios). The natural frequency f_r = sqrt(omega_d^2 + sigma^2) / (2 pi) is what the model's
undamped modes are compared with; zeta_r = sigma / (2 pi f_r). It is *measurable* when the
decay shows at least ``MIN_CYCLES`` cycles of it, both within the record and above
``NOISE_SIGMAS`` noise standard deviations (an over-damped record shows none).

The record's first-mode effective tip mass m_r = 1 / b_r^2 (b_r: the mode's mass-normalised
tip value) follows from the same fit and the declared pulse (:func:`effective_tip_mass_kg`).
It tells a wrong E from an effect: E scales the frequency and leaves m_r alone, a tip mass
adds to m_r, a compliant root raises it a little (from about a quarter of the finger's mass
towards a third), a load or mass declared wrong scales it. The declared finger's m_1 is
1 / b_1^2 of the calibration's modes scaled by the declared mass over the mesh's (SM-A's
polygonal section is 1.7 % light at the paper's ellipse; the clean SM-C records of
:mod:`ccedi.calibrate.synthetic_solid` read m_r from 0.1 % below to 1.6 % above m_1).

The checks, each named in the result:

  record_length  the free decay covers at least ``MIN_PERIODS`` periods of the declared
                 finger's first mode at E (1 - tol), its longest period
  frequency      f_r is measurable and within the band
                   f_1 sqrt(1 - tol) (1 - FREQUENCY_MARGIN) (1 - EFFECT_ALLOWANCE)
                   .. f_1 sqrt(1 + tol) (1 + FREQUENCY_MARGIN)
                 with f_1 the declared finger's first frequency (the calibration model's at
                 E_factor = 1; it scales exactly as sqrt(E_factor)); and, when f_r lies
                 below E's reach f_1 sqrt(1 - tol), m_r is at least (1 - EFFECTIVE_MASS_MARGIN)
                 times the least effective mass with which an effect takes the finger at
                 E (1 - tol) down to f_r: that of a compliant root
                 (:func:`root_effective_mass_kg`). A record whose oscillation dies out (in
                 the noise) before MIN_CYCLES cycles, although it lasts long enough to show
                 them, is too damped to have a frequency: this check is then skipped (listed
                 in ``skipped``), which is the usual case for rubber fingers near critical
                 damping
  E_bound        the baseline E_factor is not on a tolerance bound, unless the record's
                 frequency lies beyond what E alone reaches (within FREQUENCY_MARGIN) on
                 that side: there the bound is the signature of a tip mass or a compliant
                 root; or unless m_r is the declared finger's (from m_1 / (1 + MASS_ALLOWANCE)
                 up to the tip mass that E (1 + tol) allows, times 1 + MASS_ALLOWANCE): then
                 the declared mass, section and load fit the record's first mode and the
                 bound is pressed by an effect, which the loop looks for. On a record too
                 damped to show a frequency, E on either bound fails: nothing in the record
                 says that an effect, not the declaration, pressed it there

Why the effective mass (measured on the SM-C records of :mod:`ccedi.calibrate.synthetic_solid`,
``validation/calibrate_impulse_solid.json``): with the frequency band alone, a declared E
1.5 times the true one passed (the record's 4.498 Hz, 0.817 of the declared 5.507 Hz, lies
inside the band's allowance for a tip mass or compliant root, down to 0.763 f_1 at
tol = 0.2), and the loop then looked for an effect to cover it; its m_r, 16.30 g, is the
declared finger's 16.16 g, where a root taking the finger at E x 0.8 down to 4.498 Hz needs
16.87 g: now refused (``frequency``). And a correctly declared finger with a viscoelastic
root (the first 20 mm relaxing to 10 %) was refused (``E_bound``): the baseline E sits on
its bound 0.8 while f_r, 4.247 Hz, is within E's reach (4.022 Hz and up); its m_r is 0.82
m_1, inside the allowance: now adequate, and the loop looks for the effect.
"""
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, least_squares

from .experiment import Experiment
from .fit import Fit, e_factor_bound

MIN_PERIODS = 2.0
"""Periods of the declared first mode (at E (1 - tol)) the free decay must cover."""
MIN_CYCLES = 1.5
"""Cycles of its own first mode a record must show for its frequency to be measured. On
synthetic records of an earlier Euler-Bernoulli beam generator (truncated, or damped up to
zeta_1 = 0.35; the estimator uses no finger model) the estimate is within 2.3 % of the
truth from 1.5 cycles on; below, it is 8 % off at 1.16 cycles of a truncated record and
30 % off at 0.84 cycles shown by a record with zeta_1 = 0.45."""
NOISE_SIGMAS = 3.0
"""An oscillation counts while its envelope exceeds this many noise standard deviations."""
FREQUENCY_MARGIN = 0.03
"""Model form and estimation error of the first frequency [-]: the full explicit 3-D FEA
record (bundled control_fea_solid) rings 0.06 % below the calibration's FE first mode; on
the bundled records whose effect leaves the first frequency alone the estimator is within
0.16 % of the truth at zeta_1 = 0.05-0.11 and 0.8 % low at zeta_1 = 0.18
(quadratic_damping_high); on the earlier beam records it read up to 2.3 % low at
zeta_1 = 0.35."""
EFFECT_ALLOWANCE = 0.12
"""How far below E's reach the catalogued effects that lower the first frequency (tip mass,
compliant root) may take it before the declaration, not an effect, is held wrong [-]. The
bundled tip-mass records lie up to 7.8 % below E's reach (tip_mass+quadratic_damping_high,
0.800 f_1 against 0.868 f_1); a declared E twice the true one gives 0.707 f_1, 18 % below."""
EFFECTIVE_MASS_MARGIN = 0.02
"""Relative error allowed on the record's first-mode effective tip mass against the least
one a tip mass or compliant root needs to lower the frequency below E's reach [-]: the
clean SM-C records read it from 0.1 % below to 1.6 % above the declared finger's (the most
at zeta_1 = 0.14), the bundled SM-A records (whose mesh is 1.7 % light) 1.5-1.9 % below; the
SM-C record of a declared E 1.5 times the true one reads 16.30 g where a root needs 16.87 g
(3.4 % short)."""
MASS_ALLOWANCE = 0.3
"""How far the effective tip mass of a record whose frequency is within E's reach may lie
from the declared finger's (below it by the factor 1 + MASS_ALLOWANCE, or above what a tip
mass at E (1 + tol) gives by that factor) before the declared mass, section or load is held
wrong [-]: the amplitude-dependent effects move the reading; on the bundled records it lies
from 0.90 (viscoelastic) to 1.30 (quadratic_damping_high) of the declared finger's, on the
SM-C records from 0.82 (the viscoelastic root) to 1.20 (quadratic_damping_high); a load
declared 3 times too large gives 0.33."""
SAMPLES_PER_BIN = 16
"""Zero padding of the spectrum that starts the damped-sinusoid fit."""
START_ZETAS = (0.01, 0.03, 0.1, 0.3, 0.6)
"""Damping ratios the damped-sinusoid fit is started from (the lowest cost is kept)."""


@dataclass(frozen=True)
class FirstMode:
    """The record's own first mode, from its free decay (module docstring).

    Parameters
    ----------
    frequency_hz : float
        Fitted natural frequency f_r [Hz].
    damping_ratio : float
        Fitted damping ratio zeta_r [-].
    amplitude_m : float
        Amplitude of the fitted oscillation at the start of the free decay [m].
    cycles_in_record : float
        Cycles of it within the free decay [-].
    cycles_above_noise : float
        Cycles before its envelope sinks below NOISE_SIGMAS noise standard deviations
        (infinite when it does not decay) [-].
    """

    frequency_hz: float
    damping_ratio: float
    amplitude_m: float
    cycles_in_record: float
    cycles_above_noise: float

    @property
    def cycles(self):
        """Cycles the decay shows: the fewer of ``cycles_in_record`` and ``cycles_above_noise``."""
        return min(self.cycles_in_record, self.cycles_above_noise)

    @property
    def measurable(self):
        """At least MIN_CYCLES cycles shown: ``frequency_hz`` is the record's first frequency."""
        return self.cycles >= MIN_CYCLES


def _damped_sinusoid(tau, y, omega_d, sigma):
    """Residual and linear coefficients (c_0, c_1, a, b) of the module docstring's fit."""
    e = np.exp(-sigma * tau)
    basis = np.column_stack([np.ones_like(tau), tau, e * np.cos(omega_d * tau), e * np.sin(omega_d * tau)])
    coef = np.linalg.lstsq(basis, y, rcond=None)[0]
    return basis @ coef - y, coef


def _spectral_peak_rad_s(tau, y):
    """Angular frequency of the largest peak of |FFT| of the detrended y above half a cycle
    per record, refined by a parabola through the log-magnitudes at the peak [rad/s]."""
    dt = float(np.median(np.diff(tau)))
    detrended = y - np.polyval(np.polyfit(tau, y, 1), tau)
    n = SAMPLES_PER_BIN * 2 ** int(np.ceil(np.log2(len(y))))
    spec = np.abs(np.fft.rfft(detrended, n))
    df = 1.0 / (n * dt)
    first = max(1, int(np.ceil(0.5 / (tau[-1] * df))))
    k = first + int(np.argmax(spec[first:-1]))
    lo, mid, hi = np.log(np.maximum(spec[k - 1:k + 2], 1e-300))
    curvature = lo - 2.0 * mid + hi
    shift = 0.5 * (lo - hi) / curvature if curvature < 0 else 0.0
    return 2.0 * np.pi * (k + shift) * df


def record_first_mode(exp: Experiment, noise_std_m):
    """The record's own first mode from its free decay, without the finger model.

    Parameters
    ----------
    exp : Experiment
        The experiment (its record and pulse timing).
    noise_std_m : float
        Sensor noise standard deviation [m], for the cycles shown above the noise.

    Returns
    -------
    FirstMode
        Natural frequency, damping ratio, amplitude, cycles shown and whether that is
        enough to call the frequency measured (module docstring).
    """
    return free_decay_mode(exp.time_s, exp.displacement_m, free_from_s=exp.start_s + exp.duration_s,
                           noise_std_m=noise_std_m)


def free_decay_mode(time_s, displacement_m, *, free_from_s, noise_std_m):
    """The first mode of a record's free decay, from ``free_from_s`` on (module docstring).

    Parameters
    ----------
    time_s, displacement_m : numpy.ndarray
        The record [s], [m].
    free_from_s : float
        When the load has ended [s].
    noise_std_m : float
        Sensor noise standard deviation [m].

    Returns
    -------
    FirstMode
    """
    free = time_s >= free_from_s
    tau, y = time_s[free] - time_s[free][0], displacement_m[free]
    w0 = _spectral_peak_rad_s(tau, y)
    residual = lambda p: _damped_sinusoid(tau, y, p[0], p[1])[0]
    best = min((least_squares(residual, [w0, z * w0], bounds=([0.2 * w0, 0.0], [5.0 * w0, 10.0 * w0]),
                              x_scale=[w0, w0]) for z in START_ZETAS), key=lambda r: r.cost)
    omega_d, sigma = (float(x) for x in best.x)
    coef = _damped_sinusoid(tau, y, omega_d, sigma)[1]
    amplitude = float(np.hypot(coef[2], coef[3]))
    omega_n = float(np.hypot(omega_d, sigma))
    cycles_per_s = omega_d / (2.0 * np.pi)
    e_folds = np.log(amplitude / (NOISE_SIGMAS * noise_std_m)) if amplitude > NOISE_SIGMAS * noise_std_m else 0.0
    return FirstMode(frequency_hz=omega_n / (2.0 * np.pi), damping_ratio=sigma / omega_n, amplitude_m=amplitude,
                     cycles_in_record=float(tau[-1]) * cycles_per_s,
                     cycles_above_noise=e_folds / sigma * cycles_per_s if sigma > 0 else float("inf"))


def effective_tip_mass_kg(exp: Experiment, mode: FirstMode):
    """The effective tip mass of the record's own first mode, m_r = 1 / b_r^2 (module
    docstring), from its fitted frequency, damping and amplitude and the declared pulse.

    A pulse F_0 of length T leaves a mode of tip value b, natural frequency omega_n and
    decay rate sigma (omega_d = sqrt(omega_n^2 - sigma^2)) ringing with the amplitude
    F_0 b^2 |1 - i sigma / omega_d| |1 - exp((-sigma + i omega_d) T)| / omega_n^2 at the
    pulse's end; the fitted amplitude at the first free sample, ``lag`` later, is that times
    exp(-sigma lag).

    Parameters
    ----------
    exp : Experiment
        The experiment (declared pulse, record times).
    mode : FirstMode
        The record's own first mode.

    Returns
    -------
    float
        m_r [kg].
    """
    end = exp.start_s + exp.duration_s
    lag = float(exp.time_s[exp.time_s >= end][0] - end)
    omega_n = 2.0 * np.pi * mode.frequency_hz
    sigma = mode.damping_ratio * omega_n
    omega_d = omega_n * np.sqrt(max(1.0 - mode.damping_ratio**2, 1e-12))
    pulse = np.hypot(1.0, sigma / omega_d) * abs(1.0 - np.exp((-sigma + 1j * omega_d) * exp.duration_s))
    return float(exp.force_N * pulse / (mode.amplitude_m * np.exp(sigma * lag) * omega_n**2))


def _mass_scale(model):
    """The declared finger's mass over its mesh's (SM-A's polygonal section is light) [-]."""
    f = model.exp.finger
    return f.rho_kg_m3 * f.area_m2 * f.length_m / model.basis.mass_kg


def declared_effective_mass_kg(model):
    """The declared finger's first-mode effective tip mass 1 / b_1^2 [kg], scaled to the
    declared finger's mass (module docstring).

    Parameters
    ----------
    model : FingerModel
        The calibration model of the declared finger.

    Returns
    -------
    float
        m_1 [kg] (E does not change it).
    """
    return _mass_scale(model) / float(model.basis.tip[0]) ** 2


def root_effective_mass_kg(model, frequency_hz, E_factor):
    """The least effective tip mass with which a frequency-lowering effect takes the
    declared finger at E x ``E_factor`` down to ``frequency_hz``: that of a compliant root
    (a tip mass adds its whole mass for the same drop).

    Parameters
    ----------
    model : FingerModel
        The calibration model of the declared finger.
    frequency_hz : float
        The first frequency to reach [Hz].
    E_factor : float
        Young's modulus over the declared one [-].

    Returns
    -------
    float
        The effective tip mass of the first mode of the finger on the root spring that
        gives ``frequency_hz`` [kg], scaled as :func:`declared_effective_mass_kg`; the
        clamped finger's when it is not lower than ``frequency_hz``.
    """
    basis = model.basis
    target = 2.0 * np.pi * frequency_hz

    def first(log_k):
        return basis.modes(E_factor, root_stiffness=10.0**log_k, n_modes=1)

    lo, hi = np.log10(model.scales.ei_over_l) - 6.0, np.log10(model.scales.ei_over_l) + 8.0
    if first(hi).omega_rad_s[0] <= target:
        return declared_effective_mass_kg(model)
    log_k = brentq(lambda x: first(x).omega_rad_s[0] - target, lo, hi, xtol=1e-6)
    return _mass_scale(model) / float(first(log_k).tip[0]) ** 2


def frequency_band_hz(declared_hz, E_tolerance):
    """The first frequencies the declared finger reaches with E alone, and those it may show.

    Parameters
    ----------
    declared_hz : float
        The declared finger's first frequency f_1 at the declared E [Hz].
    E_tolerance : float
        Relative tolerance of E [-].

    Returns
    -------
    tuple
        ``(reach, band)``: (lowest, highest) [Hz] over E (1 -+ tol); and the band the
        record's frequency may lie in (module docstring's ``frequency`` check) [Hz].
    """
    reach = (declared_hz * np.sqrt(1.0 - E_tolerance), declared_hz * np.sqrt(1.0 + E_tolerance))
    return reach, (reach[0] * (1.0 - FREQUENCY_MARGIN) * (1.0 - EFFECT_ALLOWANCE), reach[1] * (1.0 + FREQUENCY_MARGIN))


def frequency_check(mode: FirstMode, band_hz, E_tolerance):
    """The ``frequency`` check of the module docstring.

    Parameters
    ----------
    mode : FirstMode
        The record's own first mode.
    band_hz : tuple of float
        The band of :func:`frequency_band_hz` [Hz].
    E_tolerance : float
        Relative tolerance of E [-] (named in the reason).

    Returns
    -------
    tuple
        ``(reason, skipped)``: why the check failed (None when it passed or was skipped),
        and why it was skipped (None when it was made).
    """
    if not mode.measurable and mode.cycles_above_noise <= mode.cycles_in_record:
        return None, (f"frequency (the record's oscillation sinks below {NOISE_SIGMAS:g} noise std within "
                      f"{mode.cycles_above_noise:.2g} cycles, fitted damping ratio {mode.damping_ratio:.2g}: too "
                      f"damped to show a frequency)")
    if not mode.measurable:
        return (f"the record's first mode cannot be measured: the record spans {mode.cycles_in_record:.2g} cycles of "
                f"its oscillation; at least {MIN_CYCLES:g} cycles are needed"), None
    if not band_hz[0] <= mode.frequency_hz <= band_hz[1]:
        return (f"the record's first mode is outside the {band_hz[0]:.4g}..{band_hz[1]:.4g} Hz the declared finger "
                f"reaches (E +- {E_tolerance:.0%}, a tip mass or compliant root up to {EFFECT_ALLOWANCE:.0%} lower, "
                f"{FREQUENCY_MARGIN:.0%} model margin)"), None
    return None, None


@dataclass(frozen=True)
class Adequacy:
    """Whether the declared finger can explain the record, with the evidence (module docstring).

    Parameters
    ----------
    failed : tuple of str
        The failed checks (``record_length``, ``frequency``, ``E_bound``), empty when adequate.
    reasons : tuple of str
        One sentence per failed check, in the same order.
    skipped : tuple of str
        One sentence per check that the record cannot support (``frequency`` of a record
        too damped to ring), empty when every check was made.
    first_mode : FirstMode
        The record's own first mode.
    declared_hz : float
        The declared finger's first frequency f_1 [Hz].
    band_hz : tuple of float
        The first frequencies the declared finger may show (lowest, highest) [Hz].
    E_factor : float
        The baseline fit's E_factor [-].
    E_factor_bounds : tuple of float
        Its tolerance bounds (1 - tol, 1 + tol) [-].
    E_factor_at_bound : int
        -1 or +1 when E_factor sits on its lower or upper bound, else 0.
    periods_covered : float
        Periods of the declared first mode at E (1 - tol) the free decay covers [-].
    effective_mass_kg : float or None
        The record's first-mode effective tip mass [kg] (None when its first mode is not
        measurable).
    declared_effective_mass_kg : float
        The declared finger's [kg].
    """

    failed: tuple
    reasons: tuple
    skipped: tuple
    first_mode: FirstMode
    declared_hz: float
    band_hz: tuple
    E_factor: float
    E_factor_bounds: tuple
    E_factor_at_bound: int
    periods_covered: float
    effective_mass_kg: float | None
    declared_effective_mass_kg: float

    @property
    def adequate(self):
        """True when every check passed."""
        return not self.failed

    @property
    def effect_may_explain(self):
        """False: an impulse record's checks already tell a declaration from an effect
        (the first mode's frequency and effective tip mass)."""
        return False

    @property
    def record_hz(self):
        """The record's own first frequency [Hz], or None when it is not measurable."""
        return self.first_mode.frequency_hz if self.first_mode.measurable else None

    def message(self):
        """One line: the failed checks, why, and the record's own first frequency.

        Returns
        -------
        str
            E.g. ``declared model inadequate (frequency): ...; record's own first-mode
            frequency 1.41 Hz, declared finger's 4.47 Hz``; or ``declared model adequate``.
        """
        own = f"{self.record_hz:.4g} Hz" if self.record_hz is not None else "not measurable"
        head = (f"declared model inadequate ({', '.join(self.failed)}): " + "; ".join(self.reasons) + "; "
                if self.failed else "declared model adequate: ")
        tail = "".join(f"; not checked: {why}" for why in self.skipped)
        return head + f"record's own first-mode frequency {own}, declared finger's {self.declared_hz:.4g} Hz" + tail

    def summary(self):
        """The JSON-ready evidence.

        Returns
        -------
        dict
            ``model_adequate``, ``failed_checks``, ``reasons``, ``skipped_checks``,
            ``record_first_frequency_hz`` (None when not measurable),
            ``record_first_mode`` (fitted frequency [Hz], damping ratio, amplitude [m],
            cycles in the record and above the noise, measurable), ``declared_first_frequency_hz``,
            ``allowed_band_hz``, ``E_factor``, ``E_factor_bounds``, ``E_factor_at_bound``,
            ``periods_covered``, ``min_periods``, ``record_effective_tip_mass_kg`` (None
            when not measurable), ``declared_effective_tip_mass_kg`` and ``message``.
        """
        m = self.first_mode
        return {"model_adequate": self.adequate, "failed_checks": list(self.failed), "reasons": list(self.reasons),
                "skipped_checks": list(self.skipped),
                "record_first_frequency_hz": self.record_hz,
                "record_first_mode": {"fitted_frequency_hz": m.frequency_hz, "damping_ratio": m.damping_ratio,
                                      "amplitude_m": m.amplitude_m, "cycles_in_record": m.cycles_in_record,
                                      "cycles_above_noise": m.cycles_above_noise, "measurable": m.measurable},
                "declared_first_frequency_hz": self.declared_hz, "allowed_band_hz": list(self.band_hz),
                "E_factor": self.E_factor, "E_factor_bounds": list(self.E_factor_bounds),
                "E_factor_at_bound": self.E_factor_at_bound, "periods_covered": self.periods_covered,
                "min_periods": MIN_PERIODS, "record_effective_tip_mass_kg": self.effective_mass_kg,
                "declared_effective_tip_mass_kg": self.declared_effective_mass_kg, "message": self.message()}


def assess(model, baseline: Fit, noise_std_m):
    """Check that the declared finger can explain the record (module docstring).

    Parameters
    ----------
    model : FingerModel
        The experiment's calibration model (declared finger).
    baseline : Fit
        Its baseline fit (E_factor, alpha).
    noise_std_m : float
        Sensor noise standard deviation [m].

    Returns
    -------
    Adequacy
        The failed checks with their reasons, and the evidence.
    """
    exp = model.exp
    tol = exp.E_tolerance
    f1 = model.scales.omega1 / (2.0 * np.pi)
    reach, band = frequency_band_hz(f1, tol)
    mode = record_first_mode(exp, noise_std_m)
    free_s = float(exp.time_s[-1] - (exp.start_s + exp.duration_s))
    periods = free_s * reach[0]
    E = baseline.values["E_factor"]
    side = e_factor_bound(E, tol)
    failed, reasons = [], []
    if periods < MIN_PERIODS:
        failed.append("record_length")
        reasons.append(f"the free decay ({free_s:.3g} s) covers {periods:.2f} periods of the declared first mode "
                       f"(longest period {1.0 / reach[0]:.3g} s, at E x {1.0 - tol:g}); at least {MIN_PERIODS:g} "
                       f"are needed")
    too_damped = not mode.measurable and mode.cycles_above_noise <= mode.cycles_in_record
    reason, skip = frequency_check(mode, band, tol)
    skipped = [skip + "; E on its bound is refused instead"] if skip else []
    m_1 = declared_effective_mass_kg(model)
    m_r = effective_tip_mass_kg(exp, mode) if mode.measurable else None
    if reason is None and mode.measurable and mode.frequency_hz < reach[0]:
        m_min = root_effective_mass_kg(model, mode.frequency_hz, 1.0 - tol)
        if m_r < (1.0 - EFFECTIVE_MASS_MARGIN) * m_min:
            reason = (f"the record's first mode lies below the {reach[0]:.4g} Hz the declared finger reaches with E "
                      f"alone (E x {1.0 - tol:g}), and its effective tip mass, {1e3 * m_r:.4g} g, is not raised to the "
                      f"{1e3 * m_min:.4g} g at least that a tip mass or compliant root lowering the frequency this far "
                      f"would give (the declared finger's: {1e3 * m_1:.4g} g): the declared E, length or section does "
                      f"not fit the record")
    if reason:
        failed.append("frequency")
        reasons.append(reason)
    if too_damped and side != 0:
        failed.append("E_bound")
        reasons.append(f"the baseline E_factor {E:.4g} sits on its bound {1.0 + side * tol:g} and the record is too "
                       f"damped to show the frequency that would explain it: the declared length, section, "
                       f"material or load does not fit the record")
    elif mode.measurable and ((side < 0 and mode.frequency_hz >= reach[0] * (1.0 + FREQUENCY_MARGIN))
                              or (side > 0 and mode.frequency_hz <= reach[1] * (1.0 - FREQUENCY_MARGIN))):
        heaviest = m_1 * (1.0 + tol) * (f1 / mode.frequency_hz) ** 2 * (1.0 + MASS_ALLOWANCE)
        if not m_1 / (1.0 + MASS_ALLOWANCE) <= m_r <= heaviest:
            failed.append("E_bound")
            reasons.append(f"the baseline E_factor {E:.4g} sits on its bound {1.0 + side * tol:g} although the "
                           f"record's first frequency needs no E beyond the tolerance, and the record's first-mode "
                           f"effective tip mass, {1e3 * m_r:.4g} g, is not the declared finger's ({1e3 * m_1:.4g} g; "
                           f"{1e3 * m_1 / (1.0 + MASS_ALLOWANCE):.4g}..{1e3 * heaviest:.4g} g allowed): the declared "
                           f"mass, section or load does not fit the record")
    return Adequacy(failed=tuple(failed), reasons=tuple(reasons), skipped=tuple(skipped), first_mode=mode, declared_hz=f1,
                    band_hz=band, E_factor=E, E_factor_bounds=(1.0 - tol, 1.0 + tol), E_factor_at_bound=side,
                    periods_covered=periods, effective_mass_kg=m_r, declared_effective_mass_kg=m_1)
