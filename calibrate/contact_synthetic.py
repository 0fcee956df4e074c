"""Synthetic "measured" contact records of the 8-in finger on the drum (the paper's
set-up, Table 2, Fig. 9) with injected effects: the bundled set under ``data/contact/``.

The records come from the FULL explicit FEA (:class:`ccedi.fea.contact.drum.FullContactModel`:
the 3-D neo-Hookean SM-A solid, 1872 nodes, penalty contact with Coulomb friction), NOT
from the calibration's model (the superelement chain ROM,
:class:`ccedi.rom.contact_rom.ReducedContactModel`). Each FE run is made at the record's
true Young's modulus (drawn within +-5 % of the declared one) and alpha, with its physical
effect built into the set-up:

  friction             Coulomb coefficient mu other than the declared 0.6
  drum_speed           drum speed omega other than the declared 2.095 rad/s
  timing_offset        initial drum angle theta0 off by d_theta (``theta0_offset_rad``), or
                       the record triggered late by ``trigger_delay_s`` (a control's FE run
                       read at t + delay)
  object_offset        object centre displaced by d_r along the line from the drum axis
  contact_damping      a normal contact dashpot, a fraction zeta of each contact spring's
                       critical damping (``contact_damping_ratio``)

The FE reaction force (magnitude of the in-plane force on the object, 0.5 ms outputs,
which resolve the finger's friction chatter) is then read through the transducer
(:class:`ccedi.rom.sensor.Transducer`, the declared 100 Hz Butterworth unless the record's
effect is ``sensor_bandwidth``), ``sensor_offset_drift`` adds F_0 + F_1 t, the reading is
sampled at ``SAMPLE_RATE_HZ`` and white noise of std ``NOISE_FRACTION`` x its peak is
added. The two transducer effects reuse the FE runs of two controls (a sensor effect
does not change the mechanics), with their own noise.

Not in the bundled set: ``contact_damping``. Measured on the alpha = 80 1/s control's set-up
(where the chatter is strongest): the FE reading with zeta = 0.2 (the stable limit) differs
from the control's by 0.46 noise std RMS, no more than the FEA's own change for alpha 1.7 %
off (0.56: the chatter is chaotic in the parameters), and the chain's by 0.05; a 2 % noise
record cannot show it against a rigid object. ``true_setup`` builds it all the same.

Each FE run takes ~3 minutes of CPU here; the runs are cached as ``fe/NAME.csv`` (time_s,
reaction_force_N at 0.5 ms) in the output directory and reused (``--cached-only`` writes
just the records whose run is cached). The controls at alpha 180
and 600 1/s are at the declared E (:data:`AT_DECLARED_E`): their cached runs are the full
FE runs of ``ccedi rom-check`` (validation/rom_check_sensor.json), the same model and
outputs. Regenerate:
``.venv/bin/python -m ccedi.calibrate.contact_synthetic [OUT_DIR]`` (deterministic).
"""
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.signal import lfilter

from ccedi.fea.contact.drum import DrumSetup, FullContactModel
from ccedi.fea.material import RUBBER, NeoHookean
from ccedi.fea.mesh import SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR
from ccedi.outputs import write_csv, write_json
from ccedi.rom.sensor import Transducer
from ccedi.units import m_to_inch

from .contact_model import radially_offset

RECORD_S = 1.5
"""Record length [s] (the paper's Fig. 10 span)."""
FE_OUTPUTS = 3000
"""FE outputs over the record (0.5 ms)."""
SAMPLE_RATE_HZ = 1000.0
"""Sample rate of the records [Hz]."""
NOISE_FRACTION = 0.02
"""Transducer noise std over the record's peak reading."""
DAMPING = "global"
AT_DECLARED_E = ("control_180", "control_600")
"""Controls at the declared E: their FE runs are those of ``ccedi rom-check`` (alpha 180 and
600 1/s, 3000 outputs over 1.5 s, the default set-up), brought in as ``fe/NAME.csv``."""


@dataclass(frozen=True)
class ContactTruth:
    """What a contact record contains.

    Parameters
    ----------
    E_factor : float
        True Young's modulus over the declared one [-].
    alpha_per_s : float
        True mass-proportional damping [1/s].
    effects : dict
        {effect name: {parameter: value}} (parameters as the catalogue names them).
    fe_run : str or None, optional
        Name of the record whose FE run this one reuses (the transducer effects), or None.
    damping : str, optional
        The mass-damping kind the FE run is made with, "global" or "relative" (the
        sidecar declares it). Default :data:`DAMPING`.
    """

    E_factor: float
    alpha_per_s: float
    effects: dict = field(default_factory=dict)
    fe_run: str | None = None
    damping: str = DAMPING


def declared_setup():
    """The set-up every sidecar declares: the default :class:`ccedi.fea.contact.drum.DrumSetup`.

    Returns
    -------
    ccedi.fea.contact.drum.DrumSetup
        8-in SM-A finger of the paper's rubber on the paper's drum.
    """
    return DrumSetup()


def true_setup(truth: ContactTruth, mesh=None):
    """The set-up the FE run of a record is made with (module docstring).

    Parameters
    ----------
    truth : ContactTruth
        The record's truth.
    mesh : dict, optional
        ``finger_section_elements`` / ``finger_elements_along`` of the generated finger
        other than the declared SM-A's (a generator whose discretisation differs from the
        one the calibration's chain is reduced from). Default None: SM-A.

    Returns
    -------
    ccedi.fea.contact.drum.DrumSetup
        The declared set-up at the true E with the physical effect applied.
    """
    s = declared_setup()
    e = truth.effects
    return replace(s, finger_material=NeoHookean(E=RUBBER.E * truth.E_factor, nu=RUBBER.nu, rho=RUBBER.rho),
                   friction=e.get("friction", {}).get("friction_mu", s.friction),
                   omega_rad_s=e.get("drum_speed", {}).get("omega_rad_s", s.omega_rad_s),
                   theta0_rad=s.theta0_rad + e.get("timing_offset", {}).get("theta0_offset_rad", 0.0),
                   contact_damping_ratio=e.get("contact_damping", {}).get("contact_damping_ratio", 0.0),
                   object_center_m=radially_offset(s.object_center_m,
                                                   e.get("object_offset", {}).get("object_radial_offset_m", 0.0)),
                   **(mesh or {}))


def bundled_set():
    """The truths of the bundled contact set: three clean controls (alpha 80, 180, 600
    1/s), two records of each effect, E factors drawn within +-5 % (fixed seed). In the
    order of generation: each control, then the records that reuse its FE run (the
    transducer effects, and the timing offset as a trigger delay: the record read
    ``trigger_delay_s`` late, F(t + delay), the same as a drum angle further round by
    omega x delay once the finger has settled), then one FE run per physical effect, then
    the second of each.

    Returns
    -------
    dict
        {record name: ContactTruth}.
    """
    rng = np.random.default_rng(2026)
    cases = {"control_80": (80.0, {}, None),
             "sensor_offset_drift_up": (None, {"sensor_offset_drift": {"offset_N": 0.4, "drift_N_s": 0.3}},
                                        "control_80"),
             "timing_offset_trigger_late": (None, {"timing_offset": {"trigger_delay_s": 0.012}}, "control_80"),
             "control_180": (180.0, {}, None),
             "sensor_bandwidth_low": (None, {"sensor_bandwidth": {"sensor_hz": 20.0, "sensor_damping_ratio": 0.7}},
                                      "control_180"),
             "timing_offset_trigger_early": (None, {"timing_offset": {"trigger_delay_s": -0.015}}, "control_180"),
             "control_600": (600.0, {}, None),
             "sensor_bandwidth_ringing": (None, {"sensor_bandwidth": {"sensor_hz": 40.0,
                                                                      "sensor_damping_ratio": 0.25}}, "control_600"),
             "sensor_offset_drift_down": (None, {"sensor_offset_drift": {"offset_N": -0.3, "drift_N_s": -0.5}},
                                          "control_600"),
             "friction_low": (120.0, {"friction": {"friction_mu": 0.35}}, None),
             "drum_speed_slow": (250.0, {"drum_speed": {"omega_rad_s": 1.95}}, None),
             "object_offset_out": (200.0, {"object_offset": {"object_radial_offset_m": 0.002}}, None),
             "friction_high": (300.0, {"friction": {"friction_mu": 0.9}}, None),
             "drum_speed_fast": (100.0, {"drum_speed": {"omega_rad_s": 2.25}}, None),
             "object_offset_in": (90.0, {"object_offset": {"object_radial_offset_m": -0.0015}}, None),
             "timing_offset_angle": (400.0, {"timing_offset": {"theta0_offset_rad": -0.04}}, None)}
    out = {}
    for name, (alpha, effects, fe_run) in cases.items():
        E = float(rng.uniform(0.95, 1.05))
        if name in AT_DECLARED_E:
            E = 1.0
        if fe_run is not None:
            base = out[fe_run]
            out[name] = ContactTruth(E_factor=base.E_factor, alpha_per_s=base.alpha_per_s, effects=effects,
                                     fe_run=fe_run)
        else:
            out[name] = ContactTruth(E_factor=E, alpha_per_s=alpha, effects=effects)
    return out


def fe_force(truth: ContactTruth, mesh=None):
    """The full FEA's reaction force of a record (module docstring).

    Parameters
    ----------
    truth : ContactTruth
        The record's truth (its physical effects and damping kind).
    mesh : dict, optional
        The generated finger's element counts (:func:`true_setup`). Default None: SM-A.

    Returns
    -------
    pandas.DataFrame
        ``time_s`` [s] (0.5 ms outputs from 0) and ``reaction_force_N`` [N].
    """
    res = FullContactModel(true_setup(truth, mesh), object_stress=False).run(
        truth.alpha_per_s, damping=truth.damping, t_end_s=RECORD_S, n_outputs=FE_OUTPUTS)
    h = res.history
    return pd.DataFrame({"time_s": np.concatenate([[0.0], h.time_s.to_numpy()]),
                         "reaction_force_N": np.concatenate([[0.0], h.reaction_force_N.to_numpy()])})


def declared_sidecar(noise_std_N, damping=DAMPING):
    """The sidecar of a bundled record.

    Parameters
    ----------
    noise_std_N : float
        Transducer noise std [N].
    damping : str, optional
        The declared mass-damping kind. Default :data:`DAMPING`.

    Returns
    -------
    dict
        kind, finger (declared), drum (declared [drum] keys), damping, sensor.
    """
    s = declared_setup()
    return {"kind": "contact",
            "finger": {"length_in": round(m_to_inch(s.finger_length_m), 9),
                       "section_semi_axes_m": [SEMI_AXIS_MAJOR, SEMI_AXIS_MINOR], "E_Pa": RUBBER.E,
                       "nu": RUBBER.nu, "rho_kg_m3": RUBBER.rho},
            "drum": {"drum_radius_m": s.drum_radius_m, "omega_rad_s": s.omega_rad_s, "theta0_rad": s.theta0_rad,
                     "object_center_m": list(s.object_center_m), "object_semi_axes_m": list(s.object_semi_axes_m),
                     "friction": s.friction},
            "damping": damping, "sensor": {"noise_std_N": noise_std_N}}


def reading(truth: ContactTruth, fe: pd.DataFrame):
    """The noiseless transducer reading of a record from its FE force: transducer, trigger
    delay, offset and drift, sampled at SAMPLE_RATE_HZ.

    Parameters
    ----------
    truth : ContactTruth
        The record's truth (its transducer and timing effects).
    fe : pandas.DataFrame
        The FE force (:func:`fe_force`).

    Returns
    -------
    t : numpy.ndarray
        Sample times [s] (from 1 / SAMPLE_RATE_HZ).
    y : numpy.ndarray
        The reading [N].
    """
    t_fe, f_fe = fe.time_s.to_numpy(), fe.reaction_force_N.to_numpy()
    bw = truth.effects.get("sensor_bandwidth", {})
    sensor = Transducer(bw.get("sensor_hz", Transducer().natural_frequency_hz),
                        bw.get("sensor_damping_ratio", Transducer().damping_ratio))
    y_fe = sensor.measured(t_fe, f_fe)
    t = np.arange(1, int(round(RECORD_S * SAMPLE_RATE_HZ)) + 1) / SAMPLE_RATE_HZ
    delay = truth.effects.get("timing_offset", {}).get("trigger_delay_s", 0.0)
    y = np.interp(t + delay, t_fe, y_fe, left=y_fe[0], right=y_fe[-1])
    drift = truth.effects.get("sensor_offset_drift", {})
    return t, y + drift.get("offset_N", 0.0) + drift.get("drift_N_s", 0.0) * t


def record(truth: ContactTruth, fe: pd.DataFrame, seed, *, noise_fraction=NOISE_FRACTION, noise_ar=0.0):
    """One record from its FE force: the :func:`reading` plus noise, white or
    first-order autoregressive (coloured).

    Parameters
    ----------
    truth : ContactTruth
        The record's truth (its transducer effects and damping kind).
    fe : pandas.DataFrame
        The FE force (:func:`fe_force`).
    seed : int
        Seed of the noise.
    noise_fraction : float, optional
        The noise's std over the reading's peak. Default :data:`NOISE_FRACTION`.
    noise_ar : float, optional
        Lag-1 coefficient phi of the AR(1) noise e_k = phi e_(k-1) + sqrt(1 - phi^2) w_k
        (stationary, of the stated std), in [0, 1). Default 0: white.

    Returns
    -------
    frame : pandas.DataFrame
        ``time_s`` [s] (from 1 / SAMPLE_RATE_HZ) and ``reaction_force_N`` [N].
    meta : dict
        The sidecar (the noise's std declared, the truth's damping kind).
    """
    t, y = reading(truth, fe)
    noise = noise_fraction * float(np.max(y))
    w = np.random.default_rng(seed).standard_normal(len(t))
    e = w
    if noise_ar:                                       # e_0 = w_0: stationary from the first sample
        rest = lfilter([1.0], [1.0, -noise_ar], np.sqrt(1.0 - noise_ar**2) * w[1:], zi=[noise_ar * w[0]])[0]
        e = np.concatenate([w[:1], rest])
    y = y + noise * e
    return pd.DataFrame({"time_s": np.round(t, 9), "reaction_force_N": y}), declared_sidecar(noise, truth.damping)


def write_bundled_set(out_dir, cached_only=False):
    """Write every record as NAME.csv + NAME.json, the FE runs as fe/NAME.csv (reused when
    present) and the truths as manifest.json (rewritten after every record).
    Deterministic; prints one line per record.

    Parameters
    ----------
    out_dir : str or pathlib.Path
        Output directory (created if missing).
    cached_only : bool, optional
        Write only the records whose FE run is cached (no FE run). Default False.
    """
    out_dir = Path(out_dir)
    manifest = {}
    for i, (name, truth) in enumerate(bundled_set().items()):
        run = truth.fe_run or name
        cache = out_dir / "fe" / f"{run}.csv"
        if cached_only and not cache.is_file():
            continue
        fe = cached_fe_force(cache, truth)
        frame, meta = record(truth, fe, seed=3000 + i)
        write_csv(out_dir / f"{name}.csv", frame)
        write_json(out_dir / f"{name}.json", meta)
        manifest[name] = {"E_factor": truth.E_factor, "alpha_per_s": truth.alpha_per_s, "effects": truth.effects,
                          "fe_run": run, "noise_std_N": meta["sensor"]["noise_std_N"]}
        print(f"{name}: E x {truth.E_factor:.3f}, alpha {truth.alpha_per_s:g} 1/s, {truth.effects}", flush=True)
        _write_manifest(out_dir, manifest)


def _write_manifest(out_dir, manifest):
    """The truths written so far (after every record: a long generation can be stopped)."""
    write_json(out_dir / "manifest.json", {
        "generator": "ccedi.calibrate.contact_synthetic (full explicit FEA, ccedi.fea.contact.drum.FullContactModel, "
                     "8-in SM-A finger, 0.5 ms outputs; transducer ccedi.rom.sensor.Transducer)",
        "noise_fraction_of_peak": NOISE_FRACTION, "sample_rate_hz": SAMPLE_RATE_HZ, "damping": DAMPING,
        "records": manifest})


def cached_fe_force(cache, truth: ContactTruth, mesh=None):
    """The FE force of a record, read from ``cache`` (a CSV) when there, else run
    (:func:`fe_force`, one line printed with its wall time) and written there.

    Parameters
    ----------
    cache : pathlib.Path
        The run's CSV (time_s, reaction_force_N).
    truth : ContactTruth
        The record's truth.
    mesh : dict, optional
        The generated finger's element counts (:func:`true_setup`).

    Returns
    -------
    pandas.DataFrame
        The FE force.
    """
    if cache.is_file():
        return pd.read_csv(cache)
    t0 = time.perf_counter()
    fe = fe_force(truth, mesh)
    write_csv(cache, fe)
    print(f"{cache.stem}: full FEA {time.perf_counter() - t0:.0f} s", flush=True)
    return fe


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--cached-only"]
    write_bundled_set(args[0] if args else Path(__file__).parents[1] / "data" / "contact",
                      cached_only="--cached-only" in sys.argv)
