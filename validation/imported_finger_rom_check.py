"""The contact ROM on an imported tetrahedral finger against its full FEA.

The tapered finger with a transverse hole (:func:`ccedi.fea.mesh.gmsh_fingers.write_tapered_finger`,
4-node tetrahedra of ``SIZE_M``, written as a Gmsh file and read back as an imported
mesh) on the drum with relative damping at the alphas of ``ALPHAS``: the design's ROM
(:func:`ccedi.design.surrogate.rom_factory`: the superelement chain cut at evenly spaced
stations of the tetrahedral mesh) and the full FEA each run until the next object
arrives, and every design output is compared (:func:`ccedi.design.model_error.output_error`:
relative, or at the 5 mm scale for lengths). ~9 min of FEA per alpha on one core of the
2-core AMD VM; the FEA's outputs are cached in ``validation/cache/`` (delete the CSV to
run them again).

Prints and writes ``validation/imported_finger_rom_check.json``: the mesh, the chain
(segments, fitted bending factor), and per alpha both models' outputs and the errors; per
output the largest |error|.

Run: ``.venv/bin/python validation/imported_finger_rom_check.py``.
"""
import json
import platform
import sys
from pathlib import Path

import pandas as pd

from ccedi.design.model_error import output_error
from ccedi.design.outputs import OUTPUTS
from ccedi.design.recheck import full_fea_factory
from ccedi.design.surrogate import rom_factory, run_rom
from ccedi.fea.contact.drum import DrumSetup
from ccedi.fea.mesh.gmsh_fingers import write_tapered_finger
from ccedi.fea.mesh.readers import read_finger_mesh

OUT = Path(__file__).with_suffix(".json")
SIZE_M = 0.008
ALPHAS = (7.5, 60.0, 180.0, 600.0)


def main():
    mesh_path = Path(__file__).resolve().parent / "cache" / f"tapered_tet4_{SIZE_M * 1e3:g}mm.msh"
    mesh_path.parent.mkdir(exist_ok=True)
    write_tapered_finger(mesh_path, SIZE_M, order=1)
    mesh = read_finger_mesh(mesh_path, clamp="clamp", tip="tip")
    setup = DrumSetup(finger=mesh)
    rom = rom_factory(setup)
    points = [(a, setup.finger_length_m) for a in ALPHAS]
    grid_rom = run_rom(setup, points, damping="relative")
    fea_cache = mesh_path.with_name(f"tapered_tet4_{SIZE_M * 1e3:g}mm_fea.csv")
    if fea_cache.exists():
        grid_fea = pd.read_csv(fea_cache)
    else:
        grid_fea = run_rom(setup, points, damping="relative", model_factory=full_fea_factory,
                           progress=lambda i, n: print(f"FEA run {i}/{n}", flush=True))
        grid_fea.to_csv(fea_cache, index=False)
    cases, worst = [], {}
    for (_, r), (_, f) in zip(grid_rom.iterrows(), grid_fea.iterrows()):
        err = {k: output_error(k, r[k], f[k]) for k in OUTPUTS}
        cases.append({"alpha_per_s": float(r["alpha_per_s"]), "rom": {k: float(r[k]) for k in OUTPUTS},
                      "fea": {k: float(f[k]) for k in OUTPUTS}, "error": err,
                      "wall_time_s": {"rom": float(r["wall_time_s"]), "fea": float(f["wall_time_s"])}})
        for k, e in err.items():
            if e is not None:
                worst[k] = max(worst.get(k, 0.0), abs(e))
    figures = {"model": f"tapered finger with a hole, {SIZE_M * 1e3:g} mm 4-node tetrahedra, relative damping",
               "python": sys.version.split()[0], "machine": platform.machine(), "nodes": mesh.n_nodes,
               "elements": mesh.n_elements, "segments": rom.chain.n_segments,
               "stiffness_scale": rom.chain.stiffness_scale, "largest_abs_error": worst, "cases": cases}
    for c in cases:
        print(f"alpha {c['alpha_per_s']:g}: " + ", ".join(f"{k} {v:+.1%}" for k, v in c["error"].items() if v is not None))
    OUT.write_text(json.dumps(figures, indent=2) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
