"""numba-compiled hot loop: internal forces of one-point hexahedra.

Same contract and equations as :func:`ccedi.fea.hex8.internal_forces_numpy` (the reference
path the tests compare against); see :mod:`ccedi.fea.hex8` for the formulation.
"""
import numba as nb
import numpy as np

from .fastmath import FASTMATH
from .hex8 import BULK_VISCOSITY_C0, BULK_VISCOSITY_C1, FACES

_FACES = FACES.astype(np.int64)


@nb.njit(cache=True, fastmath=FASTMATH)
def internal_forces_numba(x, v, hexes, b, volume, gamma, kappa, length_factor, mu, lam, rho, c, f):
    """Internal nodal forces of one-point (uniform-gradient) hexahedra, compiled.

    For each element e with reference volume V0 and uniform gradients b_k the kernel
    forms the deformation gradient and its rate::

        F = (1/V0) sum_k x_k b_k^T,        Fdot = (1/V0) sum_k v_k b_k^T,

    the volumetric strain rate ``e_v = tr(Fdot F^-1)``, the bulk-viscosity pressure
    ``q = rho Le (C0 Le e_v^2 - C1 c e_v)`` (compression only, ``e_v < 0``), the
    neo-Hookean first Piola-Kirchhoff stress with that pressure
    ``P = mu F + (lam ln J - mu - q J) F^-T``, the pulled-back hourglass displacements
    and their forces ``qt_a = F^-1 sum_k gamma_ak x_k``, ``Qt = K_hg qt`` (K_hg = kappa[e],
    12 x 12), ``S = sum_a Qt_a qt_a^T`` and the nodal force::

        f_k = (P - F^-T S / V0) b_k + sum_a gamma_ak F^-T Qt_a.

    The element's critical step is ``Le / (Q + sqrt(Q^2 + c^2))`` with
    ``Q = C1 c + C0 Le (-e_v)`` and the characteristic length ``Le = J V0 / A_max``
    (current volume over the largest face area, A = |d1 x d2| / 2 of the face diagonals).
    The 3x3 tensors F, Fdot, F^-1 and P live in scalar locals (registers) rather than
    small arrays, which is what makes this loop fast; the algebra is line for line
    :func:`ccedi.fea.hex8.internal_forces_numpy`.

    Parameters
    ----------
    x : (n_nodes, 3) ndarray
        Current nodal coordinates [m].
    v : (n_nodes, 3) ndarray
        Nodal velocities [m/s] (for the bulk viscosity).
    hexes : (n_elem, 8) int ndarray
        Element connectivity (node indices).
    b : (n_elem, 8, 3) ndarray
        Uniform gradients b_k = integral of grad N_k over the reference element [m^2].
    volume : (n_elem,) ndarray
        Reference element volumes V0 [m^3].
    gamma : (n_elem, 4, 8) ndarray
        Hourglass shape vectors gamma_ak [-].
    kappa : (n_elem, 12, 12) ndarray
        Hourglass stiffness K_hg per element, index mode*3 + direction [N/m]
        (:func:`ccedi.fea.hex8.hourglass_stiffness`).
    length_factor : float
        Scale on the characteristic length ``J V0 / A_max`` [-]
        (:attr:`ccedi.fea.model.Model.hex_length_factor`).
    mu : float
        Shear modulus [Pa].
    lam : float
        First Lame constant [Pa].
    rho : float
        Mass density [kg/m^3].
    c : float
        Dilatational wave speed [m/s].
    f : (n_nodes, 3) ndarray
        Output: overwritten with the internal nodal forces [N].

    Returns
    -------
    dt_min : float
        Smallest element critical time step [s] (``inf`` for no elements).
    strain_energy : float
        Stored elastic energy sum_e V0 W(F) [J].
    hourglass_energy : float
        Hourglass energy sum_e qt^T K_hg qt / 2 [J].
    bulk_viscous_power : float
        Power dissipated by the bulk viscosity [W].
    status : int
        -1 when every element has J > 0; else the index of the first inverted element
        (J <= 0), in which case the other values are 0 and ``f`` holds only the partial
        sum of the elements before it (to be discarded).
    """
    f[:, :] = 0.0
    ne = hexes.shape[0]
    dt_min = np.inf; w_s = 0.0; w_hg = 0.0; p_b = 0.0
    xe = np.empty((8, 3))
    qt = np.empty(12)
    Qt = np.empty(12)
    A = np.empty((4, 3))
    for e in range(ne):
        iV = 1.0 / volume[e]
        f00 = f01 = f02 = f10 = f11 = f12 = f20 = f21 = f22 = 0.0
        d00 = d01 = d02 = d10 = d11 = d12 = d20 = d21 = d22 = 0.0
        for k in range(8):
            nd = hexes[e, k]
            x0 = x[nd, 0]; x1 = x[nd, 1]; x2 = x[nd, 2]
            v0 = v[nd, 0]; v1 = v[nd, 1]; v2 = v[nd, 2]
            xe[k, 0] = x0; xe[k, 1] = x1; xe[k, 2] = x2
            b0 = b[e, k, 0]; b1 = b[e, k, 1]; b2 = b[e, k, 2]
            f00 += x0 * b0; f01 += x0 * b1; f02 += x0 * b2
            f10 += x1 * b0; f11 += x1 * b1; f12 += x1 * b2
            f20 += x2 * b0; f21 += x2 * b1; f22 += x2 * b2
            d00 += v0 * b0; d01 += v0 * b1; d02 += v0 * b2
            d10 += v1 * b0; d11 += v1 * b1; d12 += v1 * b2
            d20 += v2 * b0; d21 += v2 * b1; d22 += v2 * b2
        f00 *= iV; f01 *= iV; f02 *= iV; f10 *= iV; f11 *= iV; f12 *= iV; f20 *= iV; f21 *= iV; f22 *= iV
        c00 = f11 * f22 - f12 * f21
        c01 = f12 * f20 - f10 * f22
        c02 = f10 * f21 - f11 * f20
        J = f00 * c00 + f01 * c01 + f02 * c02
        if not (J > 0.0):
            return 0.0, 0.0, 0.0, 0.0, e
        iJ = 1.0 / J
        # inverse F^-1 entries g_ij
        g00 = c00 * iJ; g10 = c01 * iJ; g20 = c02 * iJ
        g01 = (f02 * f21 - f01 * f22) * iJ
        g11 = (f00 * f22 - f02 * f20) * iJ
        g21 = (f01 * f20 - f00 * f21) * iJ
        g02 = (f01 * f12 - f02 * f11) * iJ
        g12 = (f02 * f10 - f00 * f12) * iJ
        g22 = (f00 * f11 - f01 * f10) * iJ
        # e_v = tr(Fdot F^-1) = sum_ij d_ij g_ji  (d not yet divided by V0)
        e_v = iV * (d00 * g00 + d01 * g10 + d02 * g20 + d10 * g01 + d11 * g11 + d12 * g21
                    + d20 * g02 + d21 * g12 + d22 * g22)
        I1 = (f00 * f00 + f01 * f01 + f02 * f02 + f10 * f10 + f11 * f11 + f12 * f12
              + f20 * f20 + f21 * f21 + f22 * f22)
        amax2 = 0.0
        for fc in range(6):
            a0 = _FACES[fc, 0]; a1 = _FACES[fc, 1]; a2 = _FACES[fc, 2]; a3 = _FACES[fc, 3]
            p0 = xe[a2, 0] - xe[a0, 0]; p1 = xe[a2, 1] - xe[a0, 1]; p2 = xe[a2, 2] - xe[a0, 2]
            r0 = xe[a3, 0] - xe[a1, 0]; r1 = xe[a3, 1] - xe[a1, 1]; r2 = xe[a3, 2] - xe[a1, 2]
            cx = p1 * r2 - p2 * r1; cy = p2 * r0 - p0 * r2; cz = p0 * r1 - p1 * r0
            amax2 = max(amax2, cx * cx + cy * cy + cz * cz)
        V0 = volume[e]
        Le = length_factor * 2.0 * J * V0 / np.sqrt(amax2)
        qb = 0.0; Q = 0.0
        if e_v < 0.0:
            qb = rho * Le * (BULK_VISCOSITY_C0 * Le * e_v * e_v - BULK_VISCOSITY_C1 * c * e_v)
            Q = BULK_VISCOSITY_C1 * c + BULK_VISCOSITY_C0 * Le * (-e_v)
        dte = Le / (Q + np.sqrt(Q * Q + c * c))
        dt_min = min(dt_min, dte)
        lnJ = np.log(J)
        w_s += V0 * (0.5 * mu * (I1 - 3.0) - mu * lnJ + 0.5 * lam * lnJ * lnJ)
        p_b -= qb * e_v * J * V0
        co = lam * lnJ - mu - qb * J
        # P = mu F + co F^-T  -> P_ij = mu f_ij + co g_ji
        P00 = mu * f00 + co * g00; P01 = mu * f01 + co * g10; P02 = mu * f02 + co * g20
        P10 = mu * f10 + co * g01; P11 = mu * f11 + co * g11; P12 = mu * f12 + co * g21
        P20 = mu * f20 + co * g02; P21 = mu * f21 + co * g12; P22 = mu * f22 + co * g22
        # hourglass: qt_a = F^-1 q_a, Qt = K_hg qt, A_a = F^-T Qt_a, S = sum_a Qt_a qt_a^T
        for a in range(4):
            s0 = 0.0; s1 = 0.0; s2 = 0.0
            for k in range(8):
                gk = gamma[e, a, k]
                s0 += gk * xe[k, 0]; s1 += gk * xe[k, 1]; s2 += gk * xe[k, 2]
            qt[3 * a] = g00 * s0 + g01 * s1 + g02 * s2
            qt[3 * a + 1] = g10 * s0 + g11 * s1 + g12 * s2
            qt[3 * a + 2] = g20 * s0 + g21 * s1 + g22 * s2
        for r in range(12):
            acc = 0.0
            for cc in range(12):
                acc += kappa[e, r, cc] * qt[cc]
            Qt[r] = acc
        s00 = s01 = s02 = s10 = s11 = s12 = s20 = s21 = s22 = 0.0
        for a in range(4):
            t0 = Qt[3 * a]; t1 = Qt[3 * a + 1]; t2 = Qt[3 * a + 2]
            u0 = qt[3 * a]; u1 = qt[3 * a + 1]; u2 = qt[3 * a + 2]
            w_hg += 0.5 * (t0 * u0 + t1 * u1 + t2 * u2)
            s00 += t0 * u0; s01 += t0 * u1; s02 += t0 * u2
            s10 += t1 * u0; s11 += t1 * u1; s12 += t1 * u2
            s20 += t2 * u0; s21 += t2 * u1; s22 += t2 * u2
            A[a, 0] = g00 * t0 + g10 * t1 + g20 * t2
            A[a, 1] = g01 * t0 + g11 * t1 + g21 * t2
            A[a, 2] = g02 * t0 + g12 * t1 + g22 * t2
        # P -= F^-T S / V0:  (F^-T S)_ij = sum_m g_mi s_mj
        P00 -= iV * (g00 * s00 + g10 * s10 + g20 * s20)
        P01 -= iV * (g00 * s01 + g10 * s11 + g20 * s21)
        P02 -= iV * (g00 * s02 + g10 * s12 + g20 * s22)
        P10 -= iV * (g01 * s00 + g11 * s10 + g21 * s20)
        P11 -= iV * (g01 * s01 + g11 * s11 + g21 * s21)
        P12 -= iV * (g01 * s02 + g11 * s12 + g21 * s22)
        P20 -= iV * (g02 * s00 + g12 * s10 + g22 * s20)
        P21 -= iV * (g02 * s01 + g12 * s11 + g22 * s21)
        P22 -= iV * (g02 * s02 + g12 * s12 + g22 * s22)
        for k in range(8):
            b0 = b[e, k, 0]; b1 = b[e, k, 1]; b2 = b[e, k, 2]
            h0 = gamma[e, 0, k]; h1 = gamma[e, 1, k]; h2 = gamma[e, 2, k]; h3 = gamma[e, 3, k]
            nd = hexes[e, k]
            f[nd, 0] += P00 * b0 + P01 * b1 + P02 * b2 + h0 * A[0, 0] + h1 * A[1, 0] + h2 * A[2, 0] + h3 * A[3, 0]
            f[nd, 1] += P10 * b0 + P11 * b1 + P12 * b2 + h0 * A[0, 1] + h1 * A[1, 1] + h2 * A[2, 1] + h3 * A[3, 1]
            f[nd, 2] += P20 * b0 + P21 * b1 + P22 * b2 + h0 * A[0, 2] + h1 * A[1, 2] + h2 * A[2, 2] + h3 * A[3, 2]
    return dt_min, w_s, w_hg, p_b, -1
