"""How the ROM's sensor-filtered peak force against the full FEA depends on the
transducer's bandwidth.

Reads the FE reaction forces that ``ccedi rom-check --contact stations face --forces-dir
DIR`` wrote (alpha = 7.5, 180, 600 1/s, 0.5 ms outputs), reruns the co-rotational ROM
(both contact models, this code: its output force is the mean over each output
interval) at the same times, reads both through second-order Butterworth low-passes
(:class:`ccedi.rom.sensor.Transducer`, zeta = 1/sqrt(2)) of 25 Hz to 1 kHz and reports
ROM / FEA - 1 of the peak reading, and the FE's peak reading [N].

Measured (2026-12-02, from the rom-check run of validation/rom_check_sensor.json): the
face model stays within 10 % at every alpha up to 100 Hz (+2.3 to +5.2 % at alpha 7.5)
and fails alpha = 7.5 from 200 Hz (+22 %: its own chatter shows); the stations model
fails alpha = 7.5 from 100 Hz (-11.5 %, -8.6 % at 50 Hz); at alpha 180 and 600 both stay
within 5 % at every bandwidth.

Run: ``.venv/bin/python validation/sensor_bandwidth.py DIR`` (seconds); writes
validation/sensor_bandwidth.json.
"""
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from ccedi.fea.contact.drum import DrumSetup
from ccedi.outputs import report_figures
from ccedi.rom.contact_rom import ReducedContactModel
from ccedi.rom.sensor import Transducer

OUT = Path(__file__).with_suffix(".json")
BANDWIDTHS_HZ = (25.0, 50.0, 100.0, 200.0, 400.0, 1000.0)


def main(forces_dir):
    figures = {}
    roms = {c: ReducedContactModel(DrumSetup(), contact=c) for c in ("stations", "face")}
    for alpha in ("7.5", "180", "600"):
        for contact, model in roms.items():
            d = pd.read_csv(Path(forces_dir) / f"alpha_{alpha}_rom-corotational_{contact}.csv")
            t = d.time_s.to_numpy()
            rom_N = np.hypot(*model.reaction_force(float(alpha), t).T)
            for f_n in BANDWIDTHS_HZ:
                sensor = Transducer(f_n)
                fe = float(sensor.measured(t, d.fea_N).max())
                rom = float(sensor.measured(t, rom_N).max())
                figures[f"alpha {alpha}, {contact}, {f_n:g} Hz: error"] = round(rom / fe - 1.0, 4)
                figures[f"alpha {alpha}, {f_n:g} Hz: FE peak reading N"] = round(fe, 3)
    report_figures(figures, OUT)


if __name__ == "__main__":
    main(sys.argv[1])
