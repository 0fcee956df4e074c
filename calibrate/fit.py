"""Least-squares fits of the calibration model to a record, with the scores the selection
uses: BIC on the training samples and the RMS error on held-out blocks.

The record is cut into ``N_BLOCKS`` equal blocks; every fourth one (from the third) is held
out, so the held-out quarter spans the whole decay. With n training samples, k parameters
and residual sum of squares RSS [m^2]::

    BIC = n ln(RSS / n) + k ln(n)

Parameter uncertainty: the standard error from the Gauss-Newton covariance
s^2 (J^T J)^-1, s^2 = RSS / (n - k), taken through the log/linear parameter map.
"""
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from .model import FingerModel

N_BLOCKS = 20
DIVERGED = 10.0
"""Residual (in record ranges) returned where the model diverges (e.g. a strongly softening
cubic spring), so the optimiser backs off instead of failing."""


def holdout_mask(n):
    """Boolean mask of the held-out samples among ``n`` (blocks 2, 6, 10, ... of N_BLOCKS)."""
    block = np.minimum((np.arange(n) * N_BLOCKS) // n, N_BLOCKS - 1)
    return block % 4 == 2


@dataclass(frozen=True)
class Fit:
    """A fitted model: its effects, parameter values and standard errors (by name, SI),
    the sensor reading it predicts [m], its training BIC, held-out RMS [m], full-record
    RMS [m], NRMSE [-] and max error [m]."""

    effects: tuple
    values: dict
    stderr: dict
    prediction: np.ndarray
    bic: float
    holdout_rms_m: float
    rms_m: float
    nrmse: float
    max_error_m: float

    @property
    def n_parameters(self):
        return len(self.values)


def fit(model: FingerModel, effects, start=None, extra_starts=()):
    """Fit the baseline plus ``effects`` to the training part of the record. ``start`` (a
    dict) overrides the catalogue's starting values (e.g. the previous round's fit);
    ``extra_starts`` are further dicts of starting values tried, the best kept."""
    y = model.exp.displacement_m
    train = ~holdout_mask(len(y))
    spec = model.parameters(effects)
    params = [p for p, _ in spec]
    lo, hi = np.array([p.z_bounds() for p in params]).T

    def values(z):
        return {p.name: float(p.from_z(zi)) for p, zi in zip(params, z)}

    def residual(z):
        r = (model.predict(values(z)) - y)[train]
        return r if np.all(np.isfinite(r)) else np.full_like(r, DIVERGED * float(np.ptp(y)))

    best = None
    base = {p.name: x0 for p, x0 in spec} | (start or {})
    for guess in [base] + [base | s for s in extra_starts]:
        z0 = np.clip([p.to_z(guess[p.name]) for p in params], lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo))
        res = least_squares(residual, z0, bounds=(lo, hi), x_scale=1.0, diff_step=1e-4, max_nfev=60 * len(params))
        if best is None or res.cost < best.cost:
            best = res
    return _scored(model, effects, params, best, train)


def _scored(model, effects, params, res, train):
    y = model.exp.displacement_m
    v = {p.name: float(p.from_z(z)) for p, z in zip(params, res.x)}
    pred = model.predict(v)
    err = pred - y
    n, k = int(train.sum()), len(params)
    rss = float(np.sum(err[train] ** 2))
    s2 = rss / max(n - k, 1)
    cov = s2 * np.linalg.pinv(res.jac.T @ res.jac)
    sz = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    stderr = {p.name: float(v[p.name] * np.log(10.0) * s if p.log else p.scale * s) for p, s in zip(params, sz)}
    rms = float(np.sqrt(np.mean(err**2)))
    return Fit(effects=tuple(effects), values=v, stderr=stderr, prediction=pred,
               bic=float(n * np.log(rss / n) + k * np.log(n)),
               holdout_rms_m=float(np.sqrt(np.mean(err[~train] ** 2))), rms_m=rms,
               nrmse=rms / float(np.ptp(y)), max_error_m=float(np.max(np.abs(err))))


def fit_baseline(model: FingerModel, n_E=17, zetas=(0.01, 0.03, 0.1, 0.3, 1.0, 2.0)):
    """The declared model fitted: alpha and E_factor from the best point of a grid
    (n_E values of E across the tolerance x damping ratios of mode 1), refined by least squares."""
    s = model.scales
    tol = model.exp.E_tolerance
    y = model.exp.displacement_m
    best, best_err = None, np.inf
    for e in np.linspace(1.0 - tol, 1.0 + tol, n_E):
        for z in zetas:
            v = {"E_factor": float(e), "alpha_per_s": 2.0 * z * s.omega1 * np.sqrt(e)}
            err = float(np.sum((model.predict(v) - y) ** 2))
            if err < best_err:
                best, best_err = v, err
    return fit(model, (), start=best)
