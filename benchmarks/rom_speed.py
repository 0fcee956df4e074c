"""Speed-up of the reduced models over full FEA.

Impulse ROM: the 4.5-in SM-A finger, 1 N tip pulse for 10 ms, alpha = 180 1/s, 400
outputs over 0.2 s; full explicit FEA against the 6-mode ROM (building the ROM, i.e. the
eigen-solve, is reported separately: it is done once per geometry). Target: >= 5000x.

Contact ROM: the 8-in finger on the drum, alpha = 180 1/s, 1.5 s, 300 outputs; full
explicit FEA (one run, ~2 min) against the co-rotational superelement chain (median of
5 runs after compilation; building the chain is reported separately). Target: >= 500x.

Run: ``.venv/bin/python benchmarks/rom_speed.py``; writes benchmarks/rom_speed.json.
"""
import time
from pathlib import Path

import numpy as np

from ccedi.fea.cases.studies import finger_impulse_model, impulse_model
from ccedi.fea.contact.drum import DrumSetup, FullContactModel
from ccedi.outputs import report_figures
from ccedi.rom.check import compare_contact
from ccedi.rom.contact_rom import ReducedContactModel
from ccedi.rom.modal import nrmse, tip_modal_rom

OUT = Path(__file__).with_suffix(".json")


def main():
    full = finger_impulse_model(force_N=1.0, duration_s=0.01)
    full.run(180.0, 1e-3, 1)                                    # compile outside the timing
    fe = full.run(180.0, 0.2, 400)
    t0 = time.perf_counter()
    rom = tip_modal_rom(impulse_model(alpha=180.0), n_modes=6)
    build = time.perf_counter() - t0
    t = fe.history.time_s.values
    repeats = 2000
    t0 = time.perf_counter()
    for _ in range(repeats):
        y = rom.pulse_response(t, 1.0, 0.01)
    per_eval = (time.perf_counter() - t0) / repeats
    figures = {"case": "4.5-in finger impulse, alpha 180 1/s, 0.2 s, 400 outputs",
               "fe_wall_time_s": round(fe.summary["wall_time_s"], 3),
               "rom_eval_time_s": per_eval, "rom_build_time_s": round(build, 3),
               "impulse_speedup": round(fe.summary["wall_time_s"] / per_eval),
               "impulse_target_speedup": 5000,
               "nrmse_rom_vs_fe": nrmse(y, fe.history.tip_uy_m.values)}
    figures.update(contact_figures())
    report_figures(figures, OUT)


def contact_figures(alpha=180.0):
    setup = DrumSetup()
    t0 = time.perf_counter()
    reduced = ReducedContactModel(setup)
    build = time.perf_counter() - t0
    reduced.run(alpha, t_end_s=1e-3, n_outputs=1)               # compile outside the timing
    runs = [reduced.run(alpha) for _ in range(5)]
    rom_wall = float(np.median([r.summary["wall_time_s"] for r in runs]))
    full = FullContactModel(setup, object_stress=False).run(alpha)
    m = compare_contact(setup, full, runs[0])
    return {"contact_case": f"8-in finger on the drum, alpha {alpha:g} 1/s, 1.5 s, 300 outputs",
            "contact_fe_wall_time_s": round(full.summary["wall_time_s"], 2),
            "contact_rom_wall_time_s": rom_wall, "contact_rom_build_time_s": round(build, 3),
            "contact_speedup": round(full.summary["wall_time_s"] / rom_wall),
            "contact_target_speedup": 500, "contact_tip_lag_nrmse": m["nrmse"]}


if __name__ == "__main__":
    main()
