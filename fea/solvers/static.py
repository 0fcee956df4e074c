"""Consistent tangent stiffness and nonlinear static equilibrium (Newton-Raphson).

Element tangent of the one-point hexahedron (total Lagrangian, :func:`ccedi.fea.elements.hex8.tangent_stiffness`)::

    K_(ki)(lm) = (1/V0) sum_{j,L} b_kj A_ijmL b_lL + d f_hg,ki / d x_lm

with the neo-Hookean elasticity tensor A = dP/dF::

    A_ijmL = mu d_im d_jL + (mu - lam ln J) Finv_Li Finv_jm + lam Finv_ji Finv_Lm

and the exact derivative of the hourglass forces (:func:`ccedi.fea.elements.hex8.hourglass_tangent`), which at
the reference state is ``sum_ab gamma_ak K_hg,(ai)(bm) gamma_bl``.

The tetrahedra add their tangents (:func:`ccedi.fea.elements.tet4.tangent_stiffness`,
:func:`ccedi.fea.elements.tet10.tangent_stiffness`, both :func:`ccedi.fea.elements.tetra.averaged_tangent`).

Bulk viscosity is rate dependent and absent in statics.
"""
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ccedi.errors import InputError, SolverError
from ccedi.fea.elements import hex8, tet4, tet10
from ccedi.fea.elements.hex8 import internal_forces_numpy
from ccedi.fea.elements.hex8_kernels import SolidMaterial
from ccedi.fea.mesh import element_name
from ccedi.fea.model import Model, face_node_weights
from ccedi.fea.solvers.linear import Factorization


def tangent_stiffness(model: Model, x=None):
    """Assembled consistent tangent stiffness dF_int/dx of the solid elements.

    Hexahedra: element tangent and neo-Hookean elasticity tensor as in the module
    docstring; tetrahedra: :func:`ccedi.fea.elements.tetra.averaged_tangent`;
    hourglass stiffness included, bulk viscosity (rate dependent) not. Rods, point
    masses and contact are not included.

    Parameters
    ----------
    model : Model
        The model (solid elements only contribute).
    x : numpy.ndarray, optional
        Nodal positions, shape (n, 3) [m]. Default: the reference positions.

    Returns
    -------
    scipy.sparse.csr_matrix
        K, shape (3 n, 3 n) [N/m], DOF index node*3 + direction, no constraints applied.

    Raises
    ------
    SolverError
        If an element is inverted (J <= 0) at ``x``.
    """
    x = model.mesh.nodes if x is None else x
    K = _tetrahedra_tangent(model, x)
    if not len(model.mesh.hexes):
        return K
    return K + hex8.tangent_stiffness(x, model.mesh.hexes, model.geometry, kappa=model.kappa,
                                      material=model.material)


def _tetrahedra_tangent(model, x):
    """Tangent stiffness (3 n, 3 n) [N/m] of the model's 4- and 10-node tetrahedra at x;
    SolverError naming an inverted element."""
    material = SolidMaterial(*model.solid_constants)
    K = sp.csr_matrix((3 * model.mesh.n_nodes, 3 * model.mesh.n_nodes))
    for name, module, group in (("tet4", tet4, model.tet4), ("tet10", tet10, model.tet10)):
        try:
            K = K + module.tangent_stiffness(x, group, material)
        except ValueError as err:
            raise SolverError(f"{name} {err}") from None
    return K


def internal_force(model: Model, x):
    """Static internal force vector f_int(x) of the solid elements (zero velocity).

    Parameters
    ----------
    model : Model
        The model.
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].

    Returns
    -------
    numpy.ndarray
        Nodal internal forces, shape (n, 3) [N].

    Raises
    ------
    SolverError
        If an element is inverted (J <= 0) at ``x``.
    """
    g, mat = model.geometry, model.material
    f = np.zeros_like(x)
    if len(model.mesh.hexes):
        *_, bad = internal_forces_numpy(x, np.zeros_like(x), model.mesh.hexes, b=g.b, volume=g.volume, gamma=g.gamma,
                                        kappa=model.kappa, length_factor=1.0, mu=mat.mu, lam=mat.lam, rho=mat.rho,
                                        c=mat.wave_speed, f=f)
        if bad >= 0:
            raise SolverError(f"element {bad} inverted (J <= 0)")
    material = SolidMaterial(*model.solid_constants)
    for offset, module, group in ((len(model.mesh.hexes), tet4, model.tet4),
                                  (len(model.mesh.hexes) + len(model.tet4.tets), tet10, model.tet10)):
        *_, bad = module.internal_forces_numpy(x, np.zeros_like(x), group, material, f)
        if bad >= 0:
            raise SolverError(f"{element_name(model.mesh, offset + bad)} inverted (J <= 0)")
    return f


def free_dofs(model: Model):
    """Indices of the unconstrained degrees of freedom.

    Parameters
    ----------
    model : Model
        The model; its ``fixed_nodes`` have all three DOFs constrained.

    Returns
    -------
    numpy.ndarray
        Sorted DOF indices node*3 + direction (direction 0, 1, 2 = x, y, z).
    """
    fixed = np.zeros((model.mesh.n_nodes, 3), dtype=bool)
    fixed[model.fixed_nodes] = True
    return np.flatnonzero(~fixed.ravel())


MIN_LOAD_STEP = 1.0 / 64.0
"""Smallest load increment (fraction of the load) :func:`static_solve` cuts down to."""

CORRECTION_TOLERANCE = 1e-10
"""Relative residual to which a Newton correction is solved by preconditioned conjugate
gradients (:func:`_newton_correction`): far below the Newton tolerance, so the iterations
are those of full Newton."""

PRECONDITIONED_ITERATIONS = {"superlu": 12, "pardiso": 0}
"""Conjugate-gradient iterations allowed with the previous factors before the tangent is
factorised anew (0: a factorisation every Newton iteration, as direct full Newton), per
sparse solver. Worth it where a factorisation costs many solves: with SuperLU on SM-C's
tip stiffness 12 took 41 s (10 factorisations), 6 took 51 s, 20 took 47 s and direct full
Newton 77 s (17), the stiffness the same to 2e-15. PARDISO factorises SM-C's tangent in
about 15 solves' time, and direct full Newton was 2.4 x faster than 12 iterations of reuse
(8.3 s against 20.1 s, benchmarks/static_speed.py)."""


def static_solve(model: Model, f_ext, *, n_increments=2, tol=1e-7, max_iter=30, linear=False):
    """Nonlinear static equilibrium f_int(x) = f_ext by incremental Newton-Raphson.

    The load is applied in ``n_increments`` equal steps. Convergence of a step:
    ||residual|| <= tol ||f_ext||, or a Newton correction smaller than
    tol ||displacement|| (when the residual has reached its round-off floor). A step
    whose Newton iterations invert an element or do not converge is retried from the
    last equilibrium with half the increment, down to :data:`MIN_LOAD_STEP` of the load
    (a large rotation whose linear predictor folds a small element needs it).

    Parameters
    ----------
    model : Model
        The model (fixed nodes stay at their reference positions).
    f_ext : array_like
        External nodal forces, shape (n, 3) [N], finite; forces on fixed DOFs are ignored.
    n_increments : int, optional
        Number of load increments. Default 2.
    tol : float, optional
        Relative convergence tolerance [-]. Default 1e-7.
    max_iter : int, optional
        Newton iterations allowed per increment. Default 30.
    linear : bool, optional
        Solve K0 u = f_ext once instead (small-displacement answer). Default False.

    Returns
    -------
    numpy.ndarray
        Equilibrium nodal positions x, shape (n, 3) [m].

    Raises
    ------
    InputError
        If ``f_ext`` does not have the mesh's node shape (n, 3) or is not finite.
    SolverError
        If an increment of :data:`MIN_LOAD_STEP` of the load still fails (Newton does not
        converge within ``max_iter`` iterations, or an element inverts).
    """
    f_ext = np.asarray(f_ext, dtype=float)
    if f_ext.shape != model.mesh.nodes.shape or not np.all(np.isfinite(f_ext)):
        raise InputError(f"f_ext must be finite with shape {model.mesh.nodes.shape}")
    free = free_dofs(model)
    x = model.mesh.nodes.copy()
    if linear:
        K = tangent_stiffness(model)[free][:, free]
        u = np.zeros(x.size)
        u[free] = Factorization(K).solve(f_ext.ravel()[free])
        return x + u.reshape(x.shape)
    return static_path(model, f_ext, np.arange(1, n_increments + 1) / n_increments, tol=tol, max_iter=max_iter)[-1]


def static_path(model: Model, f_ext, load_factors, *, tol=1e-7, max_iter=30):
    """Nonlinear static equilibria along a load path: f_int(x) = lambda f_ext at each
    ``lambda`` of ``load_factors``, each reached from the one before by Newton-Raphson
    (one increment, halved on failure as in :func:`static_solve`).

    Parameters
    ----------
    model : Model
        The model (fixed nodes stay at their reference positions).
    f_ext : numpy.ndarray
        External nodal forces at load factor 1, shape (n, 3) [N], finite.
    load_factors : sequence of float
        Increasing load factors in (0, 1].
    tol : float, optional
        Relative convergence tolerance [-], of ``f_ext``'s norm. Default 1e-7.
    max_iter : int, optional
        Newton iterations allowed per increment. Default 30.

    Returns
    -------
    list of numpy.ndarray
        The equilibrium nodal positions (n, 3) [m] at each load factor.

    Raises
    ------
    InputError
        Load factors not increasing within (0, 1].
    SolverError
        As :func:`static_solve`.
    """
    factors = np.asarray(load_factors, dtype=float)
    if factors.ndim != 1 or not len(factors) or factors[0] <= 0.0 or factors[-1] > 1.0 or np.any(np.diff(factors) <= 0):
        raise InputError(f"load_factors = {load_factors!r}: must increase within (0, 1]")
    free = free_dofs(model)
    atol = tol * max(np.linalg.norm(f_ext), 1e-300)
    x, load, path = model.mesh.nodes.copy(), 0.0, []
    for stop in factors:
        step = stop - load
        while load < stop:
            target = min(stop, load + step)
            try:
                x = _newton(model, x, target * f_ext, free, atol, tol, max_iter)
                load = target
            except SolverError as err:
                step /= 2.0
                if step < MIN_LOAD_STEP:
                    raise SolverError(f"static solve failed at load factor {target:.3g}: {err}") from None
        path.append(x)
    return path


def _newton(model, x, f, free, atol, tol, max_iter):
    """Newton iterations from x to f_int(x) = f on the ``free`` DOFs (residual below
    ``atol`` [N], or a correction below ``tol`` of the displacement); SolverError if an
    element inverts or ``max_iter`` iterations do not converge.

    Each iteration solves with the tangent at its own state (full Newton), but by
    conjugate gradients preconditioned with the factors of an earlier tangent
    (:func:`_newton_correction`): a factorisation of SM-C's tangent took 3.4 s, a solve
    with its factors 0.04 s, and near the solution the tangent changes little. The
    factors are made anew when the preconditioned iterations do not converge."""
    factors = None
    for _ in range(max_iter):
        r = (f - internal_force(model, x)).ravel()[free]
        if np.linalg.norm(r) <= atol:
            return x
        K = tangent_stiffness(model, x)[free][:, free]
        step, factors = _newton_correction(K, r, factors)
        du = np.zeros(x.size)
        du[free] = step
        x = x + du.reshape(x.shape)
        if np.linalg.norm(du) <= tol * np.linalg.norm(x - model.mesh.nodes):
            return x                       # residual at its round-off floor; displacement converged
    raise SolverError(f"Newton did not converge in {max_iter} iterations")


def _newton_correction(K, r, factors):
    """``K^-1 r`` by conjugate gradients preconditioned with ``factors`` (to
    :data:`CORRECTION_TOLERANCE`, in at most :data:`PRECONDITIONED_ITERATIONS`), else
    directly with new factors of K; returns (the correction, the factors used)."""
    iterations = 0 if factors is None else PRECONDITIONED_ITERATIONS[factors.solver]
    if iterations > 0:
        step, info = spla.cg(K, r, rtol=CORRECTION_TOLERANCE, atol=0.0, maxiter=iterations,
                             M=factors.operator())
        if info == 0:
            return step, factors
    factors = Factorization(K) if factors is None else factors.refactorized(K)
    return factors.solve(r), factors


def tip_deflection(model: Model, force_N, *, direction=1, linear=False):
    """Static tip deflection under a tip force spread uniformly over the tip face.

    Parameters
    ----------
    model : Model
        Model whose mesh has a ``"tip"`` node set.
    force_N : float
        Total tip force along ``direction`` [N].
    direction : int, optional
        0, 1 or 2 (x, y, z) for both the force and the deflection. Default 1 (y, the
        bending direction of the paper's finger).
    linear : bool, optional
        Small-displacement solve instead of the nonlinear one. Default False.

    Returns
    -------
    float
        Area-weighted mean tip displacement along ``direction`` [m].
    """
    deflection, f_ext = _tip_load(model, force_N, direction)
    return deflection(static_solve(model, f_ext, linear=linear))


def _tip_load(model, force_N, direction):
    """A tip force of ``force_N`` [N] along ``direction`` spread over the tip face by its
    node weights: ``(deflection, f_ext)``, ``deflection(x)`` the area-weighted mean tip
    displacement along ``direction`` at positions x [m], f_ext the nodal forces (n, 3) [N]."""
    mesh = model.mesh
    tip = mesh.node_sets["tip"]
    w = face_node_weights(mesh, tip)
    f_ext = np.zeros_like(mesh.nodes)
    f_ext[tip, direction] = w * force_N
    return (lambda x: float(w @ (x[tip, direction] - mesh.nodes[tip, direction]))), f_ext


def tip_stiffness(model: Model, loads_N=(1.0, 2.0), direction=1):
    """Equivalent tip stiffness as in the paper's Table 1.

    The mean of F / delta over the nonlinear static equilibria at the given tip loads, one
    load path through them (:func:`static_path`: from rest to the smallest load, then on
    to the next, one Newton increment each).

    Parameters
    ----------
    model : Model
        Model whose mesh has a ``"tip"`` node set.
    loads_N : sequence of float, optional
        Tip loads F [N]. Default (1, 2), the paper's 1 N and 2 N.
    direction : int, optional
        Load and deflection direction 0, 1 or 2 (x, y, z). Default 1 (y).

    Returns
    -------
    float
        Tip stiffness [N/m].

    Raises
    ------
    InputError
        Loads that are not distinct, finite and positive.
    SolverError
        As :func:`static_solve`.
    """
    loads = np.sort(np.asarray(loads_N, dtype=float))
    if loads.ndim != 1 or not len(loads) or not np.all(np.isfinite(loads)) or loads[0] <= 0 \
            or np.any(np.diff(loads) == 0):
        raise InputError(f"loads_N = {loads_N!r}: must be distinct finite tip loads > 0 (N)")
    deflection, f_ext = _tip_load(model, loads[-1], direction)
    path = static_path(model, f_ext, loads / loads[-1])
    return float(np.mean([F / deflection(x) for F, x in zip(loads, path)]))
