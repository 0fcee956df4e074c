"""The friction chatter measured: small ensembles of full FE drum runs whose initial
conditions differ by a hair, per feature of the transducer reading.

At each of a few damping values (global damping, the bundled contact set-up, the declared
8-in finger), ``RUNS`` full explicit FE runs (:class:`ccedi.fea.contact.drum.FullContactModel`,
0.5 ms outputs) start from initial drum angles ``PERTURBATION_RAD`` apart (1e-6 rad: the
finger's tip moves 0.1 um, a thousandth of the FE's own contact penetration). Each run is
read through the declared transducer and sampled at 1 kHz, like the bundled records
(:func:`ccedi.calibrate.contact_synthetic.reading` without effects), and its features are
measured as the prediction measures them (:func:`ccedi.calibrate.prediction.contact_features`:
contact start and end at 10 % of the 20 Hz-filtered peak, duration, filtered peak), plus
the contact impulse. Per damping value and feature: the ensemble's mean and standard
deviation (the chatter's share of each feature's uncertainty), and the RMS difference of
the readings between runs against the bundled records' noise std: if runs 1e-6 rad apart
differ by as much as runs whose parameters differ by percents, the chatter is chaotic in
the initial conditions and its variance, not its path, is what a model can predict.

Run: ``.venv/bin/python benchmarks/contact_chatter_ensemble.py`` (``RUNS`` x 2 FE runs of
~2-3 minutes each); writes benchmarks/contact_chatter_ensemble.json.
"""
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd

from ccedi.calibrate.contact_synthetic import NOISE_FRACTION, RECORD_S, ContactTruth, declared_setup, reading
from ccedi.calibrate.prediction import contact_features
from ccedi.fea.contact.drum import FullContactModel

OUT = Path(__file__).with_suffix(".json")
ALPHAS = (80.0, 300.0)
"""Global damping values [1/s]: where the bundled records chatter most and a heavily damped one."""
RUNS = 3
PERTURBATION_RAD = 1e-6
"""Step of the initial drum angle between the ensemble's runs [rad]."""
FE_OUTPUTS = 3000


def ensemble_reading(alpha, theta_offset_rad):
    """The transducer reading at 1 kHz of one full FE run [s, N]."""
    setup = declared_setup()
    setup = replace(setup, theta0_rad=setup.theta0_rad + theta_offset_rad)
    h = FullContactModel(setup, object_stress=False).run(alpha, t_end_s=RECORD_S, n_outputs=FE_OUTPUTS).history
    fe = pd.DataFrame({"time_s": np.r_[0.0, h.time_s.to_numpy()],
                       "reaction_force_N": np.r_[0.0, h.reaction_force_N.to_numpy()]})
    return reading(ContactTruth(E_factor=1.0, alpha_per_s=alpha), fe)


def main():
    t0 = time.perf_counter()
    out = {"what": f"{RUNS} full FE drum runs per alpha, initial drum angles {PERTURBATION_RAD:g} rad apart, read "
                   "through the declared transducer at 1 kHz", "alphas": {}}
    for alpha in ALPHAS:
        runs = []
        for k in range(RUNS):
            t, y = ensemble_reading(alpha, k * PERTURBATION_RAD)
            f = contact_features(t, y) | {"contact_impulse_N_s": float(np.trapezoid(y, t))}
            runs.append((y, f))
            print(f"alpha {alpha:g} 1/s, run {k + 1}/{RUNS}: " + ", ".join(f"{n} {v:.5g}" for n, v in f.items()),
                  flush=True)
        noise = NOISE_FRACTION * float(np.mean([np.max(y) for y, _ in runs]))
        pairs = [float(np.sqrt(np.mean((a[0] - b[0]) ** 2))) for i, a in enumerate(runs) for b in runs[i + 1:]]
        out["alphas"][f"{alpha:g}"] = {
            "features": {n: {"mean": float(np.mean([f[n] for _, f in runs])),
                             "std": float(np.std([f[n] for _, f in runs], ddof=1))} for n in runs[0][1]},
            "reading_rms_difference_N": pairs, "noise_std_N": noise,
            "reading_rms_difference_over_noise": [p / noise for p in pairs]}
        print(f"alpha {alpha:g} 1/s: readings differ by {np.round(pairs, 3)} N RMS ({np.round(np.array(pairs) / noise, 2)} "
              f"noise std)", flush=True)
    out["wall_time_s"] = time.perf_counter() - t0
    OUT.write_text(json.dumps(out, indent=2) + "\n")
    print(f"wrote {OUT} ({out['wall_time_s']:.0f} s)")


if __name__ == "__main__":
    main()
