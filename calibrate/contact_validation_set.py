"""A contact validation set made by a generator that is not the calibration's model: 60
effect records and 15 clean controls of the 8-in finger on the drum, under
``data/contact_validation/``.

It differs from the bundled set (:mod:`ccedi.calibrate.contact_synthetic`, on which the
calibration's rules were set) in every way the calibration could have been tuned to:

- **another mesh**: the full explicit FEA of a finger meshed 4 x 4 hexahedra across and
  40 along (:data:`GENERATOR_MESH`; the chain the calibration fits is reduced from the
  5 x 5 SM-A mesh with its refined root), so the records carry a discretisation error
  the calibration's model does not share;
- **coloured noise**: first-order autoregressive, lag-1 coefficient drawn in
  :data:`NOISE_AR` per record, std drawn in :data:`NOISE_FRACTIONS` of the peak (the
  sidecar declares the std);
- **both damping kinds**: global and relative mass damping (the sidecar declares the
  kind), at three alphas (:data:`ALPHAS`), E drawn within +-5 % of the declared;
- **two effect sizes** per effect (:data:`SIZES`), the small one near what a 2 % noise
  record can show, with both signs.

Six FE controls (three alphas x two kinds) give the 15 controls (each with fresh noise,
the first three alphas' twice more) and the transducer-side records (sensor bandwidth,
sensor offset and drift, the record triggered early or late: a sensor effect does not
change the mechanics); the four physical effects (friction, drum speed, initial drum
angle, object offset) get an FE run each at every alpha and size, the damping kind
alternating: 6 + 24 FE runs, 60 effect records. Every record is labelled with a half,
``tuning`` or ``held_out``, alternating within each effect and size, so that rules set on
one half are scored on the other.

Regenerate (deterministic; each FE run ~1-2 minutes here, cached as ``fe/RUN.csv``)::

    .venv/bin/python -m ccedi.calibrate.contact_validation_set [OUT_DIR]
"""
import sys
from pathlib import Path

import numpy as np

from ccedi.outputs import write_csv, write_json

from .contact_synthetic import RECORD_S, SAMPLE_RATE_HZ, ContactTruth, cached_fe_force, declared_setup, record

GENERATOR_MESH = {"finger_section_elements": 4, "finger_elements_along": 40}
"""Element counts of the generator's finger (across the section, along the length)."""
ALPHAS = (70.0, 200.0, 500.0)
"""Mass-damping coefficients of the set [1/s]."""
DAMPINGS = ("global", "relative")
"""The damping kinds of the set."""
NOISE_FRACTIONS = (0.015, 0.025)
"""Range of the noise's std over the record's peak reading (drawn per record)."""
NOISE_AR = (0.3, 0.8)
"""Range of the noise's lag-1 autoregressive coefficient (drawn per record)."""
E_SPREAD = 0.05
"""True E factors are drawn in 1 +- E_SPREAD."""
_OMEGA = declared_setup().omega_rad_s
SIZES = {
    "friction": {"small": ({"friction_mu": 0.5}, {"friction_mu": 0.72}),
                 "large": ({"friction_mu": 0.35}, {"friction_mu": 0.9})},
    "drum_speed": {"small": ({"omega_rad_s": 0.97 * _OMEGA}, {"omega_rad_s": 1.03 * _OMEGA}),
                   "large": ({"omega_rad_s": 0.92 * _OMEGA}, {"omega_rad_s": 1.08 * _OMEGA})},
    "timing_offset": {"small": ({"theta0_offset_rad": -0.015}, {"theta0_offset_rad": 0.015}),
                      "large": ({"theta0_offset_rad": -0.04}, {"theta0_offset_rad": 0.04})},
    "object_offset": {"small": ({"object_radial_offset_m": -0.0007}, {"object_radial_offset_m": 0.0007}),
                      "large": ({"object_radial_offset_m": -0.002}, {"object_radial_offset_m": 0.002})},
    "sensor_bandwidth": {"small": ({"sensor_hz": 50.0, "sensor_damping_ratio": 0.5},
                                   {"sensor_hz": 60.0, "sensor_damping_ratio": 0.35}),
                         "large": ({"sensor_hz": 20.0, "sensor_damping_ratio": 0.7},
                                   {"sensor_hz": 35.0, "sensor_damping_ratio": 0.3})},
    "sensor_offset_drift": {"small": ({"offset_N": 0.08, "drift_N_s": 0.06}, {"offset_N": -0.08, "drift_N_s": -0.06}),
                            "large": ({"offset_N": 0.4, "drift_N_s": 0.3}, {"offset_N": -0.3, "drift_N_s": -0.5})},
    "trigger_delay": {"small": ({"trigger_delay_s": 0.004}, {"trigger_delay_s": -0.004}),
                      "large": ({"trigger_delay_s": 0.012}, {"trigger_delay_s": -0.012})},
}
"""Each effect's two variants (opposite signs, taken in turn over the alphas) per size.
``trigger_delay`` is the catalogue's ``timing_offset`` made by reading a control's run late
or early (:func:`ccedi.calibrate.contact_synthetic.reading`)."""
PHYSICAL = ("friction", "drum_speed", "timing_offset", "object_offset")
"""Effects built into the FE run (the others act on a control's run)."""


def catalogue_effect(effect):
    """The calibration catalogue's name of a set effect (``trigger_delay`` is a timing offset).

    Parameters
    ----------
    effect : str
        A key of :data:`SIZES`.

    Returns
    -------
    str
        The name in :data:`ccedi.calibrate.effects.CONTACT_CATALOGUE`.
    """
    return "timing_offset" if effect == "trigger_delay" else effect


def validation_set():
    """The truths of the set (module docstring), deterministic.

    Returns
    -------
    dict
        {record name: (ContactTruth, half, noise fraction, noise AR coefficient, FE run name)}.
    """
    rng = np.random.default_rng(4031)
    out, controls = {}, {}

    def noise():
        return float(rng.uniform(*NOISE_FRACTIONS)), float(rng.uniform(*NOISE_AR))

    for i, alpha in enumerate(ALPHAS):
        for j, kind in enumerate(DAMPINGS):
            run = f"control_a{alpha:g}_{kind}"
            controls[run] = ContactTruth(E_factor=float(rng.uniform(1 - E_SPREAD, 1 + E_SPREAD)), alpha_per_s=alpha,
                                         damping=kind)
            for k in range(3 if j == 0 else 2):
                out[f"{run}_{k}"] = (controls[run], ("tuning", "held_out")[(i + j + k) % 2], *noise(), run)
    for e, (effect, sizes) in enumerate(SIZES.items()):
        for s, (size, variants) in enumerate(sizes.items()):
            for i, alpha in enumerate(ALPHAS):
                params = variants[(i + s) % 2]
                half = ("tuning", "held_out")[(i + s) % 2]
                if effect in PHYSICAL:
                    kind = DAMPINGS[(i + s + e) % 2]
                    truth = ContactTruth(E_factor=float(rng.uniform(1 - E_SPREAD, 1 + E_SPREAD)), alpha_per_s=alpha,
                                         effects={effect: dict(params)}, damping=kind)
                    name = f"{effect}_{size}_a{alpha:g}_{kind}"
                    out[name] = (truth, half, *noise(), name)
                    continue
                for j, kind in enumerate(DAMPINGS):
                    run = f"control_a{alpha:g}_{kind}"
                    truth = ContactTruth(E_factor=controls[run].E_factor, alpha_per_s=alpha, damping=kind, fe_run=run,
                                         effects={catalogue_effect(effect): dict(variants[(i + s + j) % 2])})
                    out[f"{effect}_{size}_a{alpha:g}_{kind}"] = (truth, ("tuning", "held_out")[(i + s + j) % 2],
                                                               *noise(), run)
    return out


def write_validation_set(out_dir):
    """Write every record as NAME.csv + NAME.json, the FE runs as fe/RUN.csv (reused when
    present) and the truths as manifest.json (rewritten after every record; records whose
    run is cached first, so that a stopped generation leaves a usable set).

    Parameters
    ----------
    out_dir : str or pathlib.Path
        Output directory (created if missing).
    """
    out_dir = Path(out_dir)
    cases = validation_set()
    order = sorted(cases, key=lambda n: not (out_dir / "fe" / f"{cases[n][4]}.csv").is_file())
    seeds = {name: 7000 + i for i, name in enumerate(sorted(cases))}
    manifest = {}
    for i, name in enumerate(order):
        truth, half, fraction, ar, run = cases[name]
        fe = cached_fe_force(out_dir / "fe" / f"{run}.csv", truth, GENERATOR_MESH)
        frame, meta = record(truth, fe, seeds[name], noise_fraction=fraction, noise_ar=ar)
        write_csv(out_dir / f"{name}.csv", frame)
        write_json(out_dir / f"{name}.json", meta)
        manifest[name] = {"E_factor": truth.E_factor, "alpha_per_s": truth.alpha_per_s, "damping": truth.damping,
                          "effects": truth.effects, "fe_run": run, "half": half, "noise_std_N": meta["sensor"]["noise_std_N"],
                          "noise_fraction_of_peak": fraction, "noise_ar": ar}
        print(f"[{i + 1}/{len(order)}] {name}: E x {truth.E_factor:.3f}, alpha {truth.alpha_per_s:g} 1/s "
              f"{truth.damping}, {truth.effects}", flush=True)
        write_json(out_dir / "manifest.json", {
            "generator": "ccedi.calibrate.contact_validation_set (full explicit FEA, "
                         "ccedi.fea.contact.drum.FullContactModel, 8-in finger meshed "
                         f"{GENERATOR_MESH['finger_section_elements']} x {GENERATOR_MESH['finger_section_elements']} "
                         f"x {GENERATOR_MESH['finger_elements_along']} hex8, 0.5 ms outputs; AR(1) noise)",
            "record_s": RECORD_S, "sample_rate_hz": SAMPLE_RATE_HZ, "records": manifest})


if __name__ == "__main__":
    write_validation_set(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).parents[1] / "data" / "contact_validation")
