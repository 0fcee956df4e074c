"""alpha_cr of the detailed model DM (2.8 mm, the module's constants) on its 6-mode modal
ROM: the CCEDI bisection of :func:`ccedi.rom.finger_identification.finger_alpha_cr` from
2 omega_1, beside the paper's figure (the DM needs alpha = 260 1/s for an over-damped
response like SM-A's at 180) and SM-A's alpha_cr.

Prints and writes validation/dm_alpha_cr.json. Run: ``.venv/bin/python validation/dm_alpha_cr.py``
(84 s here: meshing, the modal solve and seven ROM runs).
"""
import time
from pathlib import Path

from ccedi.fea.cases.studies import finger_impulse_model
from ccedi.fea.mesh.gmsh_fingers import detailed_model
from ccedi.outputs import report_figures
from ccedi.rom.finger_identification import finger_alpha_cr
from ccedi.rom.modal import reduce_impulse_model

OUT = Path(__file__).with_suffix(".json")
PAPER_DM_OVERDAMPED_ALPHA = 260.0


def main():
    t0 = time.perf_counter()
    dm = detailed_model()
    rom = reduce_impulse_model(finger_impulse_model(mesh=dm), n_modes=6, alpha=180.0)
    crit, omega1 = finger_alpha_cr(mesh=dm, model=rom)
    report_figures({"model": "DM 2.8 mm, 6-mode modal ROM, 1 N for 10 ms", "nodes": dm.n_nodes,
            "alpha_cr_per_s": crit.alpha_cr_per_s, "bracket_per_s": list(crit.bracket_per_s), "runs": crit.n_runs,
            "omega1_rad_s": omega1, "two_omega1_per_s": 2.0 * omega1,
            "paper_overdamped_alpha_per_s": PAPER_DM_OVERDAMPED_ALPHA,
            "relative_to_paper": crit.alpha_cr_per_s / PAPER_DM_OVERDAMPED_ALPHA - 1.0,
            "wall_time_s": round(time.perf_counter() - t0, 1)}, OUT)


if __name__ == "__main__":
    main()
