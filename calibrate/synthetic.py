"""Synthetic "measured" impulse records of the 8-in finger with injected effects: the
bundled test set under ``data/measured/``.

This is deliberately NOT the calibration's code path. The calibration uses a 6-mode
Rayleigh-Ritz model on analytic cantilever modes (:mod:`ccedi.calibrate.beam`) integrated
exactly or by RK4 in modal coordinates (:mod:`ccedi.calibrate.dynamics`); this generator uses a
finite-element Euler-Bernoulli beam (``N_ELEMENTS`` Hermite-cubic elements, consistent
mass, all its 2 x N_ELEMENTS degrees of freedom) integrated in physical coordinates by the
Newmark average-acceleration rule (step ``DT_S``), with the effects built in physically:

  stiffness_damping       C = alpha M + beta K
  viscoelastic            bending force K (u - g z), z' = (u - z) / tau (one-term Prony)
  quadratic_damping       distributed drag -c |w'| w' per unit length, lumped on the nodes
                          by the trapezoidal rule [N s^2/m^3]
  coulomb_friction        tip force -F_c tanh(w_L' / 5e-4 m/s)
  tip_mass                point mass at the tip node (also under gravity)
  root_compliance         the root rotation is free, held by a rotational spring k_r
  gravity                 distributed weight rho A g_t (and tip mass), from static sag
  geometric_nonlinearity  equivalent large-amplitude stiffening: tip force -k_3 w_L^3
  sensor_nonlinearity     measured y = w_L + s_2 w_L^2
  sensor_offset_drift     measured y = w_L + offset + drift t
  time_delay              measured y(t) = w_L(t - tau)

Nonlinear forces and the viscoelastic internal variable are evaluated at the start of a
step (explicit in them, implicit in the linear beam). Records are decimated to
``SAMPLE_RATE_HZ`` and white noise of std ``NOISE_FRACTION`` x range is added. The true
Young's modulus and alpha differ from the declared ones (seeded, within +-8 % and 3-5 1/s).

One more clean control comes from the full 3-D explicit FEA of the 4.5-in SM-A finger
(:func:`ccedi.fea.studies.impulse_response`, hexahedral neo-Hookean solid, 1 s): the
beam-against-solid model-form mismatch the calibration must absorb without adding an effect.

Regenerate: ``.venv/bin/python -m ccedi.calibrate.synthetic [OUT_DIR]`` (deterministic).
"""
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.linalg import lu_factor, lu_solve

from ccedi.fea.beam_theory import ellipse_section_properties
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR
from ccedi.fea.outputs import write_csv, write_json
from ccedi.fea.studies import impulse_response
from ccedi.fea.units import inch_to_m

N_ELEMENTS = 40
DT_S = 2.5e-5
SAMPLE_RATE_HZ = 1000.0
RECORD_S = 2.0
NOISE_FRACTION = 0.01
PULSE_S = 0.01
FRICTION_SLIP_M_S = 5e-4
LENGTH_IN = 8.0
AMPLITUDES_N = {"low": 0.5, "high": 1.5}

INJECTED = {
    "stiffness_damping": {"beta_s": 1.5e-3},
    "viscoelastic": {"prony_g": 0.25, "prony_tau_s": 0.05},
    "quadratic_damping": {"drag_N_s2_m3": 8.0},
    "coulomb_friction": {"friction_N": 0.006},
    "tip_mass": {"tip_mass_kg": 0.008},
    "root_compliance": {"root_stiffness_N_m_rad": 2.0},
    "gravity": {"gravity_m_s2": 1.7},
    "geometric_nonlinearity": {"cubic_N_m3": 2000.0},
    "sensor_nonlinearity": {"sensor_quadratic_per_m": 2.0},
    "sensor_offset_drift": {"offset_m": 4e-4, "drift_m_s": 8e-4},
    "time_delay": {"delay_s": 2e-3},
}
"""The effect sizes of the bundled set (generator parameters, SI units as named)."""


@dataclass(frozen=True)
class Truth:
    """What a synthetic record really contains.

    Parameters
    ----------
    E_factor : float
        True Young's modulus over the declared one [-].
    alpha_per_s : float
        True mass-proportional damping [1/s].
    force_N : float
        Tip pulse force [N].
    effects : dict, optional
        Injected effects {name: {parameter: value}} (SI units as named). Default none.
    """

    E_factor: float
    alpha_per_s: float
    force_N: float
    effects: dict = field(default_factory=dict)


def beam_matrices(length_m, n_el, EI, rho_a):
    """Hermite-cubic Euler-Bernoulli matrices of a free uniform beam.

    DOFs (w_0, theta_0, w_1, theta_1, ...) [m, rad], ``n_el`` equal elements.

    Parameters
    ----------
    length_m : float
        Beam length [m].
    n_el : int
        Number of elements.
    EI : float
        Bending stiffness [N m^2].
    rho_a : float
        Mass per length [kg/m].

    Returns
    -------
    K : numpy.ndarray
        Stiffness, (2 (n_el + 1),) squared [N/m, N, N m].
    M : numpy.ndarray
        Consistent mass, same shape [kg, kg m, kg m^2].
    f : numpy.ndarray
        Consistent load vector of a unit distributed load [N per N/m, N m per N/m].
    """
    h = length_m / n_el
    k = EI / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                              [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])
    m = rho_a * h / 420.0 * np.array([[156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
                                      [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]])
    q = np.array([h / 2, h * h / 12, h / 2, -h * h / 12])
    n = 2 * (n_el + 1)
    K, M, f = np.zeros((n, n)), np.zeros((n, n)), np.zeros(n)
    for e in range(n_el):
        s = slice(2 * e, 2 * e + 4)
        K[s, s] += k
        M[s, s] += m
        f[s] += q
    return K, M, f


def beam_response(truth: Truth, length_m, EI, rho_a, t_end_s=RECORD_S):
    """Tip displacement of the FE beam with the truth's physical effects (module docstring).

    Newmark average acceleration with step DT_S from the (relaxed) static sag; sensor
    effects are applied separately by :func:`sensor`.

    Parameters
    ----------
    truth : Truth
        E factor, alpha, force and injected effects.
    length_m : float
        Finger length [m].
    EI : float
        Declared bending stiffness [N m^2] (multiplied by ``truth.E_factor``).
    rho_a : float
        Mass per length [kg/m].
    t_end_s : float, optional
        Record length [s]. Default RECORD_S (2 s).

    Returns
    -------
    t : numpy.ndarray
        Times k DT_S, 0 <= t <= t_end_s [s].
    w : numpy.ndarray
        Tip displacement w_L [m].
    """
    fx = truth.effects
    K, M, f_unit = beam_matrices(length_m, N_ELEMENTS, EI * truth.E_factor, rho_a)
    root = fx.get("root_compliance")
    keep = np.arange(1 if root else 2, len(K))               # clamp w_0 (and theta_0)
    Kb, M, f_unit = K[np.ix_(keep, keep)], M[np.ix_(keep, keep)], f_unit[keep]
    K = Kb.copy()
    if root:
        K[0, 0] += root["root_stiffness_N_m_rad"]
    tip = len(keep) - 2
    m_tip = fx.get("tip_mass", {}).get("tip_mass_kg", 0.0)
    M[tip, tip] += m_tip
    beta = fx.get("stiffness_damping", {}).get("beta_s", 0.0)
    C = truth.alpha_per_s * M + beta * K
    g_ve = fx.get("viscoelastic", {}).get("prony_g", 0.0)
    decay = np.exp(-DT_S / fx.get("viscoelastic", {}).get("prony_tau_s", 1.0))
    w_dofs = np.arange(len(keep))[(keep % 2) == 0]             # translational DOFs
    drag = fx.get("quadratic_damping", {}).get("drag_N_s2_m3", 0.0) * length_m / N_ELEMENTS * np.ones(len(w_dofs))
    drag[-1] *= 0.5                                            # tip node: half an element
    friction = fx.get("coulomb_friction", {}).get("friction_N", 0.0)
    cubic = fx.get("geometric_nonlinearity", {}).get("cubic_N_m3", 0.0)
    weight = fx.get("gravity", {}).get("gravity_m_s2", 0.0) * (rho_a * f_unit + m_tip * (np.arange(len(keep)) == tip))
    u = np.linalg.solve(K - g_ve * Kb, weight)                 # relaxed static sag
    z = u.copy()
    v = np.zeros_like(u)
    n_steps = int(round(t_end_s / DT_S))
    n_pulse = int(round(PULSE_S / DT_S))

    def applied(k, u, v, z):
        f = weight + g_ve * Kb @ z
        f[tip] += truth.force_N * (0.5 if k in (0, n_pulse) else 1.0) * (k <= n_pulse)
        f[tip] -= friction * np.tanh(v[tip] / FRICTION_SLIP_M_S) + cubic * u[tip] ** 3
        f[w_dofs] -= drag * np.abs(v[w_dofs]) * v[w_dofs]
        return f

    a = np.linalg.solve(M, applied(0, u, v, z) - C @ v - K @ u)
    lu = lu_factor(K + 2.0 / DT_S * C + 4.0 / DT_S**2 * M)
    y = np.empty(n_steps + 1)
    y[0] = u[tip]
    for k in range(1, n_steps + 1):
        f = applied(k, u, v, z)
        u_new = lu_solve(lu, f + M @ (4.0 / DT_S**2 * u + 4.0 / DT_S * v + a) + C @ (2.0 / DT_S * u + v))
        v_new = 2.0 / DT_S * (u_new - u) - v
        a = 4.0 / DT_S**2 * (u_new - u) - 4.0 / DT_S * v - a
        z = 0.5 * (u + u_new) + (z - 0.5 * (u + u_new)) * decay
        u, v = u_new, v_new
        y[k] = u[tip]
    return np.arange(n_steps + 1) * DT_S, y


def sensor(t, w, effects):
    """What the displacement sensor reports for a tip displacement history.

    Applies the sensor effects of ``effects``: time delay, quadratic nonlinearity,
    offset and linear drift.

    Parameters
    ----------
    t : numpy.ndarray
        Times [s].
    w : numpy.ndarray
        Tip displacement at ``t`` [m].
    effects : dict
        Injected effects {name: {parameter: value}}; others are ignored.

    Returns
    -------
    numpy.ndarray
        The sensor reading [m].
    """
    delay = effects.get("time_delay", {}).get("delay_s", 0.0)
    y = np.interp(t - delay, t, w, left=w[0]) if delay else w.copy()
    s2 = effects.get("sensor_nonlinearity", {}).get("sensor_quadratic_per_m", 0.0)
    drift = effects.get("sensor_offset_drift", {})
    return y + s2 * y**2 + drift.get("offset_m", 0.0) + drift.get("drift_m_s", 0.0) * t


def declared_finger():
    """The finger the sidecars declare: SM-A section, 8 in long, the paper's rubber.

    Returns
    -------
    dict
        The sidecar's ``finger`` object (length_in, section_semi_axes_m [m], E_Pa,
        nu, rho_kg_m3).
    """
    return {"length_in": LENGTH_IN, "section_semi_axes_m": [SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR],
            "E_Pa": RUBBER.E, "nu": RUBBER.nu, "rho_kg_m3": RUBBER.rho}


def record(truth: Truth, seed):
    """One synthetic record of the declared finger: FE beam, sensor, decimation, noise.

    Parameters
    ----------
    truth : Truth
        What the record contains.
    seed : int
        Seed of the white measurement noise.

    Returns
    -------
    frame : pandas.DataFrame
        Columns ``time_s`` [s], ``tip_displacement_m`` [m] (with noise), ``force_N`` [N].
    meta : dict
        The JSON sidecar (kind, declared finger, load, sensor noise std [m]).
    """
    area, inertia = ellipse_section_properties(SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR)
    t_fine, w = beam_response(truth, inch_to_m(LENGTH_IN), RUBBER.E * inertia, RUBBER.rho * area)
    y_fine = sensor(t_fine, w, truth.effects)
    every = int(round(1.0 / (SAMPLE_RATE_HZ * DT_S)))
    t, y = t_fine[::every], y_fine[::every]
    noise = NOISE_FRACTION * float(np.ptp(y))
    y = y + noise * np.random.default_rng(seed).standard_normal(len(t))
    force = np.where(t < PULSE_S, truth.force_N, 0.0)
    frame = pd.DataFrame({"time_s": np.round(t, 9), "tip_displacement_m": y, "force_N": force})
    meta = {"kind": "impulse", "finger": declared_finger(),
            "load": {"force_N": truth.force_N, "duration_s": PULSE_S, "at": "tip"},
            "sensor": {"noise_std_m": noise}}
    return frame, meta


def bundled_set():
    """The truths of the bundled set.

    Every catalogue effect at two amplitudes, two clean controls and one record with two
    effects (tip mass and quadratic damping); E factors and alphas drawn with a fixed seed.

    Returns
    -------
    dict
        {record name: Truth}.
    """
    rng = np.random.default_rng(2012)
    cases = {f"control_{a}": {} for a in AMPLITUDES_N}
    for name, params in INJECTED.items():
        for a in AMPLITUDES_N:
            cases[f"{name}_{a}"] = {name: params}
    cases["tip_mass+quadratic_damping_high"] = {k: INJECTED[k] for k in ("tip_mass", "quadratic_damping")}
    out = {}
    for name, effects in cases.items():
        amp = name.rsplit("_", 1)[1]
        out[name] = Truth(E_factor=float(rng.uniform(0.92, 1.08)), alpha_per_s=float(rng.uniform(3.0, 5.0)),
                          force_N=AMPLITUDES_N[amp], effects=effects)
    return out


SOLID = {"length_in": 4.5, "alpha_per_s": 20.0, "force_N": 0.3, "record_s": 1.0}
"""The 3-D FEA control: finger length [in], alpha [1/s], tip force [N], record length [s]."""


def solid_record(seed):
    """The clean control record from the full 3-D explicit FEA (module docstring).

    Parameters
    ----------
    seed : int
        Seed of the white measurement noise.

    Returns
    -------
    frame : pandas.DataFrame
        Columns ``time_s`` [s], ``tip_displacement_m`` [m] (with noise), ``force_N`` [N].
    meta : dict
        The JSON sidecar (kind, declared finger, load, sensor noise std [m]).
    """
    fe = impulse_response(length_in=SOLID["length_in"], alpha=SOLID["alpha_per_s"], force_N=SOLID["force_N"],
                          duration_s=PULSE_S, t_end_s=SOLID["record_s"],
                          n_outputs=int(round(SOLID["record_s"] * SAMPLE_RATE_HZ)))
    t = np.concatenate([[0.0], fe.history.time_s.values])
    y = np.concatenate([[0.0], fe.history.tip_uy_m.values])
    noise = NOISE_FRACTION * float(np.ptp(y))
    y = y + noise * np.random.default_rng(seed).standard_normal(len(t))
    frame = pd.DataFrame({"time_s": np.round(t, 9), "tip_displacement_m": y,
                          "force_N": np.where(t < PULSE_S, SOLID["force_N"], 0.0)})
    meta = {"kind": "impulse", "finger": declared_finger() | {"length_in": SOLID["length_in"]},
            "load": {"force_N": SOLID["force_N"], "duration_s": PULSE_S, "at": "tip"},
            "sensor": {"noise_std_m": noise}}
    return frame, meta


def write_bundled_set(out_dir):
    """Write every record as NAME.csv + NAME.json and the truths as manifest.json.

    Deterministic; prints one line per record.

    Parameters
    ----------
    out_dir : str or pathlib.Path
        Output directory (created if missing).
    """
    out_dir = Path(out_dir)
    frame, meta = solid_record(seed=999)
    write_csv(out_dir / "control_fea_solid.csv", frame)
    write_json(out_dir / "control_fea_solid.json", meta)
    manifest = {"control_fea_solid": {"E_factor": 1.0, "alpha_per_s": SOLID["alpha_per_s"],
                                      "force_N": SOLID["force_N"], "effects": {},
                                      "generator": "ccedi.fea.studies.impulse_response (3-D SM-A solid)"}}
    for i, (name, truth) in enumerate(bundled_set().items()):
        frame, meta = record(truth, seed=1000 + i)
        write_csv(out_dir / f"{name}.csv", frame)
        write_json(out_dir / f"{name}.json", meta)
        manifest[name] = {"E_factor": truth.E_factor, "alpha_per_s": truth.alpha_per_s,
                          "force_N": truth.force_N, "effects": truth.effects}
        print(f"{name}: E x {truth.E_factor:.3f}, alpha {truth.alpha_per_s:.2f} 1/s, {truth.effects}")
    write_json(out_dir / "manifest.json", {"generator": "ccedi.calibrate.synthetic", "noise_fraction": NOISE_FRACTION,
                                           "records": manifest})


if __name__ == "__main__":
    write_bundled_set(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).parents[1] / "data" / "measured")
