"""Assembly on a kept sparsity pattern against scipy's COO sum of the same entries."""
import numpy as np
import pytest
import scipy.sparse as sp

from ccedi.fea.elements.assembly import assemble


def coo_sum(element_matrices, conn, n_nodes):
    """The reference: every entry placed at its DOFs and duplicates summed by scipy."""
    e, nn = conn.shape
    dofs = (3 * conn[:, :, None] + np.arange(3)).reshape(e, 3 * nn)
    rows = np.repeat(dofs, 3 * nn, axis=1).ravel()
    cols = np.tile(dofs, (1, 3 * nn)).ravel()
    return sp.csr_matrix((element_matrices.ravel(), (rows, cols)), shape=(3 * n_nodes, 3 * n_nodes))


@pytest.mark.parametrize("seed, n_nodes, nn, e", [(0, 12, 4, 9), (1, 40, 8, 30), (2, 25, 10, 6), (3, 300, 4, 5)])
def test_assembly_equals_the_coo_sum(seed, n_nodes, nn, e):
    """Random connectivities (shared nodes, nodes in no element): the same matrix as scipy's
    COO sum to round-off, in canonical form; a second assembly on the kept pattern with
    other values is right too."""
    rng = np.random.default_rng(seed)
    conn = np.array([rng.choice(n_nodes, nn, replace=False) for _ in range(e)])
    for _ in range(2):
        Ke = rng.standard_normal((e, nn, 3, nn, 3))
        K, ref = assemble(Ke, conn, n_nodes), coo_sum(Ke, conn, n_nodes)
        assert K.shape == ref.shape
        assert abs(K - ref).max() <= 1e-13 * abs(ref).max()
        assert np.all(np.diff(K.indices[K.indptr[0]:K.indptr[1]]) > 0)
        copy = K.copy()
        copy.sum_duplicates()
        assert copy.nnz == K.nnz                       # no duplicates left in the pattern


def test_the_pattern_follows_the_connectivity():
    """Two meshes with the same sizes but other connectivity are not mixed up."""
    Ke = np.ones((2, 2, 3, 2, 3))
    a = assemble(Ke, np.array([[0, 1], [1, 2]]), 4).toarray()
    b = assemble(Ke, np.array([[0, 3], [3, 2]]), 4).toarray()
    assert a[0:3, 3:6].sum() == 9.0 and a[0:3, 9:12].sum() == 0.0
    assert b[0:3, 9:12].sum() == 9.0 and b[0:3, 3:6].sum() == 0.0
