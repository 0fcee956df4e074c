"""Natural frequencies and mode shapes of the linearised model.

Generalised eigenproblem on the free DOFs, with the tangent stiffness K at the
reference (or a preloaded) state and the lumped mass M::

    K phi = omega^2 M phi                     omega [rad/s]

solved by shift-invert Lanczos (scipy.sparse.linalg.eigsh, sigma = 0, with the factors of
:class:`ccedi.fea.solvers.linear.Factorization`, from a fixed start vector so that the
result is the same in every run), or densely when (nearly) all modes are asked for.
"""
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.linalg import eigh

from ccedi.errors import InputError
from ccedi.fea.model import Model
from ccedi.fea.solvers.linear import Factorization
from ccedi.fea.solvers.static import free_dofs, tangent_stiffness


def natural_frequencies(model: Model, *, n_modes=3, x=None, return_modes=False):
    """Lowest natural frequencies (and mode shapes) of the linearised model.

    Solves K phi = omega^2 M phi on the free DOFs, K the tangent stiffness at ``x`` and
    M the lumped mass; shift-invert Lanczos, or a dense solve when (nearly) all modes
    are asked for.

    Parameters
    ----------
    model : Model
        The finite element model (its fixed nodes are constrained).
    n_modes : int, optional
        Number of modes, an integer from 1 to the number of free DOFs. Default 3.
    x : numpy.ndarray, optional
        Nodal positions (n, 3) [m] at which K is taken (a preloaded state).
        Default: the reference positions.
    return_modes : bool, optional
        Also return the mode shapes. Default False.

    Returns
    -------
    omega : numpy.ndarray
        The ``n_modes`` lowest angular frequencies, ascending, shape (n_modes,) [rad/s].
    modes : numpy.ndarray
        Only with ``return_modes``: mass-normalised mode shapes (3 n, n_modes), DOF
        index node*3 + direction, zero on fixed DOFs.

    Raises
    ------
    InputError
        If ``n_modes`` is not an integer >= 1 or exceeds the number of free DOFs.
    """
    if int(n_modes) != n_modes or n_modes < 1:
        raise InputError(f"n_modes must be an integer >= 1, got {n_modes!r}")
    free = free_dofs(model)
    if n_modes > len(free):
        raise InputError(f"n_modes = {n_modes} exceeds the {len(free)} free degrees of freedom")
    K = tangent_stiffness(model, x)[free][:, free].tocsc()
    M = sp.diags(np.repeat(model.mass, 3)[free]).tocsc()
    if n_modes >= len(free) - 1:                 # all (or nearly all) modes: dense solve
        w2, phi = eigh(K.toarray(), M.toarray(), subset_by_index=[0, int(n_modes) - 1])
    else:
        w2, phi = spla.eigsh(K, k=int(n_modes), M=M, sigma=0.0, which="LM", OPinv=Factorization(K).operator(),
                              v0=np.ones(K.shape[0]))
    order = np.argsort(w2)
    omega = np.sqrt(np.clip(w2[order], 0.0, None))
    if not return_modes:
        return omega
    modes = np.zeros((3 * model.mesh.n_nodes, int(n_modes)))
    modes[free] = phi[:, order]
    return omega, modes
