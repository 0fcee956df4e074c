"""Kinematics of the rotating (drum) frame, written once for the FE and the reduced model.

A frame turning at the rate omega [rad/s] about the unit ``axis`` through ``center`` moves
its point x at the velocity ``v_ref = omega axis x (x - c)`` (:func:`frame_velocity`).
In the plane of the drum (axis +z through the origin) a point p of the frame at drum
angle phi sits at ``R(phi) p`` in space (:func:`rotate`); :func:`drum_to_object` carries a
drum-frame point into the frame of the fixed elliptical object (centre c_o, a-axis at
angle beta from global x): ``R(-beta) (R(phi) p - c_o)``.

Every function here is a numba kernel on scalars; the ``.py_func`` of each is its plain
Python form, which works on numpy arrays too (same operations in the same order).
"""
from collections import namedtuple

import numba as nb
import numpy as np

from ccedi.fea.elements.fastmath import FASTMATH

RotatingFrame = namedtuple("RotatingFrame", "nodes center axis omega")
RotatingFrame.__doc__ = """A frame turning at ``omega`` about the unit ``axis`` through ``center``.

The frame moves its point x at ``v_ref = omega axis x (x - center)``
(:func:`frame_velocity`) and carries the ``nodes`` rigidly (prescribed rotation).

Attributes
----------
nodes : (r,) int ndarray
    Nodes carried rigidly by the frame; empty for a frame that only serves as the
    reference of relative damping.
center : (3,) ndarray
    A point on the rotation axis [m].
axis : (3,) ndarray
    Unit rotation axis [-].
omega : float
    Rotation rate about ``axis`` [rad/s].
"""


@nb.njit(cache=True, fastmath=FASTMATH)
def frame_velocity(x, n, center, axis, omega):
    """Velocity of the rotating frame at node ``n``: omega axis x (x_n - c).

    Parameters
    ----------
    x : ndarray, shape (m, 3)
        Nodal positions [m].
    n : int
        Node index.
    center : ndarray, shape (3,)
        A point on the rotation axis [m].
    axis : ndarray, shape (3,)
        Unit rotation axis [-].
    omega : float
        Rotation rate [rad/s] (1.0 gives the lever axis x (x_n - c) [m]).

    Returns
    -------
    tuple of float
        The three velocity components [m/s].
    """
    d0 = x[n, 0] - center[0]
    d1 = x[n, 1] - center[1]
    d2 = x[n, 2] - center[2]
    return (omega * (axis[1] * d2 - axis[2] * d1), omega * (axis[2] * d0 - axis[0] * d2),
            omega * (axis[0] * d1 - axis[1] * d0))


@nb.njit(cache=True, fastmath=FASTMATH)
def frame_velocities(x, center, axis, omega):
    """Velocity of the rotating frame at every node, :func:`frame_velocity` row by row.

    Parameters
    ----------
    x : ndarray, shape (m, 3)
        Nodal positions [m].
    center : ndarray, shape (3,)
        A point on the rotation axis [m].
    axis : ndarray, shape (3,)
        Unit rotation axis [-].
    omega : float
        Rotation rate [rad/s].

    Returns
    -------
    ndarray, shape (m, 3)
        Velocities [m/s]: the rigid motion of a body turning with the frame.
    """
    v = np.empty_like(x)
    for n in range(x.shape[0]):
        v[n, 0], v[n, 1], v[n, 2] = frame_velocity(x, n, center, axis, omega)
    return v


@nb.njit(cache=True, fastmath=FASTMATH)
def planar_frame_velocity_along(qx, qy, tx, ty, omega):
    """Component along (tx, ty) of the velocity omega e_z x q of the planar rotating frame
    at the point q = (qx, qy).

    Parameters
    ----------
    qx, qy : float
        Point in the frame, from the rotation axis [m].
    tx, ty : float
        Direction (unit) [-].
    omega : float
        Rotation rate about +z [rad/s].

    Returns
    -------
    float
        omega (qx ty - qy tx) [m/s].
    """
    return omega * (qx * ty - qy * tx)


@nb.njit(cache=True, fastmath=FASTMATH)
def rotate(x, y, c, s):
    """Planar rotation by the angle whose cosine and sine are ``c``, ``s``.

    Parameters
    ----------
    x, y : float or ndarray
        Components in the turning frame (any length unit, or a direction).
    c, s : float or ndarray
        cos and sin of the frame's angle [-].

    Returns
    -------
    tuple
        (c x - s y, s x + c y), the components in the fixed frame.
    """
    return c * x - s * y, s * x + c * y


@nb.njit(cache=True, fastmath=FASTMATH)
def rotate_back(x, y, c, s):
    """Inverse of :func:`rotate`: components in the turning frame of fixed-frame (x, y).

    Parameters
    ----------
    x, y : float or ndarray
        Components in the fixed frame.
    c, s : float or ndarray
        cos and sin of the turning frame's angle [-].

    Returns
    -------
    tuple
        (c x + s y, -s x + c y).
    """
    return c * x + s * y, -s * x + c * y


@nb.njit(cache=True, fastmath=FASTMATH)
def drum_to_object(px, py, cp, sp, obj):
    """Drum-frame point into the object's frame.

    Parameters
    ----------
    px, py : float or ndarray
        Point in the drum frame [m].
    cp, sp : float or ndarray
        cos and sin of the drum angle phi [-].
    obj : ndarray, shape (6,)
        Object centre x, y [m], semi-axes a, b [m], cos and sin of its angle [-]
        (the first six entries of :meth:`ccedi.fea.contact.penalty.RigidEllipse.params`).

    Returns
    -------
    gx, gy : float or ndarray
        Global position relative to the object centre, R(phi) p - c_o [m].
    u, w : float or ndarray
        The same in the object's axes, R(-beta) (gx, gy) [m].
    """
    gx = cp * px - sp * py - obj[0]
    gy = sp * px + cp * py - obj[1]
    u, w = rotate_back(gx, gy, obj[4], obj[5])
    return gx, gy, u, w
