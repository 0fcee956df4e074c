"""numba-compiled internal forces of one-point hexahedra for several runs of one mesh at once.

The runs (the lanes) share the mesh, the material and so every element constant; they
differ in their state (positions and velocities), because they differ in damping, load or
initial state. :func:`ccedi.fea.elements.hex8_kernels.internal_forces_numba` puts the SIMD
lanes across elements; here they run across runs: the element's constants (uniform
gradients, hourglass centres and stiffness, volume) are read once per element and shared
by every lane, the gathered nodal values and the nodal sums are contiguous in the lanes,
and each element's forces are added straight into per-node lane sums.

Every lane computes, bit for bit, what :func:`internal_forces_numba` computes for that
run alone: the same expressions in the same order (no fast-math, so LLVM keeps them), each
node's force summed over its elements in ascending element order from zero and then added
to the run's force, and the energies summed in element order. ``tests/unit/fea/
test_batch.py`` checks the bits against that kernel and the values against the numpy
reference :func:`ccedi.fea.elements.hex8.internal_forces_numpy`.

The kernel is serial: the runs are shared between threads (each thread its own lanes,
:mod:`ccedi.fea.solvers.batch`), so it is compiled with ``nogil``.
"""
import functools

import numba as nb
import numpy as np

from ccedi.fea.elements.fastmath import FASTMATH
from ccedi.fea.elements.hex8_kernels import _H, _UPPER, BLOCK, bulk_viscosity, inverse_3x3

LANE_COUNTS = (4, 8)
"""Runs one kernel call can advance (:func:`lanes_kernel`): 8 fill a 512-bit vector, 4 a
256-bit one."""

# rows of the work array: gathered positions (3k + i) and velocities (24 + 3k + i); F^-1 (9),
# F (9), J, e_v, q, r_a (12), qt_a (12), dt; sum_k v_k b_k^T; Qt = K_hg qt; the nodal
# forces; ln J; A_a = F^-T Qt_a;
# P - S / V0; the lane's running results (those of ``result``)
_XV, _W, _DV, _HQ, _OUT, _LNJ, _A, _P, _R, _ROWS = 0, 48, 96, 105, 117, 141, 142, 154, 163, 168


@nb.njit(cache=True, fastmath=FASTMATH, inline="always")
def _load_lanes(wk, row, a, j, L):
    """Row ``row`` of ``wk`` = ``a[j:j + L]`` (flat arrays, L = 4 or 8): the loads come
    before the stores, at unsigned indices (no wrap-around of negative ones), so LLVM
    joins each into one vector instruction."""
    j = np.uint64(j)
    w = np.uint64(row * L)
    if L == 8:
        t = (a[j], a[j + np.uint64(1)], a[j + np.uint64(2)], a[j + np.uint64(3)],
             a[j + np.uint64(4)], a[j + np.uint64(5)], a[j + np.uint64(6)], a[j + np.uint64(7)])
        wk[w] = t[0]; wk[w + np.uint64(1)] = t[1]; wk[w + np.uint64(2)] = t[2]; wk[w + np.uint64(3)] = t[3]
        wk[w + np.uint64(4)] = t[4]; wk[w + np.uint64(5)] = t[5]; wk[w + np.uint64(6)] = t[6]
        wk[w + np.uint64(7)] = t[7]
    else:
        t4 = (a[j], a[j + np.uint64(1)], a[j + np.uint64(2)], a[j + np.uint64(3)])
        wk[w] = t4[0]; wk[w + np.uint64(1)] = t4[1]; wk[w + np.uint64(2)] = t4[2]; wk[w + np.uint64(3)] = t4[3]


@nb.njit(cache=True, fastmath=FASTMATH, inline="always")
def _add_lanes(a, j, src, k, L):
    """``a[j:j + L] += src[k:k + L]`` (flat arrays), loads before stores (see :func:`_load_lanes`)."""
    j = np.uint64(j)
    k = np.uint64(k)
    if L == 4:
        t4 = (a[j] + src[k], a[j + np.uint64(1)] + src[k + np.uint64(1)], a[j + np.uint64(2)] + src[k + np.uint64(2)],
              a[j + np.uint64(3)] + src[k + np.uint64(3)])
        a[j] = t4[0]; a[j + np.uint64(1)] = t4[1]; a[j + np.uint64(2)] = t4[2]; a[j + np.uint64(3)] = t4[3]
        return
    t = (a[j] + src[k], a[j + np.uint64(1)] + src[k + np.uint64(1)], a[j + np.uint64(2)] + src[k + np.uint64(2)],
         a[j + np.uint64(3)] + src[k + np.uint64(3)], a[j + np.uint64(4)] + src[k + np.uint64(4)],
         a[j + np.uint64(5)] + src[k + np.uint64(5)], a[j + np.uint64(6)] + src[k + np.uint64(6)],
         a[j + np.uint64(7)] + src[k + np.uint64(7)])
    a[j] = t[0]; a[j + np.uint64(1)] = t[1]; a[j + np.uint64(2)] = t[2]; a[j + np.uint64(3)] = t[3]
    a[j + np.uint64(4)] = t[4]; a[j + np.uint64(5)] = t[5]; a[j + np.uint64(6)] = t[6]; a[j + np.uint64(7)] = t[7]


@nb.njit(cache=True, fastmath=FASTMATH, inline="always")
def _element_b(block_b, blk, le):
    """The 24 uniform gradients of element ``le`` of block ``blk`` as a tuple: numbers in
    registers, which the lane loops read without LLVM having to rule out that their
    stores change them."""
    b = block_b[blk]
    return (b[0, le], b[1, le], b[2, le], b[3, le], b[4, le], b[5, le], b[6, le], b[7, le],
            b[8, le], b[9, le], b[10, le], b[11, le], b[12, le], b[13, le], b[14, le], b[15, le],
            b[16, le], b[17, le], b[18, le], b[19, le], b[20, le], b[21, le], b[22, le], b[23, le])


@nb.njit(cache=True, fastmath=FASTMATH, inline="always")
def _row12(a, e, start):
    """``a[e, start:start + 12]`` as a tuple (see :func:`_element_b`)."""
    return (a[e, start], a[e, start + 1], a[e, start + 2], a[e, start + 3], a[e, start + 4], a[e, start + 5],
            a[e, start + 6], a[e, start + 7], a[e, start + 8], a[e, start + 9], a[e, start + 10], a[e, start + 11])


@nb.njit(cache=True, fastmath=FASTMATH, inline="always")
def _hourglass_force(wk, kr, r, ll, L):
    """Row r of ``Qt = K_hg qt`` for lane ll (``kr``: row r of K_hg), into its row of ``wk``."""
    acc = 0.0
    for cc in range(12):
        acc += kr[cc] * wk[(_W + 33 + cc) * L + ll]
    wk[(_HQ + r) * L + ll] = acc


@nb.njit(cache=True, fastmath=FASTMATH, inline="always")
def _node_forces(wk, bv, k, ll, L):
    """Node k's force of lane ll, ``(P - S / V0) b_k + sum_a h_ak A_a``, into its rows of
    ``wk``; called with literal k, so that the lane loop sees fixed rows and constant h."""
    h0 = _H[0, k]; h1 = _H[1, k]; h2 = _H[2, k]; h3 = _H[3, k]
    b0 = bv[3 * k]; b1 = bv[3 * k + 1]; b2 = bv[3 * k + 2]
    for i in range(3):
        wk[(_OUT + 3 * k + i) * L + ll] = (
            wk[(_P + 3 * i) * L + ll] * b0 + wk[(_P + 3 * i + 1) * L + ll] * b1
            + wk[(_P + 3 * i + 2) * L + ll] * b2 + h0 * wk[(_A + i) * L + ll]
            + h1 * wk[(_A + 3 + i) * L + ll] + h2 * wk[(_A + 6 + i) * L + ll]
            + h3 * wk[(_A + 9 + i) * L + ll])


@nb.njit(cache=True, fastmath=FASTMATH, inline="always")
def _face_area2(wk, a0, a1, a2, a3, ll, amax2, L):
    """The larger of amax2 and |d1 x d2|^2 of the face a0 a1 a2 a3 (diagonals d1 = x_a2 -
    x_a0, d2 = x_a3 - x_a1) of lane ll: four times the squared face area; called with
    literal node numbers, so that the lane loop sees fixed rows."""
    p0 = wk[(_XV + 3 * a2) * L + ll] - wk[(_XV + 3 * a0) * L + ll]
    p1 = wk[(_XV + 3 * a2 + 1) * L + ll] - wk[(_XV + 3 * a0 + 1) * L + ll]
    p2 = wk[(_XV + 3 * a2 + 2) * L + ll] - wk[(_XV + 3 * a0 + 2) * L + ll]
    r0 = wk[(_XV + 3 * a3) * L + ll] - wk[(_XV + 3 * a1) * L + ll]
    r1 = wk[(_XV + 3 * a3 + 1) * L + ll] - wk[(_XV + 3 * a1 + 1) * L + ll]
    r2 = wk[(_XV + 3 * a3 + 2) * L + ll] - wk[(_XV + 3 * a1 + 2) * L + ll]
    cx = p1 * r2 - p2 * r1; cy = p2 * r0 - p0 * r2; cz = p0 * r1 - p1 * r0
    area2 = cx * cx + cy * cy + cz * cz
    return area2 if area2 > amax2 else amax2


def full_stiffness(group):
    """Every entry of each element's hourglass stiffness, row by row, as the single-run
    kernel uses them: entry (r, c) is its stored upper-triangle value (r, c) or (c, r).

    Parameters
    ----------
    group : HexGroup
        The hexahedra.

    Returns
    -------
    (n_elem, 144) ndarray
        K_hg [N/m].
    """
    iu, ju = np.triu_indices(12)
    return np.ascontiguousarray(group.kappa[:, iu, ju][:, _UPPER.ravel()])


@functools.cache
def lanes_kernel(lanes):
    """The kernel :func:`internal_forces_lanes` compiled for ``lanes`` runs at a time (4
    or 8: a compile-time constant, so that LLVM knows the work rows' layout and compiles
    every stage to SIMD across the lanes; with the count read at run time it needed more
    run-time alias checks than it makes). Each width is its own cache entry.

    Parameters
    ----------
    lanes : {4, 8}
        Runs per call.

    Returns
    -------
    numba dispatcher
        ``kernel(x, v, group, stiffness, material, b0, f, result)``.

    Raises
    ------
    ValueError
        ``lanes`` is not 4 or 8.
    """
    if lanes not in LANE_COUNTS:
        raise ValueError(f"lanes must be one of {LANE_COUNTS}, got {lanes!r}")
    L = lanes

    @nb.njit(cache=True, fastmath=FASTMATH, error_model="numpy", nogil=True)
    def internal_forces_lanes(x, v, group, stiffness, material, b0, f, result):
        """Internal nodal forces of one-point hexahedra for runs ``b0 .. b0 + L - 1``.

        The equations are those of :func:`ccedi.fea.elements.hex8_kernels.internal_forces_numba`.

        Parameters
        ----------
        x, v : (n_nodes, 3, n_runs) ndarray
            Nodal positions [m] and velocities [m/s] of every run (runs innermost;
            ``n_runs >= b0 + L``).
        group : HexGroup
            The hexahedra (:func:`ccedi.fea.elements.hex8_kernels.hex_group`), shared by the runs.
        stiffness : (n_elem, 144) ndarray
            The hourglass stiffness K_hg of each element, all 12 x 12 entries row by row
            (:func:`full_stiffness`) [N/m].
        material : SolidMaterial
            (mu [Pa], lam [Pa], rho [kg/m^3], c [m/s]), shared by the runs.
        b0 : int
            First run of the lanes.
        f : (n_nodes, 3, n_runs) ndarray
            Nodal forces [N]; each lane's internal forces are ADDED to its run's.
        result : (5, L) ndarray
            Filled per lane with the smallest critical step [s], the strain energy [J], the
            hourglass energy [J], the bulk-viscous power [W] and -1 or the first inverted
            element (J <= 0; the lane's forces are then meaningless).
        """
        lanes = L
        wk = np.empty(_ROWS * L)        # every work row, so LLVM sees one array and vectorises the lanes
        mu, lam, rho, c = material[0], material[1], material[2], material[3]
        lf = group.length_factor
        for ll in range(lanes):
            wk[_R * L + ll] = np.inf
            wk[(_R + 1) * L + ll] = 0.0
            wk[(_R + 2) * L + ll] = 0.0
            wk[(_R + 3) * L + ll] = 0.0
            wk[(_R + 4) * L + ll] = -1.0
        n_nodes = x.shape[0]
        n_runs = x.shape[2]
        xf, vf = x.reshape(-1), v.reshape(-1)
        sums = np.zeros(n_nodes * 3 * L)        # each node's force per lane, summed in element order
        n_elem = group.hexes.shape[0]
        for e in range(n_elem):
            blk = e // BLOCK
            le = e % BLOCK
            V0 = group.block_volume[blk, le]
            bv = _element_b(group.block_b, blk, le)
            iV = 1.0 / V0
            for k in range(8):
                nd = group.block_nodes[blk, k, le]
                for i in range(3):
                    _load_lanes(wk, _XV + 3 * k + i, xf, (3 * nd + i) * n_runs + b0, L)
                    _load_lanes(wk, _XV + 24 + 3 * k + i, vf, (3 * nd + i) * n_runs + b0, L)
            for ll in range(lanes):
                f00 = f01 = f02 = f10 = f11 = f12 = f20 = f21 = f22 = 0.0
                for k in range(8):
                    x0 = wk[(_XV + 3 * k) * L + ll]; x1 = wk[(_XV + 3 * k + 1) * L + ll]; x2 = wk[(_XV + 3 * k + 2) * L + ll]
                    b0_ = bv[3 * k]; b1 = bv[3 * k + 1]; b2 = bv[3 * k + 2]
                    f00 += x0 * b0_; f01 += x0 * b1; f02 += x0 * b2
                    f10 += x1 * b0_; f11 += x1 * b1; f12 += x1 * b2
                    f20 += x2 * b0_; f21 += x2 * b1; f22 += x2 * b2
                wk[(_W + 9) * L + ll] = f00 * iV; wk[(_W + 10) * L + ll] = f01 * iV; wk[(_W + 11) * L + ll] = f02 * iV
                wk[(_W + 12) * L + ll] = f10 * iV; wk[(_W + 13) * L + ll] = f11 * iV; wk[(_W + 14) * L + ll] = f12 * iV
                wk[(_W + 15) * L + ll] = f20 * iV; wk[(_W + 16) * L + ll] = f21 * iV; wk[(_W + 17) * L + ll] = f22 * iV
            for ll in range(lanes):
                d00 = d01 = d02 = d10 = d11 = d12 = d20 = d21 = d22 = 0.0
                for k in range(8):
                    v0 = wk[(_XV + 24 + 3 * k) * L + ll]; v1 = wk[(_XV + 25 + 3 * k) * L + ll]; v2 = wk[(_XV + 26 + 3 * k) * L + ll]
                    b0_ = bv[3 * k]; b1 = bv[3 * k + 1]; b2 = bv[3 * k + 2]
                    d00 += v0 * b0_; d01 += v0 * b1; d02 += v0 * b2
                    d10 += v1 * b0_; d11 += v1 * b1; d12 += v1 * b2
                    d20 += v2 * b0_; d21 += v2 * b1; d22 += v2 * b2
                wk[(_DV + 0) * L + ll] = d00; wk[(_DV + 1) * L + ll] = d01; wk[(_DV + 2) * L + ll] = d02
                wk[(_DV + 3) * L + ll] = d10; wk[(_DV + 4) * L + ll] = d11; wk[(_DV + 5) * L + ll] = d12
                wk[(_DV + 6) * L + ll] = d20; wk[(_DV + 7) * L + ll] = d21; wk[(_DV + 8) * L + ll] = d22
            for ll in range(lanes):
                amax2 = _face_area2(wk, 0, 3, 2, 1, ll, 0.0, L)
                amax2 = _face_area2(wk, 4, 5, 6, 7, ll, amax2, L)
                amax2 = _face_area2(wk, 0, 1, 5, 4, ll, amax2, L)
                amax2 = _face_area2(wk, 1, 2, 6, 5, ll, amax2, L)
                amax2 = _face_area2(wk, 2, 3, 7, 6, ll, amax2, L)
                amax2 = _face_area2(wk, 3, 0, 4, 7, ll, amax2, L)
                wk[(_LNJ) * L + ll] = amax2
            for ll in range(lanes):
                f00 = wk[(_W + 9) * L + ll]; f01 = wk[(_W + 10) * L + ll]; f02 = wk[(_W + 11) * L + ll]
                f10 = wk[(_W + 12) * L + ll]; f11 = wk[(_W + 13) * L + ll]; f12 = wk[(_W + 14) * L + ll]
                f20 = wk[(_W + 15) * L + ll]; f21 = wk[(_W + 16) * L + ll]; f22 = wk[(_W + 17) * L + ll]
                J, g00, g01, g02, g10, g11, g12, g20, g21, g22 = inverse_3x3(f00, f01, f02, f10, f11, f12, f20, f21,
                                                                             f22)
                e_v = iV * (wk[(_DV + 0) * L + ll] * g00 + wk[(_DV + 1) * L + ll] * g10 + wk[(_DV + 2) * L + ll] * g20 + wk[(_DV + 3) * L + ll] * g01 + wk[(_DV + 4) * L + ll] * g11
                            + wk[(_DV + 5) * L + ll] * g21 + wk[(_DV + 6) * L + ll] * g02 + wk[(_DV + 7) * L + ll] * g12 + wk[(_DV + 8) * L + ll] * g22)
                Le = lf * 2.0 * J * V0 / np.sqrt(wk[(_LNJ) * L + ll])
                qb, wk[(_W + 47) * L + ll] = bulk_viscosity(e_v, Le, rho, c)
                wk[(_W + 0) * L + ll] = g00; wk[(_W + 1) * L + ll] = g01; wk[(_W + 2) * L + ll] = g02
                wk[(_W + 3) * L + ll] = g10; wk[(_W + 4) * L + ll] = g11; wk[(_W + 5) * L + ll] = g12
                wk[(_W + 6) * L + ll] = g20; wk[(_W + 7) * L + ll] = g21; wk[(_W + 8) * L + ll] = g22
                wk[(_W + 18) * L + ll] = J; wk[(_W + 19) * L + ll] = e_v; wk[(_W + 20) * L + ll] = qb
            for a in range(4):
                c0 = group.block_centre[blk, 3 * a, le]
                c1 = group.block_centre[blk, 3 * a + 1, le]
                c2 = group.block_centre[blk, 3 * a + 2, le]
                for ll in range(lanes):
                    s0 = 0.0; s1 = 0.0; s2 = 0.0
                    for k in range(8):
                        h = _H[a, k]
                        s0 += h * wk[(_XV + 3 * k) * L + ll]; s1 += h * wk[(_XV + 3 * k + 1) * L + ll]; s2 += h * wk[(_XV + 3 * k + 2) * L + ll]
                    r0 = wk[(_W + 0) * L + ll] * s0 + wk[(_W + 1) * L + ll] * s1 + wk[(_W + 2) * L + ll] * s2
                    r1 = wk[(_W + 3) * L + ll] * s0 + wk[(_W + 4) * L + ll] * s1 + wk[(_W + 5) * L + ll] * s2
                    r2 = wk[(_W + 6) * L + ll] * s0 + wk[(_W + 7) * L + ll] * s1 + wk[(_W + 8) * L + ll] * s2
                    wk[(_W + 21 + 3 * a) * L + ll] = r0; wk[(_W + 22 + 3 * a) * L + ll] = r1; wk[(_W + 23 + 3 * a) * L + ll] = r2
                    wk[(_W + 33 + 3 * a) * L + ll] = r0 - c0
                    wk[(_W + 34 + 3 * a) * L + ll] = r1 - c1
                    wk[(_W + 35 + 3 * a) * L + ll] = r2 - c2
            for ll in range(lanes):
                wk[(_LNJ) * L + ll] = np.log(wk[(_W + 18) * L + ll])
            k0 = _row12(stiffness, e, 0); k1 = _row12(stiffness, e, 12); k2 = _row12(stiffness, e, 24)
            k3 = _row12(stiffness, e, 36); k4 = _row12(stiffness, e, 48); k5 = _row12(stiffness, e, 60)
            k6 = _row12(stiffness, e, 72); k7 = _row12(stiffness, e, 84); k8 = _row12(stiffness, e, 96)
            k9 = _row12(stiffness, e, 108); k10 = _row12(stiffness, e, 120); k11 = _row12(stiffness, e, 132)
            for ll in range(lanes):
                _hourglass_force(wk, k0, 0, ll, L); _hourglass_force(wk, k1, 1, ll, L); _hourglass_force(wk, k2, 2, ll, L)
                _hourglass_force(wk, k3, 3, ll, L); _hourglass_force(wk, k4, 4, ll, L); _hourglass_force(wk, k5, 5, ll, L)
                _hourglass_force(wk, k6, 6, ll, L); _hourglass_force(wk, k7, 7, ll, L); _hourglass_force(wk, k8, 8, ll, L)
                _hourglass_force(wk, k9, 9, ll, L); _hourglass_force(wk, k10, 10, ll, L); _hourglass_force(wk, k11, 11, ll, L)
            for ll in range(lanes):
                g00 = wk[(_W + 0) * L + ll]; g01 = wk[(_W + 1) * L + ll]; g02 = wk[(_W + 2) * L + ll]
                g10 = wk[(_W + 3) * L + ll]; g11 = wk[(_W + 4) * L + ll]; g12 = wk[(_W + 5) * L + ll]
                g20 = wk[(_W + 6) * L + ll]; g21 = wk[(_W + 7) * L + ll]; g22 = wk[(_W + 8) * L + ll]
                J = wk[(_W + 18) * L + ll]; e_v = wk[(_W + 19) * L + ll]; qb = wk[(_W + 20) * L + ll]; lnJ = wk[(_LNJ) * L + ll]
                f00 = wk[(_W + 9) * L + ll]; f01 = wk[(_W + 10) * L + ll]; f02 = wk[(_W + 11) * L + ll]
                f10 = wk[(_W + 12) * L + ll]; f11 = wk[(_W + 13) * L + ll]; f12 = wk[(_W + 14) * L + ll]
                f20 = wk[(_W + 15) * L + ll]; f21 = wk[(_W + 16) * L + ll]; f22 = wk[(_W + 17) * L + ll]
                I1 = (f00 * f00 + f01 * f01 + f02 * f02 + f10 * f10 + f11 * f11 + f12 * f12
                      + f20 * f20 + f21 * f21 + f22 * f22)
                co = lam * lnJ - mu - qb * J
                P00 = mu * f00 + co * g00; P01 = mu * f01 + co * g10; P02 = mu * f02 + co * g20
                P10 = mu * f10 + co * g01; P11 = mu * f11 + co * g11; P12 = mu * f12 + co * g21
                P20 = mu * f20 + co * g02; P21 = mu * f21 + co * g12; P22 = mu * f22 + co * g22
                s00 = s01 = s02 = s10 = s11 = s12 = s20 = s21 = s22 = 0.0
                whg = 0.0
                for a in range(4):
                    t0 = wk[(_HQ + 3 * a) * L + ll]; t1 = wk[(_HQ + 3 * a + 1) * L + ll]; t2 = wk[(_HQ + 3 * a + 2) * L + ll]
                    whg += 0.5 * (t0 * wk[(_W + 33 + 3 * a) * L + ll] + t1 * wk[(_W + 34 + 3 * a) * L + ll] + t2 * wk[(_W + 35 + 3 * a) * L + ll])
                    u0 = g00 * t0 + g10 * t1 + g20 * t2
                    u1 = g01 * t0 + g11 * t1 + g21 * t2
                    u2 = g02 * t0 + g12 * t1 + g22 * t2
                    r0 = wk[(_W + 21 + 3 * a) * L + ll]; r1 = wk[(_W + 22 + 3 * a) * L + ll]; r2 = wk[(_W + 23 + 3 * a) * L + ll]
                    s00 += u0 * r0; s01 += u0 * r1; s02 += u0 * r2
                    s10 += u1 * r0; s11 += u1 * r1; s12 += u1 * r2
                    s20 += u2 * r0; s21 += u2 * r1; s22 += u2 * r2
                    wk[(_A + 3 * a) * L + ll] = u0
                    wk[(_A + 3 * a + 1) * L + ll] = u1
                    wk[(_A + 3 * a + 2) * L + ll] = u2
                P00 -= iV * s00; P01 -= iV * s01; P02 -= iV * s02
                P10 -= iV * s10; P11 -= iV * s11; P12 -= iV * s12
                P20 -= iV * s20; P21 -= iV * s21; P22 -= iV * s22
                wk[(_P + 0) * L + ll] = P00; wk[(_P + 1) * L + ll] = P01; wk[(_P + 2) * L + ll] = P02
                wk[(_P + 3) * L + ll] = P10; wk[(_P + 4) * L + ll] = P11; wk[(_P + 5) * L + ll] = P12
                wk[(_P + 6) * L + ll] = P20; wk[(_P + 7) * L + ll] = P21; wk[(_P + 8) * L + ll] = P22
                dt_e = wk[(_W + 47) * L + ll]
                dt_min = wk[_R * L + ll]
                wk[_R * L + ll] = dt_e if dt_e < dt_min else dt_min
                wk[(_R + 1) * L + ll] += V0 * (0.5 * mu * (I1 - 3.0) - mu * lnJ + 0.5 * lam * lnJ * lnJ)
                wk[(_R + 2) * L + ll] += whg
                wk[(_R + 3) * L + ll] += -qb * e_v * J * V0
                bad = wk[(_R + 4) * L + ll]
                wk[(_R + 4) * L + ll] = e if (not (J > 0.0) and bad < 0.0) else bad
            for ll in range(lanes):
                _node_forces(wk, bv, 0, ll, L); _node_forces(wk, bv, 1, ll, L); _node_forces(wk, bv, 2, ll, L); _node_forces(wk, bv, 3, ll, L)
                _node_forces(wk, bv, 4, ll, L); _node_forces(wk, bv, 5, ll, L); _node_forces(wk, bv, 6, ll, L); _node_forces(wk, bv, 7, ll, L)
            for k in range(8):
                nd = group.block_nodes[blk, k, le]
                for i in range(3):
                    _add_lanes(sums, (3 * nd + i) * L, wk, (_OUT + 3 * k + i) * L, L)
        ff = f.reshape(-1)
        for nd in range(n_nodes):
            for i in range(3):
                _add_lanes(ff, (3 * nd + i) * n_runs + b0, sums, (3 * nd + i) * L, L)
        for r in range(5):
            for ll in range(lanes):
                result[r, ll] = wk[(_R + r) * L + ll]

    return internal_forces_lanes
