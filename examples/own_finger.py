"""Your own finger, from a mesh file to the numbers a gripper designer starts from.

A tapered finger with a hole, written by Gmsh here as a stand-in for the designer's CAD
export (physical groups ``clamp`` at the root and ``tip``), is read as any mesh file is,
then: its Table 1 row (nodes, elements, stable time step, tip stiffness at 1 N and 2 N, first
natural frequency) and its critical damping alpha_cr, found by the CCEDI bisection on the
finger's modal reduced model. ``ccedi study --config`` and ``ccedi design --config`` run
the same finger from a TOML file (``[finger] mesh``).

Run: ``.venv/bin/python examples/own_finger.py [--element-size-mm 8]`` (about a minute).
"""
import argparse
import tempfile
from pathlib import Path

from ccedi.fea.cases.studies import finger_impulse_model, table1_row
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh.gmsh_fingers import write_tapered_finger
from ccedi.fea.mesh.readers import read_finger_mesh
from ccedi.rom.ccedi import critical_alpha
from ccedi.rom.finger_identification import finger_omega1, run_length_s
from ccedi.rom.modal import reduce_impulse_model


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--element-size-mm", type=float, default=8.0, help="Gmsh element size [mm]")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "my_finger.msh"
        write_tapered_finger(path, 1e-3 * args.element_size_mm, order=1)      # the designer's CAD export
        mesh = read_finger_mesh(path, clamp="clamp", tip="tip")
    row = table1_row(mesh, RUBBER, stiffness=True, omega1=True)
    print(f"mesh: {row['nodes']} nodes, {row['elements']} {row['element_type']} elements, "
          f"stable step {row['dt_us']:.3g} us")
    print(f"tip stiffness {row['stiffness_N_per_m']:.4g} N/m, first natural frequency "
          f"{row['omega1_rad_s']:.4g} rad/s")
    omega1 = finger_omega1(mesh=mesh, material=RUBBER)
    rom = reduce_impulse_model(finger_impulse_model(mesh=mesh, material=RUBBER), n_modes=6)
    crit = critical_alpha(rom, 2.0 * omega1, run_length_s(0.01, omega1), rtol=0.02)
    print(f"alpha_cr = {crit.alpha_cr_per_s:.4g} 1/s ({crit.n_runs} runs of the modal ROM; "
          f"2 omega_1 = {2.0 * omega1:.4g} 1/s)")


if __name__ == "__main__":
    main()
