"""Calibration time of 2 s impulse records (target: seconds; the issue's budget for a
contact record is 5 minutes).

The model is the declared finger's FE modes (solved once per finger, then cached; timed
separately as ``finger_modes_s``), keeping the modes the pulse rings. Records: the bundled
two-effect record (tip mass + quadratic damping at 1.5 N: three selection rounds over the
whole catalogue, RK4 for the drag), a single-effect one (time delay at 0.5 N), a clean
control (stops after the baseline) and the short-pulse control (10 modes); 2001 samples
each. The numba kernels are compiled (and cached) before the timing. The 1-minute load
average before and after is recorded: on a shared machine the times scale with it.

Run: ``.venv/bin/python benchmarks/calibrate_speed.py``; writes benchmarks/calibrate_speed.json.
"""
import os
import time
from pathlib import Path

from ccedi.calibrate.experiment import load_experiment
from ccedi.calibrate.loop import calibrate
from ccedi.calibrate.model import FingerModel
from ccedi.outputs import report_figures

DATA = Path(__file__).parents[1] / "data" / "measured"
OUT = Path(__file__).with_suffix(".json")
RECORDS = ("tip_mass+quadratic_damping_high", "time_delay_low", "control_low", "control_short_pulse")


def main():
    figures = {"load_average_1min_before": round(os.getloadavg()[0], 1)}
    exp = load_experiment(DATA / "time_delay_low.csv")
    t0 = time.perf_counter()
    FingerModel(exp)
    figures["finger_modes_s"] = round(time.perf_counter() - t0, 2)
    calibrate(exp, candidates=["quadratic_damping"])   # compile
    for name in RECORDS:
        exp = load_experiment(DATA / f"{name}.csv")
        t0 = time.perf_counter()
        cal = calibrate(exp)
        figures[f"{name}_s"] = round(time.perf_counter() - t0, 2)
        figures[f"{name}_effects"] = "+".join(cal.final.effects) or "none"
        figures[f"{name}_modes"] = cal.model.n_modes
        figures[f"{name}_samples"] = len(exp.time_s)
    figures["load_average_1min_after"] = round(os.getloadavg()[0], 1)
    report_figures(figures, OUT)


if __name__ == "__main__":
    main()
