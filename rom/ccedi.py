"""CCEDI: the paper's coupled computational and experimental damping identification (Fig. 2).

Rayleigh damping with beta = 0 (low-frequency structures): ``C = alpha M``, so the modal
damping ratios are ``zeta_i = alpha / (2 omega_i)`` (paper Eq. 3b).

* Under-damped structure: measure zeta by log-decrement, find by simulation the
  critical coefficient alpha_cr at which the impulse response stops oscillating
  (:func:`critical_alpha`), and set ``alpha = zeta alpha_cr``.
* Over-damped structure: search alpha until the simulated impulse response matches the
  measured one in the least-squares sense (:func:`match_alpha`).

Both take an impulse model (:class:`ccedi.models.ImpulseModel`: the full FE model,
:class:`ccedi.fea.cases.studies.FullImpulseModel`, or its modal ROM,
:class:`ccedi.rom.modal.ModalImpulseModel`) with the length ``t_end_s`` [s] and the
output count ``n_outputs`` of every run, so the full and a reduced model are swapped with
one argument; they read only the core ``time_s`` and ``tip_uy_m`` columns of each
:class:`ccedi.models.ImpulseResponse`. Both report how many simulations they used.
"""
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize_scalar

from ccedi.errors import InputError, require_finite_positive
from ccedi.models import ImpulseModel, ImpulseResponse, run_alphas

from .damping import _validate_signal, log_decrement, noise_level, oscillates


def _tip_signal(model, alpha, t_end_s, n_outputs):
    """One run of an impulse model as arrays (the searches' only contact with a model).

    Parameters
    ----------
    model : ccedi.models.ImpulseModel
        The model.
    alpha : float
        Mass-proportional damping coefficient [1/s].
    t_end_s : float
        Simulated time [s].
    n_outputs : int
        Output times.

    Returns
    -------
    tuple of numpy.ndarray
        ``(time_s [s], tip_uy_m [m])`` of :meth:`ccedi.models.ImpulseResponse.tip_signal`.

    Raises
    ------
    InputError
        The model answers something other than an :class:`ccedi.models.ImpulseResponse`.
    """
    return _signal_of(model, model.run(alpha, t_end_s, n_outputs))


def _signal_of(model, response):
    """``response.tip_signal()``; InputError when ``model`` answered something other than
    an :class:`ccedi.models.ImpulseResponse`."""
    if not isinstance(response, ImpulseResponse):
        raise InputError(f"{model.name}.run must answer an ImpulseResponse, got {type(response).__name__}")
    return response.tip_signal()


def _require_impulse_model(model):
    """Check that ``model`` speaks the impulse-model interface.

    Parameters
    ----------
    model : object
        What the caller passed as the model.

    Raises
    ------
    InputError
        ``model`` is not a :class:`ccedi.models.ImpulseModel` (no ``run``, ``name``,
        ``force_N`` or ``duration_s``).
    """
    if not isinstance(model, ImpulseModel):
        raise InputError(f"expected an impulse model (ccedi.models.ImpulseModel: name, force_N, duration_s and "
                         f"run(alpha, t_end_s, n_outputs)), got {type(model).__name__}")


@dataclass(frozen=True)
class CriticalAlpha:
    """Result of :func:`critical_alpha`.

    Parameters
    ----------
    alpha_cr_per_s : float
        Midpoint of the final bracket [1/s].
    bracket_per_s : tuple
        (oscillating, not oscillating) [1/s].
    n_runs : int
        Simulations used.
    runs : list
        [(alpha [1/s], oscillates), ...] in the order run.
    reduced_alpha_cr_per_s : float or None
        alpha_cr of the reduced model that set the first bracket
        (:func:`critical_alpha_narrowed`) [1/s]; None without one.
    """

    alpha_cr_per_s: float
    bracket_per_s: tuple
    n_runs: int
    runs: list = field(default_factory=list)
    reduced_alpha_cr_per_s: float | None = None


NARROW_WIDENINGS = 6
"""Widenings by the bracket's own width tried around the reduced model's alpha_cr before the
full model's search starts afresh from it (:func:`critical_alpha_narrowed`)."""


def critical_alpha_narrowed(full, reduced, alpha_guess, *, t_end_s, rtol=0.01, noise_band=1e-6, n_outputs=400,
                            runs_per_round=8):
    """alpha_cr of ``full`` with its bracket set by ``reduced`` first: the reduced model's
    alpha_cr (to rtol / 10, cheap) centres one round of ``runs_per_round`` full runs,
    spaced 0.95 rtol apart, so that one pass brackets alpha_cr to within rtol when the
    reduced model is that close. When it is a little off, the end that does not bracket
    moves out by the bracket's own width, one full run at a time (up to
    :data:`NARROW_WIDENINGS`), which brackets to within rtol at once; when it is far off,
    the search starts afresh from the reduced model's value as :func:`critical_alpha`.

    Parameters
    ----------
    full : ccedi.models.ImpulseModel
        The model whose alpha_cr is wanted (the full FE model: its runs are batched).
    reduced : ccedi.models.ImpulseModel
        A cheap model of the same structure (its modal ROM).
    alpha_guess : float
        Starting guess for the reduced model's search [1/s], > 0 (2 omega_1).
    t_end_s : float
        Simulated time of every run [s], > 0.
    rtol : float, optional
        Final bracket width relative to its upper end, in (0, 0.1).
    noise_band : float, optional
        Crossing band relative to the largest excursion [-].
    n_outputs : int, optional
        Output times of every run.
    runs_per_round : int, optional
        Full runs per round, >= 1.

    Returns
    -------
    CriticalAlpha
        Of the full model; ``reduced_alpha_cr_per_s`` the reduced model's, ``runs`` and
        ``n_runs`` the full model's runs only.

    Raises
    ------
    InputError
        Invalid arguments, or no bracket found.
    """
    if not 0.0 < rtol < 0.1:
        raise InputError(f"rtol must be in (0, 0.1), got {rtol!r}")
    first = critical_alpha(reduced, alpha_guess, t_end_s, rtol=rtol / 10.0, noise_band=noise_band,
                           n_outputs=n_outputs)
    half = 0.95 * rtol * max(runs_per_round - 1, 1) / 2.0
    common = dict(rtol=rtol, noise_band=noise_band, n_outputs=n_outputs, runs_per_round=runs_per_round)
    try:                               # the ROM a little off: widen by the bracket's own width
        crit = critical_alpha(full, first.alpha_cr_per_s, t_end_s, bracket=(1.0 - half, 1.0 + half),
                              widen=(1.0 + half) / (1.0 - half), max_expand=NARROW_WIDENINGS, **common)
    except InputError:                 # far off: the ROM's value is only a first guess
        crit = critical_alpha(full, first.alpha_cr_per_s, t_end_s, **common)
    return CriticalAlpha(crit.alpha_cr_per_s, crit.bracket_per_s, crit.n_runs, crit.runs,
                         reduced_alpha_cr_per_s=first.alpha_cr_per_s)


def critical_alpha(model, alpha_guess, t_end_s, *, rtol=0.01, bracket=(0.8, 1.1), noise_band=1e-6, max_expand=6,
                   n_outputs=400, runs_per_round=1, widen=1.5):
    """Critical mass-proportional coefficient alpha_cr [1/s] by bisection on "the
    simulated tip response oscillates" (:func:`ccedi.rom.damping.oscillates`: after its
    largest excursion the response crosses its final value, 0 after an impulse, by more
    than ``noise_band`` x that excursion).

    The search starts from the bracket ``alpha_guess * bracket`` (a good guess is
    2 omega_1, the critical value of mode 1 alone), widens it by ``widen`` until the low end
    oscillates and the high end does not, then halves it until its width is below
    ``rtol`` x its upper end. The simulation must run long enough for a nearly critical
    response to cross zero (about 12 / omega_1 after the load ends).

    Parameters
    ----------
    model : ccedi.models.ImpulseModel
        The impulse model (full or reduced), run for ``t_end_s`` at ``n_outputs`` times.
    alpha_guess : float
        Centre of the first bracket [1/s], > 0.
    t_end_s : float
        Simulated time of every run [s], > 0 (about the load duration + 12 / omega_1).
    rtol : float, optional
        Final bracket width relative to its upper end, in (0, 1).
    bracket : tuple, optional
        (low, high) factors on ``alpha_guess``, 0 < low < high.
    noise_band : float, optional
        Crossing band relative to the largest excursion [-].
    max_expand : int, optional
        Widening steps allowed at either end.
    n_outputs : int, optional
        Output times of every run.
    runs_per_round : int, optional
        Runs evaluated together per round, >= 1.
    widen : float, optional
        Factor by which an end that does not bracket moves outwards, > 1.

    Returns
    -------
    CriticalAlpha

    Raises
    ------
    InputError
        Not an impulse model, invalid arguments, or no bracket found within
        ``max_expand`` widenings.
    """
    _require_impulse_model(model)
    alpha_guess = require_finite_positive("alpha_guess (1/s)", alpha_guess)
    lo, hi = alpha_guess * bracket[0], alpha_guess * bracket[1]
    if not 0.0 < lo < hi:
        raise InputError(f"bracket must be two factors 0 < low < high, got {bracket!r}")
    if not 0.0 < rtol < 1.0:
        raise InputError(f"rtol must be in (0, 1), got {rtol!r}")
    if not (isinstance(runs_per_round, (int, np.integer)) and runs_per_round >= 1):
        raise InputError(f"runs_per_round must be an integer >= 1, got {runs_per_round!r}")
    if not (np.isfinite(widen) and widen > 1.0):
        raise InputError(f"widen must be a factor > 1, got {widen!r}")
    runs = []
    seen = {}

    def oscillating(*alphas):
        new = [float(a) for a in alphas if float(a) not in seen]
        for alpha, response in zip(new, run_alphas(model, new, t_end_s, n_outputs=n_outputs)):
            t, y = _signal_of(model, response)
            seen[alpha] = bool(oscillates(t, y, y_final=0.0, noise_band=noise_band))
            runs.append((alpha, seen[alpha]))
        return [seen[float(a)] for a in alphas]

    def narrowed(lo, hi):
        """The tightest bracket the runs so far give inside (lo, hi)."""
        lo = max([a for a, osc in seen.items() if osc and lo <= a < hi], default=lo)
        hi = min([a for a, osc in seen.items() if not osc and lo < a <= hi], default=hi)
        return lo, hi

    if runs_per_round > 1:
        oscillating(*np.linspace(lo, hi, runs_per_round))
    for _ in range(max_expand):
        if oscillating(lo)[0]:
            break
        hi, lo = lo, lo / widen
    else:
        raise InputError(f"no oscillating response down to alpha = {lo:.4g} 1/s: check the model and load")
    for _ in range(max_expand):
        if not oscillating(hi)[0]:
            break
        lo, hi = hi, hi * widen
    else:
        raise InputError(f"the response still oscillates at alpha = {hi:.4g} 1/s: run longer or widen the bracket")
    lo, hi = narrowed(lo, hi)
    while hi - lo > rtol * hi:
        oscillating(*np.linspace(lo, hi, runs_per_round + 2)[1:-1])
        lo, hi = narrowed(lo, hi)
    return CriticalAlpha(alpha_cr_per_s=0.5 * (lo + hi), bracket_per_s=(lo, hi), n_runs=len(runs), runs=runs)


@dataclass(frozen=True)
class AlphaMatch:
    """Result of :func:`match_alpha`.

    Parameters
    ----------
    alpha_per_s : float
        Matched alpha [1/s].
    rms_error_m : float
        Smallest RMS misfit [m].
    relative_rms_error : float
        That misfit over the RMS of the measured response [-].
    n_runs : int
        Simulations used.
    evaluations : list
        [(alpha [1/s], misfit [m]), ...].
    """

    alpha_per_s: float
    rms_error_m: float
    relative_rms_error: float
    n_runs: int
    evaluations: list = field(default_factory=list)


def match_alpha(model, time_s, tip_displacement_m, *, bounds_per_s, xatol_rel=0.002, t_end_s=None, n_outputs=400):
    """alpha [1/s] minimising the RMS difference between the simulated and the measured
    tip response on the measured times (bounded Brent search, scipy.optimize).

    The simulation is interpolated onto ``time_s`` (which must lie within the simulated
    time span). ``xatol_rel`` is the absolute tolerance on alpha relative to the upper
    bound.

    Parameters
    ----------
    model : ccedi.models.ImpulseModel
        The impulse model (full or reduced).
    time_s, tip_displacement_m : array_like
        The measured response: times [s] and tip displacement [m].
    bounds_per_s : tuple
        (low, high) search bounds on alpha [1/s].
    xatol_rel : float, optional
        Tolerance on alpha relative to the upper bound.
    t_end_s : float, optional
        Simulated time of every run [s] (default: the last measured time).
    n_outputs : int, optional
        Output times of every run.

    Returns
    -------
    AlphaMatch

    Raises
    ------
    InputError
        Not an impulse model, invalid signal or bounds, or measured times outside the
        simulated span.
    """
    _require_impulse_model(model)
    t, y = _validate_signal(time_s, tip_displacement_m)
    t_end_s = float(t[-1]) if t_end_s is None else t_end_s
    lo, hi = (require_finite_positive(f"bounds_per_s[{i}] (1/s)", b, allow_zero=True)
              for i, b in enumerate(bounds_per_s))
    if not lo < hi:
        raise InputError(f"bounds_per_s must be (low, high) with low < high, got {bounds_per_s!r}")
    evaluations = []
    y_rms = float(np.sqrt(np.mean(y**2)))

    def misfit(alpha):
        ts, ys = _tip_signal(model, alpha, t_end_s, n_outputs)
        if t[0] < ts[0] - 1e-12 or t[-1] > ts[-1] + 1e-12:
            raise InputError(f"measured times [{t[0]:.4g}, {t[-1]:.4g}] s fall outside the simulation "
                             f"[{ts[0]:.4g}, {ts[-1]:.4g}] s")
        err = float(np.sqrt(np.mean((np.interp(t, ts, ys) - y) ** 2)))
        evaluations.append((float(alpha), err))
        return err

    res = minimize_scalar(misfit, bounds=(lo, hi), method="bounded", options={"xatol": xatol_rel * hi})
    best = min(evaluations, key=lambda e: e[1])
    return AlphaMatch(alpha_per_s=float(res.x), rms_error_m=best[1], relative_rms_error=best[1] / y_rms,
                      n_runs=len(evaluations), evaluations=evaluations)


@dataclass(frozen=True)
class Identification:
    """Result of :func:`identify`.

    Parameters
    ----------
    regime : str
        The CCEDI branch taken, "under-damped" or "over-damped".
    alpha_per_s : float
        Identified alpha [1/s].
    zeta : float
        Damping ratio [-]: measured, or alpha / alpha_cr when over-damped (NaN without
        alpha_cr).
    alpha_cr_per_s : float or None
        Critical alpha [1/s] (None when not computed).
    n_runs : int
        Simulations used.
    detail : dict
        Branch-specific figures (confidence interval, noise band, misfit, ...).
    """

    regime: str
    alpha_per_s: float
    zeta: float
    alpha_cr_per_s: float | None
    n_runs: int
    detail: dict = field(default_factory=dict)


def identify(time_s, tip_displacement_m, model, *, alpha_guess, bounds_per_s=None, noise_band=0.02,
             critical=None, t_end_s=None, n_outputs=400):
    """The CCEDI procedure (paper Fig. 2) on a measured impulse response.

    If the measured response oscillates (crosses its final value, after its peak, by more
    than the band: ``noise_band`` x the peak, or five times the measurement noise
    estimated by :func:`ccedi.rom.damping.noise_level` if larger), zeta comes from log-decrement and
    ``alpha = zeta alpha_cr`` with alpha_cr from :func:`critical_alpha` (or ``critical``,
    a precomputed CriticalAlpha). Otherwise alpha is matched by :func:`match_alpha`
    within ``bounds_per_s`` (default 0.2 to 10 x ``alpha_guess``).

    Parameters
    ----------
    time_s, tip_displacement_m : array_like
        The measured impulse response: times [s] and tip displacement [m].
    model : ccedi.models.ImpulseModel
        The impulse model (full or reduced).
    alpha_guess : float
        Starting alpha [1/s] (2 omega_1 is a good one).
    bounds_per_s : tuple, optional
        Search bounds of the over-damped branch [1/s].
    noise_band : float, optional
        Least crossing band relative to the peak [-].
    critical : CriticalAlpha, optional
        A precomputed alpha_cr (no search then).
    t_end_s : float, optional
        Simulated time of every run [s] (default: the last measured time; the
        alpha_cr search needs about 12 / omega_1 after the load).
    n_outputs : int, optional
        Output times of every run.

    Returns
    -------
    Identification

    Raises
    ------
    InputError
        Not an impulse model, invalid signal, or a failed alpha_cr bracket.
    """
    _require_impulse_model(model)
    t, y = _validate_signal(time_s, tip_displacement_m)
    t_end_s = float(t[-1]) if t_end_s is None else t_end_s
    final = float(np.mean(y[int(0.9 * len(y)):]))
    peak = float(np.max(np.abs(y - final)))
    band = min(max(noise_band, 5.0 * noise_level(y) / peak), 0.5) if peak > 0 else noise_band
    if oscillates(t, y, y_final=final, noise_band=band):
        ld = log_decrement(t, y, y_final=final, noise_band=band)
        crit = critical or critical_alpha(model, alpha_guess, t_end_s, n_outputs=n_outputs)
        return Identification(regime="under-damped", alpha_per_s=ld.zeta * crit.alpha_cr_per_s, zeta=ld.zeta,
                              alpha_cr_per_s=crit.alpha_cr_per_s, n_runs=0 if critical else crit.n_runs,
                              detail={"zeta_ci95": ld.zeta_ci95, "n_cycles": ld.n_cycles, "noise_band": band,
                                      "omega_d_rad_s": ld.omega_d_rad_s,
                                      "alpha_cr_bracket_per_s": crit.bracket_per_s})
    bounds = bounds_per_s or (0.2 * alpha_guess, 10.0 * alpha_guess)
    match = match_alpha(model, t, y, bounds_per_s=bounds, t_end_s=t_end_s, n_outputs=n_outputs)
    zeta = match.alpha_per_s / critical.alpha_cr_per_s if critical else float("nan")
    return Identification(regime="over-damped", alpha_per_s=match.alpha_per_s, zeta=zeta,
                          alpha_cr_per_s=critical.alpha_cr_per_s if critical else None, n_runs=match.n_runs,
                          detail={"rms_error_m": match.rms_error_m, "noise_band": band,
                                  "relative_rms_error": match.relative_rms_error})


def power_law_fit(x, y):
    """Least-squares fit of ``y = c x^p`` in log-log space.

    Parameters
    ----------
    x, y : array_like
        At least two positive pairs.

    Returns
    -------
    tuple
        (c, p).

    Raises
    ------
    InputError
        Fewer than two pairs, unequal lengths or non-positive values.
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if len(x) < 2 or x.shape != y.shape or np.any(x <= 0) or np.any(y <= 0):
        raise InputError("power_law_fit needs at least two positive (x, y) pairs of equal length")
    p, logc = np.polyfit(np.log(x), np.log(y), 1)
    return float(np.exp(logc)), float(p)


def paper_alpha_cr(length_in):
    """Paper Eq. (8): alpha_cr = 3120.4 x^-1.983 [1/s], finger length x in inches, 3 <= x <= 8.

    Parameters
    ----------
    length_in : float or array_like
        Finger length [in].

    Returns
    -------
    numpy.ndarray
        alpha_cr [1/s].
    """
    return 3120.4 * np.asarray(length_in, dtype=float) ** -1.983


def paper_alpha(length_in):
    """Paper Eq. (7): alpha [1/s] of the rubber fingers against length x [in], 3 <= x <= 8:
    56.667 x^2 - 705 x + 2205 for x <= 6, -3.75 x + 37.5 above.

    Parameters
    ----------
    length_in : float or array_like
        Finger length [in].

    Returns
    -------
    numpy.ndarray
        alpha [1/s].
    """
    x = np.asarray(length_in, dtype=float)
    return np.where(x <= 6.0, 56.667 * x**2 - 705.0 * x + 2205.0, -3.75 * x + 37.5)


def piecewise_alpha_fit(length_in, alpha):
    """The form of paper Eq. (7) fitted to four (length [in], alpha [1/s]) points at
    3, 4.5, 6 and 8 in: a quadratic through the first three and a line through the last
    two.

    Parameters
    ----------
    length_in : array_like
        Four increasing lengths [in].
    alpha : array_like
        Four alphas [1/s].

    Returns
    -------
    tuple
        ((a2, a1, a0), (b1, b0)).

    Raises
    ------
    InputError
        Not four increasing lengths and four alphas.
    """
    x = np.asarray(length_in, dtype=float)
    a = np.asarray(alpha, dtype=float)
    if x.shape != (4,) or a.shape != (4,) or not np.all(np.diff(x) > 0):
        raise InputError("piecewise_alpha_fit needs four increasing lengths and four alphas")
    quad = np.polyfit(x[:3], a[:3], 2)
    line = np.polyfit(x[2:], a[2:], 1)
    return tuple(float(c) for c in quad), tuple(float(c) for c in line)
