"""Export meshes and results to VTU (meshio) for ParaView.

Point data ``displacement_m`` [m]; cell data ``von_mises_Pa`` [Pa]. A time series is a
set of VTU files plus a ``.pvd`` collection that ParaView opens as one animation.
"""
from pathlib import Path

import meshio
import numpy as np

from .explicit import RunResult
from .hex8 import deformation_gradient
from .material import cauchy_von_mises
from .model import Model


def write_vtu(path, model: Model, x=None):
    """Write the mesh at positions x (default: reference) with displacement and von Mises stress."""
    mesh = model.mesh
    x = mesh.nodes if x is None else x
    F = deformation_gradient(x[mesh.hexes], model.geometry)
    vm = cauchy_von_mises(F, model.material.mu, model.material.lam)
    out = meshio.Mesh(points=x, cells=[("hexahedron", mesh.hexes)],
                      point_data={"displacement_m": x - mesh.nodes},
                      cell_data={"von_mises_Pa": [vm]})
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    meshio.write(path, out)
    return path


def write_series(directory, model: Model, result: RunResult, stem="frame"):
    """Write every snapshot of ``result`` as VTU plus ``<stem>.pvd``; returns the pvd path."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    entries = []
    for i, (t, x) in enumerate(result.snapshots):
        name = f"{stem}_{i:05d}.vtu"
        write_vtu(directory / name, model, x)
        entries.append(f'    <DataSet timestep="{t:.9g}" file="{name}"/>')
    pvd = directory / f"{stem}.pvd"
    pvd.write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
                   + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n")
    return pvd
