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
:mod:`ccedi.fea.contact.drum`. Station 0 is clamped to the drum.

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
:mod:`ccedi.fea.contact.penalty`, for the point's effective mass) and the step shrunk by 0.9. Friction
is Coulomb, applied as in :mod:`ccedi.fea.solvers.explicit`: the impulse that would stop the point's
tangential velocity within the step (through the stations' masses and inertias, the
point's flexibility t J M^-1 J^T t), clipped to mu f_n.

Central differences: ``v^{n+1/2} = [(1 - alpha dt/2) v^{n-1/2} + dt f / m] / (1 + alpha dt/2)``
with the damping centred and Coriolis from v^{n-1/2}.
"""
from collections import namedtuple

import numba as nb
import numpy as np
from scipy.linalg import eigh

from ccedi.errors import InputError
from ccedi.fea.contact.penalty import STEP_SHRINK, _ellipse_gap, penalty_stiffness
from ccedi.fea.elements.fastmath import FASTMATH
from ccedi.fea.solvers.explicit import TSSFAC
from ccedi.fea.solvers.rotating_frame import drum_to_object, planar_frame_velocity_along, rotate, rotate_back

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


ChainState = namedtuple("ChainState", "P TH V W")
ChainState.__doc__ = """Station state of the chain in the drum frame, updated in place.

Attributes
----------
P : (n, 2) ndarray
    Station centres (p1 radial, p2 tangential) [m].
TH : (n,) ndarray
    Station rotations about the drum axis, relative to the drum frame [rad].
V : (n, 2) ndarray
    Half-step station velocities in the drum frame [m/s].
W : (n,) ndarray
    Half-step station angular velocities in the drum frame [rad/s].
"""
ChainGroup = namedtuple("ChainGroup", "mass inertia l0 Kn h nonlinear")
ChainGroup.__doc__ = """The superelement chain (station 0 clamped to the drum).

Attributes
----------
mass : (n,) ndarray
    Station masses [kg].
inertia : (n,) ndarray
    Station rotary inertias about the drum axis [kg m^2].
l0 : (n-1,) ndarray
    Segment rest lengths [m].
Kn : (n-1, 3, 3) ndarray
    Natural stiffness of each segment, mapping the natural deformations
    e = [l - l0 [m], theta_a - psi [rad], theta_b - psi [rad]] to the section forces
    s = [N [N], M_a [N m], M_b [N m]].
h : float
    Largest face offset of the contact points [m] (the reach that culls segments far
    from the object).
nonlinear : bool
    True: co-rotational (large rotation) kinematics; False: linear kinematics frozen
    at the straight finger.
"""
DrumFrame = namedtuple("DrumFrame", "omega theta0 alpha relative")
DrumFrame.__doc__ = """The drum's rotation and the chain's mass damping.

Attributes
----------
omega : float
    Constant drum rotation rate Omega [rad/s].
theta0 : float
    Drum angle at t = 0 [rad]; phi = theta0 + Omega t.
alpha : float
    Mass-proportional damping coefficient [1/s].
relative : bool
    True: damping of the velocity in the drum frame; False: of the absolute velocity.
"""
ContactPoints = namedtuple("ContactPoints", "seg xi h k zeta mu obj")
ContactPoints.__doc__ = """Contact points along the chain (each on both faces) and the object.

Attributes
----------
seg : (p,) int ndarray
    Segment of each point (stations seg and seg + 1).
xi : (p,) ndarray
    Fraction of the segment length at which the point sits [-], in [0, 1].
h : (p, 2) ndarray
    Offsets of the point's +y and -y face from the chain's centre line [m] (the
    section's half thickness there, :attr:`ccedi.rom.superelement.FingerChain.face_offsets_m`).
k : (p,) ndarray
    Penalty stiffness of each point [N/m].
zeta : float
    Normal contact damping, a fraction of each point's critical damping
    2 sqrt(k m_eff) [-] (m_eff: the point's effective mass, 1 / (n J M^-1 J^T n));
    :func:`ccedi.fea.contact.penalty.contact_damping` is the FE's.
mu : float
    Coulomb friction coefficient [-] (0: frictionless).
obj : (6,) ndarray
    The elliptical object: centre x, y [m], semi-axes a, b [m], cos and sin of its
    angle [-] (first six entries of :meth:`ccedi.fea.contact.penalty.RigidEllipse.params`).
"""
ChainOutputs = namedtuple("ChainOutputs", "t_out P_out TH_out C_out")
ChainOutputs.__doc__ = """Output times and the arrays that receive the records at them.

Attributes
----------
t_out : (k,) ndarray
    Increasing output times [s].
P_out : (k, n, 2) ndarray
    Station centres in the drum frame at each output [m].
TH_out : (k, n) ndarray
    Station rotations at each output [rad].
C_out : (k, 6) ndarray
    Contact record at each output: force on the object x, y (global) [N], averaged
    over the steps since the previous output (what an ideal anti-aliased acquisition
    samples: the chain's contact chatter, at up to its highest frequencies, does not
    alias into the outputs), then, of the step reaching the output, the number of
    points in contact, the force-weighted contact point x, y (global) [m] and the
    deepest penetration [m].
"""
ContactWork = namedtuple("ContactWork", "F Mo E J far fn nx ny")
ContactWork.__doc__ = """Scratch arrays of a run (built by :func:`contact_work`).

Attributes
----------
F : (n, 2) ndarray
    Station forces [N].
Mo : (n,) ndarray
    Station moments [N m].
E : (n-1, 3) ndarray
    Natural deformations of the segments [m, rad, rad].
J : (2, 6) ndarray
    Jacobian of one face point against its segment's end DOFs [m/m, m/rad].
far : (n-1,) bool ndarray
    Segments culled as unable to touch the object this step.
fn : (2p,) ndarray
    Normal force of each face point [N].
nx : (2p,) ndarray
    Drum-frame normal of each face point, x component [-].
ny : (2p,) ndarray
    Drum-frame normal of each face point, y component [-].
"""


def contact_work(n_stations, n_points):
    """Scratch arrays (:data:`ContactWork`) for a chain of ``n_stations`` and ``n_points``
    contact points (two face points each).

    Parameters
    ----------
    n_stations : int
        Stations of the chain.
    n_points : int
        Contact points along it.

    Returns
    -------
    ContactWork
        Zeroed arrays.
    """
    npt = 2 * n_points
    return ContactWork(np.zeros((n_stations, 2)), np.zeros(n_stations), np.zeros((n_stations - 1, 3)),
                       np.zeros((2, 6)), np.zeros(n_stations - 1, dtype=np.bool_), np.zeros(npt), np.zeros(npt),
                       np.zeros(npt))


@nb.njit(cache=True, fastmath=FASTMATH)
def _station_loads(state, chain, work):
    """Station forces and moments = minus the internal forces, into work.F, work.Mo."""
    F, Mo = work.F, work.Mo
    n = F.shape[0]
    for i in range(n):
        F[i, 0] = 0.0
        F[i, 1] = 0.0
        Mo[i] = 0.0
    _internal_forces(state.P, state.TH, chain.l0, chain.Kn, chain.nonlinear, F, Mo, work.E)
    for i in range(n):
        F[i, 0] = -F[i, 0]
        F[i, 1] = -F[i, 1]
        Mo[i] = -Mo[i]


@nb.njit(cache=True, fastmath=FASTMATH)
def _cull_segments(P, chain, obj, cp, sp, far):
    """Mark in ``far`` the segments that cannot touch the object at drum angle (cp, sp).

    A segment whose points all lie within r of its chord midpoint cannot touch the object
    when the midpoint is outside the ellipse grown by r (semi-axes a + r, b + r contain
    the curve parallel to the ellipse at r)."""
    for a in range(chain.l0.shape[0]):
        mx = 0.5 * (P[a, 0] + P[a + 1, 0])
        my = 0.5 * (P[a, 1] + P[a + 1, 1])
        _, _, u, w = drum_to_object(mx, my, cp, sp, obj)
        r = 0.75 * chain.l0[a] + 2.0 * chain.h
        far[a] = (u / (obj[2] + r)) ** 2 + (w / (obj[3] + r)) ** 2 >= 1.0


@nb.njit(cache=True, fastmath=FASTMATH)
def _penalty_contact(state, chain, drum, points, cp, sp, work):
    """Penalty normal forces of the face points on the object, added to the stations:
    f = k d, or with contact damping f = max(k d + c d', 0), c = 2 zeta sqrt(k m_eff) and
    d' = -(n . absolute velocity of the point) (frame velocity plus J [V, W]).

    Stores each point's normal force and drum-frame normal in work.fn, work.nx, work.ny.
    Returns the contact record (force on the object x, y [N], force-weighted point sums
    x, y [N m], force sum [N], deepest penetration [m], active points)."""
    P, TH = state.P, state.TH
    F, Mo, J, far, fn = work.F, work.Mo, work.J, work.far, work.fn
    obj = points.obj
    fx_sum = 0.0
    fy_sum = 0.0
    px_sum = 0.0
    py_sum = 0.0
    fn_sum = 0.0
    pen_max = 0.0
    n_act = 0
    for p in range(points.seg.shape[0]):
        a = points.seg[p]
        fn[2 * p] = 0.0
        fn[2 * p + 1] = 0.0
        if far[a]:
            continue
        for j in range(2):
            pt = 2 * p + j
            side = 1.0 if j == 0 else -1.0
            qx, qy = _face_point(P, TH, a, points.xi[p], side, points.h[p, j], chain.nonlinear, J)
            gx, gy, u, w = drum_to_object(qx, qy, cp, sp, obj)
            if (u / obj[2]) ** 2 + (w / obj[3]) ** 2 >= 1.0:
                continue
            gap, lx, ly = _ellipse_gap(u, w, obj[2], obj[3])
            if gap >= 0.0:
                continue
            ngx, ngy = rotate(lx, ly, obj[4], obj[5])
            ndx, ndy = rotate_back(ngx, ngy, cp, sp)      # normal in the drum frame
            f = -points.k[p] * gap
            if points.zeta > 0.0:
                f = max(f - _damping_force(state, chain, drum, points, a, qx, qy, ndx, ndy, J, p), 0.0)
            fx = f * ndx
            fy = f * ndy
            for e in range(2):
                F[a + e, 0] += J[0, 3 * e] * fx + J[1, 3 * e] * fy
                F[a + e, 1] += J[0, 3 * e + 1] * fx + J[1, 3 * e + 1] * fy
                Mo[a + e] += J[0, 3 * e + 2] * fx + J[1, 3 * e + 2] * fy
            fn[pt] = f
            work.nx[pt] = ndx
            work.ny[pt] = ndy
            fx_sum -= f * ngx
            fy_sum -= f * ngy
            px_sum += f * (gx + obj[0])
            py_sum += f * (gy + obj[1])
            fn_sum += f
            pen_max = max(pen_max, -gap)
            n_act += 1
    return fx_sum, fy_sum, px_sum, py_sum, fn_sum, pen_max, n_act


@nb.njit(cache=True, fastmath=FASTMATH)
def _damping_force(state, chain, drum, points, a, qx, qy, nx, ny, J, p):
    """c v_n of face point p on segment a at (qx, qy) with drum-frame normal (nx, ny): its
    absolute velocity along the normal v_n (the penetration rate is -v_n) times
    c = 2 zeta sqrt(k m_eff), m_eff = 1 / (n J M^-1 J^T n) over the free end stations."""
    vn = planar_frame_velocity_along(qx, qy, nx, ny, drum.omega)
    flex = 0.0
    for e in range(2):
        i = a + e
        if i == 0:
            continue
        gx = J[0, 3 * e] * nx + J[1, 3 * e] * ny
        gy = J[0, 3 * e + 1] * nx + J[1, 3 * e + 1] * ny
        gr = J[0, 3 * e + 2] * nx + J[1, 3 * e + 2] * ny
        vn += gx * state.V[i, 0] + gy * state.V[i, 1] + gr * state.W[i]
        flex += (gx * gx + gy * gy) / chain.mass[i] + gr * gr / chain.inertia[i]
    return 2.0 * points.zeta * np.sqrt(points.k[p] / flex) * vn


@nb.njit(cache=True, fastmath=FASTMATH)
def _frame_load(i, state, chain, drum, F, Mo):
    """Load on station i in the drum frame: station force and moment plus the centripetal
    and Coriolis forces, and (``global`` damping) the drag of the frame's own motion."""
    P, V = state.P, state.V
    m = chain.mass[i]
    omega, alpha = drum.omega, drum.alpha
    fx = F[i, 0] + m * omega * (omega * P[i, 0] + 2.0 * V[i, 1])
    fy = F[i, 1] + m * omega * (omega * P[i, 1] - 2.0 * V[i, 0])
    mz = Mo[i]
    if not drum.relative:
        fx += alpha * m * omega * P[i, 1]
        fy -= alpha * m * omega * P[i, 0]
        mz -= alpha * chain.inertia[i] * omega
    return fx, fy, mz


@nb.njit(cache=True, fastmath=FASTMATH)
def _velocity_update(state, chain, drum, work, dt, damp_lo, damp_hi):
    """Central-difference velocities v^{n+1/2} of the free stations (damping centred)."""
    V, W = state.V, state.W
    for i in range(1, chain.mass.shape[0]):
        fx, fy, mz = _frame_load(i, state, chain, drum, work.F, work.Mo)
        m = chain.mass[i]
        V[i, 0] = (damp_lo * V[i, 0] + dt * fx / m) / damp_hi
        V[i, 1] = (damp_lo * V[i, 1] + dt * fy / m) / damp_hi
        W[i] = (damp_lo * W[i] + dt * mz / chain.inertia[i]) / damp_hi


@nb.njit(cache=True, fastmath=FASTMATH)
def _coulomb_friction(state, chain, drum, points, cp, sp, work, dt, damp_hi, fx_sum, fy_sum):
    """Friction impulse of every face point in contact on the stations' velocities: the
    impulse that stops the point's absolute tangential velocity within the step, through
    its flexibility t J M^-1 J^T t, clipped to mu f_n. Returns the force on the object
    (fx_sum, fy_sum) [N] with the friction reactions subtracted."""
    P, TH, V, W = state.P, state.TH, state.V, state.W
    mass, inertia = chain.mass, chain.inertia
    J, fn = work.J, work.fn
    for p in range(points.seg.shape[0]):
        a = points.seg[p]
        for j in range(2):
            pt = 2 * p + j
            if fn[pt] == 0.0:
                continue
            side = 1.0 if j == 0 else -1.0
            qx, qy = _face_point(P, TH, a, points.xi[p], side, points.h[p, j], chain.nonlinear, J)
            tx = -work.ny[pt]
            ty = work.nx[pt]
            # absolute tangential velocity of the point (drum-frame components),
            # its generalised direction g = J^T t and flexibility t J M^-1 J^T t
            vt = planar_frame_velocity_along(qx, qy, tx, ty, drum.omega)
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
            limit = points.mu * fn[pt]
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
            rx, ry = rotate(tx, ty, cp, sp)
            fx_sum -= ft * rx
            fy_sum -= ft * ry
    return fx_sum, fy_sum


@nb.njit(cache=True, fastmath=FASTMATH)
def _drift(state, dt):
    """Positions x^{n+1} = x^n + dt v^{n+1/2} of the free stations; False on a non-finite state."""
    P, TH, V, W = state.P, state.TH, state.V, state.W
    for i in range(1, P.shape[0]):
        P[i, 0] += dt * V[i, 0]
        P[i, 1] += dt * V[i, 1]
        TH[i] += dt * W[i]
        if not (np.isfinite(P[i, 0]) and np.isfinite(P[i, 1]) and np.isfinite(TH[i])):
            return False
    return True


@nb.njit(cache=True, fastmath=FASTMATH)
def _record(k, back, state, outputs, record, mean_fx, mean_fy):
    """Output k: station states moved back by ``back`` [s] to the output time (linear in the
    step), the force on the object averaged since the last output and the rest of the
    contact record of the last step."""
    P, TH, V, W = state.P, state.TH, state.V, state.W
    for i in range(P.shape[0]):
        outputs.P_out[k, i, 0] = P[i, 0] - back * V[i, 0]
        outputs.P_out[k, i, 1] = P[i, 1] - back * V[i, 1]
        outputs.TH_out[k, i] = TH[i] - back * W[i]
    fx_sum, fy_sum, px_sum, py_sum, fn_sum, pen_max, n_act = record
    C = outputs.C_out
    C[k, _FX] = mean_fx
    C[k, _FY] = mean_fy
    C[k, _NPTS] = n_act
    C[k, _PX] = px_sum / fn_sum if fn_sum > 0.0 else 0.0
    C[k, _PY] = py_sum / fn_sum if fn_sum > 0.0 else 0.0
    C[k, _PEN] = pen_max


@nb.njit(cache=True, fastmath=FASTMATH)
def _chain_run(state, chain, drum, points, dt, outputs, work):
    """Integrate to every output time; the state is updated in place.
    Returns (status, steps): status 0 ok, 1 non-finite state."""
    damp_lo = 1.0 - 0.5 * drum.alpha * dt
    damp_hi = 1.0 + 0.5 * drum.alpha * dt
    t_out = outputs.t_out
    record = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0)
    t = 0.0
    steps = 0
    for k in range(t_out.shape[0]):
        fx_acc = 0.0
        fy_acc = 0.0
        n_acc = 0
        while t < t_out[k] - 1e-12 * dt:
            _station_loads(state, chain, work)
            phi = drum.theta0 + drum.omega * t
            cp = np.cos(phi)
            sp = np.sin(phi)
            _cull_segments(state.P, chain, points.obj, cp, sp, work.far)
            record = _penalty_contact(state, chain, drum, points, cp, sp, work)
            _velocity_update(state, chain, drum, work, dt, damp_lo, damp_hi)
            if points.mu > 0.0:
                fx_sum, fy_sum = _coulomb_friction(state, chain, drum, points, cp, sp, work, dt, damp_hi,
                                                   record[0], record[1])
                record = (fx_sum, fy_sum, record[2], record[3], record[4], record[5], record[6])
            if not _drift(state, dt):
                return 1, steps
            t += dt
            steps += 1
            fx_acc += record[0]
            fy_acc += record[1]
            n_acc += 1
        if n_acc > 0:
            _record(k, t - t_out[k], state, outputs, record, fx_acc / n_acc, fy_acc / n_acc)
        else:
            _record(k, t - t_out[k], state, outputs, record, record[0], record[1])
    return 0, steps


def chain_run(state, chain, drum, *, points, dt, outputs, backend="numba"):
    """Integrate the chain on the rotating drum to every output time.

    Parameters
    ----------
    state : ChainState
        Initial station state (drum frame), updated in place.
    chain : ChainGroup
        The superelement chain (station 0 is clamped to the drum).
    drum : DrumFrame
        Rotation and damping.
    points : ContactPoints
        Contact points and the object.
    dt : float
        Step [s].
    outputs : ChainOutputs
        Output times [s] and the arrays that receive the records.
    backend : {"numba", "numpy"}
        Compiled kernels, or the plain Python / numpy reference
        (:func:`chain_run_numpy`, same algorithm, slow).

    Returns
    -------
    status : int
        0 ok, 1 the state became non-finite.
    steps : int
        Steps taken.

    Raises
    ------
    InputError
        If ``backend`` is neither ``"numba"`` nor ``"numpy"``.
    """
    work = contact_work(chain.mass.shape[0], points.seg.shape[0])
    if backend == "numba":
        return _chain_run(state, chain, drum, points, float(dt), outputs, work)
    if backend == "numpy":
        return chain_run_numpy(state, chain, drum, points=points, dt=float(dt), outputs=outputs)
    raise InputError(f"backend must be 'numba' or 'numpy', got {backend!r}")


def _internal_forces_numpy(P, TH, chain):
    """Station forces (n, 2) [N] and moments (n,) [N m] of the chain's section forces
    (vectorised over the segments, the formulas of :func:`_internal_forces`)."""
    d = P[1:] - P[:-1]
    l0 = chain.l0
    if chain.nonlinear:
        ln = np.hypot(d[:, 0], d[:, 1])
        c, sn = d[:, 0] / ln, d[:, 1] / ln
        psi = np.arctan2(d[:, 1], d[:, 0])
        e1 = ln - l0
    else:
        ln, c, sn = l0, np.ones_like(l0), np.zeros_like(l0)
        psi = d[:, 1] / ln
        e1 = d[:, 0] - ln
    e = np.column_stack([e1, TH[:-1] - psi, TH[1:] - psi])
    N, Ma, Mb = np.einsum("sij,sj->si", chain.Kn, e).T
    sh = (Ma + Mb) / ln
    fa = np.column_stack([-c * N - sn * sh, -sn * N + c * sh])
    F = np.zeros_like(P)
    Mo = np.zeros(len(P))
    F[:-1] += fa
    F[1:] -= fa
    Mo[:-1] += Ma
    Mo[1:] += Mb
    return F, Mo


def chain_run_numpy(state, chain, drum, *, points, dt, outputs):
    """Reference of :func:`_chain_run`: the same algorithm in plain Python and numpy (no
    numba), for the tests. Same arguments and result as :func:`chain_run`.

    Parameters
    ----------
    state : ChainState
        Initial station state (drum frame), updated in place.
    chain : ChainGroup
        The superelement chain.
    drum : DrumFrame
        Rotation and damping.
    points : ContactPoints
        Contact points and the object.
    dt : float
        Step [s].
    outputs : ChainOutputs
        Output times [s] and the arrays that receive the records.

    Returns
    -------
    status, steps : int
        0 ok or 1 non-finite state; steps taken.
    """
    face_point, ellipse_gap = _face_point.py_func, _ellipse_gap.py_func
    P, TH, V, W = state
    m, I = chain.mass[1:], chain.inertia[1:]
    cx, cy, oa, ob, ca, sa = points.obj
    om, alpha = drum.omega, drum.alpha
    damp_lo, damp_hi = 1.0 - 0.5 * alpha * dt, 1.0 + 0.5 * alpha * dt
    Jp = np.zeros((2, 6))
    t, steps = 0.0, 0
    record = np.zeros(6)
    for k, t_k in enumerate(outputs.t_out):
        acc = []                                            # force on the object of each step
        while t < t_k - 1e-12 * dt:
            F, Mo = _internal_forces_numpy(P, TH, chain)
            F, Mo = -F, -Mo
            phi = drum.theta0 + om * t
            cp, sp = np.cos(phi), np.sin(phi)
            rot = np.array([[cp, -sp], [sp, cp]])            # drum frame -> global
            mid = 0.5 * (P[:-1] + P[1:]) @ rot.T - [cx, cy]
            u = ca * mid[:, 0] + sa * mid[:, 1]
            w = -sa * mid[:, 0] + ca * mid[:, 1]
            r = 0.75 * chain.l0 + 2.0 * chain.h
            far = (u / (oa + r)) ** 2 + (w / (ob + r)) ** 2 >= 1.0
            active = []                                     # (segment, xi, side, offset, f_n, drum-frame normal)
            f_obj = np.zeros(2)
            moment, f_sum, pen, n_act = np.zeros(2), 0.0, 0.0, 0
            for a, xi, kp, hp in zip(points.seg, points.xi, points.k, points.h):
                if far[a]:
                    continue
                for side, h in zip((1.0, -1.0), hp):
                    q = np.array(face_point(P, TH, a, xi, side, h, chain.nonlinear, Jp))
                    g = rot @ q - [cx, cy]
                    u, w = ca * g[0] + sa * g[1], -sa * g[0] + ca * g[1]
                    if (u / oa) ** 2 + (w / ob) ** 2 >= 1.0:
                        continue
                    gap, lx, ly = ellipse_gap(u, w, oa, ob)
                    if gap >= 0.0:
                        continue
                    n_glob = np.array([ca * lx - sa * ly, sa * lx + ca * ly])
                    n_drum = rot.T @ n_glob
                    f = -kp * gap
                    if points.zeta > 0.0:
                        g_n = (n_drum @ Jp).reshape(2, 3)       # J^T n per end station
                        v_n = om * (q[0] * n_drum[1] - q[1] * n_drum[0])
                        flex = 0.0
                        for e in (0, 1):
                            i = a + e
                            if i > 0:
                                v_n += g_n[e, :2] @ V[i] + g_n[e, 2] * W[i]
                                flex += g_n[e, :2] @ g_n[e, :2] / chain.mass[i] + g_n[e, 2] ** 2 / chain.inertia[i]
                        f = max(f - 2.0 * points.zeta * np.sqrt(kp / flex) * v_n, 0.0)
                    gen = Jp.T @ (f * n_drum)                   # on [Pa, theta_a, Pb, theta_b]
                    F[a:a + 2] += gen.reshape(2, 3)[:, :2]
                    Mo[a:a + 2] += gen.reshape(2, 3)[:, 2]
                    active.append((a, xi, side, h, f, n_drum))
                    f_obj -= f * n_glob
                    moment += f * (g + [cx, cy])
                    f_sum += f
                    pen = max(pen, -gap)
                    n_act += 1
            # central differences in the drum frame: centripetal, Coriolis, (global) frame drag
            fx = F[1:, 0] + m * om * (om * P[1:, 0] + 2.0 * V[1:, 1])
            fy = F[1:, 1] + m * om * (om * P[1:, 1] - 2.0 * V[1:, 0])
            mz = Mo[1:].copy()
            if not drum.relative:
                fx += alpha * m * om * P[1:, 1]
                fy -= alpha * m * om * P[1:, 0]
                mz -= alpha * I * om
            V[1:, 0] = (damp_lo * V[1:, 0] + dt * fx / m) / damp_hi
            V[1:, 1] = (damp_lo * V[1:, 1] + dt * fy / m) / damp_hi
            W[1:] = (damp_lo * W[1:] + dt * mz / I) / damp_hi
            if points.mu > 0.0:
                for a, xi, side, h, f, n_drum in active:
                    q = np.array(face_point(P, TH, a, xi, side, h, chain.nonlinear, Jp))
                    tang = np.array([-n_drum[1], n_drum[0]])
                    g = (tang @ Jp).reshape(2, 3)                # J^T t per end station
                    vt = om * (q[0] * tang[1] - q[1] * tang[0])
                    flex = 0.0
                    for e in range(2):
                        i = a + e
                        if i == 0:
                            continue
                        vt += g[e, 0] * V[i, 0] + g[e, 1] * V[i, 1] + g[e, 2] * W[i]
                        flex += (g[e, 0] ** 2 + g[e, 1] ** 2) / chain.mass[i] + g[e, 2] ** 2 / chain.inertia[i]
                    ft = float(np.clip(-vt / (flex * dt / damp_hi), -points.mu * f, points.mu * f))
                    for e in range(2):
                        i = a + e
                        if i == 0:
                            continue
                        V[i] += dt / damp_hi * ft * g[e, :2] / chain.mass[i]
                        W[i] += dt / damp_hi * ft * g[e, 2] / chain.inertia[i]
                    f_obj -= ft * (rot @ tang)
            P[1:] += dt * V[1:]
            TH[1:] += dt * W[1:]
            if not (np.isfinite(P).all() and np.isfinite(TH).all()):
                return 1, steps
            t += dt
            steps += 1
            point = moment / f_sum if f_sum > 0.0 else np.zeros(2)
            record = np.array([f_obj[0], f_obj[1], n_act, point[0], point[1], pen])
            acc.append(record[:2].copy())
        if acc:
            record[:2] = np.mean(acc, axis=0)
        back = t - t_k
        outputs.P_out[k] = P - back * V
        outputs.TH_out[k] = TH - back * W
        outputs.C_out[k, [_FX, _FY, _NPTS, _PX, _PY, _PEN]] = record
    return 0, steps


def stable_step(omega_max):
    """Time step of the station-contact chain, as :mod:`ccedi.fea.solvers.explicit` chooses it.

    ``dt = TSSFAC x STEP_SHRINK x 2 / omega_max`` (0.9 x 0.9 x the central-difference
    limit 2 / omega_max).

    Parameters
    ----------
    omega_max : float
        Highest natural frequency of the chain [rad/s].

    Returns
    -------
    float
        Time step [s].
    """
    return TSSFAC * STEP_SHRINK * 2.0 / omega_max


def contact_point_stiffness(mass, inertia, half_thickness_m, *, omega_max):
    """Penalty stiffness per station contact point.

    :func:`ccedi.fea.contact.penalty.penalty_stiffness` with ``dt_cfl = 2 / omega_max`` for the
    point's effective mass ``m_eff = 1 / (1/m + h^2 / I)`` (a face point at lever arm h
    from the station centre).

    Parameters
    ----------
    mass : float or (n,) ndarray
        Station masses [kg].
    inertia : float or (n,) ndarray
        Station rotary inertias [kg m^2].
    half_thickness_m : float or (n,) ndarray
        Lever arm h of the face point from the station centre [m].
    omega_max : float
        Highest natural frequency of the chain [rad/s].

    Returns
    -------
    float or (n,) ndarray
        Penalty stiffness per point [N/m].
    """
    m_eff = 1.0 / (1.0 / mass + half_thickness_m**2 / inertia)
    return penalty_stiffness(m_eff, 2.0 / omega_max)


def face_points(station_z_m, plane_z_m, nonlinear=True):
    """Contact points along the finger, one per face per node plane.

    A point for every node plane z of ``plane_z_m`` but the root (z = 0); the tip plane
    is xi = 1 of the last segment. The tributary length is half the distance to the
    neighbouring planes (the tip's is half a layer). The linear model takes the
    stations only (its kinematics has no points between them).

    Parameters
    ----------
    station_z_m : (n,) array_like
        Increasing station positions along the finger, from the root z = 0 [m].
    plane_z_m : array_like
        Positions of the FE node planes along the finger [m] (ignored when
        ``nonlinear`` is False).
    nonlinear : bool, optional
        Co-rotational model (points at every plane, default) or linear model (points
        at the stations).

    Returns
    -------
    seg : (p,) int64 ndarray
        Segment of each point.
    xi : (p,) ndarray
        Fraction along the segment [-].
    trib : (p,) ndarray
        Tributary length of each point along the finger [m].
    """
    z = np.asarray(station_z_m, dtype=float)
    planes = np.unique(np.asarray(plane_z_m, dtype=float)) if nonlinear else z
    planes = planes[planes > 1e-12 * z[-1]]
    seg = np.clip(np.searchsorted(z, planes, side="right") - 1, 0, len(z) - 2)
    xi = (planes - z[seg]) / (z[seg + 1] - z[seg])
    full = np.r_[0.0, planes]
    trib = 0.5 * (np.diff(full) + np.r_[np.diff(full)[1:], 0.0])
    return seg.astype(np.int64), xi, trib


def contact_omega(K, M, *, pt_seg, pt_xi, pt_k, pt_h, station_z_m, nonlinear=True):
    """Highest frequency of the clamped chain with one face's contact springs engaged.

    Every contact spring of one face acts across the finger (normal along the
    section's y): ``K_c = sum_p k_p J_p^T e_y e_y^T J_p``, J_p the Jacobian of the face
    point at the straight finger; the result is the largest omega of
    ``(K + K_c) phi = omega^2 M phi``. An upper bound for the contact frequencies the
    run can meet (fewer springs engage at once).

    Parameters
    ----------
    K : (3(n-1), 3(n-1)) ndarray
        Stiffness matrix of the linear clamped chain (station 0 removed), DOFs
        (p1, p2, theta) per station [N/m, N, N m] (:func:`ccedi.rom.superelement.linear_matrices`).
    M : (3(n-1), 3(n-1)) ndarray
        Mass matrix of the same DOFs [kg, kg m^2].
    pt_seg : (p,) int array_like
        Segment of each contact point.
    pt_xi : (p,) array_like
        Fraction of the segment length of each point [-].
    pt_k : (p,) array_like
        Penalty stiffness of each point [N/m].
    pt_h : float or (p,) array_like
        Offset of each point's face from the centre line [m].
    station_z_m : (n,) array_like
        Station positions along the straight finger [m].
    nonlinear : bool, optional
        Face-point kinematics of the co-rotational (default) or linear model.

    Returns
    -------
    float
        Highest natural frequency omega_c [rad/s].
    """
    n = len(station_z_m)
    Kc = np.zeros((3 * n, 3 * n))
    P = np.column_stack([station_z_m, np.zeros(n)])
    TH = np.zeros(n)
    J = np.zeros((2, 6))
    for a, xi, k, h in zip(pt_seg, pt_xi, pt_k, np.broadcast_to(pt_h, np.shape(pt_k))):
        _face_point(P, TH, int(a), float(xi), 1.0, float(h), nonlinear, J)
        row = J[1]
        Kc[3 * a:3 * a + 6, 3 * a:3 * a + 6] += k * np.outer(row, row)
    w2 = eigh(K + Kc[3:, 3:], M, eigvals_only=True)
    return float(np.sqrt(w2[-1]))
