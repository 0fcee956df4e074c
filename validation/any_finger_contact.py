"""An imported finger that is not a prism on the drum: energy balance and cost of the contact run.

The tapered finger with a hole (:func:`ccedi.fea.mesh.gmsh_fingers.write_tapered_finger`, written
to a Gmsh file and read back as an imported mesh), 4-node and 10-node tetrahedra at a coarse
size, goes on the drum (``DrumSetup(finger=mesh)``) and sweeps over the object at
alpha = 180 1/s with global damping. The initial angle puts the undeformed finger on the
object 20 ms after the start (:func:`ccedi.fea.contact.drum.first_contact_angle`), so that
``T_END_S`` covers the approach, the contact and the sliding; the object stress is off
(its static solves are not what is measured). Prints and writes to
validation/any_finger_contact.json, per element type: nodes, elements, steps, wall time [s],
ns per element-cycle, contact start and end [s], peak force [N], energy balance error,
validity warnings.

Run: ``.venv/bin/python validation/any_finger_contact.py``.
"""
import platform
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

from ccedi.fea.contact.drum import DrumSetup, contact_run, contact_summary, first_contact_angle
from ccedi.fea.mesh.gmsh_fingers import write_tapered_finger
from ccedi.fea.mesh.readers import read_finger_mesh
from ccedi.outputs import report_figures

OUT = Path(__file__).with_suffix(".json")
SIZE_M = 0.012
LEAD_S = 0.02
T_END_S = 0.3
ALPHA = 180.0


def main():
    figures = {"model": f"tapered finger with a hole, {1e3 * SIZE_M:g} mm tetrahedra, on the drum, alpha "
                        f"{ALPHA:g} 1/s, global damping, first touch {LEAD_S:g} s, {T_END_S:g} s simulated",
               "python": sys.version.split()[0], "machine": platform.machine()}
    with tempfile.TemporaryDirectory() as tmp:
        for kind, order in (("tet4", 1), ("tet10", 2)):
            path = Path(tmp) / f"finger_{kind}.msh"
            write_tapered_finger(path, SIZE_M, order=order)
            mesh = read_finger_mesh(path, clamp="clamp", tip="tip")
            setup = DrumSetup(finger=mesh, theta0_rad=0.0)
            setup = replace(setup, theta0_rad=first_contact_angle(setup) - setup.omega_rad_s * LEAD_S)
            contact_run(setup, ALPHA, t_end_s=1e-4, n_outputs=1, object_stress=False)    # compile outside the timing
            result, model = contact_run(setup, ALPHA, t_end_s=T_END_S, n_outputs=300, progress=True,
                                        object_stress=False)
            s = contact_summary(setup, result, model)
            figures.update({f"{kind}_{k}": v for k, v in {
                "nodes": mesh.n_nodes, "elements": mesh.n_elements, "steps": result.summary["steps"],
                "wall_time_s": round(result.summary["wall_time_s"], 2),
                "ns_per_element_cycle": round(result.summary["ns_per_element_cycle"], 1),
                "contact_start_s": s["contact_start_s"], "contact_end_s": s["contact_end_s"],
                "peak_reaction_force_N": round(s["peak_reaction_force_N"], 4),
                "energy_balance_error": s["energy_balance_error"], "warnings": s["warnings"]}.items()})
    report_figures(figures, OUT)


if __name__ == "__main__":
    main()
