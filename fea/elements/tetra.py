"""What the 4-node and 10-node tetrahedra share: faces, the characteristic length, and
the pure-numpy reference of their internal forces.

Both tetrahedra (:mod:`ccedi.fea.elements.tet4`, :mod:`ccedi.fea.elements.tet10`) are total-Lagrangian
integration-point elements whose potential splits ccedi's compressible neo-Hookean law
``W = mu/2 (I1 - 3) - mu ln J + lam/2 (ln J)^2`` into a part taken at the integration
points and a volumetric part taken on *averaged* volumes::

    Pi = sum_e sum_g w_g [mu/2 (I1(F_g) - 3) - mu ln J_g]  +  sum_G V0_G lam/2 (ln Jbar_G)^2

    v_e = sum_g w_g J_g            (current element volume, w_g = reference volume of point g)
    V_G = sum_e S_Ge v_e,  V0_G = sum_e S_Ge V0_e,  Jbar_G = V_G / V0_G

with an averaging matrix S: the nodal averaging of the 4-node tetrahedron (one group per
node, ``S_ae = 1/4`` for the 4 corners a of e) or the mean dilatation of the 10-node one
(one group per element, ``S = I``). The nodal forces are the exact derivatives of Pi::

    f_k = sum_g w_g [mu (F_g - F_g^-T) + (pbar_e - q_e) J_g F_g^-T] grad0 N_k(g)
    p_G = lam ln(Jbar_G) / Jbar_G,     pbar_e = sum_G S_Ge p_G

(``dv_e/dx_k = sum_g w_g J_g F_g^-T grad0 N_k``), so the energy balances. At small strain
the point part is mu eps:eps, the full shear energy; only the lam term is averaged, which
removes the volumetric locking of nearly incompressible rubber.

Bulk viscosity as for the hexahedron (:mod:`ccedi.fea.elements.hex8`): a pressure
``q_e = rho h (C0 h e_v^2 - C1 c e_v)`` in compression (``e_v = (dv_e/dt) / v_e < 0``)
added to the element's pressure, h = Le for the 10-node element and the element's own
minimum altitude for the 4-node one (its Le, scaled to the nodal pressure's assembled
limit, is 2.3-3.5 times the altitude: a viscosity on Le gave the highest mode of a tapered
8 mm finger a damping ratio of 0.24 instead of C1 = 0.06, and the run at 0.9 of the
undamped limit diverged under a 1 N tip load); it dissipates ``-q_e e_v v_e`` [W] (the kernels also
return its nodal forces, whose work the run takes on the mid-step velocity, as the work
of every other force). The critical step is
paper Eq. (6) (:func:`ccedi.fea.elements.hex8.element_time_step`) with the characteristic length
``Le = kappa_e h_e``, h_e the current minimum altitude of the corner tetrahedron and
kappa_e fixed at construction (:func:`time_step_length_factors`): the element's own
eigenvalue limit (a rigorous bound of the assembled one), scaled so that at rest the step
is the assembled limit 2/omega_max. No fixed factor of h is safe: the real limit per h
ranges 0.29-0.39 (10-node) on straight-edged meshes but down to 0.18 on Gmsh's curved
elements, where a factor 0.42 gave 1.22-1.77 times the limit. Measured (nu = 0.49) ratio
of the real limit to the element bound: 4-node 1.64-2.45 (box meshes); 10-node 1.28-1.67
(box meshes), 1.94 (SM-C), 1.20-2.02 (tapered Gmsh fingers, 8 to 4 mm); to the computed
step: 1.000-1.003 on all of them.
"""
import numba as nb
import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ccedi.fea.elements.assembly import assemble
from ccedi.fea.elements.fastmath import FASTMATH
from ccedi.fea.elements.hex8 import BULK_VISCOSITY_C0, BULK_VISCOSITY_C1, element_time_step
from ccedi.fea.material import strain_energy_density

CORNER_FACES = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
"""The four triangular faces of a tetrahedron (local corner ids)."""
QUADRATIC_FACES = np.array([[0, 1, 2, 4, 5, 6], [0, 1, 3, 4, 8, 7], [1, 2, 3, 5, 9, 8], [0, 2, 3, 6, 9, 7]])
"""The four 6-node faces of the 10-node tetrahedron: corners, then the mid-edge nodes
of the edges 0-1, 1-2, 2-0 of the face (VTK node order)."""
_FACES = CORNER_FACES.astype(np.int64)


def corner_volume(p):
    """Signed volume of tetrahedra from their corners.

    ``V = (x1 - x0) . ((x2 - x0) x (x3 - x0)) / 6``, positive for the orientation of
    :class:`ccedi.fea.mesh.Mesh`.

    Parameters
    ----------
    p : numpy.ndarray
        Corner positions, shape (e, 4, 3) [m].

    Returns
    -------
    numpy.ndarray
        Volumes, shape (e,) [m^3].
    """
    d = p[:, 1:] - p[:, :1]
    return np.einsum("ei,ei->e", d[:, 0], np.cross(d[:, 1], d[:, 2])) / 6.0


def min_altitude(p):
    """Smallest altitude of tetrahedra, ``3 V / A_max`` (volume over the largest face).

    Parameters
    ----------
    p : numpy.ndarray
        Corner positions, shape (e, 4, 3) [m].

    Returns
    -------
    numpy.ndarray
        Minimum altitudes, shape (e,) [m] (negative for an inverted tetrahedron).
    """
    f = p[:, CORNER_FACES]                                   # (e, 4, 3, 3)
    area = 0.5 * np.linalg.norm(np.cross(f[:, :, 1] - f[:, :, 0], f[:, :, 2] - f[:, :, 0]), axis=-1)
    return 3.0 * corner_volume(p) / area.max(axis=1)


def deformation_gradients(x, conn, grad):
    """Deformation gradient at every integration point, ``F = sum_k x_k (x) grad0 N_k``.

    Given velocities instead of positions it returns the rate dF/dt.

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions (n, 3) [m] (or velocities [m/s]).
    conn : numpy.ndarray
        Connectivity, shape (e, nn).
    grad : numpy.ndarray
        Reference shape-function gradients dN_k/dX at the points, shape (e, g, nn, 3) [1/m].

    Returns
    -------
    numpy.ndarray
        F [-] (or dF/dt [1/s]), shape (e, g, 3, 3).
    """
    return np.einsum("eki,egkj->egij", x[conn], grad)


@nb.njit(cache=True, fastmath=FASTMATH)
def deformation_gradients_numba(x, conn, grad):
    """:func:`deformation_gradients`, compiled: the same sums without the (e, nn, 3)
    gather, for the outputs of a run (max stress and strain at every output time).

    Parameters
    ----------
    x : (n, 3) ndarray
        Nodal positions [m] (or velocities [m/s]).
    conn : (e, nn) int ndarray
        Connectivity.
    grad : (e, g, nn, 3) ndarray
        Reference shape-function gradients at the points [1/m].

    Returns
    -------
    (e, g, 3, 3) ndarray
        F [-] (or dF/dt [1/s]).
    """
    ne, ng, nn = grad.shape[0], grad.shape[1], grad.shape[2]
    F = np.zeros((ne, ng, 3, 3))
    for e in range(ne):
        for g in range(ng):
            for k in range(nn):
                nd = conn[e, k]
                for i in range(3):
                    xi = x[nd, i]
                    for j in range(3):
                        F[e, g, i, j] += xi * grad[e, g, k, j]
    return F


def averaging_matrix(conn, n_nodes, nodal):
    """The averaging matrix S of the module docstring.

    Parameters
    ----------
    conn : numpy.ndarray
        Connectivity, shape (e, nn); its first 4 columns are the corners.
    n_nodes : int
        Number of mesh nodes.
    nodal : bool
        True: nodal averaging (``S_ae = 1/4`` for the corners a of e, shape (n_nodes, e));
        False: one group per element (the identity, shape (e, e)).

    Returns
    -------
    scipy.sparse.csr_matrix
        S.
    """
    e = len(conn)
    if not nodal:
        return sp.identity(e, format="csr")
    return sp.csr_matrix((np.full(4 * e, 0.25), (conn[:, :4].ravel(), np.repeat(np.arange(e), 4))),
                         shape=(n_nodes, e))


def averaged_forces_numpy(x, v, conn, *, grad, weight, average, Le, mu, lam, rho, c, f, bulk_force,
                          viscous_length=None):
    """Internal forces of averaged-volume tetrahedra, pure numpy; the reference of the
    compiled tetrahedron kernels.

    Equations of the module docstring; the forces are *added* to ``f``.

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    v : numpy.ndarray
        Nodal velocities, shape (n, 3) [m/s] (for the bulk viscosity).
    conn : numpy.ndarray
        Connectivity, shape (e, nn).
    grad : numpy.ndarray
        Reference shape-function gradients at the points, shape (e, g, nn, 3) [1/m].
    weight : numpy.ndarray
        Reference volume of each point (quadrature weight times det J0), shape (e, g) [m^3].
    average : scipy.sparse.csr_matrix
        Averaging matrix S (:func:`averaging_matrix`), shape (groups, e).
    Le : numpy.ndarray
        Current characteristic lengths of the step, shape (e,) [m].
    mu : float
        Shear modulus [Pa].
    lam : float
        First Lame constant [Pa].
    rho : float
        Density [kg/m^3].
    c : float
        Dilatational wave speed [m/s].
    f : numpy.ndarray
        Nodal forces (n, 3) [N], added to.
    bulk_force : numpy.ndarray
        Output (n, 3) [N]: the bulk-viscosity part of the forces,
        ``-sum_g w_g q_e J_g F_g^-T grad0 N_k`` (the run takes its work on the mid-step
        velocity).
    viscous_length : numpy.ndarray, optional
        Length of the viscosity pressure, shape (e,) [m] (:func:`bulk_viscosity`; default Le).

    Returns
    -------
    dt_min : float
        Smallest element critical step, paper Eq. (6) [s] (inf without elements).
    strain_energy : float
        Pi of the module docstring [J].
    bulk_viscous_power : float
        Power dissipated by the bulk viscosity [W].
    status : int
        -1 when every point has J > 0; else the index of the first element with J <= 0
        at a point (``f`` then untouched, the other values 0).
    """
    if len(conn) == 0:
        return np.inf, 0.0, 0.0, -1
    F = deformation_gradients(x, conn, grad)
    J = np.linalg.det(F)
    if np.any(J <= 0.0):
        return 0.0, 0.0, 0.0, int(np.argmax((J <= 0.0).any(axis=1)))
    Finv = np.linalg.inv(F)
    Fdot = deformation_gradients(v, conn, grad)
    vol = np.sum(weight * J, axis=1)
    vol_rate = np.sum(weight * J * np.einsum("egij,egji->eg", Fdot, Finv), axis=1)
    e_v = vol_rate / vol
    h = Le if viscous_length is None else viscous_length
    q = np.where(e_v < 0.0, rho * h * (BULK_VISCOSITY_C0 * h * e_v**2 - BULK_VISCOSITY_C1 * c * e_v), 0.0)
    ref = average @ np.sum(weight, axis=1)
    Jbar = (average @ vol) / ref
    pbar = average.T @ (lam * np.log(Jbar) / Jbar)
    FinvT = Finv.swapaxes(-1, -2)
    P = mu * (F - FinvT) + ((pbar - q)[:, None] * J)[..., None, None] * FinvT
    np.add.at(f, conn, np.einsum("eg,egij,egkj->eki", weight, P, grad))
    bulk_force[:] = 0.0
    np.add.at(bulk_force, conn, np.einsum("eg,egij,egkj->eki", weight, (-q[:, None] * J)[..., None, None] * FinvT, grad))
    w_dev = np.sum(weight * strain_energy_density(F, mu, 0.0))
    strain_energy = float(w_dev + np.sum(ref * 0.5 * lam * np.log(Jbar) ** 2))
    dt_min = float(element_time_step(Le, c, e_v, viscous_length=h).min())
    return dt_min, strain_energy, float(np.sum(-q * e_v * vol)), -1


@nb.njit(cache=True, fastmath=FASTMATH)
def corner_min_altitude(x, conn, e):
    """Compiled :func:`min_altitude` of the corner tetrahedron of element ``e``.

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    conn : numpy.ndarray
        Connectivity, shape (e, nn); its first 4 columns are the corners.
    e : int
        Element index.

    Returns
    -------
    float
        ``3 V / A_max`` of the corners' current positions [m].
    """
    a0 = conn[e, 0]; a1 = conn[e, 1]; a2 = conn[e, 2]; a3 = conn[e, 3]
    d10 = x[a1, 0] - x[a0, 0]; d11 = x[a1, 1] - x[a0, 1]; d12 = x[a1, 2] - x[a0, 2]
    d20 = x[a2, 0] - x[a0, 0]; d21 = x[a2, 1] - x[a0, 1]; d22 = x[a2, 2] - x[a0, 2]
    d30 = x[a3, 0] - x[a0, 0]; d31 = x[a3, 1] - x[a0, 1]; d32 = x[a3, 2] - x[a0, 2]
    six_v = d10 * (d21 * d32 - d22 * d31) + d11 * (d22 * d30 - d20 * d32) + d12 * (d20 * d31 - d21 * d30)
    amax2 = 0.0
    for fc in range(4):
        i0 = conn[e, _FACES[fc, 0]]; i1 = conn[e, _FACES[fc, 1]]; i2 = conn[e, _FACES[fc, 2]]
        p0 = x[i1, 0] - x[i0, 0]; p1 = x[i1, 1] - x[i0, 1]; p2 = x[i1, 2] - x[i0, 2]
        r0 = x[i2, 0] - x[i0, 0]; r1 = x[i2, 1] - x[i0, 1]; r2 = x[i2, 2] - x[i0, 2]
        cx = p1 * r2 - p2 * r1; cy = p2 * r0 - p0 * r2; cz = p0 * r1 - p1 * r0
        amax2 = max(amax2, cx * cx + cy * cy + cz * cz)
    return six_v / np.sqrt(amax2)          # 3 (six_v / 6) / (sqrt(amax2) / 2)


@nb.njit(cache=True, fastmath=FASTMATH)
def bulk_viscosity(Le, h, e_v, rho, c):
    """Bulk-viscosity pressure and critical step of one element, paper Eq. (6)
    (:func:`ccedi.fea.elements.hex8.element_time_step`).

    Parameters
    ----------
    Le : float
        Characteristic length of the step [m].
    h : float
        Length the viscosity pressure is taken on [m]: Le, or the element's own altitude
        when Le is scaled to an assembled limit (the 4-node element).
    e_v : float
        Volumetric strain rate [1/s]; the viscosity acts in compression (e_v < 0).
    rho : float
        Density [kg/m^3].
    c : float
        Dilatational wave speed [m/s].

    Returns
    -------
    q : float
        ``rho h (C0 h e_v^2 - C1 c e_v)`` for e_v < 0, else 0 [Pa].
    dt : float
        ``Le / (Q + sqrt(Q^2 + c^2))``, ``Q = (h / Le)(C1 c + C0 h |e_v|)`` for e_v < 0,
        else 0 [s].
    """
    q = 0.0
    Q = 0.0
    if e_v < 0.0:
        q = rho * h * (BULK_VISCOSITY_C0 * h * e_v * e_v - BULK_VISCOSITY_C1 * c * e_v)
        Q = h / Le * (BULK_VISCOSITY_C1 * c + BULK_VISCOSITY_C0 * h * (-e_v))
    return q, Le / (Q + np.sqrt(Q * Q + c * c))


@nb.njit(cache=True, fastmath=FASTMATH)
def inverse3(F, G):
    """Determinant and inverse of a 3x3 matrix.

    Parameters
    ----------
    F : numpy.ndarray
        Matrix, shape (3, 3).
    G : numpy.ndarray
        Output, shape (3, 3): F^-1 (left untouched when det F <= 0).

    Returns
    -------
    float
        det F.
    """
    c00 = F[1, 1] * F[2, 2] - F[1, 2] * F[2, 1]
    c01 = F[1, 2] * F[2, 0] - F[1, 0] * F[2, 2]
    c02 = F[1, 0] * F[2, 1] - F[1, 1] * F[2, 0]
    J = F[0, 0] * c00 + F[0, 1] * c01 + F[0, 2] * c02
    if not (J > 0.0):
        return J
    iJ = 1.0 / J
    G[0, 0] = c00 * iJ; G[1, 0] = c01 * iJ; G[2, 0] = c02 * iJ
    G[0, 1] = (F[0, 2] * F[2, 1] - F[0, 1] * F[2, 2]) * iJ
    G[1, 1] = (F[0, 0] * F[2, 2] - F[0, 2] * F[2, 0]) * iJ
    G[2, 1] = (F[0, 1] * F[2, 0] - F[0, 0] * F[2, 1]) * iJ
    G[0, 2] = (F[0, 1] * F[1, 2] - F[0, 2] * F[1, 1]) * iJ
    G[1, 2] = (F[0, 2] * F[1, 0] - F[0, 0] * F[1, 2]) * iJ
    G[2, 2] = (F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]) * iJ
    return J


@nb.njit(cache=True, fastmath=FASTMATH)
def point_gradients(x, v, conn, grad_eg, e, F, Fdot):
    """F and dF/dt at one integration point of element ``e``.

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    v : numpy.ndarray
        Nodal velocities, shape (n, 3) [m/s].
    conn : numpy.ndarray
        Connectivity, shape (e, nn).
    grad_eg : numpy.ndarray
        Reference shape-function gradients at the point, shape (nn, 3) [1/m].
    e : int
        Element index.
    F : numpy.ndarray
        Output (3, 3): sum_k x_k (x) grad_k [-].
    Fdot : numpy.ndarray
        Output (3, 3): sum_k v_k (x) grad_k [1/s].
    """
    F[:, :] = 0.0
    Fdot[:, :] = 0.0
    for k in range(conn.shape[1]):
        nd = conn[e, k]
        for i in range(3):
            xi = x[nd, i]
            vi = v[nd, i]
            for j in range(3):
                F[i, j] += xi * grad_eg[k, j]
                Fdot[i, j] += vi * grad_eg[k, j]


@nb.njit(cache=True, fastmath=FASTMATH)
def add_point_forces(f, conn, grad_eg, e, w, F, G, J, mu, p):
    """Add one point's nodal forces ``w [mu (F - F^-T) + p J F^-T] grad_k`` to ``f``.

    Parameters
    ----------
    f : numpy.ndarray
        Nodal forces (n, 3) [N], added to.
    conn : numpy.ndarray
        Connectivity, shape (e, nn).
    grad_eg : numpy.ndarray
        Reference shape-function gradients at the point, shape (nn, 3) [1/m].
    e : int
        Element index.
    w : float
        Reference volume of the point [m^3].
    F : numpy.ndarray
        Deformation gradient (3, 3) [-].
    G : numpy.ndarray
        Its inverse (3, 3) [-].
    J : float
        det F [-].
    mu : float
        Shear modulus [Pa].
    p : float
        Pressure-like coefficient (pbar - q) [Pa].

    Returns
    -------
    float
        The point's deviatoric energy ``w (mu/2 (I1 - 3) - mu ln J)`` [J].
    """
    co = p * J - mu
    P00 = mu * F[0, 0] + co * G[0, 0]; P01 = mu * F[0, 1] + co * G[1, 0]; P02 = mu * F[0, 2] + co * G[2, 0]
    P10 = mu * F[1, 0] + co * G[0, 1]; P11 = mu * F[1, 1] + co * G[1, 1]; P12 = mu * F[1, 2] + co * G[2, 1]
    P20 = mu * F[2, 0] + co * G[0, 2]; P21 = mu * F[2, 1] + co * G[1, 2]; P22 = mu * F[2, 2] + co * G[2, 2]
    for k in range(conn.shape[1]):
        b0 = w * grad_eg[k, 0]; b1 = w * grad_eg[k, 1]; b2 = w * grad_eg[k, 2]
        nd = conn[e, k]
        f[nd, 0] += P00 * b0 + P01 * b1 + P02 * b2
        f[nd, 1] += P10 * b0 + P11 * b1 + P12 * b2
        f[nd, 2] += P20 * b0 + P21 * b1 + P22 * b2
    I1 = 0.0
    for i in range(3):
        for j in range(3):
            I1 += F[i, j] * F[i, j]
    return w * (0.5 * mu * (I1 - 3.0) - mu * np.log(J))


def averaged_tangent(x, conn, grad, *, weight, average, mu, lam):
    """Consistent tangent stiffness d f / d x of averaged-volume tetrahedra (no bulk viscosity).

    With the point part's elasticity tensor ``A_ijmL = mu d_im d_jL + mu Finv_Li Finv_jm``
    (ccedi's neo-Hookean law with lam = 0; ``grad_k A grad_l = mu [(grad_k . grad_l) d_im +
    c_km c_li]``), the volume gradients
    ``a_e = dv_e/dx`` (``a_(k,i) = sum_g w_g J_g (F_g^-T grad0 N_k)_i``), their averages
    ``G = S a`` (a sparse matrix of d V_G / d x, one row per group) and the volume
    Hessians ``H_e = sum_g w_g J_g (c_ki c_lm - c_li c_km)``, ``c_k = F_g^-T grad0 N_k``::

        K = sum_e [sum_g w_g grad_k A grad_l + pbar_e H_e] + G^T diag(U''(Jbar_G) / V0_G) G

    ``U(J) = lam/2 (ln J)^2``, ``U'' = lam (1 - ln J) / J^2``. For the nodal averaging G
    couples all the elements around a node.

    Parameters
    ----------
    x : numpy.ndarray
        Nodal positions, shape (n, 3) [m].
    conn : numpy.ndarray
        Connectivity, shape (e, nn).
    grad : numpy.ndarray
        Reference shape-function gradients at the points, shape (e, g, nn, 3) [1/m].
    weight : numpy.ndarray
        Reference volume of each point, shape (e, g) [m^3].
    average : scipy.sparse.csr_matrix
        Averaging matrix S (:func:`averaging_matrix`), shape (groups, e).
    mu : float
        Shear modulus [Pa].
    lam : float
        First Lame constant [Pa].

    Returns
    -------
    scipy.sparse.csr_matrix
        K, shape (3 n, 3 n) [N/m], DOF index node*3 + direction.

    Raises
    ------
    ValueError
        Naming the first element with J <= 0 at a point.
    """
    n3 = 3 * len(x)
    ne, nn = conn.shape
    if ne == 0:
        return sp.csr_matrix((n3, n3))
    F = deformation_gradients(x, conn, grad)
    J = np.linalg.det(F)
    if np.any(J <= 0.0):
        raise ValueError(f"element {int(np.argmax((J <= 0.0).any(axis=1)))} inverted (J <= 0)")
    Fi = np.linalg.inv(F)
    cs = np.einsum("egji,egkj->egki", Fi, grad)               # spatial gradients F^-T grad0 N_k
    # grad_k A grad_h = mu [(grad_k . grad_h) d_im + c_km c_hi]
    w_mu = mu * weight
    Ke = ((w_mu[:, :, None, None] * grad) @ grad.transpose(0, 1, 3, 2)).sum(axis=1)[:, :, None, :, None] \
        * np.eye(3)[None, None, :, None, :]
    Ke += np.einsum("eg,egkm,eghi->ekihm", w_mu, cs, cs, optimize=True)
    wJ = weight * J
    H = np.einsum("eg,egki,eglm->ekilm", wJ, cs, cs, optimize=True)
    H = H - H.transpose(0, 3, 2, 1, 4)                        # c_ki c_lm - c_li c_km
    vol = wJ.sum(axis=1)
    a = np.einsum("eg,egki->eki", wJ, cs).reshape(ne, 3 * nn)
    ref = average @ weight.sum(axis=1)
    Jbar = (average @ vol) / ref
    lnJ = np.log(Jbar)
    pbar = average.T @ (lam * lnJ / Jbar)
    Ke += pbar[:, None, None, None, None] * H
    dofs = (3 * conn[:, :, None] + np.arange(3)).reshape(ne, 3 * nn)
    K = assemble(Ke, conn, len(x))
    volume_gradient = sp.csr_matrix((a.ravel(), (np.repeat(np.arange(ne), 3 * nn), dofs.ravel())), shape=(ne, n3))
    G = average @ volume_gradient
    return (K + G.T @ sp.diags(lam * (1.0 - lnJ) / (Jbar**2 * ref)) @ G).tocsr()


def reference_element_stiffness(grad, weight, *, mu, lam):
    """Stiffness of each element alone at the reference state (F = I), with the element's
    own, un-averaged volumetric term.

    ``K_(ki)(lm) = sum_g w_g mu [(g_k . g_l) d_im + g_km g_li] + lam a_ki a_lm / V0``,
    ``g_k = grad0 N_k(g)``, ``a_k = sum_g w_g g_k`` (= dv/dx_k), ``V0 = sum_g w_g``: the
    tangent of :func:`averaged_tangent` for one element, one group of its own. For the
    mean dilatation (one group per element) it is the element's exact share of the
    assembled tangent; for the nodal averaging it bounds that share from above, since
    ``V0_a (sum_e w_ae eps_e)^2 <= sum_e V0_e/4 eps_e^2`` (Jensen, ``w_ae = V0_e / (4 V0_a)``).

    Parameters
    ----------
    grad : numpy.ndarray
        Reference shape-function gradients at the points, shape (e, g, nn, 3) [1/m].
    weight : numpy.ndarray
        Reference volume of each point, shape (e, g) [m^3].
    mu : float
        Shear modulus [Pa].
    lam : float
        First Lame constant [Pa].

    Returns
    -------
    numpy.ndarray
        K_e, shape (e, 3 nn, 3 nn) [N/m], DOF index node*3 + direction.
    """
    ne, _, nn, _ = grad.shape
    K = np.einsum("eg,egkm,egli->ekilm", mu * weight, grad, grad, optimize=True)
    gg = np.einsum("eg,egkj,eglj->ekl", mu * weight, grad, grad, optimize=True)
    diag = np.arange(3)
    K[:, :, diag, :, diag] += gg[None]                           # (3, e, nn, nn) view of d_im
    a = np.einsum("eg,egki->eki", weight, grad).reshape(ne, 3 * nn)
    return K.reshape(ne, 3 * nn, 3 * nn) + (lam / weight.sum(axis=1))[:, None, None] * a[:, :, None] * a[:, None, :]


def largest_frequency(K, m):
    """Largest natural frequency of the undamped system (K, diag m): the square root of
    the largest eigenvalue of ``M^-1/2 K M^-1/2``.

    Dense ``eigvalsh`` up to 600 DOFs, else Lanczos (``eigsh``, largest algebraic, from a
    fixed start vector so that every process gets the same bits); the Ritz value is raised
    by its residual norm, which bounds its distance to an eigenvalue.

    Parameters
    ----------
    K : scipy.sparse.spmatrix
        Stiffness, shape (3 n, 3 n) [N/m], symmetric positive semi-definite.
    m : numpy.ndarray
        Nodal masses, shape (n,) [kg]; nodes with m = 0 (and their K rows) are left out.

    Returns
    -------
    float
        omega_max [rad/s]; nan when Lanczos does not converge.
    """
    dofs = (3 * np.flatnonzero(m > 0.0)[:, None] + np.arange(3)).ravel()
    s = sp.diags(1.0 / np.sqrt(np.repeat(m[m > 0.0], 3)))
    A = (s @ sp.csr_matrix(K)[dofs][:, dofs] @ s).tocsr()
    if A.shape[0] <= 600:
        return float(np.sqrt(sla.eigvalsh(A.toarray())[-1]))
    try:
        theta, y = spla.eigsh(A, k=1, which="LA", tol=1e-10,
                              v0=np.random.default_rng(0).standard_normal(A.shape[0]))   # reproducible
    except spla.ArpackNoConvergence:
        return np.nan
    return float(np.sqrt(theta[0] + np.linalg.norm(A @ y[:, 0] - theta[0] * y[:, 0])))


def time_step_length_factors(nodes, conn, grad, *, weight, average, element_mass, mu, lam, c, tangent=None):
    """Per-element factors kappa_e of the characteristic length ``Le = kappa_e h_e``
    (h the current minimum altitude of the corner tetrahedron) of paper Eq. (6).

    Each element's largest generalised eigenvalue omega_e^2 of (K_e, M_e) at the
    reference state (K_e of :func:`reference_element_stiffness`, M_e its lumped masses)
    bounds the assembled one: with ``K <= sum_e K_e`` and ``M = sum_e M_e`` the Rayleigh
    quotient gives ``omega_max <= max_e omega_e`` (the element eigenvalue theorem). This
    bound is conservative on assembled meshes (the neighbours share each element's
    stiffest mode), so it is scaled by the measured ``s = max_e omega_e / omega_max`` of
    the assembled reference tangent (:func:`largest_frequency`)::

        kappa_e = s c (2 / omega_e) / h_e0

    At rest Eq. (6) then gives ``min_e kappa_e h_e0 / c = 2 / omega_max``, the exact
    limit of central differences; during the run ``Le`` follows each element's altitude
    and enters the bulk viscosity. Without a converged Lanczos value s = 1 (the bound).

    Parameters
    ----------
    nodes : numpy.ndarray
        Reference nodal positions, shape (n, 3) [m].
    conn : numpy.ndarray
        Connectivity, shape (e, nn); its first 4 columns are the corners.
    grad : numpy.ndarray
        Reference shape-function gradients at the points, shape (e, g, nn, 3) [1/m].
    weight : numpy.ndarray
        Reference volume of each point, shape (e, g) [m^3].
    average : scipy.sparse.csr_matrix
        Averaging matrix S (:func:`averaging_matrix`).
    element_mass : numpy.ndarray
        Lumped masses of each element's nodes, shape (e, nn) [kg], all > 0.
    mu : float
        Shear modulus [Pa].
    lam : float
        First Lame constant [Pa].
    c : float
        Dilatational wave speed [m/s].
    tangent : scipy.sparse.spmatrix, optional
        The assembled reference tangent, shape (3 n, 3 n) [N/m], when it is not
        :func:`averaged_tangent` (an element that also smooths its shear; that tangent
        must be bounded by the sum of the K_e). Default: :func:`averaged_tangent`.

    Returns
    -------
    numpy.ndarray
        kappa_e, shape (e,) [-].
    """
    if len(conn) == 0:
        return np.zeros(0)
    s = 1.0 / np.sqrt(np.repeat(element_mass, 3, axis=1))
    Ke = reference_element_stiffness(grad, weight, mu=mu, lam=lam)
    omega_e = np.sqrt(np.linalg.eigvalsh(s[:, :, None] * Ke * s[:, None, :])[:, -1])
    m = np.zeros(len(nodes))
    np.add.at(m, conn, element_mass)
    if tangent is None:
        tangent = averaged_tangent(nodes, conn, grad, weight=weight, average=average, mu=mu, lam=lam)
    omega_max = largest_frequency(tangent, m)
    scale = max(1.0, omega_e.max() / omega_max) if omega_max > 0.0 else 1.0
    return scale * c * (2.0 / omega_e) / min_altitude(nodes[conn[:, :4]])
