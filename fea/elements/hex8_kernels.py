"""numba-compiled hot loop: internal forces of one-point hexahedra, in blocks of elements.

Same equations as :func:`ccedi.fea.elements.hex8.internal_forces_numpy` (the reference path the
tests compare against); see :mod:`ccedi.fea.elements.hex8` for the formulation. Two exact
rewrites make the kernel cheaper than the reference:

* the hourglass vectors ``gamma_ak = h_ak - b_k . G_a / V0`` with ``G_a = sum_k h_ak X_k``
  (:func:`ccedi.fea.elements.hex8.element_geometry`) give ``q_a = gamma_a . x = h_a . x - F G_a``,
  so the pulled-back hourglass displacement is ``qt_a = r_a - G_a`` with
  ``r_a = F^-1 (h_a . x)``; the hourglass force ``sum_a gamma_ak F^-T Qt_a`` and the
  pull-back term ``-F^-T S b_k / V0`` combine into
  ``sum_a h_ak A_a - (sum_a A_a r_a^T) b_k / V0`` with ``A_a = F^-T Qt_a``. Only the
  +-1 base vectors h_a and the 12 numbers G_a are needed, not the 32 gamma_ak;
* K_hg is symmetric, so its 78 upper-triangle entries are stored.

Elements are processed in blocks of :data:`BLOCK` (structure of arrays, element index
last), every stage a loop over the block's elements that LLVM compiles to SIMD
instructions (the stages write to arrays allocated in the block, which LLVM knows alias
nothing else; the logarithm, which has no SIMD form without Intel's SVML, has its own
loop). Each element's nodal forces go to a per-element array, and each node then sums the
forces of its elements in ascending element order and adds the sum to its force: the
same sum, bit for bit, as a scatter element by element into a zeroed force, and
conflict-free. Blocks (dealt into :data:`CHUNKS` chunks,
each with one set of work arrays) and nodes are spread over numba's threads (``prange``)
and the element values are reduced in element order afterwards, so the results do not
depend on the number of threads (``numba.set_num_threads``).
"""
from collections import namedtuple

import numba as nb
import numpy as np

from ccedi.fea.elements.fastmath import FASTMATH
from ccedi.fea.elements.hex8 import BULK_VISCOSITY_C0, BULK_VISCOSITY_C1, FACES, HOURGLASS_BASE

BLOCK = 32
"""Elements per block: the block's work arrays (about 150 numbers per element) stay in
the 32 KiB first-level cache."""

CHUNKS = 8
"""Blocks are split into this many chunks of consecutive blocks, the unit of work of a
thread (a constant, so that the kernel can be cached: numba's thread count is a run-time
value): up to 8 threads share a mesh's blocks evenly, and on the node-ordered mesh each
thread's elements touch a range of nodes close to the range its node sums cover, so little
data moves between the cores' caches (dealt round-robin instead, two threads ran the drum
step at 137.5 against 123.7 us, one thread 168.8 / 168.6 us)."""

_FACES = FACES.astype(np.int64)
_H = HOURGLASS_BASE.copy()
_UPPER = np.array([[min(r, c) * 12 - min(r, c) * (min(r, c) - 1) // 2 + abs(r - c) for c in range(12)]
                   for r in range(12)], dtype=np.int64)
"""Index of K[r, c] in the packed upper triangle (row by row) of a symmetric 12 x 12."""

# rows of the per-element output: 24 nodal forces, then these
_J, _DT, _WS, _WHG, _PB = range(24, 29)

SolidMaterial = namedtuple("SolidMaterial", "mu lam rho c")
SolidMaterial.__doc__ = """The solid elements' neo-Hookean constants.

Attributes
----------
mu : float
    Shear modulus [Pa].
lam : float
    First Lame constant [Pa].
rho : float
    Mass density [kg/m^3].
c : float
    Dilatational wave speed [m/s].
"""
HexGroup = namedtuple("HexGroup", "hexes b volume gamma kappa length_factor "
                                  "block_nodes block_b block_centre block_stiffness block_volume "
                                  "node_start node_slots element_out")
HexGroup.__doc__ = """One-point hexahedra: the reference arrays and their blocked copies, as
:func:`internal_forces_numba` takes them (:func:`hex_group` builds it).

Attributes
----------
hexes : (n_elem, 8) int ndarray
    Element connectivity.
b : (n_elem, 8, 3) ndarray
    Uniform gradients (reference-volume integrals of the shape-function gradients) [m^2].
volume : (n_elem,) ndarray
    Reference element volumes [m^3].
gamma : (n_elem, 4, 8) ndarray
    Hourglass shape vectors [-].
kappa : (n_elem, 12, 12) ndarray
    Hourglass stiffness K_hg per element, index mode*3 + direction [N/m]
    (:func:`ccedi.fea.elements.hex8.hourglass_stiffness`).
length_factor : float
    Scale on the characteristic length V / A_max of paper Eq. (6) [-]
    (:attr:`ccedi.fea.model.Model.hex_length_factor`).
block_nodes : (n_blocks, 8, BLOCK) int ndarray
    Connectivity by block; element ``i BLOCK + l`` is lane l of block i, and the lanes
    past the last element repeat it.
block_b : (n_blocks, 24, BLOCK) ndarray
    ``b``, row node*3 + direction [m^2].
block_centre : (n_blocks, 12, BLOCK) ndarray
    ``G_a = sum_k h_ak X_k``, row mode*3 + direction [m].
block_stiffness : (n_blocks, 78, BLOCK) ndarray
    Upper triangle of K_hg, row by row [N/m].
block_volume : (n_blocks, BLOCK) ndarray
    Reference volumes [m^3].
node_start : (n_nodes + 1,) int ndarray
    The slots of node n are ``node_slots[node_start[n]:node_start[n + 1]]``.
node_slots : (8 n_elem,) int ndarray
    Flat index into ``element_out`` of the x force of each (element, node) pair, by node
    and then by ascending element.
element_out : (n_blocks, 29, BLOCK) ndarray
    Work array: per element its 24 nodal forces [N], J [-], critical step [s], strain
    energy [J], hourglass energy [J] and bulk-viscous power [W].
"""


def hex_group(nodes, hexes, geometry, *, kappa, length_factor):
    """Blocked hexahedron data for :func:`internal_forces_numba`.

    Parameters
    ----------
    nodes : (n_nodes, 3) ndarray
        Reference nodal positions [m].
    hexes : (n_elem, 8) int ndarray
        Connectivity.
    geometry : ccedi.fea.elements.hex8.ElementGeometry
        Uniform gradients b [m^2], volumes [m^3] and hourglass vectors of the elements.
    kappa : (n_elem, 12, 12) ndarray
        Hourglass stiffness [N/m], symmetric.
    length_factor : float
        Scale on the characteristic length [-].

    Returns
    -------
    HexGroup
        The reference arrays, their blocks and the node-to-element slots.
    """
    hexes = np.asarray(hexes, dtype=np.int64).reshape(-1, 8)
    ne = len(hexes)
    nb_ = -(-ne // BLOCK)
    pad = np.minimum(np.arange(nb_ * BLOCK), max(ne - 1, 0))

    def blocked(a):
        return np.ascontiguousarray(a[pad].reshape(nb_, BLOCK, a.shape[1]).transpose(0, 2, 1))

    centre = np.einsum("ak,eki->eai", _H, nodes[hexes]).reshape(ne, 12)
    iu, ju = np.triu_indices(12)
    upper = kappa[:, iu, ju]
    element_out = np.zeros((nb_, 29, BLOCK))
    e = np.repeat(np.arange(ne), 8)
    k = np.tile(np.arange(8), ne)
    slot = (e // BLOCK) * 29 * BLOCK + 3 * k * BLOCK + e % BLOCK
    order = np.lexsort((e, hexes.ravel()))
    node_start = np.searchsorted(hexes.ravel()[order], np.arange(len(nodes) + 1)).astype(np.int64)
    return HexGroup(hexes, geometry.b, geometry.volume, geometry.gamma, kappa, float(length_factor),
                    blocked(hexes), blocked(geometry.b.reshape(ne, 24)), blocked(centre), blocked(upper),
                    np.ascontiguousarray(geometry.volume[pad].reshape(nb_, BLOCK)), node_start, slot[order],
                    element_out)


@nb.njit(cache=True, fastmath=FASTMATH, inline="always")
def inverse_3x3(f00, f01, f02, f10, f11, f12, f20, f21, f22):
    """J = det F and the entries of F^-1 (``gij`` = (F^-1)_ij), by cofactors: the
    arithmetic both hexahedron kernels share, in one order (their results agree to the bit).

    Parameters
    ----------
    f00, f01, f02, f10, f11, f12, f20, f21, f22 : float
        F, row by row.

    Returns
    -------
    tuple
        ``(J, g00, g01, g02, g10, g11, g12, g20, g21, g22)``.
    """
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
    return J, g00, g01, g02, g10, g11, g12, g20, g21, g22


@nb.njit(cache=True, fastmath=FASTMATH, inline="always")
def bulk_viscosity(e_v, Le, rho, c):
    """Bulk-viscosity pressure and critical step of an element (module docstring of
    :mod:`ccedi.fea.elements.hex8`), shared by both hexahedron kernels.

    Parameters
    ----------
    e_v : float
        Volumetric strain rate [1/s].
    Le : float
        Characteristic length [m].
    rho : float
        Density [kg/m^3].
    c : float
        Dilatational wave speed [m/s].

    Returns
    -------
    tuple
        ``(q [Pa], dt [s])``: q = rho Le (C0 Le e_v^2 - C1 c e_v) in compression, else 0;
        dt = Le / (Q + sqrt(Q^2 + c^2)), Q = C1 c + C0 Le |e_v| in compression, else 0.
    """
    compress = e_v < 0.0
    qb = rho * Le * (BULK_VISCOSITY_C0 * Le * e_v * e_v - BULK_VISCOSITY_C1 * c * e_v) if compress else 0.0
    Q = BULK_VISCOSITY_C1 * c + BULK_VISCOSITY_C0 * Le * (-e_v) if compress else 0.0
    return qb, Le / (Q + np.sqrt(Q * Q + c * c))


@nb.njit(cache=True, fastmath=FASTMATH, error_model="numpy", inline="always")
def _element_block(i, x, v, group, mu, lam, rho, c, xv, w, lnj, dv, hq, out):
    """Nodal forces and element values of block i into ``group.element_out[i]``; xv ... out
    are the work arrays of :func:`_block_chunk`."""
    conn, bb, cen, kk, vol = (group.block_nodes[i], group.block_b[i], group.block_centre[i],
                              group.block_stiffness[i], group.block_volume[i])
    lf = group.length_factor
    for k in range(8):
        for ll in range(BLOCK):
            nd = conn[k, ll]
            xv[3 * k, ll] = x[nd, 0]; xv[3 * k + 1, ll] = x[nd, 1]; xv[3 * k + 2, ll] = x[nd, 2]
            xv[24 + 3 * k, ll] = v[nd, 0]; xv[25 + 3 * k, ll] = v[nd, 1]; xv[26 + 3 * k, ll] = v[nd, 2]
    for ll in range(BLOCK):
        iV = 1.0 / vol[ll]
        f00 = f01 = f02 = f10 = f11 = f12 = f20 = f21 = f22 = 0.0
        for k in range(8):
            x0 = xv[3 * k, ll]; x1 = xv[3 * k + 1, ll]; x2 = xv[3 * k + 2, ll]
            b0 = bb[3 * k, ll]; b1 = bb[3 * k + 1, ll]; b2 = bb[3 * k + 2, ll]
            f00 += x0 * b0; f01 += x0 * b1; f02 += x0 * b2
            f10 += x1 * b0; f11 += x1 * b1; f12 += x1 * b2
            f20 += x2 * b0; f21 += x2 * b1; f22 += x2 * b2
        w[9, ll] = f00 * iV; w[10, ll] = f01 * iV; w[11, ll] = f02 * iV
        w[12, ll] = f10 * iV; w[13, ll] = f11 * iV; w[14, ll] = f12 * iV
        w[15, ll] = f20 * iV; w[16, ll] = f21 * iV; w[17, ll] = f22 * iV
    for ll in range(BLOCK):
        d00 = d01 = d02 = d10 = d11 = d12 = d20 = d21 = d22 = 0.0
        for k in range(8):
            v0 = xv[24 + 3 * k, ll]; v1 = xv[25 + 3 * k, ll]; v2 = xv[26 + 3 * k, ll]
            b0 = bb[3 * k, ll]; b1 = bb[3 * k + 1, ll]; b2 = bb[3 * k + 2, ll]
            d00 += v0 * b0; d01 += v0 * b1; d02 += v0 * b2
            d10 += v1 * b0; d11 += v1 * b1; d12 += v1 * b2
            d20 += v2 * b0; d21 += v2 * b1; d22 += v2 * b2
        dv[0, ll] = d00; dv[1, ll] = d01; dv[2, ll] = d02
        dv[3, ll] = d10; dv[4, ll] = d11; dv[5, ll] = d12
        dv[6, ll] = d20; dv[7, ll] = d21; dv[8, ll] = d22
    for ll in range(BLOCK):
        amax2 = 0.0
        for fc in range(6):
            a0 = _FACES[fc, 0]; a1 = _FACES[fc, 1]; a2 = _FACES[fc, 2]; a3 = _FACES[fc, 3]
            p0 = xv[3 * a2, ll] - xv[3 * a0, ll]
            p1 = xv[3 * a2 + 1, ll] - xv[3 * a0 + 1, ll]
            p2 = xv[3 * a2 + 2, ll] - xv[3 * a0 + 2, ll]
            r0 = xv[3 * a3, ll] - xv[3 * a1, ll]
            r1 = xv[3 * a3 + 1, ll] - xv[3 * a1 + 1, ll]
            r2 = xv[3 * a3 + 2, ll] - xv[3 * a1 + 2, ll]
            cx = p1 * r2 - p2 * r1; cy = p2 * r0 - p0 * r2; cz = p0 * r1 - p1 * r0
            amax2 = max(amax2, cx * cx + cy * cy + cz * cz)
        lnj[ll] = amax2
    for ll in range(BLOCK):
        V0 = vol[ll]
        iV = 1.0 / V0
        f00 = w[9, ll]; f01 = w[10, ll]; f02 = w[11, ll]
        f10 = w[12, ll]; f11 = w[13, ll]; f12 = w[14, ll]
        f20 = w[15, ll]; f21 = w[16, ll]; f22 = w[17, ll]
        J, g00, g01, g02, g10, g11, g12, g20, g21, g22 = inverse_3x3(f00, f01, f02, f10, f11, f12, f20, f21, f22)
        e_v = iV * (dv[0, ll] * g00 + dv[1, ll] * g10 + dv[2, ll] * g20 + dv[3, ll] * g01 + dv[4, ll] * g11
                    + dv[5, ll] * g21 + dv[6, ll] * g02 + dv[7, ll] * g12 + dv[8, ll] * g22)
        Le = lf * 2.0 * J * V0 / np.sqrt(lnj[ll])
        qb, w[47, ll] = bulk_viscosity(e_v, Le, rho, c)
        w[0, ll] = g00; w[1, ll] = g01; w[2, ll] = g02
        w[3, ll] = g10; w[4, ll] = g11; w[5, ll] = g12
        w[6, ll] = g20; w[7, ll] = g21; w[8, ll] = g22
        w[18, ll] = J; w[19, ll] = e_v; w[20, ll] = qb
    for a in range(4):
        for ll in range(BLOCK):
            s0 = 0.0; s1 = 0.0; s2 = 0.0
            for k in range(8):
                h = _H[a, k]
                s0 += h * xv[3 * k, ll]; s1 += h * xv[3 * k + 1, ll]; s2 += h * xv[3 * k + 2, ll]
            r0 = w[0, ll] * s0 + w[1, ll] * s1 + w[2, ll] * s2
            r1 = w[3, ll] * s0 + w[4, ll] * s1 + w[5, ll] * s2
            r2 = w[6, ll] * s0 + w[7, ll] * s1 + w[8, ll] * s2
            w[21 + 3 * a, ll] = r0; w[22 + 3 * a, ll] = r1; w[23 + 3 * a, ll] = r2
            w[33 + 3 * a, ll] = r0 - cen[3 * a, ll]
            w[34 + 3 * a, ll] = r1 - cen[3 * a + 1, ll]
            w[35 + 3 * a, ll] = r2 - cen[3 * a + 2, ll]
    for ll in range(BLOCK):
        lnj[ll] = np.log(w[18, ll])
    for r in range(12):
        for ll in range(BLOCK):
            acc = 0.0
            for cc in range(12):
                acc += kk[_UPPER[r, cc], ll] * w[33 + cc, ll]
            hq[r, ll] = acc
    for ll in range(BLOCK):
        g00 = w[0, ll]; g01 = w[1, ll]; g02 = w[2, ll]
        g10 = w[3, ll]; g11 = w[4, ll]; g12 = w[5, ll]
        g20 = w[6, ll]; g21 = w[7, ll]; g22 = w[8, ll]
        J = w[18, ll]; e_v = w[19, ll]; qb = w[20, ll]; lnJ = lnj[ll]
        V0 = vol[ll]
        iV = 1.0 / V0
        f00 = w[9, ll]; f01 = w[10, ll]; f02 = w[11, ll]
        f10 = w[12, ll]; f11 = w[13, ll]; f12 = w[14, ll]
        f20 = w[15, ll]; f21 = w[16, ll]; f22 = w[17, ll]
        I1 = (f00 * f00 + f01 * f01 + f02 * f02 + f10 * f10 + f11 * f11 + f12 * f12
              + f20 * f20 + f21 * f21 + f22 * f22)
        co = lam * lnJ - mu - qb * J
        P00 = mu * f00 + co * g00; P01 = mu * f01 + co * g10; P02 = mu * f02 + co * g20
        P10 = mu * f10 + co * g01; P11 = mu * f11 + co * g11; P12 = mu * f12 + co * g21
        P20 = mu * f20 + co * g02; P21 = mu * f21 + co * g12; P22 = mu * f22 + co * g22
        s00 = s01 = s02 = s10 = s11 = s12 = s20 = s21 = s22 = 0.0
        whg = 0.0
        # A_a = F^-T Qt_a, S = sum_a A_a r_a^T; forces: (P - S / V0) b_k + sum_a h_ak A_a
        A00 = A01 = A02 = A10 = A11 = A12 = A20 = A21 = A22 = A30 = A31 = A32 = 0.0
        for a in range(4):
            t0 = hq[3 * a, ll]; t1 = hq[3 * a + 1, ll]; t2 = hq[3 * a + 2, ll]
            whg += 0.5 * (t0 * w[33 + 3 * a, ll] + t1 * w[34 + 3 * a, ll] + t2 * w[35 + 3 * a, ll])
            u0 = g00 * t0 + g10 * t1 + g20 * t2
            u1 = g01 * t0 + g11 * t1 + g21 * t2
            u2 = g02 * t0 + g12 * t1 + g22 * t2
            r0 = w[21 + 3 * a, ll]; r1 = w[22 + 3 * a, ll]; r2 = w[23 + 3 * a, ll]
            s00 += u0 * r0; s01 += u0 * r1; s02 += u0 * r2
            s10 += u1 * r0; s11 += u1 * r1; s12 += u1 * r2
            s20 += u2 * r0; s21 += u2 * r1; s22 += u2 * r2
            if a == 0:
                A00 = u0; A01 = u1; A02 = u2
            elif a == 1:
                A10 = u0; A11 = u1; A12 = u2
            elif a == 2:
                A20 = u0; A21 = u1; A22 = u2
            else:
                A30 = u0; A31 = u1; A32 = u2
        P00 -= iV * s00; P01 -= iV * s01; P02 -= iV * s02
        P10 -= iV * s10; P11 -= iV * s11; P12 -= iV * s12
        P20 -= iV * s20; P21 -= iV * s21; P22 -= iV * s22
        for k in range(8):
            b0 = bb[3 * k, ll]; b1 = bb[3 * k + 1, ll]; b2 = bb[3 * k + 2, ll]
            h0 = _H[0, k]; h1 = _H[1, k]; h2 = _H[2, k]; h3 = _H[3, k]
            out[3 * k, ll] = P00 * b0 + P01 * b1 + P02 * b2 + h0 * A00 + h1 * A10 + h2 * A20 + h3 * A30
            out[3 * k + 1, ll] = P10 * b0 + P11 * b1 + P12 * b2 + h0 * A01 + h1 * A11 + h2 * A21 + h3 * A31
            out[3 * k + 2, ll] = P20 * b0 + P21 * b1 + P22 * b2 + h0 * A02 + h1 * A12 + h2 * A22 + h3 * A32
        out[_J, ll] = J
        out[_DT, ll] = w[47, ll]
        out[_WS, ll] = V0 * (0.5 * mu * (I1 - 3.0) - mu * lnJ + 0.5 * lam * lnJ * lnJ)
        out[_WHG, ll] = whg
        out[_PB, ll] = -qb * e_v * J * V0
    dest = group.element_out[i]
    for r in range(29):
        for ll in range(BLOCK):
            dest[r, ll] = out[r, ll]


@nb.njit(cache=True, fastmath=FASTMATH, error_model="numpy", inline="always")
def _block_chunk(ch, chunks, x, v, group, mu, lam, rho, c):
    """Chunk ch of ``chunks`` (consecutive blocks) with one set of work arrays.

    The work arrays are allocated here, in the function that uses them (inlined with
    :func:`_element_block`), so that LLVM knows they alias nothing else and compiles the
    stages to SIMD loops; once per chunk rather than once per block."""
    xv = np.empty((48, BLOCK))           # gathered positions (row 3k + i) and velocities (24 + 3k + i)
    w = np.empty((48, BLOCK))            # F^-1 (9), F (9), J, e_v, q, r_a (12), qt_a (12), dt
    lnj = np.empty(BLOCK)
    dv = np.empty((9, BLOCK))            # sum_k v_k b_k^T
    hq = np.empty((12, BLOCK))           # Qt = K_hg qt
    out = np.empty((29, BLOCK))
    n = group.block_nodes.shape[0]
    for i in range(ch * n // chunks, (ch + 1) * n // chunks):
        _element_block(i, x, v, group, mu, lam, rho, c, xv, w, lnj, dv, hq, out)


@nb.njit(cache=True, fastmath=FASTMATH, parallel=True)
def internal_forces_numba(x, v, group, material, f):
    """Internal nodal forces of one-point (uniform-gradient) hexahedra, compiled.

    For each element e with reference volume V0 and uniform gradients b_k the kernel
    forms the deformation gradient and its rate::

        F = (1/V0) sum_k x_k b_k^T,        Fdot = (1/V0) sum_k v_k b_k^T,

    the volumetric strain rate ``e_v = tr(Fdot F^-1)``, the bulk-viscosity pressure
    ``q = rho Le (C0 Le e_v^2 - C1 c e_v)`` (compression only, ``e_v < 0``), the
    neo-Hookean first Piola-Kirchhoff stress with that pressure
    ``P = mu F + (lam ln J - mu - q J) F^-T``, the pulled-back hourglass displacements
    ``r_a = F^-1 sum_k h_ak x_k``, ``qt_a = r_a - G_a``, their forces ``Qt = K_hg qt``
    (K_hg 12 x 12), ``A_a = F^-T Qt_a``, ``S = sum_a A_a r_a^T`` and the nodal force::

        f_k = (P - S / V0) b_k + sum_a h_ak A_a

    (equal to the reference's ``(P - F^-T S_ref / V0) b_k + sum_a gamma_ak A_a``, see the
    module docstring). The element's critical step is ``Le / (Q + sqrt(Q^2 + c^2))``
    with ``Q = C1 c + C0 Le (-e_v)`` and the characteristic length
    ``Le = length_factor J V0 / A_max`` (current volume over the largest face area,
    A = |d1 x d2| / 2 of the face diagonals).

    Parameters
    ----------
    x : (n_nodes, 3) ndarray
        Current nodal coordinates [m].
    v : (n_nodes, 3) ndarray
        Nodal velocities [m/s] (for the bulk viscosity).
    group : HexGroup
        The hexahedra (:func:`hex_group`); its ``element_out`` is overwritten.
    material : tuple
        (mu [Pa], lam [Pa], rho [kg/m^3], c [m/s]): shear modulus, first Lame constant,
        density, dilatational wave speed (:class:`SolidMaterial`).
    f : (n_nodes, 3) ndarray
        Nodal forces [N]; the internal forces are ADDED to it (the force-term contract of
        :mod:`ccedi.fea.solvers.force_terms`).

    Returns
    -------
    dt_min : float
        Smallest element critical time step [s] (``inf`` for no elements, which add
        nothing).
    strain_energy : float
        Stored elastic energy sum_e V0 W(F) [J], summed in element order.
    hourglass_energy : float
        Hourglass energy sum_e qt^T K_hg qt / 2 [J].
    bulk_viscous_power : float
        Power dissipated by the bulk viscosity [W].
    status : int
        -1 when every element has J > 0; else the index of the first inverted element
        (J <= 0), in which case the other values are 0 and ``f`` is untouched.
    """
    if group.hexes.shape[0] == 0:
        return np.inf, 0.0, 0.0, 0.0, -1
    mu, lam, rho, c = material[0], material[1], material[2], material[3]
    chunks = min(CHUNKS, group.block_nodes.shape[0])
    for ch in nb.prange(chunks):
        _block_chunk(ch, chunks, x, v, group, mu, lam, rho, c)
    out = group.element_out
    dt_min = np.inf; w_s = 0.0; w_hg = 0.0; p_b = 0.0
    for e in range(group.hexes.shape[0]):
        i = e // BLOCK
        ll = e % BLOCK
        if not (out[i, _J, ll] > 0.0):
            return 0.0, 0.0, 0.0, 0.0, e
        dt_min = min(dt_min, out[i, _DT, ll])
        w_s += out[i, _WS, ll]
        w_hg += out[i, _WHG, ll]
        p_b += out[i, _PB, ll]
    flat = out.reshape(-1)
    start, slots = group.node_start, group.node_slots
    for nd in nb.prange(f.shape[0]):
        s0 = 0.0; s1 = 0.0; s2 = 0.0
        for s in range(start[nd], start[nd + 1]):
            j = slots[s]
            s0 += flat[j]; s1 += flat[j + BLOCK]; s2 += flat[j + 2 * BLOCK]
        f[nd, 0] += s0; f[nd, 1] += s1; f[nd, 2] += s2
    return dt_min, w_s, w_hg, p_b, -1
