"""Craig-Bampton reduction (the linear core of the superelement chain).

Split the free degrees of freedom of a linearised FE model into boundary DOFs b (kept
physically: the root/drum interface, the contact-side surface nodes) and interior DOFs i.
The interior motion is spanned by the static constraint modes and the first n
fixed-interface normal modes::

    u_i = Psi u_b + Phi q,     Psi = -K_ii^-1 K_ib,     K_ii Phi = M_ii Phi Omega^2

    [u_i]   [Psi  Phi] [u_b]                     K_r = T^T K T,  M_r = T^T M T
    [u_b] = [ I    0 ] [ q ]  = T [u_b; q]        f_r = T^T f

With n = 0 this is Guyan static condensation, exact for static loads on the boundary;
with every interior mode kept it is exact for all frequencies.
"""
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.linalg import eigh

from ccedi.errors import InputError
from ccedi.fea.model import Model
from ccedi.fea.solvers.static import free_dofs, tangent_stiffness


def fe_matrices(model: Model, x=None):
    """Tangent stiffness and lumped mass of a model on its free DOFs.

    Parameters
    ----------
    model : Model
        The finite element model (solid elements contribute to K).
    x : numpy.ndarray, optional
        Nodal positions (n, 3) [m] at which K is taken. Default: the reference positions.

    Returns
    -------
    K : scipy.sparse.csc_matrix
        Tangent stiffness on the free DOFs, (n_free, n_free) [N/m].
    M : scipy.sparse.csc_matrix
        Diagonal lumped mass on the free DOFs, (n_free, n_free) [kg].
    dofs : numpy.ndarray
        Global DOF index (node * 3 + direction) of each row, sorted.

    Raises
    ------
    SolverError
        If an element is inverted at ``x``.
    """
    dofs = free_dofs(model)
    K = tangent_stiffness(model, x)[dofs][:, dofs].tocsc()
    M = sp.diags(np.repeat(model.mass, 3)[dofs]).tocsc()
    return K, M, dofs


@dataclass(frozen=True)
class CraigBampton:
    """A Craig-Bampton reduced model in coordinates z = [u_b (n_b), q (n_modes)].

    Parameters
    ----------
    K_r : numpy.ndarray
        Reduced stiffness T^T K T, dense, symmetric, (n_r, n_r) [N/m in u_b].
    M_r : numpy.ndarray
        Reduced mass T^T M T, dense, symmetric, (n_r, n_r) [kg in u_b].
    T : numpy.ndarray
        Transformation to the free DOFs, (n_free, n_r), u_free = T z.
    boundary_dofs : numpy.ndarray
        Global DOF ids of the boundary coordinates u_b (sorted, unique).
    free_dofs : numpy.ndarray
        Global DOF ids of the free DOFs (the rows of T).
    interface_omega_rad_s : numpy.ndarray
        Fixed-interface natural frequencies of the kept modes, (n_modes,) [rad/s].
    """

    K_r: np.ndarray
    M_r: np.ndarray
    T: np.ndarray
    boundary_dofs: np.ndarray
    free_dofs: np.ndarray
    interface_omega_rad_s: np.ndarray

    def expand(self, z):
        """Free-DOF displacements from reduced coordinates, u = T z.

        Parameters
        ----------
        z : numpy.ndarray
            Reduced coordinates, (n_r,) (or (n_r, k) for k states).

        Returns
        -------
        numpy.ndarray
            Displacements on the free DOFs, (n_free,) [m].
        """
        return self.T @ z

    def reduce_force(self, f_free):
        """Reduced load T^T f of a free-DOF load vector.

        Parameters
        ----------
        f_free : numpy.ndarray
            Load on the free DOFs, (n_free,) [N].

        Returns
        -------
        numpy.ndarray
            Reduced load, (n_r,).
        """
        return self.T.T @ f_free


def craig_bampton(K, M, dofs, *, boundary_dofs, n_modes):
    """Craig-Bampton reduction of (K, M) keeping ``boundary_dofs`` and ``n_modes`` modes.

    Constraint modes Psi = -K_ii^-1 K_ib and the ``n_modes`` lowest fixed-interface modes
    of K_ii Phi = M_ii Phi Omega^2 span the interior (module docstring); ``n_modes = 0``
    is Guyan condensation.

    Parameters
    ----------
    K : scipy.sparse matrix or numpy.ndarray
        Stiffness on the free DOFs, (n_free, n_free) [N/m] (from :func:`fe_matrices`).
    M : scipy.sparse matrix or numpy.ndarray
        Mass on the free DOFs, (n_free, n_free) [kg].
    dofs : numpy.ndarray
        Sorted global DOF ids of the rows of K and M.
    boundary_dofs : array_like
        Global DOF ids kept as physical coordinates; each must be in ``dofs``.
    n_modes : int
        Fixed-interface modes kept, an integer from 0 to the number of interior DOFs.

    Returns
    -------
    CraigBampton
        Reduced matrices, transformation and interface frequencies.

    Raises
    ------
    InputError
        If a boundary DOF is not a free DOF, or ``n_modes`` is out of range.
    """
    boundary_dofs = np.unique(np.asarray(boundary_dofs, dtype=np.int64))
    pos = np.searchsorted(dofs, boundary_dofs)
    if np.any(pos >= len(dofs)) or np.any(dofs[np.minimum(pos, len(dofs) - 1)] != boundary_dofs):
        raise InputError("boundary_dofs must be free degrees of freedom of the model")
    b = pos
    i = np.setdiff1d(np.arange(len(dofs)), b)
    if int(n_modes) != n_modes or not 0 <= n_modes <= len(i):
        raise InputError(f"n_modes must be an integer in 0..{len(i)}, got {n_modes!r}")
    K, M = sp.csc_matrix(K), sp.csc_matrix(M)
    Kii, Kib, Mii = K[i][:, i].tocsc(), K[i][:, b].tocsc(), M[i][:, i].tocsc()
    psi = -spla.splu(Kii).solve(Kib.toarray())
    if n_modes == 0:
        omega, phi = np.zeros(0), np.zeros((len(i), 0))
    elif n_modes >= len(i) - 1:
        w2, phi = eigh(Kii.toarray(), Mii.toarray(), subset_by_index=[0, int(n_modes) - 1])
        omega = np.sqrt(np.clip(w2, 0.0, None))
    else:
        w2, phi = spla.eigsh(Kii, k=int(n_modes), M=Mii, sigma=0.0, which="LM")
        order = np.argsort(w2)
        omega, phi = np.sqrt(np.clip(w2[order], 0.0, None)), phi[:, order]
    n_b = len(b)
    T = np.zeros((len(dofs), n_b + len(omega)))
    T[i, :n_b] = psi
    T[i, n_b:] = phi
    T[b, :n_b] = np.eye(n_b)
    K_r = T.T @ (K @ T)
    M_r = T.T @ (M @ T)
    return CraigBampton(K_r=0.5 * (K_r + K_r.T), M_r=0.5 * (M_r + M_r.T), T=T, boundary_dofs=boundary_dofs,
                        free_dofs=dofs, interface_omega_rad_s=omega)
