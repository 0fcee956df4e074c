"""Modal reduced model of a linearised FE model with Rayleigh damping.

From the tangent stiffness K (at the undeformed or a preloaded state) and the lumped
mass M, the first N mass-normalised modes phi_i (K phi = omega^2 M phi) decouple the
equations of motion. With Rayleigh damping C = alpha M + beta K every mode is a
single-DOF oscillator, paper Eq. (3b)::

    q_i'' + 2 zeta_i omega_i q_i' + omega_i^2 q_i = (phi_i . f_shape) F(t)
    zeta_i = alpha / (2 omega_i) + beta omega_i / 2
    y(t)   = sum_i (c . phi_i) q_i(t)

with f_shape the nodal distribution of a unit load and c the output weights (here: the
area-weighted tip displacement). g_i = (c . phi_i)(phi_i . f_shape) [m/N per (rad/s)^2]
is the mode's gain: its static flexibility contribution is g_i / omega_i^2.

The response to a rectangular pulse of force F held for T seconds is exact, whatever the
damping (under-, critically or over-damped), from the unit step response of each mode::

    s(t) = (1 - exp(-zeta w t) [cos(w_d t) + zeta w sin(w_d t) / w_d]) / w^2,
    w_d = w sqrt(1 - zeta^2)   (complex when zeta > 1; sin(w_d t)/w_d -> t at zeta = 1)
    y(t) = F sum_i g_i [s_i(t) - H(t - T) s_i(t - T)]

"Fitted from the FEA" (:func:`fit_to_response`): omega_i, zeta_i and g_i are refined
by bounded least squares against a full FE impulse response, so the surrogate matches
what the full model does (its lumped-mass explicit dynamics and, at the amplitude of the
fit, its geometric nonlinearity); the fit's residual is reported.
"""
import time
from dataclasses import dataclass, replace

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

from ccedi.errors import InputError, require_finite_positive
from ccedi.fea.model import Model, face_node_weights
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.fea.solvers.validity import cantilever_length_m, issue, run_label, tip_deflection_warnings
from ccedi.models import ImpulseResponse, pulse_times, validate_run_args


@dataclass(frozen=True)
class ModalROM:
    """N uncoupled Rayleigh-damped modes from one force input to one displacement output.

    Parameters
    ----------
    omega_rad_s : numpy.ndarray
        Natural frequencies (N,) [rad/s].
    gain : numpy.ndarray
        Modal gains g_i (N,) [m/(N s^2)] (see the module docstring).
    alpha : float, optional
        Mass-proportional damping [1/s].
    beta : float, optional
        Stiffness-proportional damping [s].
    zeta_fitted : numpy.ndarray, optional
        Damping ratios (N,) [-] that override the Rayleigh ones (a fitted model).
    """

    omega_rad_s: np.ndarray
    gain: np.ndarray
    alpha: float = 0.0
    beta: float = 0.0
    zeta_fitted: np.ndarray | None = None

    @property
    def n_modes(self):
        """Number of modes N."""
        return len(self.omega_rad_s)

    @property
    def zeta(self):
        """Modal damping ratios: fitted, or alpha / (2 omega) + beta omega / 2."""
        if self.zeta_fitted is not None:
            return self.zeta_fitted
        return self.alpha / (2.0 * self.omega_rad_s) + self.beta * self.omega_rad_s / 2.0

    def with_damping(self, alpha, beta=0.0):
        """The same modes with Rayleigh damping (drops fitted zeta).

        Parameters
        ----------
        alpha : float
            Mass-proportional damping [1/s], >= 0.
        beta : float, optional
            Stiffness-proportional damping [s], >= 0.

        Returns
        -------
        ModalROM

        Raises
        ------
        InputError
            Negative or non-finite alpha or beta.
        """
        return replace(self, alpha=require_finite_positive("alpha (1/s)", alpha, allow_zero=True),
                       beta=require_finite_positive("beta (s)", beta, allow_zero=True), zeta_fitted=None)

    @property
    def static_flexibility(self):
        """Tip displacement per unit static force [m/N]: sum g_i / omega_i^2."""
        return float(np.sum(self.gain / self.omega_rad_s**2))

    def pulse_response(self, time_s, force_N, duration_s):
        """Output for a rectangular force pulse (exact, any damping).

        Parameters
        ----------
        time_s : array_like
            Output times [s].
        force_N : float
            Force [N], held from 0 to ``duration_s``.
        duration_s : float
            Pulse length [s].

        Returns
        -------
        numpy.ndarray
            Displacement [m] at ``time_s``.
        """
        t = np.asarray(time_s, dtype=float)
        y = _step(self.omega_rad_s, self.zeta, t) - _step(self.omega_rad_s, self.zeta, t - duration_s)
        return force_N * (self.gain @ y)

    def state_space(self):
        """The model as a python-control state-space system.

        Returns
        -------
        control.StateSpace
            State (q_1..q_N, q_1'..q_N'), input force [N], output displacement [m].
        """
        import control  # python-control loads only for the state-space form

        n = self.n_modes
        w, z = self.omega_rad_s, self.zeta
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.diag(w**2), -np.diag(2 * z * w)]])
        B = np.concatenate([np.zeros(n), np.ones(n)])[:, None]
        C = np.concatenate([self.gain, np.zeros(n)])[None, :]
        return control.ss(A, B, C, np.zeros((1, 1)))


def _step(omega, zeta, t):
    """Unit step responses s_i(t) (N, len(t)) of q'' + 2 zeta w q' + w^2 q = H(t).

    Written in real arithmetic for each regime so that it stays finite for any damping:
    with mu = w sqrt(|1 - zeta^2|), e^(-zeta w t) cos(w_d t) is e^(-zeta w t) cos(mu t) below
    critical damping and (e^(r+ t) + e^(r- t)) / 2 above it, r+- = -zeta w +- mu <= 0;
    likewise sin(w_d t) / w_d becomes (e^(r+ t) - e^(r- t)) / (2 mu) (-> t e^(-zeta w t) at mu = 0).
    """
    w = omega[:, None]
    z = zeta[:, None]
    tt = np.clip(t, 0.0, None)[None, :]
    mu = w * np.sqrt(np.abs(1.0 - z**2))
    over = (z >= 1.0)[:, 0]
    cos_part = np.empty((len(omega), len(t)))
    sin_part = np.empty_like(cos_part)
    u = ~over
    decay = np.exp(-z[u] * w[u] * tt)
    cos_part[u] = decay * np.cos(mu[u] * tt)
    sin_part[u] = decay * tt * np.sinc(mu[u] * tt / np.pi)          # e^(-zwt) sin(mu t) / mu
    zw, m = z[over] * w[over], mu[over]
    fast, slow = np.exp(-(zw + m) * tt), np.exp((m - zw) * tt)
    cos_part[over] = 0.5 * (slow + fast)
    sin_part[over] = np.where(m * tt > 1e-8, (slow - fast) / (2.0 * np.maximum(m, 1e-300)), tt * np.exp(-zw * tt))
    s = (1.0 - (cos_part + z * w * sin_part)) / w**2
    return np.where(t[None, :] > 0.0, s, 0.0)


@dataclass(frozen=True)
class ModalBasis:
    """The lowest mass-normalised modes of a linearised FE model, with the nodal masses:
    what every modal reduction starts from (:func:`modal_rom` here, the calibration's Ritz
    basis in :mod:`ccedi.calibrate.finger_modes`).

    Parameters
    ----------
    omega_rad_s : numpy.ndarray
        Angular frequencies, ascending, (N,) [rad/s].
    phi : numpy.ndarray
        Mass-normalised modes, (3 n_nodes, N) [1/sqrt(kg)], nodal DOFs interleaved (x, y, z).
    mass_kg : numpy.ndarray
        Lumped nodal masses, (n_nodes,) [kg].
    """

    omega_rad_s: np.ndarray
    phi: np.ndarray
    mass_kg: np.ndarray

    def weighted(self, nodes, weights, direction=1):
        """Weighted mean displacement of ``nodes`` along ``direction`` in each mode.

        Parameters
        ----------
        nodes : array_like of int
            Node indices.
        weights : array_like
            Their weights (e.g. area weights of a face, sum 1).
        direction : int, optional
            0, 1 or 2 (x, y, z). Default 1.

        Returns
        -------
        numpy.ndarray
            (N,) [1/sqrt(kg)].
        """
        return np.asarray(weights) @ self.phi[3 * np.asarray(nodes) + direction]


def modal_basis(model: Model, n_modes, *, x=None):
    """The ``n_modes`` lowest modes of ``model`` (:func:`ccedi.fea.solvers.modal.natural_frequencies`:
    tangent stiffness at ``x``, lumped mass).

    Parameters
    ----------
    model : ccedi.fea.model.Model
        The FE model (its supports fixed).
    n_modes : int
        Modes solved, an integer >= 1.
    x : numpy.ndarray, optional
        Positions (n_nodes, 3) [m] to linearise at (default: the reference).

    Returns
    -------
    ModalBasis

    Raises
    ------
    InputError
        ``n_modes`` not an integer >= 1.
    """
    if int(n_modes) != n_modes or n_modes < 1:
        raise InputError(f"n_modes must be an integer >= 1, got {n_modes!r}")
    omega, phi = natural_frequencies(model, n_modes=n_modes, x=x, return_modes=True)
    return ModalBasis(omega_rad_s=omega, phi=phi, mass_kg=model.mass)


def modal_rom(model: Model, n_modes, *, load_nodes, load_weights, direction=1, output_nodes=None,
              output_weights=None, x=None):
    """Modal ROM of an FE model from a shared unit force to a weighted displacement.

    Parameters
    ----------
    model : ccedi.fea.model.Model
        The FE model (damping: its alpha and beta).
    n_modes : int
        Modes kept (the lowest).
    load_nodes, load_weights : array_like
        Nodes sharing the unit force and their weights (sum 1).
    direction : int, optional
        0, 1 or 2: the force and output direction (x, y, z).
    output_nodes, output_weights : array_like, optional
        Output displacement nodes and weights (default: the load nodes and weights).
    x : numpy.ndarray, optional
        Positions (n_nodes, 3) [m] to linearise at (default: the reference).

    Returns
    -------
    ModalROM

    Raises
    ------
    InputError
        ``n_modes`` not an integer >= 1 or ``direction`` not 0, 1 or 2.
    """
    if direction not in (0, 1, 2):
        raise InputError(f"direction must be 0, 1 or 2, got {direction!r}")
    basis = modal_basis(model, n_modes, x=x)
    output_nodes = load_nodes if output_nodes is None else output_nodes
    output_weights = load_weights if output_weights is None else output_weights
    b = basis.weighted(load_nodes, load_weights, direction)
    c = basis.weighted(output_nodes, output_weights, direction)
    return ModalROM(omega_rad_s=basis.omega_rad_s, gain=b * c, alpha=model.alpha, beta=model.beta)


def tip_modal_rom(model: Model, n_modes=6, direction=1):
    """Modal ROM from a uniform tip-face force to the mean tip displacement (the paper's
    impulse test).

    Keeps the ``n_modes`` modes with the largest static contribution g_i / omega_i^2
    among the lowest 3 x n_modes (modes in the other bending plane or in torsion have no
    gain here).

    Parameters
    ----------
    model : ccedi.fea.model.Model
        A clamped finger with a ``tip`` node set.
    n_modes : int, optional
        Modes kept.
    direction : int, optional
        Force and output direction (1: the soft direction y).

    Returns
    -------
    ModalROM
    """
    tip = model.mesh.node_sets["tip"]
    w = face_node_weights(model.mesh, tip)
    full = modal_rom(model, 3 * n_modes, load_nodes=tip, load_weights=w, direction=direction)
    keep = np.sort(np.argsort(-np.abs(full.gain / full.omega_rad_s**2))[:n_modes])
    return replace(full, omega_rad_s=full.omega_rad_s[keep], gain=full.gain[keep])


@dataclass(frozen=True)
class ModalFit:
    """Result of :func:`fit_to_response`.

    Parameters
    ----------
    rom : ModalROM
        The fitted ROM.
    nrmse_before, nrmse_after : float
        NRMSE [-] against the data before and after the fit (:func:`nrmse`).
    """

    rom: ModalROM
    nrmse_before: float
    nrmse_after: float


def nrmse(y_model, y_reference):
    """Root-mean-square difference over the range (max - min) of the reference.

    Parameters
    ----------
    y_model, y_reference : array_like
        Equal-length signals.

    Returns
    -------
    float
        NRMSE [-].

    Raises
    ------
    InputError
        A constant reference.
    """
    y_reference = np.asarray(y_reference, dtype=float)
    span = float(np.ptp(y_reference))
    if span == 0.0:
        raise InputError("reference response is constant: NRMSE undefined")
    return float(np.sqrt(np.mean((np.asarray(y_model) - y_reference) ** 2)) / span)


PRIOR_WEIGHT = 1e-4
"""Weight of the pull towards the FE model's omega_i and g_i in :func:`fit_to_response`:
moving a frequency or gain by 1 % costs as much as an RMS misfit of 0.01 % of the
response's range, so parameters the data cannot resolve (a heavily damped high mode)
stay at their FE values instead of drifting."""


def fit_to_response(rom: ModalROM, time_s, y, *, force_N, duration_s):
    """Refine omega_i (within +-20 %), zeta_i (> 0) and g_i (within a factor 2) so that
    the pulse response matches ``y`` at ``time_s`` (e.g. a full FE impulse response) in
    the least-squares sense, with a weak prior towards the FE values (``PRIOR_WEIGHT``).

    Parameters
    ----------
    rom : ModalROM
        Starting model (e.g. :func:`tip_modal_rom`).
    time_s, y : array_like
        The response to match: times [s] and displacement [m], 1-D, equal length.
    force_N : float
        Pulse force [N].
    duration_s : float
        Pulse length [s].

    Returns
    -------
    ModalFit

    Raises
    ------
    InputError
        ``time_s`` and ``y`` not 1-D of equal length, or ``y`` constant.
    """
    t = np.asarray(time_s, dtype=float)
    y = np.asarray(y, dtype=float)
    if t.shape != y.shape or t.ndim != 1:
        raise InputError("time_s and y must be 1-D arrays of equal length")
    w0, z0, g0 = rom.omega_rad_s, np.maximum(rom.zeta, 1e-4), rom.gain
    n = rom.n_modes
    p0 = np.concatenate([np.ones(n), np.log(z0), np.ones(n)])
    lo = np.concatenate([np.full(n, 0.8), np.log(z0) - 5.0, np.where(g0 > 0, 0.5, 2.0)])
    hi = np.concatenate([np.full(n, 1.2), np.log(z0) + 5.0, np.where(g0 > 0, 2.0, 0.5)])
    scale = float(np.ptp(y)) or 1.0

    def model_of(p):
        return replace(rom, omega_rad_s=w0 * p[:n], zeta_fitted=np.exp(p[n:2 * n]), gain=g0 * p[2 * n:])

    def residual(p):
        misfit = (model_of(p).pulse_response(t, force_N, duration_s) - y) / (scale * np.sqrt(len(t)))
        prior = PRIOR_WEIGHT * np.concatenate([(p[:n] - 1.0) / 0.01, np.log(np.abs(p[2 * n:])) / 0.01])
        return np.concatenate([misfit, prior])

    fit = least_squares(residual, p0, bounds=(np.minimum(lo, hi), np.maximum(lo, hi)), x_scale="jac")
    fitted = model_of(fit.x)
    return ModalFit(rom=fitted, nrmse_before=nrmse(rom.pulse_response(t, force_N, duration_s), y),
                    nrmse_after=nrmse(fitted.pulse_response(t, force_N, duration_s), y))


class ModalImpulseModel:
    """The modal ROM of an impulse test, a :class:`ccedi.models.ImpulseModel` (the reduced
    counterpart of :class:`ccedi.fea.cases.studies.FullImpulseModel`, from
    :func:`reduce_impulse_model`).

    Parameters
    ----------
    rom : ModalROM
        The modes; its ``beta`` is kept, alpha is set per run (a fitted zeta is dropped,
        as :meth:`ModalROM.with_damping` does).
    force_N : float
        Pulse force [N].
    duration_s : float
        Pulse length [s].
    name : str, optional
        The ``model`` summary key (default ``"modal-N"``).
    length_m : float, optional
        Length of the structure from the clamp to the tip [m], for the tip deflection
        check of every run (:func:`ccedi.fea.solvers.validity.tip_deflection_warnings`, the one
        of the full model). None: unknown, not checked.

    Raises
    ------
    InputError
        A pulse length or structure length that is not finite and positive.
    """

    def __init__(self, rom: ModalROM, force_N, duration_s, *, name=None, length_m=None):
        self.rom = rom
        self.force_N = float(force_N)
        self.duration_s = require_finite_positive("duration_s (pulse length, s)", duration_s)
        self.name = f"modal-{rom.n_modes}" if name is None else name
        self.length_m = None if length_m is None else require_finite_positive("length_m (structure length, m)",
                                                                                length_m)

    def run(self, alpha, t_end_s, n_outputs=400):
        """Exact modal response to the pulse (:meth:`ModalROM.pulse_response`).

        Parameters
        ----------
        alpha : float
            Mass-proportional damping coefficient [1/s].
        t_end_s : float
            Simulated time [s].
        n_outputs : int, optional
            Output times.

        Returns
        -------
        ccedi.models.ImpulseResponse
            History: the core columns only; summary: the core keys (``warnings``: the tip
            deflection check, when ``length_m`` is known), ``beta_s`` and ``n_modes``.

        Raises
        ------
        InputError
            Invalid arguments (:func:`ccedi.models.validate_run_args`).
        SolverError
            The tip deflection reaches the length: the linear answer means nothing.
        """
        alpha, t_end_s, n_outputs = validate_run_args(alpha, t_end_s, n_outputs)
        t0 = time.perf_counter()
        t = pulse_times(t_end_s, n_outputs)
        y = self.rom.with_damping(alpha, self.rom.beta).pulse_response(t, self.force_N, self.duration_s)
        found = [] if self.length_m is None else tip_deflection_warnings(y, self.length_m)
        issue(found, f"{self.name}, {run_label(alpha)}")
        summary = {"model": self.name, "alpha_per_s": alpha, "wall_time_s": time.perf_counter() - t0,
                   "warnings": found, "beta_s": float(self.rom.beta), "n_modes": self.rom.n_modes}
        return ImpulseResponse(history=pd.DataFrame({"time_s": t, "tip_uy_m": y}), summary=summary)


def reduce_impulse_model(full, *, n_modes=6, alpha=0.0, fit_t_end_s=None, fit_n_outputs=400):
    """Reductor: the modal ROM of a full FE impulse model, with the same interface.

    Parameters
    ----------
    full : ccedi.fea.cases.studies.FullImpulseModel
        The full model (a clamped finger with a ``tip`` node set; its ``force_N`` and
        ``duration_s`` must be known).
    n_modes : int, optional
        Modes kept (:func:`tip_modal_rom`).
    alpha : float, optional
        Damping [1/s] of the FE model the modes are taken from (and of the fit's run).
    fit_t_end_s : float, optional
        When given, the modes are refined by :func:`fit_to_response` against a full run
        of this length [s] at ``alpha``.
    fit_n_outputs : int, optional
        Outputs of that run.

    Returns
    -------
    ModalImpulseModel
        With the full model's length (root to tip node set), so that its runs get the
        same tip deflection check.

    Raises
    ------
    InputError
        The full model's pulse is unknown, or it has no solid elements.
    """
    if full.force_N is None or full.duration_s is None:
        raise InputError("the full model's pulse (force_N, duration_s) must be known to reduce it")
    model = full.fea_model(alpha)
    if model.mesh.n_elements == 0:
        raise InputError(f"the modal reductor needs solid elements (its modes come from their tangent); the full "
                         f"model {full.name!r} has none (a structure of rods, such as the steel rod)")
    rom = tip_modal_rom(model, n_modes=n_modes)
    if fit_t_end_s is not None:
        t, y = full.run(alpha, fit_t_end_s, fit_n_outputs).tip_signal()
        rom = fit_to_response(rom, t, y, force_N=full.force_N, duration_s=full.duration_s).rom
    return ModalImpulseModel(rom, full.force_N, full.duration_s, length_m=cantilever_length_m(model.mesh))
