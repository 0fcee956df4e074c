"""Sparse solves with the symmetric tangent stiffness, factorised once and reused.

The tangent of a hyperelastic finger on its free DOFs is symmetric, and positive definite
away from buckling; the static solves (:mod:`ccedi.fea.solvers.static`) and the
shift-invert eigen-solves (:mod:`ccedi.fea.solvers.modal`) factorise it and then solve
with the factors, several times. Two libraries:

* **PARDISO** (Intel oneMKL, through ``pypardiso``, installed with ccedi on x86-64), in
  its real symmetric indefinite mode (an LDL^T with Bunch-Kaufman pivoting on the upper
  triangle): a Newton iterate away from equilibrium can have an indefinite tangent (on
  SM-A at 2 N the first iterates had eigenvalues down to -1.4 N/m), which the
  positive-definite mode refuses (error -4); measured on SM-C's 22 404-DOF tangent:
  0.50 s to factorise against SuperLU's 1.10 s (benchmarks/static_speed.py);
* **SuperLU** (scipy), always there (the fallback where MKL is not, e.g. on ARM), in its
  symmetric mode (diagonal pivots, the column ordering applied to both sides: 1.29 s
  against 1.63 s in its general mode on SM-C, the solution the same within 4e-11).

:data:`SOLVER` says which one a process uses; ``CCEDI_SPARSE_SOLVER=superlu`` forces
SuperLU (for comparisons).
"""
import glob
import os
import sys
import weakref

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ccedi.errors import SolverError


def _mkl_runtime():
    """Path of MKL's runtime library in this environment's lib folder, or None. pypardiso
    otherwise searches the whole environment recursively for it each time a solver is made
    (0.17 s in a 2 GB environment), so the path is found once and handed to it."""
    found = sorted(glob.glob(os.path.join(sys.prefix, "lib", "libmkl_rt.so*")), key=len)
    return found[0] if found else None


if "PYPARDISO_MKL_RT" not in os.environ and (_found := _mkl_runtime()) is not None:
    os.environ["PYPARDISO_MKL_RT"] = _found

try:                                   # optional: PARDISO when installed, else SuperLU
    import pypardiso
except ImportError:                    # pragma: no cover - depends on the installation
    pypardiso = None

SOLVER_ENV = "CCEDI_SPARSE_SOLVER"
"""Environment variable that forces a solver: ``superlu`` or ``pardiso``."""

SINGULAR = "the tangent stiffness is singular: a rigid-body motion is free (check the supports) or the finger buckles"
"""What a factorisation of a singular matrix raises (:class:`ccedi.errors.SolverError`)."""

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
    SolverError
        ``K`` singular (:data:`SINGULAR`).
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
            self._pardiso = pypardiso.PyPardisoSolver(mtype=-2)
            self._own_pardiso()
            try:
                self._pardiso.factorize(self._upper)
            except ValueError as err:                    # an empty row: "Matrix A is singular"
                raise SolverError(f"{SINGULAR} (PARDISO: {err})") from None
            self._check_pivots()
        else:
            try:
                self._lu = spla.splu(sp.csc_matrix(K), permc_spec="COLAMD", diag_pivot_thresh=0.0,
                                     options={"SymmetricMode": True})
            except RuntimeError as err:                  # "Factor is exactly singular"
                raise SolverError(f"{SINGULAR} (SuperLU: {err})") from None

    def _check_pivots(self):
        """PARDISO replaces a pivot too small to divide by (a singular matrix) by a tiny
        one and solves on: its solution is then meaningless, so perturbed pivots fail as
        SuperLU's exactly singular factor does."""
        perturbed = int(self._pardiso.iparm[13])
        if perturbed:
            raise SolverError(f"{SINGULAR} (PARDISO: {perturbed} pivot(s) perturbed)")

    def _own_pardiso(self):
        """MKL keeps a handle's memory until told: it is released when this object goes."""
        self._release = weakref.finalize(self, self._pardiso.free_memory, True)

    def refactorized(self, K):
        """The factors of ``K``, a matrix with this one's sparsity pattern (the tangent at the
        next Newton iterate), reusing this factorisation's analysis where the library keeps
        it apart: PARDISO's fill-reducing ordering and symbolic factorisation, about 45 % of a
        factorisation of SM-C's tangent, are kept and only the numerical factorisation is
        redone; this object's factors are handed over and it can no longer solve. SuperLU,
        or another pattern: a new :class:`Factorization`.

        Parameters
        ----------
        K : scipy.sparse matrix
            Square and symmetric, shape as this one's matrix.

        Returns
        -------
        Factorization

        Raises
        ------
        SolverError
            ``K`` singular (:data:`SINGULAR`).
        """
        upper = sp.triu(K, format="csr") if self.solver == "pardiso" else None
        if (upper is None or self._pardiso is None or upper.shape != self._upper.shape
                or not np.array_equal(upper.indptr, self._upper.indptr)
                or not np.array_equal(upper.indices, self._upper.indices)):
            return type(self)(K, self.solver)
        new = object.__new__(type(self))
        new.solver, new.shape, new._upper = self.solver, self.shape, upper
        self._release.detach()
        new._pardiso, self._pardiso = self._pardiso, None
        new._own_pardiso()
        new._pardiso.factorized_A = (new._pardiso._hash_csr_matrix(upper) if upper.nnz > new._pardiso.size_limit_storage
                                     else upper.copy())
        new._pardiso.set_phase(22)                     # numerical factorisation on the kept analysis
        new._pardiso._call_pardiso(upper, np.zeros((upper.shape[0], 1)))
        new._check_pivots()
        return new

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

        Raises
        ------
        RuntimeError
            The factors were handed over to another object by :meth:`refactorized`.
        """
        b = np.asarray(b, dtype=float)
        if self.solver == "pardiso":
            if self._pardiso is None:
                raise RuntimeError("these factors were handed over by refactorized(); solve with its result")
            return np.asarray(self._pardiso.solve(self._upper, b)).reshape(b.shape)
        return self._lu.solve(b)

    def operator(self):
        """The inverse as a linear operator (the OPinv of a shift-invert eigen-solve).

        Returns
        -------
        scipy.sparse.linalg.LinearOperator
        """
        return spla.LinearOperator(self.shape, matvec=self.solve, dtype=float)
