"""The one-point hexahedron's internal forces on an NVIDIA GPU, many runs of one mesh at once
(optional: numba-cuda and a CUDA GPU; nothing else in ccedi needs it).

The batched layout of :mod:`ccedi.fea.elements.hex8_lanes` with one GPU thread per element
and run, runs innermost: nodal arrays are ``(n_nodes, 3, runs)``, so that the threads of a
warp (32 runs of one element) read neighbouring addresses. :func:`element_forces` computes
each element's nodal forces, Jacobian, critical step and energies (the arithmetic of
:func:`ccedi.fea.elements.hex8_kernels.internal_forces_numba`, in the same order; the GPU
may contract a multiply and an add, so the results agree to round-off, not to the bit);
:func:`node_forces` sums them per node in ascending element order (no atomics: the sums
are the same on every launch). This module imports only numpy, math and numba.cuda and
takes plain arrays, so that a benchmark can run it where ccedi's other dependencies are
not installed (``benchmarks/gpu_speed.py``).
"""
import math

import numpy as np
from numba import cuda

ELEMENT_VALUES = 5
"""Per element and run, after its 24 nodal forces: J [-], critical step [s], strain
energy [J], hourglass energy [J], bulk-viscous power [W]."""


@cuda.jit
def element_forces(x, v, hexes, b, vol, centre, kappa, H, faces, params, fe, values):
    """One thread per (element e, run r): the element's nodal forces into ``fe[e, :, r]``
    and its values into ``values[e, :, r]`` (:data:`ELEMENT_VALUES`).

    Parameters
    ----------
    x, v : device arrays (n_nodes, 3, runs)
        Positions [m] and velocities [m/s].
    hexes : (n_elem, 8) int64
        Connectivity.
    b : (n_elem, 8, 3)
        Uniform gradients [m^2].
    vol : (n_elem,)
        Reference volumes [m^3].
    centre : (n_elem, 12)
        Reference hourglass displacements ``sum_k h_ak X_k`` [m].
    kappa : (n_elem, 12, 12)
        Hourglass stiffness [N/m].
    H : (4, 8)
        Hourglass base vectors.
    faces : (6, 4) int64
        The faces' corner nodes.
    params : (7,)
        mu [Pa], lam [Pa], rho [kg/m^3], c [m/s], length factor, bulk-viscosity C0, C1.
    fe : (n_elem, 24, runs)
        Out: nodal forces [N], row 3 k + i.
    values : (n_elem, 5, runs)
        Out: :data:`ELEMENT_VALUES`.
    """
    runs = x.shape[2]
    t = cuda.grid(1)
    e = t // runs
    r = t - e * runs
    if e >= hexes.shape[0]:
        return
    mu = params[0]; lam = params[1]; rho = params[2]; c = params[3]; lf = params[4]
    xs = cuda.local.array(24, np.float64)
    vs = cuda.local.array(24, np.float64)
    for k in range(8):
        nd = hexes[e, k]
        for i in range(3):
            xs[3 * k + i] = x[nd, i, r]
            vs[3 * k + i] = v[nd, i, r]
    V0 = vol[e]
    iV = 1.0 / V0
    f00 = f01 = f02 = f10 = f11 = f12 = f20 = f21 = f22 = 0.0
    d00 = d01 = d02 = d10 = d11 = d12 = d20 = d21 = d22 = 0.0
    for k in range(8):
        b0 = b[e, k, 0]; b1 = b[e, k, 1]; b2 = b[e, k, 2]
        x0 = xs[3 * k]; x1 = xs[3 * k + 1]; x2 = xs[3 * k + 2]
        f00 += x0 * b0; f01 += x0 * b1; f02 += x0 * b2
        f10 += x1 * b0; f11 += x1 * b1; f12 += x1 * b2
        f20 += x2 * b0; f21 += x2 * b1; f22 += x2 * b2
        v0 = vs[3 * k]; v1 = vs[3 * k + 1]; v2 = vs[3 * k + 2]
        d00 += v0 * b0; d01 += v0 * b1; d02 += v0 * b2
        d10 += v1 * b0; d11 += v1 * b1; d12 += v1 * b2
        d20 += v2 * b0; d21 += v2 * b1; d22 += v2 * b2
    f00 *= iV; f01 *= iV; f02 *= iV; f10 *= iV; f11 *= iV; f12 *= iV; f20 *= iV; f21 *= iV; f22 *= iV
    c00 = f11 * f22 - f12 * f21
    c01 = f12 * f20 - f10 * f22
    c02 = f10 * f21 - f11 * f20
    J = f00 * c00 + f01 * c01 + f02 * c02
    iJ = 1.0 / J
    g00 = c00 * iJ; g10 = c01 * iJ; g20 = c02 * iJ
    g01 = (f02 * f21 - f01 * f22) * iJ
    g11 = (f00 * f22 - f02 * f20) * iJ
    g21 = (f01 * f20 - f00 * f21) * iJ
    g02 = (f01 * f12 - f02 * f11) * iJ
    g12 = (f02 * f10 - f00 * f12) * iJ
    g22 = (f00 * f11 - f01 * f10) * iJ
    e_v = iV * (d00 * g00 + d01 * g10 + d02 * g20 + d10 * g01 + d11 * g11 + d12 * g21 + d20 * g02 + d21 * g12
                + d22 * g22)
    amax2 = 0.0
    for fc in range(6):
        a0 = faces[fc, 0]; a1 = faces[fc, 1]; a2 = faces[fc, 2]; a3 = faces[fc, 3]
        p0 = xs[3 * a2] - xs[3 * a0]; p1 = xs[3 * a2 + 1] - xs[3 * a0 + 1]; p2 = xs[3 * a2 + 2] - xs[3 * a0 + 2]
        q0 = xs[3 * a3] - xs[3 * a1]; q1 = xs[3 * a3 + 1] - xs[3 * a1 + 1]; q2 = xs[3 * a3 + 2] - xs[3 * a1 + 2]
        cx = p1 * q2 - p2 * q1; cy = p2 * q0 - p0 * q2; cz = p0 * q1 - p1 * q0
        amax2 = max(amax2, cx * cx + cy * cy + cz * cz)
    Le = lf * 2.0 * J * V0 / math.sqrt(amax2)
    qb = 0.0
    Q = 0.0
    if e_v < 0.0:
        qb = rho * Le * (params[5] * Le * e_v * e_v - params[6] * c * e_v)
        Q = params[6] * c + params[5] * Le * (-e_v)
    dt = Le / (Q + math.sqrt(Q * Q + c * c))
    rr = cuda.local.array(12, np.float64)           # r_a = F^-1 sum_k h_ak x_k
    qt = cuda.local.array(12, np.float64)           # qt_a = r_a - G_a
    for a in range(4):
        s0 = 0.0; s1 = 0.0; s2 = 0.0
        for k in range(8):
            h = H[a, k]
            s0 += h * xs[3 * k]; s1 += h * xs[3 * k + 1]; s2 += h * xs[3 * k + 2]
        r0 = g00 * s0 + g01 * s1 + g02 * s2
        r1 = g10 * s0 + g11 * s1 + g12 * s2
        r2 = g20 * s0 + g21 * s1 + g22 * s2
        rr[3 * a] = r0; rr[3 * a + 1] = r1; rr[3 * a + 2] = r2
        qt[3 * a] = r0 - centre[e, 3 * a]; qt[3 * a + 1] = r1 - centre[e, 3 * a + 1]
        qt[3 * a + 2] = r2 - centre[e, 3 * a + 2]
    lnJ = math.log(J)
    I1 = f00 * f00 + f01 * f01 + f02 * f02 + f10 * f10 + f11 * f11 + f12 * f12 + f20 * f20 + f21 * f21 + f22 * f22
    co = lam * lnJ - mu - qb * J
    P00 = mu * f00 + co * g00; P01 = mu * f01 + co * g10; P02 = mu * f02 + co * g20
    P10 = mu * f10 + co * g01; P11 = mu * f11 + co * g11; P12 = mu * f12 + co * g21
    P20 = mu * f20 + co * g02; P21 = mu * f21 + co * g12; P22 = mu * f22 + co * g22
    s00 = s01 = s02 = s10 = s11 = s12 = s20 = s21 = s22 = 0.0
    whg = 0.0
    A = cuda.local.array(12, np.float64)            # A_a = F^-T Qt_a
    for a in range(4):
        t0 = 0.0; t1 = 0.0; t2 = 0.0
        for cc in range(12):
            q = qt[cc]
            t0 += kappa[e, 3 * a, cc] * q; t1 += kappa[e, 3 * a + 1, cc] * q; t2 += kappa[e, 3 * a + 2, cc] * q
        whg += 0.5 * (t0 * qt[3 * a] + t1 * qt[3 * a + 1] + t2 * qt[3 * a + 2])
        u0 = g00 * t0 + g10 * t1 + g20 * t2
        u1 = g01 * t0 + g11 * t1 + g21 * t2
        u2 = g02 * t0 + g12 * t1 + g22 * t2
        r0 = rr[3 * a]; r1 = rr[3 * a + 1]; r2 = rr[3 * a + 2]
        s00 += u0 * r0; s01 += u0 * r1; s02 += u0 * r2
        s10 += u1 * r0; s11 += u1 * r1; s12 += u1 * r2
        s20 += u2 * r0; s21 += u2 * r1; s22 += u2 * r2
        A[3 * a] = u0; A[3 * a + 1] = u1; A[3 * a + 2] = u2
    P00 -= iV * s00; P01 -= iV * s01; P02 -= iV * s02
    P10 -= iV * s10; P11 -= iV * s11; P12 -= iV * s12
    P20 -= iV * s20; P21 -= iV * s21; P22 -= iV * s22
    for k in range(8):
        b0 = b[e, k, 0]; b1 = b[e, k, 1]; b2 = b[e, k, 2]
        h0 = H[0, k]; h1 = H[1, k]; h2 = H[2, k]; h3 = H[3, k]
        fe[e, 3 * k, r] = P00 * b0 + P01 * b1 + P02 * b2 + h0 * A[0] + h1 * A[3] + h2 * A[6] + h3 * A[9]
        fe[e, 3 * k + 1, r] = P10 * b0 + P11 * b1 + P12 * b2 + h0 * A[1] + h1 * A[4] + h2 * A[7] + h3 * A[10]
        fe[e, 3 * k + 2, r] = P20 * b0 + P21 * b1 + P22 * b2 + h0 * A[2] + h1 * A[5] + h2 * A[8] + h3 * A[11]
    values[e, 0, r] = J
    values[e, 1, r] = dt
    values[e, 2, r] = V0 * (0.5 * mu * (I1 - 3.0) - mu * lnJ + 0.5 * lam * lnJ * lnJ)
    values[e, 3, r] = whg
    values[e, 4, r] = -qb * e_v * J * V0


@cuda.jit
def node_forces(node_start, node_element, node_corner, fe, f):
    """One thread per (node, run): ``f[n, :, r] += sum of its elements' forces``, in
    ascending element order (the order of ``node_element`` within the node's slots).

    Parameters
    ----------
    node_start : (n_nodes + 1,) int64
        Each node's first slot.
    node_element, node_corner : (slots,) int64
        The element and its corner (0-7) of each slot, by node, elements ascending.
    fe : (n_elem, 24, runs)
        Element nodal forces [N] (:func:`element_forces`).
    f : (n_nodes, 3, runs)
        Nodal forces [N], added to.
    """
    runs = f.shape[2]
    t = cuda.grid(1)
    nd = t // runs
    r = t - nd * runs
    if nd >= f.shape[0]:
        return
    s0 = 0.0; s1 = 0.0; s2 = 0.0
    for s in range(node_start[nd], node_start[nd + 1]):
        e = node_element[s]
        k = node_corner[s]
        s0 += fe[e, 3 * k, r]; s1 += fe[e, 3 * k + 1, r]; s2 += fe[e, 3 * k + 2, r]
    f[nd, 0, r] += s0; f[nd, 1, r] += s1; f[nd, 2, r] += s2


def node_slots(hexes, n_nodes):
    """The node-to-element slots of :func:`node_forces`.

    Parameters
    ----------
    hexes : numpy.ndarray
        Connectivity (n_elem, 8).
    n_nodes : int
        Number of nodes.

    Returns
    -------
    tuple of numpy.ndarray
        (node_start (n_nodes + 1,), node_element, node_corner), int64, elements ascending
        within each node.
    """
    hexes = np.asarray(hexes, dtype=np.int64)
    element = np.repeat(np.arange(len(hexes)), 8)
    corner = np.tile(np.arange(8), len(hexes))
    order = np.lexsort((element, hexes.ravel()))
    start = np.searchsorted(hexes.ravel()[order], np.arange(n_nodes + 1)).astype(np.int64)
    return start, element[order].astype(np.int64), corner[order].astype(np.int64)


def internal_forces(x, v, *, mesh_arrays, params, threads_per_block=128):
    """Internal nodal forces of many runs of one hexahedral mesh on the GPU.

    Parameters
    ----------
    x, v : numpy.ndarray or device arrays
        Positions [m] and velocities [m/s], (n_nodes, 3, runs).
    mesh_arrays : dict
        Device (or host) arrays ``hexes``, ``b``, ``vol``, ``centre``, ``kappa``, ``H``,
        ``faces``, ``node_start``, ``node_element``, ``node_corner`` (see
        :func:`element_forces` and :func:`node_slots`).
    params : numpy.ndarray
        (7,): mu, lam, rho, c, length factor, C0, C1 (:func:`element_forces`).
    threads_per_block : int, optional
        CUDA block size.

    Returns
    -------
    tuple
        (f (n_nodes, 3, runs) [N], values (n_elem, 5, runs), :data:`ELEMENT_VALUES`), as
        device arrays.
    """
    m = mesh_arrays
    n_nodes, _, runs = x.shape
    n_elem = m["hexes"].shape[0]
    fe = cuda.device_array((n_elem, 24, runs))
    values = cuda.device_array((n_elem, ELEMENT_VALUES, runs))
    f = cuda.to_device(np.zeros((n_nodes, 3, runs)))
    blocks = -(-n_elem * runs // threads_per_block)
    element_forces[blocks, threads_per_block](x, v, m["hexes"], m["b"], m["vol"], m["centre"], m["kappa"], m["H"],
                                              m["faces"], params, fe, values)
    node_forces[-(-n_nodes * runs // threads_per_block), threads_per_block](m["node_start"], m["node_element"],
                                                                           m["node_corner"], fe, f)
    return f, values
