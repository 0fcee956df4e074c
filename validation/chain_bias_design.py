"""The contact chain's mean bias against the full FEA over a space-filling design of FE runs:
the runs, the bias model fitted to them (:mod:`ccedi.calibrate.chain_bias`) and its error
on runs left out.

Design: ``RUNS`` points of a Latin hypercube (scipy.stats.qmc, seeded) over the parameters
the calibration moves the chain's dynamics with: alpha log-uniform in 50-700 1/s, E factor
in 0.92-1.08, friction mu in 0.3-0.95, drum speed x 0.9-1.1, initial drum angle +-0.05 rad,
object radial offset +-2.5 mm; the damping kind alternates, global and relative. Each
point: the full explicit FEA of the declared 8-in SM-A finger on the declared drum (the
model the chain is reduced from), 1.5 s, force every 0.5 ms, and the chain at the same
point, both cached under validation/cache/chain_bias/ (not in git; ~1-3 minutes per FE
run here).

Then the bias model is fitted to all runs (written to data/contact/chain_bias.json, which
``DrumContactModel.bias`` reads) and to every run left out in turn: per run, the RMS of
the reading's error through the declared transducer [N] with the chain alone and with the
left-out model's correction, over the record's 2 % noise std.

Run: ``.venv/bin/python validation/chain_bias_design.py [--fit-only]``; writes
validation/chain_bias_design.json.
"""
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.stats import qmc

from ccedi.calibrate.chain_bias import BUNDLED_BIAS, fit_chain_bias, run_bias
from ccedi.calibrate.contact_model import DrumContactModel
from ccedi.calibrate.experiment import load_experiment
from ccedi.outputs import report_figures, write_csv
from ccedi.rom.sensor import Transducer

ROOT = Path(__file__).parents[1]
CACHE = ROOT / "validation" / "cache" / "chain_bias"
OUT = Path(__file__).with_suffix(".json")
RECORD = ROOT / "data" / "contact" / "control_80.csv"
"""A record of the declared set-up: its sidecar gives the finger and drum, its samples the times."""
RUNS = 24
BOUNDS = {"log_alpha": (np.log(50.0), np.log(700.0)), "E_factor": (0.92, 1.08), "friction_mu": (0.3, 0.95),
          "omega_factor": (0.9, 1.1), "theta0_offset_rad": (-0.05, 0.05), "object_radial_offset_m": (-2.5e-3, 2.5e-3)}
NOISE_FRACTION = 0.02
"""The records' noise std over their peak reading (for the errors' scale)."""


def design():
    """The design's points: [(damping kind, parameter values)], deterministic."""
    unit = qmc.LatinHypercube(d=len(BOUNDS), seed=31).random(RUNS)
    lo, hi = np.array([b[0] for b in BOUNDS.values()]), np.array([b[1] for b in BOUNDS.values()])
    omega = load_experiment(RECORD).drum["omega_rad_s"]
    points = []
    for i, x in enumerate(lo + unit * (hi - lo)):
        p = dict(zip(BOUNDS, x))
        points.append((("global", "relative")[i % 2],
                       {"alpha_per_s": float(np.exp(p["log_alpha"])), "E_factor": float(p["E_factor"]),
                        "friction_mu": float(p["friction_mu"]), "omega_rad_s": float(p["omega_factor"] * omega),
                        "theta0_offset_rad": float(p["theta0_offset_rad"]),
                        "object_radial_offset_m": float(p["object_radial_offset_m"])}))
    return points


def run(i, kind, v, fit_only):
    """(time_s, FE force at the record's times, chain force) of design point i [s, N, N], cached."""
    path = CACHE / f"run_{i:02d}.csv"
    model = DrumContactModel(replace(load_experiment(RECORD), damping=kind))
    if not path.is_file():
        if fit_only:
            return None
        t0 = time.perf_counter()
        fe = model._at_record_times(*model.fea_force(v))
        write_csv(path, pd.DataFrame({"time_s": model.exp.time_s, "fe_force_N": fe, "chain_force_N": model.force(v)}))
        print(f"run {i} ({kind}, {', '.join(f'{k} {x:.4g}' for k, x in v.items())}): full FEA "
              f"{time.perf_counter() - t0:.0f} s", flush=True)
    frame = pd.read_csv(path)
    return frame.time_s.to_numpy(), frame.fe_force_N.to_numpy(), frame.chain_force_N.to_numpy()


def reading_error(t, fe, chain, correction):
    """RMS of the transducer reading's error [N] of the chain plus ``correction`` against the FE."""
    sensor = Transducer()
    return float(np.sqrt(np.mean((sensor.measured(t, fe) - sensor.measured(t, chain + correction)) ** 2)))


def main(args):
    fit_only = "--fit-only" in args
    points = design()
    runs = []
    for i, (kind, v) in enumerate(points):
        r = run(i, kind, v, fit_only)
        if r is not None:
            runs.append((kind, v, *r))
    model = fit_chain_bias(runs)
    model.write(BUNDLED_BIAS)
    rows = {}
    for i, (kind, v, t, fe, chain) in enumerate(runs):
        left_out = fit_chain_bias(runs[:i] + runs[i + 1:])
        noise = NOISE_FRACTION * float(np.max(Transducer().measured(t, fe)))
        before = reading_error(t, fe, chain, 0.0)
        after = reading_error(t, fe, chain, left_out.force_bias(t, chain, v=v, damping=kind))
        fitted = reading_error(t, fe, chain, run_bias(t, fe, chain))
        rows[i] = {"damping": kind, "params": v, "chain_error_over_noise": before / noise,
                   "corrected_error_over_noise_left_out": after / noise,
                   "smooth_bias_removed_error_over_noise": fitted / noise}
        print(i, kind, f"chain {before / noise:.3f}, corrected (left out) {after / noise:.3f}, "
                       f"own smooth bias removed {fitted / noise:.3f} noise std", flush=True)
    before = np.array([r["chain_error_over_noise"] for r in rows.values()])
    after = np.array([r["corrected_error_over_noise_left_out"] for r in rows.values()])
    report_figures({"runs": len(runs), "design": {"points": RUNS, "bounds": {k: list(b) for k, b in BOUNDS.items()},
                                                  "damping": "alternating global, relative"},
                    "model": model.summary(),
                    "chain_error_over_noise_median": float(np.median(before)),
                    "corrected_error_over_noise_left_out_median": float(np.median(after)),
                    "runs_improved_left_out": f"{int(np.sum(after < before))} of {len(runs)}",
                    "per_run": rows}, OUT)


if __name__ == "__main__":
    main(sys.argv[1:])
