"""numba-compiled hot loop: internal forces of one-point hexahedra.

Same contract and equations as :func:`fea.hex8.internal_forces_numpy` (the reference
path the tests compare against); see :mod:`fea.hex8` for the formulation.
"""
import numba as nb
import numpy as np

from .hex8 import BULK_VISCOSITY_C0, BULK_VISCOSITY_C1, FACES

_FACES = FACES.astype(np.int64)


@nb.njit(cache=True, fastmath=True)
def internal_forces_numba(x, v, hexes, b, volume, gamma, kappa, mu, lam, rho, c, f):
    """Nodal internal forces into ``f`` (n, 3) [N]; returns
    ``(dt_min, strain_energy, hourglass_energy, bulk_viscous_power, status)``."""
    f[:, :] = 0.0
    ne = hexes.shape[0]
    dt_min = np.inf
    w_strain = 0.0
    w_hg = 0.0
    p_bulk = 0.0
    xe = np.empty((8, 3))
    ve = np.empty((8, 3))
    F = np.empty((3, 3))
    Fd = np.empty((3, 3))
    Fi = np.empty((3, 3))
    P = np.empty((3, 3))
    q = np.empty((4, 3))
    fe = np.empty((8, 3))
    for e in range(ne):
        V0 = volume[e]
        for k in range(8):
            n = hexes[e, k]
            for i in range(3):
                xe[k, i] = x[n, i]
                ve[k, i] = v[n, i]
        for i in range(3):
            for j in range(3):
                s = 0.0
                sd = 0.0
                for k in range(8):
                    s += xe[k, i] * b[e, k, j]
                    sd += ve[k, i] * b[e, k, j]
                F[i, j] = s / V0
                Fd[i, j] = sd / V0
        # cofactor inverse
        c00 = F[1, 1] * F[2, 2] - F[1, 2] * F[2, 1]
        c01 = F[1, 2] * F[2, 0] - F[1, 0] * F[2, 2]
        c02 = F[1, 0] * F[2, 1] - F[1, 1] * F[2, 0]
        J = F[0, 0] * c00 + F[0, 1] * c01 + F[0, 2] * c02
        if not (J > 0.0):
            return 0.0, 0.0, 0.0, 0.0, e
        Fi[0, 0] = c00 / J
        Fi[1, 0] = c01 / J
        Fi[2, 0] = c02 / J
        Fi[0, 1] = (F[0, 2] * F[2, 1] - F[0, 1] * F[2, 2]) / J
        Fi[1, 1] = (F[0, 0] * F[2, 2] - F[0, 2] * F[2, 0]) / J
        Fi[2, 1] = (F[0, 1] * F[2, 0] - F[0, 0] * F[2, 1]) / J
        Fi[0, 2] = (F[0, 1] * F[1, 2] - F[0, 2] * F[1, 1]) / J
        Fi[1, 2] = (F[0, 2] * F[1, 0] - F[0, 0] * F[1, 2]) / J
        Fi[2, 2] = (F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]) / J
        e_v = 0.0
        I1 = 0.0
        for i in range(3):
            for j in range(3):
                e_v += Fd[i, j] * Fi[j, i]
                I1 += F[i, j] * F[i, j]
        # characteristic length Le = V / A_max (current)
        amax = 0.0
        for fc in range(6):
            a0 = _FACES[fc, 0]
            a1 = _FACES[fc, 1]
            a2 = _FACES[fc, 2]
            a3 = _FACES[fc, 3]
            d1x = xe[a2, 0] - xe[a0, 0]
            d1y = xe[a2, 1] - xe[a0, 1]
            d1z = xe[a2, 2] - xe[a0, 2]
            d2x = xe[a3, 0] - xe[a1, 0]
            d2y = xe[a3, 1] - xe[a1, 1]
            d2z = xe[a3, 2] - xe[a1, 2]
            cx = d1y * d2z - d1z * d2y
            cy = d1z * d2x - d1x * d2z
            cz = d1x * d2y - d1y * d2x
            area = 0.5 * np.sqrt(cx * cx + cy * cy + cz * cz)
            if area > amax:
                amax = area
        Le = J * V0 / amax
        qbv = 0.0
        Q = 0.0
        if e_v < 0.0:
            qbv = rho * Le * (BULK_VISCOSITY_C0 * Le * e_v * e_v - BULK_VISCOSITY_C1 * c * e_v)
            Q = BULK_VISCOSITY_C1 * c + BULK_VISCOSITY_C0 * Le * (-e_v)
        dte = Le / (Q + np.sqrt(Q * Q + c * c))
        if dte < dt_min:
            dt_min = dte
        lnJ = np.log(J)
        w_strain += V0 * (0.5 * mu * (I1 - 3.0) - mu * lnJ + 0.5 * lam * lnJ * lnJ)
        p_bulk += -qbv * e_v * J * V0
        coef = lam * lnJ - mu - qbv * J
        for i in range(3):
            for j in range(3):
                P[i, j] = mu * F[i, j] + coef * Fi[j, i]
        kap = kappa[e]
        for a in range(4):
            for i in range(3):
                s = 0.0
                for k in range(8):
                    s += gamma[e, a, k] * xe[k, i]
                q[a, i] = s
                w_hg += 0.5 * kap * s * s
        for k in range(8):
            for i in range(3):
                s = 0.0
                for j in range(3):
                    s += P[i, j] * b[e, k, j]
                h = 0.0
                for a in range(4):
                    h += gamma[e, a, k] * q[a, i]
                fe[k, i] = s + kap * h
        for k in range(8):
            n = hexes[e, k]
            for i in range(3):
                f[n, i] += fe[k, i]
    return dt_min, w_strain, w_hg, p_bulk, -1
