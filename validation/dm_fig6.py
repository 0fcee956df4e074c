"""Paper Fig. 6 with the detailed model: the DM's modal ROM against a full explicit run.

The DM of :func:`ccedi.fea.mesh.gmsh_fingers.detailed_model` (at ``--size-mm``, default the
paper's 2.8 mm) under the paper's impulse (1 N for 10 ms at the tip, alpha = 180 1/s):

* its cost, first estimated (steps = t_end / dt, ~1.6 us per 10-node element-cycle,
  ``benchmarks/tet_speed.json``) and written, then measured;
* the full explicit run of ``--t-end-s`` (default 0.05 s) against the 6-mode modal ROM of
  the FE model linearised at rest (:func:`ccedi.rom.modal.reduce_impulse_model`): NRMSE
  (acceptance: below 2 %); the ROM fitted to that run (:func:`ccedi.rom.modal.fit_to_response`);
* SM-A's full explicit run at alpha = 180 over 0.2 s, the DM's matching alpha on both
  ROMs (:func:`ccedi.rom.ccedi.match_alpha`; paper 260 1/s), the peak von Mises stresses
  of both full runs and the quasi-static estimates the study uses
  (:func:`ccedi.rom.finger_identification.detailed_model_comparison`).

Prints and writes validation/dm_fig6.json (``--estimate-only``: the mesh and the estimate).

Run: ``.venv/bin/python validation/dm_fig6.py [--size-mm 2.8] [--t-end-s 0.05] [--estimate-only]``.
"""
import argparse
import platform
import time
from pathlib import Path

import numpy as np

from ccedi.fea.cases.studies import finger_impulse_model
from ccedi.fea.mesh import sm_a
from ccedi.fea.mesh.gmsh_fingers import DM_CONE_RADIUS, DM_RIB_THICKNESS, detailed_model
from ccedi.fea.solvers.explicit import TSSFAC, critical_time_step
from ccedi.outputs import report_figures
from ccedi.rom.ccedi import match_alpha
from ccedi.rom.finger_identification import PAPER_FIG6, detailed_model_comparison
from ccedi.rom.modal import ModalImpulseModel, fit_to_response, nrmse, reduce_impulse_model

OUT = Path(__file__).with_suffix(".json")
TET10_NS_PER_ELEMENT_CYCLE = 1592.0
"""Measured explicit cost of a 10-node tetrahedron per step [ns] (benchmarks/tet_speed.json)."""
ALPHA = PAPER_FIG6["alpha_per_s"]
N_OUTPUTS = 400


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--size-mm", type=float, default=2.8)
    p.add_argument("--t-end-s", type=float, default=0.05)
    p.add_argument("--estimate-only", action="store_true")
    args = p.parse_args()
    t0 = time.perf_counter()
    mesh = detailed_model(1e-3 * args.size_mm)
    full = finger_impulse_model(mesh=mesh)
    dt = TSSFAC * critical_time_step(full.fea_model(ALPHA))
    steps = int(np.ceil(args.t_end_s / dt))
    fig = {"size_mm": args.size_mm, "cone_radius_m": DM_CONE_RADIUS, "rib_thickness_m": DM_RIB_THICKNESS,
           "nodes": mesh.n_nodes, "elements": mesh.n_elements, "mesh_wall_s": round(time.perf_counter() - t0, 1),
           "dt_us": dt * 1e6, "t_end_s": args.t_end_s, "steps": steps,
           "estimated_wall_s": round(steps * mesh.n_elements * TET10_NS_PER_ELEMENT_CYCLE * 1e-9, 0),
           "python": platform.python_version(), "machine": platform.machine()}
    report_figures(fig, OUT)
    if args.estimate_only:
        return
    t0 = time.perf_counter()
    rom = reduce_impulse_model(full, n_modes=6, alpha=ALPHA)
    fig["rom_wall_s"] = round(time.perf_counter() - t0, 1)
    res = full.run(ALPHA, args.t_end_s, N_OUTPUTS)
    t, y_fe = res.tip_signal()
    y_rom = rom.run(ALPHA, args.t_end_s, N_OUTPUTS).tip_signal()[1]
    fitted = fit_to_response(rom.rom, t, y_fe, force_N=full.force_N, duration_s=full.duration_s)
    fig.update({"fe_wall_s": round(res.summary["wall_time_s"], 1), "fe_steps": res.summary["steps"],
                "fe_ns_per_element_cycle": round(res.summary["ns_per_element_cycle"], 1),
                "fe_peak_tip_uy_m": float(y_fe.max()),
                "fe_peak_von_mises_Pa": float(res.history.max_von_mises_Pa.max()),
                "rom_peak_tip_uy_m": float(y_rom.max()), "rom_nrmse": nrmse(y_rom, y_fe),
                "fitted_rom_nrmse": fitted.nrmse_after, "fe_warnings": res.summary["warnings"]})
    report_figures(fig, OUT)
    sm = finger_impulse_model(mesh=sm_a(length_in=4.5)).run(ALPHA, 0.2, N_OUTPUTS)
    t_sm, y_sm = sm.tip_signal()
    fitted_model = ModalImpulseModel(fitted.rom, full.force_N, full.duration_s)
    match = match_alpha(fitted_model, t_sm, y_sm, bounds_per_s=(100.0, 600.0), t_end_s=0.2, n_outputs=N_OUTPUTS)
    cmp = detailed_model_comparison(mesh)
    fig.update({"sm_a_fe_peak_tip_uy_m": float(y_sm.max()),
                "sm_a_fe_peak_von_mises_Pa": float(sm.history.max_von_mises_Pa.max()),
                "sm_a_fe_wall_s": round(sm.summary["wall_time_s"], 1),
                "fitted_rom_matching_alpha_per_s": match.alpha_per_s,
                "fitted_rom_matching_relative_rms": match.relative_rms_error,
                "rom_matching_alpha_per_s": cmp.match.alpha_per_s,
                "paper_matching_alpha_per_s": PAPER_FIG6["dm_matching_alpha_per_s"],
                "rom_dm_under_damped_at_180": cmp.dm_under_damped,
                "rom_sm_a_under_damped_at_180": cmp.sm_a_under_damped,
                "quasi_static_peak_von_mises_Pa": cmp.peak_stress_Pa, "omega1_rad_s": cmp.omega1_rad_s,
                "total_wall_s": round(time.perf_counter() - t0, 1)})
    report_figures(fig, OUT)


if __name__ == "__main__":
    main()
