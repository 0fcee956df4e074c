"""Synthetic "measured" impulse records of the 8-in finger with injected effects: the
bundled test set under ``data/measured/``.

This is deliberately NOT the calibration's model. The calibration uses the lowest
y-bending modes of the clamped finger (those below the sampling rate), with a tip mass
and a compliant root added as Ritz terms and the other effects as modal or tip forces
(:mod:`ccedi.calibrate.finger_modes`, :mod:`ccedi.calibrate.model`), integrated exactly or by
RK4 (:mod:`ccedi.calibrate.dynamics`). This generator builds the linear FE solid of the
finger (SM-A hexahedra, the tangent stiffness K at the reference and the lumped mass M of
:mod:`ccedi.fea`) with the effects built into its matrices and nodal forces, takes the lowest
``N_GEN_MODES`` modes of that modified system (of every kind: both bending planes,
torsion, stretching) and integrates them by the Newmark average-acceleration rule (step
``DT_S``), nonlinear forces evaluated on the nodes:

  stiffness_damping       C = alpha M + beta K
  viscoelastic            elastic force K (u - g z), z' = (u - z) / tau (one-term Prony)
  quadratic_damping       drag -c |v_y| v_y on every node, times its share of the length
                          m_node L / m_finger [N s^2/m^3]
  coulomb_friction        tip-face force -F_c tanh(w_L' / 5e-4 m/s), area-weighted
  tip_mass                m_t spread over the tip-face nodes by area (all three directions)
  root_compliance         the root face rotates rigidly about its x axis (the root nodes
                          move as u_z = -(y - y_root) theta), held by a spring k_r on theta
  gravity                 nodal weights g_t M e_y (and tip mass), from the static sag
  geometric_nonlinearity  equivalent large-amplitude stiffening: tip-face force -k_3 w_L^3
  sensor_nonlinearity     measured y = w_L + s_2 w_L^2
  sensor_offset_drift     measured y = w_L + offset + drift t
  time_delay              measured y(t) = w_L(t - tau)

and, outside the catalogue (records ``outside_*``, manifest ``in_catalogue: false``):

  magnet_attraction       the tip magnet pulled towards the steel body of the displacement
                          sensor at gap d: tip-face force F_m (d / (d - w_L))^2; the record
                          starts at rest at the pulled equilibrium and the sensor is tared
                          there (reads w_L - w_0)

w_L is the area-weighted mean y displacement of the tip face. Nonlinear forces and the
viscoelastic internal variable are evaluated at the start of a step (explicit in them,
implicit in the linear part). Records are decimated to ``SAMPLE_RATE_HZ`` and white noise
of std ``NOISE_FRACTION`` x range is added. The true Young's modulus and alpha differ from
the declared ones (seeded, within +-8 % and 3-5 1/s).

One more clean control comes from the full 3-D explicit FEA of the 4.5-in SM-A finger
(:func:`ccedi.fea.cases.studies.finger_impulse_model`, hexahedral neo-Hookean solid, 1 s): the
nonlinear, lumped-mass explicit solid the calibration's linear modes must match without
an effect. It is kept when present (regenerating it takes minutes; ``--solid`` forces it).

Regenerate: ``.venv/bin/python -m ccedi.calibrate.synthetic [OUT_DIR] [--solid]`` (deterministic).
"""
import sys
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np
import pandas as pd
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ccedi.fea.cases.studies import finger_impulse_model
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR, sm_a
from ccedi.fea.model import cantilever_model, face_node_weights
from ccedi.fea.solvers.static import free_dofs, tangent_stiffness
from ccedi.outputs import write_csv, write_json
from ccedi.units import inch_to_m

N_GEN_MODES = 40
DT_S = 2.5e-5
SAMPLE_RATE_HZ = 1000.0
RECORD_S = 2.0
NOISE_FRACTION = 0.01
PULSE_S = 0.01
FRICTION_SLIP_M_S = 5e-4
LENGTH_IN = 8.0
AMPLITUDES_N = {"low": 0.5, "high": 1.5}
SHORT_PULSE = {"force_N": 10.0, "duration_s": 0.001}
"""The clean short-pulse control: a 1 ms pulse that rings the second and third modes."""

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
OUTSIDE = {"magnet_attraction": {"magnet_force_N": 0.02, "gap_m": 0.06}}
"""Effects outside the calibration's catalogue (generator parameters)."""


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
    duration_s : float, optional
        Pulse duration [s]. Default PULSE_S.
    """

    E_factor: float
    alpha_per_s: float
    force_N: float
    effects: dict = field(default_factory=dict)
    duration_s: float = PULSE_S


@dataclass(frozen=True)
class SolidSystem:
    """The lowest modes of the linear FE solid with its built-in linear effects.

    Parameters
    ----------
    omega_rad_s : numpy.ndarray
        Angular frequencies (n,) [rad/s].
    tip : numpy.ndarray
        Tip-face mean y displacement per mode (n,) [1/sqrt(kg)].
    weight : numpy.ndarray
        Participations in a unit transverse acceleration, phi^T M e_y (n,) [sqrt(kg)].
    node_y : numpy.ndarray
        y displacement of every node per mode (n_nodes, n) [1/sqrt(kg)].
    drag_length_m : numpy.ndarray
        Each node's share of the finger length, m_node L / m_finger (n_nodes,) [m].
    relaxing : numpy.ndarray
        The stiffness of the part of the solid that relaxes when it is viscoelastic, in the
        modal coordinates, phi^T K_v phi (n, n) [rad^2/s^2]: diag(omega^2) when the whole
        finger is viscoelastic.
    """

    omega_rad_s: np.ndarray
    tip: np.ndarray
    weight: np.ndarray
    node_y: np.ndarray
    drag_length_m: np.ndarray
    relaxing: np.ndarray


@lru_cache(maxsize=2)
def _solid(length_m):
    """(model, K full [N/m]) of the SM-A finger at the declared E."""
    model = cantilever_model(sm_a(length_m=length_m), RUBBER)
    return model, tangent_stiffness(model).tocsr()


@lru_cache(maxsize=16)
def solid_system(length_m, E_factor, *, tip_mass_kg=0.0, root_stiffness=None):
    """Modes of the SM-A FE solid at E x ``E_factor`` with a tip mass and a compliant root
    built in (:func:`modal_system`).

    Parameters
    ----------
    length_m : float
        Finger length [m].
    E_factor : float
        Young's modulus over RUBBER.E [-].
    tip_mass_kg : float, optional
        Tip mass [kg]. Default 0.
    root_stiffness : float or None, optional
        Root rotational stiffness [N m/rad]; None: clamped. Default None.

    Returns
    -------
    SolidSystem
        The lowest N_GEN_MODES modes, mass-normalised.
    """
    model, K_full = _solid(length_m)
    return modal_system(model, E_factor * K_full, tip_mass_kg=tip_mass_kg, root_stiffness=root_stiffness)


def modal_system(model, stiffness, *, tip_mass_kg=0.0, root_stiffness=None, relaxing=None):
    """Modes of a clamped FE solid of stiffness ``stiffness`` with a tip mass and a
    compliant root built in.

    The tip mass is spread over the tip-face nodes by their area weights (all three
    directions); a compliant root frees the root face to rotate rigidly about its x axis
    (u_z = -(y - y_root) theta on the root nodes) against a spring k_r on theta.

    Parameters
    ----------
    model : ccedi.fea.model.Model
        The finger (mesh with node sets ``root`` and ``tip``, lumped masses, clamped root).
    stiffness : scipy.sparse.spmatrix
        Its stiffness, unconstrained (3 n_nodes, 3 n_nodes) [N/m].
    tip_mass_kg : float, optional
        Tip mass [kg]. Default 0.
    root_stiffness : float or None, optional
        Root rotational stiffness [N m/rad]; None: clamped. Default None.
    relaxing : scipy.sparse.spmatrix or None, optional
        The stiffness of the part that relaxes when viscoelastic (3 n_nodes, 3 n_nodes)
        [N/m]; None: the whole ``stiffness``. Default None.

    Returns
    -------
    SolidSystem
        The lowest N_GEN_MODES modes, mass-normalised.
    """
    mesh, mass = model.mesh, model.mass
    tip = mesh.node_sets["tip"]
    w_tip = face_node_weights(mesh, tip)
    n_nodes = len(mass)
    m = mass.copy()
    m[tip] += tip_mass_kg * w_tip
    free = free_dofs(model)
    T = sp.lil_matrix((3 * n_nodes, len(free) + (root_stiffness is not None)))
    T[free, np.arange(len(free))] = 1.0
    if root_stiffness is not None:
        root = model.fixed_nodes
        y = mesh.nodes[root, 1]
        T[3 * root + 2, len(free)] = -(y - y.mean())[:, None]
    T = T.tocsr()
    K = (T.T @ stiffness @ T).tocsc()
    if root_stiffness is not None:
        K[-1, -1] += root_stiffness
    M = (T.T @ sp.diags(np.repeat(m, 3)) @ T).tocsc()
    w2, vec = spla.eigsh(K, k=N_GEN_MODES, M=M, sigma=0.0, which="LM")
    order = np.argsort(w2)
    phi = T @ vec[:, order]
    node_y = phi[1::3]
    length = float(np.ptp(mesh.nodes[:, 2]))
    relax = np.diag(w2[order]) if relaxing is None else phi.T @ (relaxing @ phi)
    return SolidSystem(omega_rad_s=np.sqrt(w2[order]), tip=w_tip @ node_y[tip], weight=m @ node_y, node_y=node_y,
                       drag_length_m=mass * length / mass.sum(), relaxing=relax)


def solid_response(truth: Truth, length_m, t_end_s=RECORD_S, *, system=None):
    """Tip displacement of the FE solid with the truth's physical effects (module docstring).

    Newmark average acceleration in the system's modal coordinates with step DT_S, from
    rest at the (relaxed) static sag, or at the pulled equilibrium of a tip magnet; sensor
    effects are applied separately by :func:`sensor`.

    Parameters
    ----------
    truth : Truth
        E factor, alpha, force, pulse duration and injected effects.
    length_m : float
        Finger length [m].
    t_end_s : float, optional
        Record length [s]. Default RECORD_S (2 s).
    system : SolidSystem or None, optional
        The modes of the solid with the truth's tip mass, root and viscoelastic part built
        in (another mesh, :mod:`ccedi.calibrate.synthetic_solid`); None: the SM-A solid of
        ``length_m`` at the truth's E, tip mass and root stiffness (:func:`solid_system`).
        Default None.

    Returns
    -------
    t : numpy.ndarray
        Times k DT_S, 0 <= t <= t_end_s [s].
    w : numpy.ndarray
        Tip displacement w_L [m] (from the magnet's equilibrium, when there is one).
    """
    fx = truth.effects
    root = fx.get("root_compliance", {}).get("root_stiffness_N_m_rad")
    m_tip = fx.get("tip_mass", {}).get("tip_mass_kg", 0.0)
    s = solid_system(length_m, truth.E_factor, tip_mass_kg=m_tip, root_stiffness=root) if system is None else system
    w2, b = s.omega_rad_s**2, s.tip
    beta = fx.get("stiffness_damping", {}).get("beta_s", 0.0)
    c = truth.alpha_per_s + beta * w2
    g_ve = fx.get("viscoelastic", {}).get("prony_g", 0.0)
    decay = np.exp(-DT_S / fx.get("viscoelastic", {}).get("prony_tau_s", 1.0))
    drag = fx.get("quadratic_damping", {}).get("drag_N_s2_m3", 0.0) * s.drag_length_m
    friction = fx.get("coulomb_friction", {}).get("friction_N", 0.0)
    cubic = fx.get("geometric_nonlinearity", {}).get("cubic_N_m3", 0.0)
    magnet = fx.get("magnet_attraction", {})
    f_m, gap = magnet.get("magnet_force_N", 0.0), magnet.get("gap_m", 1.0)
    weight = fx.get("gravity", {}).get("gravity_m_s2", 0.0) * s.weight
    q = np.linalg.solve(np.diag(w2) - g_ve * s.relaxing, weight)   # relaxed static sag
    for _ in range(200 if f_m else 0):                         # pulled equilibrium of the magnet
        q = (weight + b * f_m * (gap / (gap - b @ q)) ** 2) / w2
    w0 = float(b @ q) if f_m else 0.0
    z = q.copy()
    v = np.zeros_like(q)
    n_steps = int(round(t_end_s / DT_S))
    n_pulse = int(round(truth.duration_s / DT_S))

    def applied(k, q, v, z):
        u, du = float(b @ q), float(b @ v)
        f_tip = truth.force_N * (0.5 if k in (0, n_pulse) else 1.0) * (k <= n_pulse)
        f_tip -= friction * np.tanh(du / FRICTION_SLIP_M_S) + cubic * u**3
        if f_m:
            f_tip += f_m * (gap / (gap - u)) ** 2
        f = weight + g_ve * (s.relaxing @ z) + b * f_tip
        if drag.any():
            vy = s.node_y @ v
            f = f - s.node_y.T @ (drag * np.abs(vy) * vy)
        return f

    a = applied(0, q, v, z) - c * v - w2 * q
    lhs = w2 + 2.0 / DT_S * c + 4.0 / DT_S**2
    y = np.empty(n_steps + 1)
    y[0] = b @ q
    for k in range(1, n_steps + 1):
        f = applied(k, q, v, z)
        q_new = (f + 4.0 / DT_S**2 * q + 4.0 / DT_S * v + a + c * (2.0 / DT_S * q + v)) / lhs
        v_new = 2.0 / DT_S * (q_new - q) - v
        a = 4.0 / DT_S**2 * (q_new - q) - 4.0 / DT_S * v - a
        z = 0.5 * (q + q_new) + (z - 0.5 * (q + q_new)) * decay
        q, v = q_new, v_new
        y[k] = b @ q
    return np.arange(n_steps + 1) * DT_S, y - w0


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


def record(truth: Truth, seed, *, system=None, sample_rate_hz=SAMPLE_RATE_HZ):
    """One synthetic record of the declared finger: FE solid, sensor, decimation, noise.

    Parameters
    ----------
    truth : Truth
        What the record contains.
    seed : int
        Seed of the white measurement noise.
    system : SolidSystem or None, optional
        The solid's modes with the truth's linear effects built in (:func:`solid_response`);
        None: the SM-A solid. Default None.
    sample_rate_hz : float, optional
        Sampling rate of the record [Hz], dividing 1 / DT_S. Default SAMPLE_RATE_HZ.

    Returns
    -------
    frame : pandas.DataFrame
        Columns ``time_s`` [s], ``tip_displacement_m`` [m] (with noise), ``force_N`` [N].
    meta : dict
        The JSON sidecar (kind, declared finger, load, sensor noise std [m]).
    """
    t_fine, w = solid_response(truth, inch_to_m(LENGTH_IN), system=system)
    y_fine = sensor(t_fine, w, truth.effects)
    every = int(round(1.0 / (sample_rate_hz * DT_S)))
    t, y = t_fine[::every], y_fine[::every]
    noise = NOISE_FRACTION * float(np.ptp(y))
    y = y + noise * np.random.default_rng(seed).standard_normal(len(t))
    force = np.where(t < truth.duration_s, truth.force_N, 0.0)
    frame = pd.DataFrame({"time_s": np.round(t, 9), "tip_displacement_m": y, "force_N": force})
    meta = {"kind": "impulse", "finger": declared_finger(),
            "load": {"force_N": truth.force_N, "duration_s": truth.duration_s, "at": "tip"},
            "sensor": {"noise_std_m": noise}}
    return frame, meta


def bundled_set():
    """The truths of the bundled set.

    Every catalogue effect at two amplitudes, two clean controls and one record with two
    effects (tip mass and quadratic damping); then a clean control hit by a short pulse
    (SHORT_PULSE, ringing modes 2 and 3) and the out-of-catalogue effects (OUTSIDE) at the
    high amplitude. E factors and alphas drawn with a fixed seed.

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
    out["control_short_pulse"] = Truth(E_factor=float(rng.uniform(0.92, 1.08)), alpha_per_s=float(rng.uniform(3.0, 5.0)),
                                       force_N=SHORT_PULSE["force_N"], duration_s=SHORT_PULSE["duration_s"])
    for name, params in OUTSIDE.items():
        out[f"outside_{name}_high"] = Truth(E_factor=float(rng.uniform(0.92, 1.08)),
                                            alpha_per_s=float(rng.uniform(3.0, 5.0)), force_N=AMPLITUDES_N["high"],
                                            effects={name: params})
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
    fe = finger_impulse_model(length_in=SOLID["length_in"], force_N=SOLID["force_N"], duration_s=PULSE_S).run(
        SOLID["alpha_per_s"], SOLID["record_s"], int(round(SOLID["record_s"] * SAMPLE_RATE_HZ)))
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


def write_bundled_set(out_dir, solid=False):
    """Write every record as NAME.csv + NAME.json and the truths as manifest.json.

    Deterministic; prints one line per record.

    Parameters
    ----------
    out_dir : str or pathlib.Path
        Output directory (created if missing).
    solid : bool, optional
        Recompute the full-FEA control even when ``control_fea_solid.csv`` exists. Default False.
    """
    out_dir = Path(out_dir)
    if solid or not (out_dir / "control_fea_solid.csv").is_file():
        frame, meta = solid_record(seed=999)
        write_csv(out_dir / "control_fea_solid.csv", frame)
        write_json(out_dir / "control_fea_solid.json", meta)
    manifest = {"control_fea_solid": {"E_factor": 1.0, "alpha_per_s": SOLID["alpha_per_s"],
                                      "force_N": SOLID["force_N"], "duration_s": PULSE_S, "effects": {},
                                      "in_catalogue": True,
                                      "generator": "ccedi.fea.cases.studies.finger_impulse_model (3-D SM-A solid)"}}
    for i, (name, truth) in enumerate(bundled_set().items()):
        frame, meta = record(truth, seed=1000 + i)
        write_csv(out_dir / f"{name}.csv", frame)
        write_json(out_dir / f"{name}.json", meta)
        manifest[name] = {"E_factor": truth.E_factor, "alpha_per_s": truth.alpha_per_s,
                          "force_N": truth.force_N, "duration_s": truth.duration_s, "effects": truth.effects,
                          "in_catalogue": not set(truth.effects) & set(OUTSIDE)}
        print(f"{name}: E x {truth.E_factor:.3f}, alpha {truth.alpha_per_s:.2f} 1/s, {truth.effects}")
    write_json(out_dir / "manifest.json", {"generator": "ccedi.calibrate.synthetic (linear FE solid, SM-A, "
                                                        f"{N_GEN_MODES} modes, Newmark)",
                                           "noise_fraction": NOISE_FRACTION, "records": manifest})


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--solid"]
    write_bundled_set(args[0] if args else Path(__file__).parents[1] / "data" / "measured", solid="--solid" in sys.argv)
