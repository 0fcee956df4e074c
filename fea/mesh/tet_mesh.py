"""Tetrahedral meshes made from hexahedral ones: each hexahedron split into 6 tetrahedra,
and 4-node tetrahedra raised to 10-node ones by mid-edge nodes.

The split cuts every hexahedron along its diagonal 0-6 into the 6 tetrahedra around it
(Kuhn's triangulation); on a structured mesh whose hexahedra share one local orientation
(such as :func:`ccedi.fea.mesh.elliptical_cantilever`) the face diagonals of neighbours
match, so the tetrahedral mesh is conforming.
"""
import numpy as np

from ccedi.fea.elements.tetra import corner_volume
from ccedi.fea.mesh import Mesh

KUHN_TETS = np.array([[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]])
"""The 6 tetrahedra of a hexahedron around its diagonal 0-6 (local node ids)."""
TET10_EDGES = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])
"""Corner pairs of the mid-edge nodes 4-9 of the 10-node tetrahedron (VTK order)."""


def split_hexes(mesh):
    """The mesh with every hexahedron split into 6 four-node tetrahedra (same nodes).

    Parameters
    ----------
    mesh : Mesh
        A mesh of hexahedra.

    Returns
    -------
    Mesh
        Same nodes and node sets, ``tets4`` of 6 per hexahedron, positively oriented.
    """
    tets = mesh.hexes[:, KUHN_TETS].reshape(-1, 4)
    flip = corner_volume(mesh.nodes[tets]) < 0.0
    tets[flip] = tets[flip][:, [0, 2, 1, 3]]
    return Mesh(nodes=mesh.nodes, node_sets=dict(mesh.node_sets), tets4=tets)


def quadratic_tets(mesh):
    """The 10-node tetrahedral mesh of a 4-node one: a node at the middle of every edge.

    A mid-edge node joins a node set when both ends of its edge belong to it.

    Parameters
    ----------
    mesh : Mesh
        A mesh of 4-node tetrahedra.

    Returns
    -------
    Mesh
        The corner nodes (same ids) followed by the mid-edge nodes; ``tets10``.
    """
    n = mesh.n_nodes
    edges = np.sort(mesh.tets4[:, TET10_EDGES].reshape(-1, 2), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    nodes = np.vstack([mesh.nodes, 0.5 * (mesh.nodes[unique[:, 0]] + mesh.nodes[unique[:, 1]])])
    tets10 = np.hstack([mesh.tets4, n + inverse.reshape(-1, 6)])
    node_sets = {}
    for name, ids in mesh.node_sets.items():
        member = np.zeros(n, dtype=bool)
        member[ids] = True
        mids = n + np.flatnonzero(member[unique[:, 0]] & member[unique[:, 1]])
        node_sets[name] = np.concatenate([np.asarray(ids, dtype=np.int64), mids])
    return Mesh(nodes=nodes, node_sets=node_sets, tets10=tets10)


def box_cantilever(length_m, width_m, height_m, *, nx, ny, nz):
    """Hexahedral mesh of a rectangular prism along +z, root face at z = 0.

    The section spans x in [-width/2, width/2] and y in [-height/2, height/2]; node sets
    ``root`` (z = 0) and ``tip`` (z = length).

    Parameters
    ----------
    length_m : float
        Length along z [m].
    width_m : float
        Width along x [m].
    height_m : float
        Height along y [m].
    nx : int
        Elements along x, >= 1.
    ny : int
        Elements along y, >= 1.
    nz : int
        Elements along z, >= 1.

    Returns
    -------
    Mesh
        (nx+1)(ny+1)(nz+1) nodes and nx ny nz hexahedra.
    """
    x = np.linspace(-width_m / 2, width_m / 2, nx + 1)
    y = np.linspace(-height_m / 2, height_m / 2, ny + 1)
    z = np.linspace(0.0, length_m, nz + 1)
    Z, Y, X = np.meshgrid(z, y, x, indexing="ij")
    nodes = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
    row, layer = nx + 1, (nx + 1) * (ny + 1)
    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    base = (k * layer + j * row + i).ravel()
    quad = np.array([0, 1, row + 1, row])
    hexes = np.concatenate([base[:, None] + quad, base[:, None] + quad + layer], axis=1)
    ids = np.arange(len(nodes))
    return Mesh(nodes=nodes, hexes=hexes, node_sets={"root": ids[nodes[:, 2] == 0.0],
                                                     "tip": ids[nodes[:, 2] == z[-1]]})
