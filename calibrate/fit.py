"""Least-squares fits of the calibration model to a record, with the scores the selection
uses: the log evidence and BIC on the training samples, and the RMS error on held-out blocks.

The record is cut into ``N_BLOCKS`` equal blocks; every fourth one (from the third) is held
out, so the held-out quarter spans the whole decay. The fit minimises the sum of squares
of the training residual whitened by the record's noise model (generalised least
squares, :mod:`ccedi.calibrate.likelihood`; the residual itself under white noise). With
m innovations, k parameters and their sum of squares RSS_e [m^2, or N^2 for a contact
record]::

    BIC = m ln(RSS_e / m) + k ln(m)

and the log evidence ln Z by Laplace's method (:func:`ccedi.calibrate.likelihood.laplace_log_evidence`).

Parameter uncertainty: the standard error from the Gauss-Newton covariance
s^2 (J_e^T J_e)^-1, s^2 = RSS_e / (m - k), J_e the Jacobian of the innovations, taken
through the log/linear parameter map.
"""
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from .likelihood import MAX_AR_ORDER, WHITE, NoiseModel, estimate_noise, laplace_log_evidence, rough_part

N_BLOCKS = 20
ROUGH_EXCESS = 0.1
"""Relative excess of the rough part's std over the declared noise std beyond which its
correlation is not taken for the noise's."""
QUIET_LEVEL = 0.01
"""A sample is off the discrepancy's support where its variance is below this fraction of
the largest (the timing term follows the smoothed record's noise a little)."""
QUIET_SAMPLES = 200
"""Fewest training samples off the discrepancy's support the noise is estimated on."""
DIVERGED = 10.0
"""Residual (in record ranges) returned where the model diverges (e.g. a strongly softening
cubic spring), so the optimiser backs off instead of failing."""


def holdout_mask(n):
    """Boolean mask of the held-out samples: blocks 2, 6, 10, ... of N_BLOCKS equal blocks.

    Parameters
    ----------
    n : int
        Number of samples.

    Returns
    -------
    numpy.ndarray
        Boolean mask, shape (n,), True on held-out samples (about a quarter).
    """
    block = np.minimum((np.arange(n) * N_BLOCKS) // n, N_BLOCKS - 1)
    return block % 4 == 2


@dataclass(frozen=True)
class Fit:
    """A fitted calibration model and its scores.

    Parameters
    ----------
    effects : tuple of str
        The effects added to the baseline.
    values : dict
        Fitted parameter values by name (SI units, as named).
    stderr : dict
        Standard errors by name, from the Gauss-Newton covariance (module docstring).
    prediction : numpy.ndarray
        Predicted sensor reading at the record's samples [m] (a contact record's
        transducer reading [N]; the ``_m`` fields below are then in N).
    bic : float
        BIC of the whitened training residual [-].
    log_evidence : float
        ln Z, Laplace's approximation with uniform priors over the parameters' bounds [-].
    noise : ccedi.calibrate.likelihood.NoiseModel
        The noise model the fit was made and scored under.
    chi_square : float
        Mean square of its standardised innovations on the training samples [-]: about 1
        when the residual is what the noise model (noise and the base model's
        discrepancy) allows; nan under a noise model of unknown scale.
    holdout_rms_m : float
        RMS error on the held-out samples [m].
    rms_m : float
        RMS error on the full record [m].
    nrmse : float
        Full-record RMS over the record's range [-].
    max_error_m : float
        Largest absolute error [m].
    correlation : dict
        {(p, q): correlation coefficient} of every pair of parameters p before q, from
        the same covariance [-].
    unique_share : dict
        Per parameter, the share of its signature (its column of the Jacobian of the
        training residual) that the other parameters cannot mimic, ``1 - R^2`` of that
        column regressed on the others [-]: 1 when no combination of them reproduces it,
        0 when one does exactly (:func:`unique_shares`).
    """

    effects: tuple
    values: dict
    stderr: dict
    prediction: np.ndarray
    bic: float
    log_evidence: float
    noise: object
    chi_square: float
    holdout_rms_m: float
    rms_m: float
    nrmse: float
    max_error_m: float
    correlation: dict
    unique_share: dict = field(default_factory=dict)

    @property
    def n_parameters(self):
        """Number of fitted parameters k."""
        return len(self.values)


def fit(model, effects, *, start=None, extra_starts=(), parent=None, noise=WHITE):
    """Fit the baseline plus ``effects`` to the training part of the record.

    Bounded least squares in the parameters' optimiser variables (log or scaled,
    :class:`ccedi.calibrate.effects.Parameter`); a diverging prediction is given a
    large constant residual so the optimiser backs off. The Jacobian is by forward
    differences, with each parameter's absolute ``step`` when every parameter has one
    (the contact chain), else with scipy's relative step 1e-4. The optimiser stops on a
    relative change of the cost or of z below the model's ``fit_tolerance`` (default 1e-8).

    Parameters
    ----------
    model : ccedi.calibrate.interface.CalibrationModel
        The calibration model of the experiment.
    effects : iterable of str
        Effect names from the model's catalogue, added to the baseline (E_factor, alpha).
    start : dict, optional
        Starting values by parameter name overriding the catalogue's (e.g. the
        previous round's fit). Default None.
    extra_starts : iterable of dict, optional
        Further starting values tried (each merged over the base start); the best fit
        (lowest cost) is kept. Default none.
    parent : Fit, optional
        The fit this one extends (its effects a subset of ``effects``). When the starts
        above end worse than it on the training samples (a local minimum, a stalled
        optimiser), the fit restarts from it, the added effects where they vanish
        (:meth:`ccedi.calibrate.effects.Parameter.absent_z`): a nested fit does not end
        worse than its parent (beyond what an effect's bound leaves of it). Default None.
    noise : ccedi.calibrate.likelihood.NoiseModel, optional
        The noise model whose innovations are minimised and scored. Default white.

    Returns
    -------
    Fit
        Values, standard errors, prediction and scores.
    """
    y = model.exp.signal
    train = ~holdout_mask(len(y))
    spec = model.parameters(effects)
    params = [p for p, _ in spec]
    lo, hi = np.array([p.z_bounds() for p in params]).T

    def values(z):
        return {p.name: float(p.from_z(zi)) for p, zi in zip(params, z)}

    diverged = np.full(len(noise.innovations(y, train)), DIVERGED * float(np.ptp(y)))

    def residual(z):
        r = model.predict(values(z)) - y
        return noise.innovations(r, train) if np.all(np.isfinite(r)) else diverged

    tol = getattr(model, "fit_tolerance", 1e-8)
    jac, fun = "2-point", residual
    if all(p.step is not None for p in params):
        jac, fun = _absolute_step_jacobian(residual, np.array([p.step for p in params]), lo, hi)
    def solved(z0):
        z0 = np.clip(z0, lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo))
        return least_squares(fun, z0, jac=jac, bounds=(lo, hi), x_scale=1.0, diff_step=1e-4,
                             max_nfev=60 * len(params), ftol=tol, xtol=tol)

    base = {p.name: x0 for p, x0 in spec} | (start or {})
    best = min((solved([p.to_z(guess[p.name]) for p in params]) for guess in [base] + [base | s for s in extra_starts]),
               key=lambda res: res.cost)
    if parent is not None and best.cost > 0.5 * float(np.sum(noise.innovations(parent.prediction - y, train) ** 2)):
        z_parent = [p.to_z(parent.values[p.name]) if p.name in parent.values
                    else (p.absent_z() if p.absent is not None else p.to_z(base[p.name])) for p in params]
        best = min(best, solved(z_parent), key=lambda res: res.cost)
    return _scored(model, effects, params, best, train, noise)


def _absolute_step_jacobian(residual, steps, lo, hi):
    """Forward-difference Jacobian of ``residual`` with absolute steps in z (stepping
    backwards at an upper bound); the residual at z is remembered from the last call."""
    last = {}

    def jac(z):
        key = z.tobytes()
        if last.get("z") != key:
            last.update(z=key, r=residual(z))
        r0 = last["r"]
        J = np.empty((len(r0), len(z)))
        for k, h in enumerate(steps):
            h = h if z[k] + h <= hi[k] else -h
            zk = z.copy()
            zk[k] += h
            J[:, k] = (residual(zk) - r0) / h
        return J

    def fun(z):
        r = residual(z)
        last.update(z=z.tobytes(), r=r)
        return r

    return jac, fun


def _scored(model, effects, params, res, train, noise):
    y = model.exp.signal
    v = {p.name: float(p.from_z(z)) for p, z in zip(params, res.x)}
    pred = model.predict(v)
    err = pred - y
    e = noise.innovations(err, train)
    n, k = len(e), len(params)
    rss = float(e @ e)
    s2 = rss / max(n - k, 1)
    cov = s2 * np.linalg.pinv(res.jac.T @ res.jac)
    sz = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    stderr = {p.name: float(v[p.name] * np.log(10.0) * s if p.log else p.scale * s) for p, s in zip(params, sz)}
    outer = np.outer(sz, sz)
    corr = np.divide(cov, outer, out=np.zeros_like(cov), where=outer > 0)
    pairs = {(params[i].name, params[j].name): float(corr[i, j]) for i in range(len(params))
             for j in range(i + 1, len(params))}
    rms = float(np.sqrt(np.mean(err**2)))
    return Fit(effects=tuple(effects), values=v, stderr=stderr, prediction=pred,
               bic=float(n * np.log(rss / n) + k * np.log(n)),
               log_evidence=laplace_log_evidence(e, res.jac, np.array([np.ptp(p.z_bounds()) for p in params])),
               noise=noise, chi_square=rss / n if np.isfinite(noise.innovation_std) else float("nan"),
               holdout_rms_m=float(np.sqrt(np.mean(err[~train] ** 2))), rms_m=rms,
               nrmse=rms / float(np.ptp(y)), max_error_m=float(np.max(np.abs(err))), correlation=pairs,
               unique_share=dict(zip((p.name for p in params), unique_shares(res.jac))))


def unique_shares(jacobian):
    """The share of each column of a Jacobian that the other columns cannot reproduce.

    ``1 - R^2`` of column i regressed (least squares, no intercept) on the others:
    ``|(I - P_others) J_i|^2 / |J_i|^2``, with ``P_others`` the projection on their span.
    Scale-free (a column's units and the optimiser's variables do not matter).

    Parameters
    ----------
    jacobian : numpy.ndarray
        Sensitivities of the residual, shape (samples, parameters).

    Returns
    -------
    list of float
        Per column, in [0, 1]; 1 for a single column, 0 for a zero column.
    """
    J = np.asarray(jacobian, dtype=float)
    shares = []
    for i in range(J.shape[1]):
        col, others = J[:, i], np.delete(J, i, axis=1)
        norm = float(col @ col)
        if norm == 0.0:
            shares.append(0.0)
            continue
        if others.shape[1] == 0:
            shares.append(1.0)
            continue
        left = col - others @ np.linalg.lstsq(others, col, rcond=None)[0]
        shares.append(float(np.clip(left @ left / norm, 0.0, 1.0)))
    return shares


def fit_baseline(model):
    """The declared model fitted: E_factor and alpha, and the record's noise model.

    Starts from the best of the model's starting points (``model.baseline_starts()``:
    for an impulse record a grid of E across its tolerance times first-mode damping
    ratios, :meth:`ccedi.calibrate.model.FingerModel.baseline_starts`), refined by least
    squares, then refitted under the noise model of its residual (:func:`under_own_noise`).

    Parameters
    ----------
    model : ccedi.calibrate.interface.CalibrationModel
        The calibration model of the experiment.

    Returns
    -------
    Fit
        The baseline fit (no effects), with its ``noise``.
    """
    y = model.exp.signal
    best, best_err = None, np.inf
    for v in model.baseline_starts():
        err = float(np.sum((model.predict(v) - y) ** 2))
        if err < best_err:
            best, best_err = v, err
    return under_own_noise(model, fit(model, (), start=best))


def under_own_noise(model, fitted):
    """A fit refitted under the noise model of its own residual: the AR noise estimated on
    it (:func:`ccedi.calibrate.likelihood.estimate_noise`) plus the base model's discrepancy
    at its reading (``model.discrepancy_covariance``), or itself when that is the noise
    model it was made under (:meth:`ccedi.calibrate.likelihood.NoiseModel.same_as`). With
    a discrepancy, the noise is the sensor's, white, of the std of the residual's rough
    part where the discrepancy's variance is negligible (``QUIET_LEVEL``) at the model's
    reading and at the record's own (smoothed) one (off contact: not the chatter, which the discrepancy carries), when
    there are at least ``QUIET_SAMPLES`` training samples there: the few hundred samples
    off contact do not resolve an AR model (on drum_speed_fast's white noise the
    deconvolution found order 5, low-frequency gain 0.54). When the sidecar declares the
    noise std, the noise keeps the estimate's correlation and takes that std: estimated on
    the residual, the std would take in what the model misses and the chi-square tests of
    the loop would pass it. Where the rough part's std exceeds what the noise and the base
    model's own error allow (the declared std and the discrepancy's RMS std in quadrature)
    by more than ``ROUGH_EXCESS``, the rough part holds misfit, not only noise (a higher
    mode the model places wrong: root_compliance_low of the solid set, order 5 with phi_1
    0.56), and the declared noise is taken white.

    Parameters
    ----------
    model : ccedi.calibrate.interface.CalibrationModel
        The calibration model of the experiment.
    fitted : Fit
        A fit of it.

    Returns
    -------
    Fit
        The fit under its residual's noise model.
    """
    y, t = model.exp.signal, model.exp.time_s
    scored = ~holdout_mask(len(y))
    dt = float(t[1] - t[0])
    discrepancy = model.discrepancy_covariance(fitted.prediction)
    max_order = MAX_AR_ORDER
    if discrepancy is not None:
        on_record = model.discrepancy_covariance(y - rough_part(y, dt))      # where the record itself is in contact
        quiet = scored & _quiet(discrepancy) & _quiet(on_record)
        scored, max_order = (quiet, 0) if quiet.sum() >= QUIET_SAMPLES else (scored, max_order)
    noise = estimate_noise(fitted.prediction - y, scored, dt, max_order=max_order)
    if model.exp.declared_noise is not None:            # the sensor's std as declared, the estimate's correlation
        declared = float(model.exp.declared_noise)
        allowed = declared if discrepancy is None else float(np.hypot(declared, np.sqrt(np.mean(np.diag(discrepancy)))))
        ar = noise.ar if np.sqrt(noise.process_variance()) <= (1.0 + ROUGH_EXCESS) * allowed else np.zeros(0)
        noise = NoiseModel(ar, declared / np.sqrt(NoiseModel(ar, 1.0).process_variance()))
    noise = noise.with_discrepancy(discrepancy)
    if noise.same_as(fitted.noise):
        return fitted
    return fit(model, fitted.effects, start=fitted.values, noise=noise)


def _quiet(covariance):
    """Samples where a discrepancy's variance is below QUIET_LEVEL of its largest."""
    variance = np.diag(covariance)
    return variance <= QUIET_LEVEL * float(np.max(variance))


def e_factor_bound(E_factor, tol):
    """Which tolerance bound a fitted E_factor sits on.

    On a bound means within 1 % of the tolerance (at least 1e-5) of it.

    Parameters
    ----------
    E_factor : float
        Fitted Young's modulus over the declared one [-].
    tol : float
        Relative tolerance of the declared E [-].

    Returns
    -------
    int
        -1 on the lower bound 1 - tol, +1 on the upper bound 1 + tol, else 0.
    """
    width = 0.01 * max(tol, 1e-3)
    if E_factor - (1.0 - tol) < width:
        return -1
    return 1 if (1.0 + tol) - E_factor < width else 0
