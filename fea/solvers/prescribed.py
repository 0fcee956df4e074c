"""Prescribed motion: nodes carried rigidly by a rotation about a fixed axis (a drum).

The constrained nodes get, each step, the velocity that moves them from their current
positions to their rigidly rotated reference positions in one step (Rodrigues'
formula), so that they follow the rotation exactly without drift.
"""
import numba as nb
import numpy as np

from ccedi.fea.elements.fastmath import FASTMATH
from ccedi.fea.solvers.rotating_frame import frame_velocity


@nb.njit(cache=True, fastmath=FASTMATH)
def prescribed_rotation(nodes, X, x, v_pres, center, axis, angle, dt):
    """Velocities that carry ``nodes`` to their rotated reference positions in one step.

    Rodrigues: ``c + d cos + (k x d) sin + k (k . d)(1 - cos)``, d = X - c.

    Parameters
    ----------
    nodes : ndarray of int, shape (r,)
        The rotating nodes.
    X : ndarray, shape (n, 3)
        Reference positions [m].
    x : ndarray, shape (n, 3)
        Current positions [m].
    v_pres : ndarray, shape (n, 3)
        Prescribed velocities [m/s], written for ``nodes``.
    center : ndarray, shape (3,)
        A point on the rotation axis [m].
    axis : ndarray, shape (3,)
        Unit rotation axis k [-].
    angle : float
        Rotation angle at the end of the step [rad].
    dt : float
        Step [s].
    """
    ct = np.cos(angle)
    st = np.sin(angle)
    for r in range(nodes.shape[0]):
        n = nodes[r]
        d0 = X[n, 0] - center[0]
        d1 = X[n, 1] - center[1]
        d2 = X[n, 2] - center[2]
        kd = axis[0] * d0 + axis[1] * d1 + axis[2] * d2
        c0, c1, c2 = frame_velocity(X, n, center, axis, 1.0)          # k x d
        v_pres[n, 0] = (center[0] + d0 * ct + c0 * st + axis[0] * kd * (1.0 - ct) - x[n, 0]) / dt
        v_pres[n, 1] = (center[1] + d1 * ct + c1 * st + axis[1] * kd * (1.0 - ct) - x[n, 1]) / dt
        v_pres[n, 2] = (center[2] + d2 * ct + c2 * st + axis[2] * kd * (1.0 - ct) - x[n, 2]) / dt
