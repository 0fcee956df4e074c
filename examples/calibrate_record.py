"""Close the loop on a measured record: calibrate the declared finger, see what it finds.

The bundled ``data/measured/control_low`` record is an 8-in finger's tip response to a
0.5 N, 10 ms pulse (its JSON sidecar declares the finger, the load and the sensor noise).
The calibration fits the finger's damping alpha and E within the declared tolerance,
checks that the declared finger can explain the record at all, and adds a physical effect
from its catalogue only when the residual asks for one. ``ccedi calibrate RECORD.csv``
does the same from the command line, with a report.

Run: ``.venv/bin/python examples/calibrate_record.py [RECORD.csv]`` (seconds).
"""
import sys
from pathlib import Path

from ccedi.calibrate.experiment import load_experiment
from ccedi.calibrate.loop import calibrate, summary

RECORD = Path(__file__).resolve().parents[1] / "data" / "measured" / "control_low.csv"


def main():
    record = Path(sys.argv[1]) if len(sys.argv) > 1 else RECORD
    result = summary(calibrate(load_experiment(record)))
    b = result["baseline"]
    print(f"{record.name}: declared model {'adequate' if result['model_adequate'] else 'inadequate'}")
    print(f"alpha = {b['params']['alpha_per_s']:.4g} 1/s, E x {b['params']['E_factor']:.4f} "
          f"(baseline NRMSE {b['nrmse']:.3%})")
    found = [e["name"] for e in result["effects_found"]]
    print(f"effects added: {', '.join(found) if found else 'none'}; {result['stop_reason']}")


if __name__ == "__main__":
    main()
