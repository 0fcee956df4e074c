"""Explicit dynamics of the superelement chain on the rotating drum, with penalty contact
and Coulomb friction against the rigid elliptical object (issue 5, part B).

Frame: the drum's rotating frame (floating frame of reference). Planar coordinates
p = (p1, p2) of each station centre: p1 along the undeformed finger (radial, from the
drum axis), p2 across it (tangential); station rotation theta about the drum axis. A
point p of the frame sits at ``X = R(phi) p`` in space, phi = theta0 + Omega t. The drum
turns at the constant rate Omega, so the absolute acceleration of a station is::

    a_abs = p'' + 2 Omega J p' - Omega^2 p           J = [[0, -1], [1, 0]]
              (relative + Coriolis + centripetal; the Euler term Omega' J p is zero)

and each station (mass m, rotary inertia I) obeys::

    m p''     = f_int + f_contact + m Omega^2 p - 2 m Omega J p' - f_damp
    I theta'' = m_int + m_contact - m_damp
    f_damp = alpha m (p' + Omega J p),  m_damp = alpha I (theta' + Omega)   (damping "global")
    f_damp = alpha m p',                m_damp = alpha I theta'             (damping "relative")

Global damping acts on the absolute velocity (the drag that makes a damped finger
trail the drum), relative damping on the velocity in the drum's frame, as in
:mod:`fea.drum`. Station 0 is clamped to the drum.

Internal forces, co-rotational (``nonlinear=True``): each segment's chord of current
length l and angle psi defines its frame; the natural deformations
``e = [l - l0, theta_a - psi, theta_b - psi]`` give the section forces ``s = K_n e``
and the station forces ``f = B^T s`` with B = de/dq (Crisfield's planar co-rotational
beam). Large rotations are exact; strains within a segment stay small. Linear
(``nonlinear=False``): the same with B, l and psi frozen at the straight finger,
``psi = (V_b - V_a) / l0``: the Craig-Bampton model of small displacements.

Contact points sit on both faces of every station, at r = R(theta) (0, +-h)
(linear: r = (0, +-h) + theta J (0, +-h)), h the section's half thickness. Each point
penetrating the object gets ``f_n = k d`` along the object's outward normal, with
``k = (1/0.81 - 1) (2/dt_cfl)^2 / (1/m + h^2/I)`` (the rule of :mod:`fea.contact`, for the
point's effective mass) and the step shrunk by 0.9. Friction is Coulomb, applied as in
:mod:`fea.explicit`: the force that would stop the point's tangential velocity within
the step, clipped to mu f_n.

Central differences: ``v^{n+1/2} = [(1 - alpha dt/2) v^{n-1/2} + dt f / m] / (1 + alpha dt/2)``
with the damping centred and Coriolis from v^{n-1/2}.
"""
import numba as nb
import numpy as np

from fea.contact import STEP_SHRINK, _ellipse_gap, penalty_stiffness
from fea.explicit import TSSFAC
from fea.kernels import FASTMATH

# per-output contact record slots
_FX, _FY, _NPTS, _PX, _PY, _PEN = range(6)


@nb.njit(cache=True, fastmath=FASTMATH)
def _internal_forces(P, TH, l0, Kn, nonlinear, F, Mo, E):
    """Station forces F (n+1, 2), moments Mo (n+1,) (ADDED) and natural deformations E (n, 3)."""
    for s in range(l0.shape[0]):
        a = s
        b = s + 1
        dx = P[b, 0] - P[a, 0]
        dy = P[b, 1] - P[a, 1]
        if nonlinear:
            ln = np.sqrt(dx * dx + dy * dy)
            c = dx / ln
            sn = dy / ln
            psi = np.arctan2(dy, dx)
            e1 = ln - l0[s]
        else:
            ln = l0[s]
            c = 1.0
            sn = 0.0
            psi = dy / ln
            e1 = dx - ln
        e2 = TH[a] - psi
        e3 = TH[b] - psi
        N = Kn[s, 0, 0] * e1 + Kn[s, 0, 1] * e2 + Kn[s, 0, 2] * e3
        Ma = Kn[s, 1, 0] * e1 + Kn[s, 1, 1] * e2 + Kn[s, 1, 2] * e3
        Mb = Kn[s, 2, 0] * e1 + Kn[s, 2, 1] * e2 + Kn[s, 2, 2] * e3
        sh = (Ma + Mb) / ln
        F[a, 0] += -c * N - sn * sh
        F[a, 1] += -sn * N + c * sh
        F[b, 0] += c * N + sn * sh
        F[b, 1] += sn * N - c * sh
        Mo[a] += Ma
        Mo[b] += Mb
        E[s, 0] = e1
        E[s, 1] = e2
        E[s, 2] = e3


@nb.njit(cache=True, fastmath=FASTMATH)
def _contact_point(P, TH, i, side, h, nonlinear):
    """Position q (drum frame) of a station's contact point and its lever arm r (q = p + r
    for the co-rotational model; the linear model moves the point by the linearised
    rotation and uses the reference arm, consistently with its kinematics)."""
    if nonlinear:
        rx = -np.sin(TH[i]) * side * h
        ry = np.cos(TH[i]) * side * h
        return P[i, 0] + rx, P[i, 1] + ry, rx, ry
    return P[i, 0] - TH[i] * side * h, P[i, 1] + side * h, 0.0, side * h


@nb.njit(cache=True, fastmath=FASTMATH)
def _chain_run(P, TH, V, W, mass, inertia, l0, Kn, h, nonlinear, relative, alpha, omega, theta0, k_c, mu,
               obj, dt, t_out, P_out, TH_out, C_out):
    """Integrate to every time of ``t_out``; states P, TH, V, W are updated in place.
    Returns (status, steps): status 0 ok, 1 non-finite state."""
    n = mass.shape[0]
    F = np.zeros((n, 2))
    Mo = np.zeros(n)
    E = np.zeros((l0.shape[0], 3))
    npt = 2 * n
    fn = np.zeros(npt)
    nx_d = np.zeros(npt)
    ny_d = np.zeros(npt)
    cx, cy, oa, ob, ca, sa = obj[0], obj[1], obj[2], obj[3], obj[4], obj[5]
    damp_lo = 1.0 - 0.5 * alpha * dt
    damp_hi = 1.0 + 0.5 * alpha * dt
    t = 0.0
    steps = 0
    for k in range(t_out.shape[0]):
        while t < t_out[k] - 1e-12 * dt:
            for i in range(n):
                F[i, 0] = 0.0
                F[i, 1] = 0.0
                Mo[i] = 0.0
            _internal_forces(P, TH, l0, Kn, nonlinear, F, Mo, E)
            for i in range(n):
                F[i, 0] = -F[i, 0]
                F[i, 1] = -F[i, 1]
                Mo[i] = -Mo[i]
            phi = theta0 + omega * t
            cp = np.cos(phi)
            sp = np.sin(phi)
            fx_sum = 0.0
            fy_sum = 0.0
            px_sum = 0.0
            py_sum = 0.0
            fn_sum = 0.0
            pen_max = 0.0
            n_act = 0
            for i in range(1, n):
                for j in range(2):
                    pt = 2 * i + j
                    fn[pt] = 0.0
                    side = 1.0 if j == 0 else -1.0
                    qx, qy, rx, ry = _contact_point(P, TH, i, side, h, nonlinear)
                    gx = cp * qx - sp * qy - cx
                    gy = sp * qx + cp * qy - cy
                    u = ca * gx + sa * gy
                    w = -sa * gx + ca * gy
                    if (u / oa) ** 2 + (w / ob) ** 2 >= 1.0:
                        continue
                    gap, lx, ly = _ellipse_gap(u, w, oa, ob)
                    if gap >= 0.0:
                        continue
                    ngx = ca * lx - sa * ly
                    ngy = sa * lx + ca * ly
                    ndx = cp * ngx + sp * ngy               # normal in the drum frame
                    ndy = -sp * ngx + cp * ngy
                    f = -k_c[i] * gap
                    F[i, 0] += f * ndx
                    F[i, 1] += f * ndy
                    Mo[i] += rx * f * ndy - ry * f * ndx
                    fn[pt] = f
                    nx_d[pt] = ndx
                    ny_d[pt] = ndy
                    fx_sum -= f * ngx
                    fy_sum -= f * ngy
                    px_sum += f * (gx + cx)
                    py_sum += f * (gy + cy)
                    fn_sum += f
                    pen_max = max(pen_max, -gap)
                    n_act += 1
            for i in range(1, n):
                m = mass[i]
                fx = F[i, 0] + m * omega * (omega * P[i, 0] + 2.0 * V[i, 1])
                fy = F[i, 1] + m * omega * (omega * P[i, 1] - 2.0 * V[i, 0])
                mz = Mo[i]
                if not relative:
                    fx += alpha * m * omega * P[i, 1]
                    fy -= alpha * m * omega * P[i, 0]
                    mz -= alpha * inertia[i] * omega
                V[i, 0] = (damp_lo * V[i, 0] + dt * fx / m) / damp_hi
                V[i, 1] = (damp_lo * V[i, 1] + dt * fy / m) / damp_hi
                W[i] = (damp_lo * W[i] + dt * mz / inertia[i]) / damp_hi
            if mu > 0.0:
                for i in range(1, n):
                    for j in range(2):
                        pt = 2 * i + j
                        if fn[pt] == 0.0:
                            continue
                        side = 1.0 if j == 0 else -1.0
                        qx, qy, rx, ry = _contact_point(P, TH, i, side, h, nonlinear)
                        tx = -ny_d[pt]
                        ty = nx_d[pt]
                        # absolute velocity of the point, in drum-frame components
                        vx = V[i, 0] - W[i] * ry - omega * qy
                        vy = V[i, 1] + W[i] * rx + omega * qx
                        vt = vx * tx + vy * ty
                        arm = rx * ty - ry * tx
                        flex = dt / damp_hi * (1.0 / mass[i] + arm * arm / inertia[i])
                        ft = -vt / flex
                        limit = mu * fn[pt]
                        if ft > limit:
                            ft = limit
                        elif ft < -limit:
                            ft = -limit
                        g = dt / damp_hi * ft
                        V[i, 0] += g * tx / mass[i]
                        V[i, 1] += g * ty / mass[i]
                        W[i] += g * arm / inertia[i]
                        fx_sum -= ft * (cp * tx - sp * ty)
                        fy_sum -= ft * (sp * tx + cp * ty)
            for i in range(1, n):
                P[i, 0] += dt * V[i, 0]
                P[i, 1] += dt * V[i, 1]
                TH[i] += dt * W[i]
                if not (np.isfinite(P[i, 0]) and np.isfinite(P[i, 1]) and np.isfinite(TH[i])):
                    return 1, steps
            t += dt
            steps += 1
        back = t - t_out[k]                                 # positions at t_out[k]: linear in the step
        for i in range(n):
            P_out[k, i, 0] = P[i, 0] - back * V[i, 0]
            P_out[k, i, 1] = P[i, 1] - back * V[i, 1]
            TH_out[k, i] = TH[i] - back * W[i]
        C_out[k, _FX] = fx_sum
        C_out[k, _FY] = fy_sum
        C_out[k, _NPTS] = n_act
        C_out[k, _PX] = px_sum / fn_sum if fn_sum > 0.0 else 0.0
        C_out[k, _PY] = py_sum / fn_sum if fn_sum > 0.0 else 0.0
        C_out[k, _PEN] = pen_max
    return 0, steps


def stable_step(omega_max, contact=True):
    """Time step [s]: TSSFAC x 2 / omega_max, times 0.9 with contact (as :mod:`fea.explicit`)."""
    return TSSFAC * (STEP_SHRINK if contact else 1.0) * 2.0 / omega_max


def contact_point_stiffness(mass, inertia, half_thickness_m, omega_max):
    """Penalty stiffness [N/m] per station contact point: :func:`fea.contact.penalty_stiffness`
    for the point's effective mass 1 / (1/m + h^2 / I)."""
    m_eff = 1.0 / (1.0 / mass + half_thickness_m**2 / inertia)
    return penalty_stiffness(m_eff, 2.0 / omega_max)
