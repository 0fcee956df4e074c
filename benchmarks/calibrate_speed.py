"""Calibration time of a 2 s impulse record (target: under 60 s).

Records: the bundled two-effect record (tip mass + quadratic damping at 1.5 N, the slowest:
three selection rounds over the whole catalogue) and a single-effect one (time delay at
0.5 N); 2001 samples each. The numba kernels are compiled (and cached) before the timing.

Run: ``.venv/bin/python benchmarks/calibrate_speed.py``; writes benchmarks/calibrate_speed.json.
"""
import time
from pathlib import Path

from _output import report  # benchmarks/ is on sys.path when run as a script

from ccedi.calibrate.experiment import load_experiment
from ccedi.calibrate.loop import calibrate

DATA = Path(__file__).parents[1] / "data" / "measured"
OUT = Path(__file__).with_suffix(".json")
RECORDS = ("tip_mass+quadratic_damping_high", "time_delay_low")


def main():
    figures = {"target_s": 60.0}
    calibrate(load_experiment(DATA / "time_delay_low.csv"), candidates=["quadratic_damping"])   # compile
    for name in RECORDS:
        exp = load_experiment(DATA / f"{name}.csv")
        t0 = time.perf_counter()
        cal = calibrate(exp)
        figures[f"{name}_s"] = round(time.perf_counter() - t0, 2)
        figures[f"{name}_effects"] = "+".join(cal.final.effects) or "none"
        figures[f"{name}_samples"] = len(exp.time_s)
        figures[f"{name}_record_s"] = float(exp.time_s[-1] - exp.time_s[0])
    report(figures, OUT)


if __name__ == "__main__":
    main()
