"""Export meshes and results to VTU (meshio) for ParaView.

Point data ``displacement_m`` [m]; cell data ``von_mises_Pa`` [Pa]. Cells by element type:
VTK ``hexahedron``, ``tetra`` and ``tetra10`` (quadratic tetrahedron, the node order of
:class:`ccedi.fea.mesh.Mesh`). A time series is a set of VTU files plus a ``.pvd`` collection
that ParaView opens as one animation.
"""
from pathlib import Path

import meshio

from ccedi.fea.elements.hex8 import deformation_gradient
from ccedi.fea.elements.tetra import deformation_gradients
from ccedi.fea.material import cauchy_von_mises
from ccedi.fea.model import Model
from ccedi.fea.solvers.explicit import RunResult
from ccedi.outputs import atomic_write, write_text

VTK_CELL_TYPES = {"hex8": "hexahedron", "tet4": "tetra", "tet10": "tetra10"}
"""meshio (VTK) cell type of each ccedi element type."""


def cell_blocks(model: Model, x):
    """The model's solid cells by type with each cell's von Mises stress at positions ``x``.

    Parameters
    ----------
    model : Model
        The model (hexahedra, 4- and 10-node tetrahedra).
    x : numpy.ndarray
        Nodal positions (n, 3) [m].

    Returns
    -------
    list of tuple
        ``(meshio cell type, connectivity, von Mises [Pa] per cell)`` for each element type
        present: a hexahedron's and a 4-node tetrahedron's one stress, the largest of a
        10-node tetrahedron's four integration points.
    """
    mesh, mat = model.mesh, model.material
    blocks = []
    if len(mesh.hexes):
        F = deformation_gradient(x[mesh.hexes], model.geometry)
        blocks.append((VTK_CELL_TYPES["hex8"], mesh.hexes, cauchy_von_mises(F, mat.mu, mat.lam)))
    if len(mesh.tets4):
        F = deformation_gradients(x, model.tet4.tets, model.tet4.grad[:, None]).reshape(-1, 3, 3)
        blocks.append((VTK_CELL_TYPES["tet4"], mesh.tets4, cauchy_von_mises(F, mat.mu, mat.lam)))
    if len(mesh.tets10):
        F = deformation_gradients(x, model.tet10.tets, model.tet10.grad).reshape(-1, 3, 3)
        vm = cauchy_von_mises(F, mat.mu, mat.lam).reshape(len(mesh.tets10), -1).max(axis=1)
        blocks.append((VTK_CELL_TYPES["tet10"], mesh.tets10, vm))
    return blocks


def write_vtu(path, model: Model, x=None):
    """Write the mesh at positions ``x`` as a VTU file for ParaView.

    Point data ``displacement_m`` = x - X [m]; cell data ``von_mises_Pa``, the von Mises
    stress of the neo-Hookean Cauchy stress [Pa] (:func:`cell_blocks`). Parent directories
    are created.

    Parameters
    ----------
    path : str or pathlib.Path
        Output file (``.vtu``).
    model : Model
        The model whose mesh, element geometry and material are written.
    x : numpy.ndarray, optional
        Nodal positions (n, 3) [m]. Default: the reference positions (zero displacement).

    Returns
    -------
    pathlib.Path
        The path written.
    """
    mesh = model.mesh
    x = mesh.nodes if x is None else x
    blocks = cell_blocks(model, x)
    out = meshio.Mesh(points=x, cells=[(kind, cells) for kind, cells, _ in blocks],
                      point_data={"displacement_m": x - mesh.nodes},
                      cell_data={"von_mises_Pa": [vm for _, _, vm in blocks]})
    return atomic_write(path, lambda tmp: meshio.write(tmp, out, file_format="vtu"))


def write_series(directory, model: Model, result: RunResult, *, stem="frame"):
    """Write every snapshot of ``result`` as VTU plus a ``<stem>.pvd`` collection.

    ParaView opens the ``.pvd`` file as one animation, each VTU file tagged with its time.

    Parameters
    ----------
    directory : str or pathlib.Path
        Output directory (created if missing).
    model : Model
        The model that produced ``result``.
    result : RunResult
        Explicit run whose ``snapshots`` ((t [s], x (n, 3) [m]) pairs) are written.
    stem : str, optional
        File name stem: ``<stem>_00000.vtu``, ... and ``<stem>.pvd``. Default ``"frame"``.

    Returns
    -------
    pathlib.Path
        The path of the ``.pvd`` collection.
    """
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    entries = []
    for i, (t, x) in enumerate(result.snapshots):
        name = f"{stem}_{i:05d}.vtu"
        write_vtu(directory / name, model, x)
        entries.append(f'    <DataSet timestep="{t:.9g}" file="{name}"/>')
    return write_text(directory / f"{stem}.pvd",
                      '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
                      + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n")
