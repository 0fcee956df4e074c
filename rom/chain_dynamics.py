"""Explicit dynamics of the superelement chain on the rotating drum, with penalty contact
and Coulomb friction against the rigid elliptical object.

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
:mod:`ccedi.fea.drum`. Station 0 is clamped to the drum.

Internal forces, co-rotational (``nonlinear=True``): each segment's chord of current
length l and angle psi defines its frame; the natural deformations
``e = [l - l0, theta_a - psi, theta_b - psi]`` give the section forces ``s = K_n e``
and the station forces ``f = B^T s`` with B = de/dq (Crisfield's planar co-rotational
beam). Large rotations are exact; strains within a segment stay small. Linear
(``nonlinear=False``): the same with B, l and psi frozen at the straight finger,
``psi = (V_b - V_a) / l0``: the Craig-Bampton model of small displacements.

Contact points sit on both faces of the finger at chosen fractions xi of the segments
(:func:`face_points`: every FE node plane by default, three per 12 mm segment), on the
segment's cubic centre line at r = +-h from it (h the section's half thickness;
:func:`_face_point`); at xi = 0 or 1 a point is the station's own, p + R(theta) (0, +-h)
(linear model: stations only, r = (0, +-h) + theta J (0, +-h)). Each point penetrating
the object gets ``f_n = k d`` along the object's outward normal, passed to the two end
stations as J^T f with J the exact derivative of the point's position (the contact is
conservative). The step is TSSFAC x 2 / omega_c, omega_c the chain's highest frequency
with one face's contact springs all engaged (:func:`contact_omega`). The earlier
station-only model (``contact="stations"`` in :mod:`ccedi.rom.contact_rom`) takes
``k = (1/0.81 - 1) (2/dt_cfl)^2 / (1/m + h^2/I)`` per station point (the rule of
:mod:`ccedi.fea.contact`, for the point's effective mass) and the step shrunk by 0.9. Friction
is Coulomb, applied as in :mod:`ccedi.fea.explicit`: the impulse that would stop the point's
tangential velocity within the step (through the stations' masses and inertias, the
point's flexibility t J M^-1 J^T t), clipped to mu f_n.

Central differences: ``v^{n+1/2} = [(1 - alpha dt/2) v^{n-1/2} + dt f / m] / (1 + alpha dt/2)``
with the damping centred and Coriolis from v^{n-1/2}.
"""
import numba as nb
import numpy as np
from scipy.linalg import eigh

from ccedi.fea.contact import STEP_SHRINK, _ellipse_gap, penalty_stiffness
from ccedi.fea.explicit import TSSFAC
from ccedi.fea.kernels import FASTMATH

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
def _face_point(P, TH, a, xi, side, h, nonlinear, J):
    """Position (qx, qy) in the drum frame of the face point at fraction ``xi`` of segment
    a -> a + 1, on face ``side`` (+-1), and its Jacobian J (2 x 6) [m / (m, m, rad, m, m,
    rad)] against the end DOFs [Pa_x, Pa_y, theta_a, Pb_x, Pb_y, theta_b], so that a force
    f on the point acts on the stations as J^T f (exactly: J is the derivative of the
    position, the contact is conservative) and the point moves at J q'.

    Co-rotational: chord of length l and angle psi (axes e1 along it, e2 across), end
    rotations beta = theta - psi, cubic (Hermite) centre line in the chord frame::

        x = Pa + xi l e1 + w e2 + side h n(theta_x)
        w = l (H2 beta_a + H4 beta_b),  theta_x = psi + H2' beta_a + H4' beta_b
        H2 = xi (1 - xi)^2,  H4 = -xi^2 (1 - xi),  n(t) = (-sin t, cos t)

    (exact for uniform curvature: mid-segment sagitta kappa l^2 / 8). At xi = 0 and 1 it is
    the station's own point Pa + R(theta_a) (0, side h). Linear model (``nonlinear=False``):
    station points only (xi 0 or 1), moved by the linearised rotation,
    q = P + (-theta side h, side h), with the reference lever arm."""
    for r in range(2):
        for c in range(6):
            J[r, c] = 0.0
    if not nonlinear:
        i = a if xi < 0.5 else a + 1
        c0 = 0 if xi < 0.5 else 3
        J[0, c0] = 1.0
        J[1, c0 + 1] = 1.0
        J[0, c0 + 2] = -side * h
        return P[i, 0] - TH[i] * side * h, P[i, 1] + side * h
    b = a + 1
    dx = P[b, 0] - P[a, 0]
    dy = P[b, 1] - P[a, 1]
    ln = np.sqrt(dx * dx + dy * dy)
    e1x = dx / ln
    e1y = dy / ln
    e2x = -e1y
    e2y = e1x
    psi = np.arctan2(dy, dx)
    ba = TH[a] - psi
    bb = TH[b] - psi
    om = 1.0 - xi
    H2 = xi * om * om
    H4 = -xi * xi * om
    H2p = om * (1.0 - 3.0 * xi)
    H4p = xi * (3.0 * xi - 2.0)
    w = ln * (H2 * ba + H4 * bb)
    th = psi + H2p * ba + H4p * bb
    nx = -np.sin(th)
    ny = np.cos(th)
    dnx = -ny                                   # dn / dtheta = (-cos, -sin)
    dny = nx
    qx = P[a, 0] + xi * ln * e1x + w * e2x + side * h * nx
    qy = P[a, 1] + xi * ln * e1y + w * e2y + side * h * ny
    # d x / d l (psi, theta fixed) and d x / d psi (l, theta fixed)
    Ax = xi * e1x + w / ln * e2x
    Ay = xi * e1y + w / ln * e2y
    cpsi = ln * (xi - H2 - H4)
    cn = side * h * (1.0 - H2p - H4p)
    Bx = cpsi * e2x - w * e1x + cn * dnx
    By = cpsi * e2y - w * e1y + cn * dny
    # dl/dPb = e1, dpsi/dPb = e2 / l; the negatives for Pa
    J[0, 3] = Ax * e1x + Bx * e2x / ln
    J[0, 4] = Ax * e1y + Bx * e2y / ln
    J[1, 3] = Ay * e1x + By * e2x / ln
    J[1, 4] = Ay * e1y + By * e2y / ln
    J[0, 0] = 1.0 - J[0, 3]
    J[0, 1] = -J[0, 4]
    J[1, 0] = -J[1, 3]
    J[1, 1] = 1.0 - J[1, 4]
    J[0, 2] = ln * H2 * e2x + side * h * H2p * dnx
    J[1, 2] = ln * H2 * e2y + side * h * H2p * dny
    J[0, 5] = ln * H4 * e2x + side * h * H4p * dnx
    J[1, 5] = ln * H4 * e2y + side * h * H4p * dny
    return qx, qy


@nb.njit(cache=True, fastmath=FASTMATH)
def _chain_run(P, TH, V, W, mass, inertia, l0, Kn, h, nonlinear, relative, alpha, omega, theta0,
               pt_seg, pt_xi, pt_k, mu, obj, dt, t_out, P_out, TH_out, C_out):
    """Integrate to every time of ``t_out``; states P, TH, V, W are updated in place.
    Contact points: ``pt_seg`` (segment), ``pt_xi`` (fraction along it), ``pt_k`` (penalty
    stiffness, N/m), each on both faces (:func:`_face_point`).
    Returns (status, steps): status 0 ok, 1 non-finite state."""
    n = mass.shape[0]
    F = np.zeros((n, 2))
    Mo = np.zeros(n)
    E = np.zeros((l0.shape[0], 3))
    J = np.zeros((2, 6))
    far = np.zeros(l0.shape[0], dtype=np.bool_)
    npt = 2 * pt_seg.shape[0]
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
            for a in range(l0.shape[0]):
                # cull: a segment whose points all lie within r of its chord midpoint cannot
                # touch the object when the midpoint is outside the ellipse grown by r
                # (semi-axes a + r, b + r contain the curve parallel to the ellipse at r)
                mx = 0.5 * (P[a, 0] + P[a + 1, 0])
                my = 0.5 * (P[a, 1] + P[a + 1, 1])
                gx = cp * mx - sp * my - cx
                gy = sp * mx + cp * my - cy
                u = ca * gx + sa * gy
                w = -sa * gx + ca * gy
                r = 0.75 * l0[a] + 2.0 * h
                far[a] = (u / (oa + r)) ** 2 + (w / (ob + r)) ** 2 >= 1.0
            fx_sum = 0.0
            fy_sum = 0.0
            px_sum = 0.0
            py_sum = 0.0
            fn_sum = 0.0
            pen_max = 0.0
            n_act = 0
            for p in range(pt_seg.shape[0]):
                a = pt_seg[p]
                fn[2 * p] = 0.0
                fn[2 * p + 1] = 0.0
                if far[a]:
                    continue
                for j in range(2):
                    pt = 2 * p + j
                    side = 1.0 if j == 0 else -1.0
                    qx, qy = _face_point(P, TH, a, pt_xi[p], side, h, nonlinear, J)
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
                    f = -pt_k[p] * gap
                    fx = f * ndx
                    fy = f * ndy
                    for e in range(2):
                        F[a + e, 0] += J[0, 3 * e] * fx + J[1, 3 * e] * fy
                        F[a + e, 1] += J[0, 3 * e + 1] * fx + J[1, 3 * e + 1] * fy
                        Mo[a + e] += J[0, 3 * e + 2] * fx + J[1, 3 * e + 2] * fy
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
                for p in range(pt_seg.shape[0]):
                    a = pt_seg[p]
                    for j in range(2):
                        pt = 2 * p + j
                        if fn[pt] == 0.0:
                            continue
                        side = 1.0 if j == 0 else -1.0
                        qx, qy = _face_point(P, TH, a, pt_xi[p], side, h, nonlinear, J)
                        tx = -ny_d[pt]
                        ty = nx_d[pt]
                        # absolute tangential velocity of the point (drum-frame components),
                        # its generalised direction g = J^T t and flexibility t J M^-1 J^T t
                        vt = omega * (qx * ty - qy * tx)
                        flex = 0.0
                        for e in range(2):
                            i = a + e
                            if i == 0:
                                continue                    # the clamped root station
                            gx_ = J[0, 3 * e] * tx + J[1, 3 * e] * ty
                            gy_ = J[0, 3 * e + 1] * tx + J[1, 3 * e + 1] * ty
                            gr_ = J[0, 3 * e + 2] * tx + J[1, 3 * e + 2] * ty
                            vt += gx_ * V[i, 0] + gy_ * V[i, 1] + gr_ * W[i]
                            flex += (gx_ * gx_ + gy_ * gy_) / mass[i] + gr_ * gr_ / inertia[i]
                        flex *= dt / damp_hi
                        ft = -vt / flex
                        limit = mu * fn[pt]
                        if ft > limit:
                            ft = limit
                        elif ft < -limit:
                            ft = -limit
                        g = dt / damp_hi * ft
                        for e in range(2):
                            i = a + e
                            if i == 0:
                                continue
                            V[i, 0] += g * (J[0, 3 * e] * tx + J[1, 3 * e] * ty) / mass[i]
                            V[i, 1] += g * (J[0, 3 * e + 1] * tx + J[1, 3 * e + 1] * ty) / mass[i]
                            W[i] += g * (J[0, 3 * e + 2] * tx + J[1, 3 * e + 2] * ty) / inertia[i]
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


def stable_step(omega_max):
    """Time step [s] of the station-contact chain: TSSFAC x 2 / omega_max, times 0.9 for the
    contact (as :mod:`ccedi.fea.explicit`)."""
    return TSSFAC * STEP_SHRINK * 2.0 / omega_max


def contact_point_stiffness(mass, inertia, half_thickness_m, omega_max):
    """Penalty stiffness [N/m] per station contact point: :func:`ccedi.fea.contact.penalty_stiffness`
    for the point's effective mass 1 / (1/m + h^2 / I)."""
    m_eff = 1.0 / (1.0 / mass + half_thickness_m**2 / inertia)
    return penalty_stiffness(m_eff, 2.0 / omega_max)


def face_points(station_z_m, plane_z_m, nonlinear=True):
    """Contact points along the finger: (segment, fraction xi along it, tributary length
    [m]) for every node plane z of ``plane_z_m`` but the root (z = 0), one point per face
    per plane; the tip plane is xi = 1 of the last segment. The tributary length is half
    the distance to the neighbouring planes (the tip's is half a layer). The linear model
    takes the stations only (its kinematics has no points between them)."""
    z = np.asarray(station_z_m, dtype=float)
    planes = np.unique(np.asarray(plane_z_m, dtype=float)) if nonlinear else z
    planes = planes[planes > 1e-12 * z[-1]]
    seg = np.clip(np.searchsorted(z, planes, side="right") - 1, 0, len(z) - 2)
    xi = (planes - z[seg]) / (z[seg + 1] - z[seg])
    full = np.r_[0.0, planes]
    trib = 0.5 * (np.diff(full) + np.r_[np.diff(full)[1:], 0.0])
    return seg.astype(np.int64), xi, trib


def contact_omega(K, M, pt_seg, pt_xi, pt_k, half_thickness_m, station_z_m, nonlinear=True):
    """Highest frequency [rad/s] of the linear clamped chain (K, M of
    :func:`ccedi.rom.superelement.linear_matrices`) with every contact spring of one face
    engaged across the finger (normal along the section's y): K_c = sum_p k_p J_p^T e_y
    e_y^T J_p, J_p of :func:`_face_point` at the straight finger. An upper bound for the
    contact frequencies the run can meet (fewer springs engage at once)."""
    n = len(station_z_m)
    Kc = np.zeros((3 * n, 3 * n))
    P = np.column_stack([station_z_m, np.zeros(n)])
    TH = np.zeros(n)
    J = np.zeros((2, 6))
    for a, xi, k in zip(pt_seg, pt_xi, pt_k):
        _face_point(P, TH, int(a), float(xi), 1.0, half_thickness_m, nonlinear, J)
        row = J[1]
        Kc[3 * a:3 * a + 6, 3 * a:3 * a + 6] += k * np.outer(row, row)
    w2 = eigh(K + Kc[3:, 3:], M, eigvals_only=True)
    return float(np.sqrt(w2[-1]))
