"""Speed of the contact study.

The full 8-in finger on the drum, 1.5 s at alpha = 7.5 1/s with global damping, object
stress at each of 300 outputs, with a progress bar. Prints and writes to
benchmarks/contact_speed.json: wall time [s], steps, ns per element-cycle, and the
contact summary. Target: under 5 minutes on the 2-core CI machine.

Run: ``.venv/bin/python benchmarks/contact_speed.py``.
"""
import platform
import sys
from pathlib import Path

from _output import report  # benchmarks/ is on sys.path when run as a script

from ccedi.fea.drum import DrumSetup, contact_run, contact_summary

OUT = Path(__file__).with_suffix(".json")


def main():
    setup = DrumSetup()
    contact_run(setup, 7.5, t_end_s=1e-3, n_outputs=1, object_stress=False)        # compile outside the timing
    result, model = contact_run(setup, 7.5, t_end_s=1.5, n_outputs=300, progress=True)
    s = contact_summary(setup, result, model)
    figures = {"model": "8-in SM-A finger on drum over elliptical object, alpha 7.5 1/s, global damping, 1.5 s",
               "wall_time_s": round(result.summary["wall_time_s"], 2), "steps": result.summary["steps"],
               "elements": result.summary["elements"],
               "ns_per_element_cycle": round(result.summary["ns_per_element_cycle"], 1),
               "target_wall_time_s": 300.0, "contact_start_s": s["contact_start_s"],
               "contact_duration_s": s["contact_duration_s"], "python": sys.version.split()[0],
               "machine": platform.machine()}
    report(figures, OUT)


if __name__ == "__main__":
    main()
