"""Sparse solves with the symmetric tangent stiffness, factorised once and reused.

The tangent of a hyperelastic finger on its free DOFs is symmetric, and positive definite
away from buckling; the static solves (:mod:`ccedi.fea.solvers.static`) and the
shift-invert eigen-solves (:mod:`ccedi.fea.solvers.modal`) factorise it and then solve
with the factors, several times. Two libraries:

* **PARDISO** (Intel oneMKL, through ``pypardiso``), in its symmetric positive-definite
  mode (a sparse Cholesky on the upper triangle), when ``pypardiso`` is installed
  (``pip install pypardiso``: MKL for x86-64, several hundred MB); measured on SM-C's
  22 404-DOF tangent: 0.80 s to factorise against SuperLU's 1.29 s (same machine, under
  load; benchmarks/static_speed.py);
* **SuperLU** (scipy), always there, in its symmetric mode (diagonal pivots, the column
  ordering applied to both sides: 1.29 s against 1.63 s in its general mode on SM-C,
  the solution the same within 4e-11).

:data:`SOLVER` says which one a process uses; ``CCEDI_SPARSE_SOLVER=superlu`` forces
SuperLU (for comparisons).
"""
import os

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

try:                                   # optional: PARDISO when installed, else SuperLU
    import pypardiso
except ImportError:                    # pragma: no cover - depends on the installation
    pypardiso = None

SOLVER_ENV = "CCEDI_SPARSE_SOLVER"
"""Environment variable that forces a solver: ``superlu`` or ``pardiso``."""

SOLVERS = ("pardiso", "superlu")
"""The solvers known, the preferred first."""


def _solver():
    """The solver of this process: the environment's choice, else PARDISO if installed."""
    wanted = os.environ.get(SOLVER_ENV, "").strip().lower()
    if wanted == "superlu" or pypardiso is None:
        return "superlu"
    return "pardiso"


SOLVER = _solver()
"""The sparse solver this process uses, ``"pardiso"`` or ``"superlu"``."""


class Factorization:
    """The factors of a symmetric (positive-definite) sparse matrix, to solve with.

    Parameters
    ----------
    K : scipy.sparse matrix
        Square and symmetric, (n, n).
    solver : {"pardiso", "superlu"}, optional
        Default :data:`SOLVER`.

    Raises
    ------
    ValueError
        ``K`` not square, or an unknown solver.
    """

    def __init__(self, K, solver=None):
        solver = SOLVER if solver is None else solver
        if solver not in SOLVERS or (solver == "pardiso" and pypardiso is None):
            raise ValueError(f"solver = {solver!r}: must be one of {', '.join(SOLVERS)} (pardiso needs pypardiso)")
        if K.shape[0] != K.shape[1]:
            raise ValueError(f"K must be square, got shape {K.shape}")
        self.solver = solver
        self.shape = K.shape
        if solver == "pardiso":
            self._upper = sp.triu(K, format="csr")
            self._pardiso = pypardiso.PyPardisoSolver(mtype=2)
            self._pardiso.factorize(self._upper)
        else:
            self._lu = spla.splu(sp.csc_matrix(K), permc_spec="COLAMD", diag_pivot_thresh=0.0,
                                 options={"SymmetricMode": True})

    def solve(self, b):
        """``K^-1 b``.

        Parameters
        ----------
        b : numpy.ndarray
            Right-hand side(s), (n,) or (n, k).

        Returns
        -------
        numpy.ndarray
            The solution, shaped as ``b``.
        """
        b = np.asarray(b, dtype=float)
        if self.solver == "pardiso":
            return np.asarray(self._pardiso.solve(self._upper, b)).reshape(b.shape)
        return self._lu.solve(b)

    def operator(self):
        """The inverse as a linear operator (the OPinv of a shift-invert eigen-solve).

        Returns
        -------
        scipy.sparse.linalg.LinearOperator
        """
        return spla.LinearOperator(self.shape, matvec=self.solve, dtype=float)
