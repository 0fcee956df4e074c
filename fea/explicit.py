"""Explicit dynamics: central difference with Rayleigh damping and a CFL time step.

Equation of motion, paper Eq. (1) with Eq. (2): ``M a + (alpha M + beta K) v + f_int(x) = f_ext``.

Update from t^n to t^{n+1} = t^n + dt^{n+1/2} (variable step, lumped mass m)::

    Dt^n = (dt^{n-1/2} + dt^{n+1/2}) / 2
    v^{n+1/2} = [(1 - alpha Dt/2) v^{n-1/2} + Dt (f_ext - f_int - f_beta) / m] / (1 + alpha Dt/2)
    x^{n+1}  = x^n + dt^{n+1/2} v^{n+1/2}

The mass-proportional term is centred (average of the two half-step velocities), so it
adds no stability limit: any alpha >= 0 is stable. The stiffness-proportional force is
``f_beta = beta K v ~ beta (f_int^n - f_int^{n-1}) / dt^{n-1/2}``; it lowers the stable
step to ``dt <= (2/w_max)(sqrt(1 + xi^2) - xi)``, ``xi = beta w_max / 2``, ``w_max = 2/dt_cfl``.

Time step, paper Eq. (5): ``dt = TSSFAC x min_e dt_e`` (TSSFAC = 0.9), recomputed every step
on the deformed mesh. Energies are accumulated so that
``W_ext = KE + IE + HG + E_damping + E_bulk`` (checked by the tests).

The step loop is written once (``_advance``); it is compiled by numba with the numba
force kernel, and run as plain Python with the numpy reference kernel
(``backend="numpy"``), which the tests compare.
"""
import time as _time
from dataclasses import dataclass, field

import numba as nb
import numpy as np
import pandas as pd

from .errors import InputError, SolverError, require_finite_positive
from .hex8 import deformation_gradient, internal_forces_numpy
from .kernels import FASTMATH, internal_forces_numba
from .material import cauchy_stress, von_mises
from .model import Model, face_node_weights
from .rod import rod_forces_numba, rod_forces_numpy, rod_max_stress

TSSFAC = 0.9
"""Time-step scale factor of paper Eq. (5)."""

# energy accumulator slots
_W_EXT, _E_DAMP, _E_BULK, _KE, _IE, _HG = range(6)
_OK, _INVERTED, _DIVERGED, _STEP_TOO_LARGE, _FOLDED = 0, 1, 2, 3, 4


def _advance(forces, rod_forces, t, t_stop, dt_prev, dt_user, tssfac, beta, alpha,
             x, v, X, f_int, f_int_prev, f_ext, v_pres, mass, free,
             pulse_nodes, pulse_forces, pulse_t0, pulse_t1,
             rot_nodes, rot_center, rot_axis, rot_omega,
             hexes, b, volume, gamma, kappa, mu, lam, rho, c,
             segments, rest_length, axial_stiffness, hinges, bending_stiffness, dt_rod,
             energy, reaction):
    """Advance until t >= t_stop (the last step is not shortened: cutting a step to land on
    an output time perturbs the highest mode and, repeated, can destabilise a mesh whose
    CFL estimate is tight). Returns (t, dt_prev, steps, status, info, dt_min_seen)."""
    steps = 0
    dt_seen = np.inf
    while t < t_stop:
        dte, w_int, w_hg, p_bulk, bad = forces(x, v, hexes, b, volume, gamma, kappa, mu, lam, rho, c, f_int)
        if bad >= 0:
            return t, dt_prev, steps, _INVERTED, bad, dt_seen
        w_rod, folded = rod_forces(x, segments, rest_length, axial_stiffness, hinges, bending_stiffness, f_int)
        if folded >= 0:
            return t, dt_prev, steps, _FOLDED, folded, dt_seen
        w_int += w_rod
        dte = min(dte, dt_rod)
        dt_stable = dte
        if beta > 0.0:
            xi = beta / dte
            dt_stable = dte * (np.sqrt(1.0 + xi * xi) - xi)
        if dt_user > 0.0:
            if dt_user > dt_stable:
                return t, dt_prev, steps, _STEP_TOO_LARGE, 0, dt_stable
            dt = dt_user
        else:
            dt = tssfac * dt_stable
        dt_seen = min(dt_seen, dt)
        f_ext[:, :] = 0.0
        for p in range(pulse_nodes.shape[0]):
            if pulse_t0[p] <= t and t < pulse_t1[p]:
                for i in range(3):
                    f_ext[pulse_nodes[p], i] += pulse_forces[p, i]
        if rot_nodes.shape[0] > 0:
            th = rot_omega * (t + dt)
            ct, st = np.cos(th), np.sin(th)
            for r in range(rot_nodes.shape[0]):
                n = rot_nodes[r]
                d = X[n, :] - rot_center
                kxd = np.cross(rot_axis, d)
                kd = np.dot(rot_axis, d)
                x_new = rot_center + d * ct + kxd * st + rot_axis * kd * (1.0 - ct)
                v_pres[n, :] = (x_new - x[n, :]) / dt
        Dt = 0.5 * (dt_prev + dt)
        inv_den = 1.0 / (1.0 + 0.5 * alpha * Dt)
        c_v = (1.0 - 0.5 * alpha * Dt) * inv_den
        c_f = Dt * inv_den
        beta_rate = beta / dt_prev if (beta > 0.0 and dt_prev > 0.0) else 0.0
        w_ext = 0.0
        w_damp = 0.0
        ke = 0.0
        for n in range(x.shape[0]):
            m = mass[n]
            is_free = free[n] > 0.0
            for i in range(3):
                fb = beta_rate * (f_int[n, i] - f_int_prev[n, i])
                if is_free:
                    vn = c_v * v[n, i] + c_f * (f_ext[n, i] - f_int[n, i] - fb) / m
                    reaction[n, i] = 0.0
                else:
                    # constrained: prescribed velocity; the support supplies what is missing
                    vn = v_pres[n, i]
                    reaction[n, i] = (m * (vn - v[n, i]) / Dt + 0.5 * alpha * m * (vn + v[n, i])
                                      + f_int[n, i] + fb - f_ext[n, i])
                vb = 0.5 * (v[n, i] + vn)
                w_ext += (f_ext[n, i] + reaction[n, i]) * vb
                w_damp += (alpha * m * vb + fb) * vb
                ke += m * vb * vb
                v[n, i] = vn
                x[n, i] += dt * vn
                f_int_prev[n, i] = f_int[n, i]
        energy[_W_EXT] += Dt * w_ext
        energy[_E_DAMP] += Dt * w_damp
        energy[_E_BULK] += Dt * p_bulk
        energy[_KE] = 0.5 * ke
        energy[_IE] = w_int
        energy[_HG] = w_hg
        if not (energy[_KE] < np.inf):       # also catches NaN; survives fast-math
            return t, dt_prev, steps, _DIVERGED, steps, dt_seen
        t += dt
        dt_prev = dt
        steps += 1
    return t, dt_prev, steps, _OK, 0, dt_seen


_advance_numba = nb.njit(cache=True, fastmath=FASTMATH)(_advance)


@dataclass
class RunResult:
    """Output of :func:`run`.

    history : DataFrame, one row per output time, columns with units in their names.
    summary : dict (nodes, elements, dt_initial_s, dt_min_s, steps, wall_time_s, ...).
    x : final nodal positions (n, 3) [m]; v : final half-step velocities [m/s].
    snapshots : list of (time_s, positions) when requested.
    """

    history: pd.DataFrame
    summary: dict
    x: np.ndarray
    v: np.ndarray
    snapshots: list = field(default_factory=list)


def _pulse_arrays(pulses):
    nodes, forces, t0, t1 = [], [], [], []
    for p in pulses:
        nodes.append(p.nodes)
        forces.append(p.weights[:, None] * p.force_N[None, :])
        t0.append(np.full(len(p.nodes), p.t_start_s))
        t1.append(np.full(len(p.nodes), p.t_end_s))
    if not nodes:
        return np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros(0), np.zeros(0)
    return np.concatenate(nodes), np.concatenate(forces), np.concatenate(t0), np.concatenate(t1)


def max_von_mises(model, x):
    """Largest von Mises stress [Pa] at nodal positions x: Cauchy stress of the solid
    elements, and the normal stress bound of the rods (:func:`fea.rod.rod_max_stress`)."""
    sigma = rod_max_stress(x, model.rod_arrays)
    if model.mesh.n_elements:
        F = deformation_gradient(x[model.mesh.hexes], model.geometry)
        sigma = max(sigma, float(von_mises(cauchy_stress(F, model.material.mu, model.material.lam)).max()))
    return sigma


def rod_time_step(model):
    """Smallest critical step of the rod elements [s] (inf without rods), see :mod:`fea.rod`."""
    r = model.rod_arrays
    return float(min(np.min(r.segment_time_step, initial=np.inf), np.min(r.hinge_time_step, initial=np.inf)))


def critical_time_step(model, x=None, v=None):
    """Smallest element critical step min_e dt_e (paper Eq. 6) [s] at positions x
    (default: reference), before the TSSFAC scale factor."""
    x = model.mesh.nodes if x is None else x
    v = np.zeros_like(x) if v is None else v
    g = model.geometry
    f = np.zeros_like(x)
    dt, *_ , bad = internal_forces_numba(x, v, model.mesh.hexes, g.b, g.volume, g.gamma, model.kappa,
                                        *model.solid_constants, f)
    if bad >= 0:
        raise SolverError(f"element {bad} is inverted (J <= 0)")
    return min(dt, rod_time_step(model))


def _initial_state(name, value, shape):
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a numeric array of shape {shape}") from None
    if a.shape != shape or not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be finite with shape {shape}, got shape {a.shape}")
    return a


def run(model: Model, t_end_s, n_outputs=400, dt_s=None, backend="numba", tip_set="tip",
        reaction_set="root", snapshot_every=0, x0=None, v0=None):
    """Integrate ``model`` from rest (or x0, v0) to ``t_end_s`` [s].

    dt_s : fixed step [s] (default: CFL-controlled, TSSFAC x min dt_e, every step).
    backend : ``"numba"`` (compiled) or ``"numpy"`` (pure-numpy reference, slow).
    Records ``n_outputs`` evenly spaced rows: tip displacement (area-weighted mean over
    ``tip_set``), reaction force summed over ``reaction_set``, max von Mises stress and
    the energy terms. Steps are never shortened to hit an output time: positions (and
    the displacement and stress derived from them) are interpolated to the output time,
    exactly, since central differences move nodes linearly within a step; energies and
    reactions are those of the step that reaches it (at most one step later). The final
    state ``x, v`` is at ``summary["t_final_s"]`` (>= t_end_s, by less than one step).
    """
    if not isinstance(model, Model):
        raise InputError("model must be a fea.model.Model")
    t_end_s = require_finite_positive("t_end_s (end time, s)", t_end_s)
    if int(n_outputs) != n_outputs or n_outputs < 1:
        raise InputError(f"n_outputs must be an integer >= 1, got {n_outputs!r}")
    if backend not in ("numba", "numpy"):
        raise InputError(f"backend must be 'numba' or 'numpy', got {backend!r}")
    mesh, g = model.mesh, model.geometry
    dt_user = 0.0 if dt_s is None else require_finite_positive("dt_s (time step, s)", dt_s)
    dt_cfl = critical_time_step(model)
    if dt_user > dt_cfl:
        raise InputError(f"dt_s = {dt_user:.4g} s exceeds the CFL limit {dt_cfl:.4g} s "
                         f"(paper Eq. 6); use dt_s <= {TSSFAC * dt_cfl:.4g} s or leave it unset")
    dt_first = dt_user if dt_user else TSSFAC * dt_cfl
    if t_end_s / n_outputs < dt_first:
        raise InputError(f"n_outputs = {n_outputs} gives an output interval {t_end_s / n_outputs:.3g} s shorter "
                         f"than the time step {dt_first:.3g} s; use n_outputs <= {int(t_end_s / dt_first)}")
    X = mesh.nodes
    x = X.copy() if x0 is None else _initial_state("x0 (initial positions, m)", x0, X.shape)
    v = np.zeros_like(X) if v0 is None else _initial_state("v0 (initial velocities, m/s)", v0, X.shape)
    free = np.ones(mesh.n_nodes)
    free[model.fixed_nodes] = 0.0
    rot = model.rotating
    if rot is not None:
        free[rot.nodes] = 0.0
        rot_args = (rot.nodes, rot.center_m, rot.axis, float(rot.omega_rad_s))
    else:
        rot_args = (np.zeros(0, np.int64), np.zeros(3), np.array([0.0, 0.0, 1.0]), 0.0)
    v *= free[:, None]
    pulse_args = _pulse_arrays(model.pulses)
    tip = mesh.node_sets[tip_set]
    tip_w = face_node_weights(mesh, tip) if len(tip) > 1 else np.ones(1)
    react_nodes = mesh.node_sets[reaction_set]
    f_int, f_int_prev, f_ext, v_pres, reaction = (np.zeros_like(X) for _ in range(5))
    energy = np.zeros(6)
    if backend == "numba":
        advance, forces, rod_forces = _advance_numba, internal_forces_numba, rod_forces_numba
    else:
        advance, forces, rod_forces = _advance, internal_forces_numpy, rod_forces_numpy
    ra = model.rod_arrays
    const = (mesh.hexes, g.b, g.volume, g.gamma, model.kappa, *model.solid_constants,
             ra.segments, ra.rest_length, ra.axial_stiffness, ra.hinges, ra.bending_stiffness, rod_time_step(model))

    rows, snapshots = [], []
    t, dt_prev, steps, dt_min = 0.0, 0.0, 0, np.inf
    wall0 = _time.perf_counter()
    for i_out, t_out in enumerate(np.linspace(0.0, t_end_s, n_outputs + 1)[1:]):
        t, dt_prev, n, status, info, dt_seen = advance(
            forces, rod_forces, t, t_out, dt_prev, dt_user, TSSFAC, model.beta, model.alpha,
            x, v, X, f_int, f_int_prev, f_ext, v_pres, model.mass, free, *pulse_args, *rot_args, *const,
            energy, reaction)
        steps += n
        dt_min = min(dt_min, dt_seen)
        if status == _INVERTED:
            raise SolverError(f"element {info} inverted (J <= 0) at t = {t:.6g} s, step {steps}")
        if status == _FOLDED:
            raise SolverError(f"rod hinge {info} folded back on itself (turning angle >= 180 deg) "
                              f"at t = {t:.6g} s, step {steps}")
        if status == _DIVERGED:
            raise SolverError(f"solution diverged (non-finite velocity) at step {steps + 1}, t = {t:.6g} s")
        if status == _STEP_TOO_LARGE:
            raise SolverError(f"dt_s = {dt_user:.4g} s exceeds the current stable step {dt_seen:.4g} s "
                              f"at step {steps}, t = {t:.6g} s (the mesh deformed)")
        # positions at t_out: central differences move each node linearly over a step
        x_out = x - (t - t_out) * v
        u_tip = tip_w @ (x_out[tip] - X[tip])
        r = reaction[react_nodes].sum(axis=0)
        rows.append((t_out, *u_tip, *r, max_von_mises(model, x_out), *energy))
        if snapshot_every and (i_out + 1) % snapshot_every == 0:
            snapshots.append((t_out, x_out))
    wall = _time.perf_counter() - wall0
    cols = ["time_s", "tip_ux_m", "tip_uy_m", "tip_uz_m", "reaction_x_N", "reaction_y_N", "reaction_z_N",
            "max_von_mises_Pa", "external_work_J", "damping_energy_J", "bulk_viscosity_energy_J",
            "kinetic_energy_J", "internal_energy_J", "hourglass_energy_J"]
    history = pd.DataFrame(rows, columns=cols)
    n_elements = mesh.n_elements + len(ra.segments)
    summary = {"nodes": mesh.n_nodes, "elements": n_elements, "dt_initial_s": TSSFAC * dt_cfl,
               "dt_min_s": float(dt_min), "steps": int(steps), "t_end_s": t_end_s, "t_final_s": t,
               "wall_time_s": wall, "backend": backend, "alpha_per_s": model.alpha, "beta_s": model.beta,
               "ns_per_element_cycle": 1e9 * wall / max(1, steps * n_elements)}
    return RunResult(history=history, summary=summary, x=x, v=v, snapshots=snapshots)
