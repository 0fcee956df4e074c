"""Coulomb friction of the contact nodes as a velocity impulse (see :mod:`ccedi.fea.contact.penalty`).

After the frictionless trial velocity v^{n+1/2} of a node in contact is known, its
tangential part v_t is reduced by at most ``mu f_n Dt / m_eff`` (slip) or set to zero
(stick), ``m_eff = m (1 + alpha Dt / 2)`` the node's mass seen through the centred mass
damping. No regularisation is needed and the sliding direction cannot reverse within a
step.
"""
import numba as nb
import numpy as np

from ccedi.fea.elements.fastmath import FASTMATH


@nb.njit(cache=True, fastmath=FASTMATH)
def coulomb_friction(v, v_new, f_ext, mass, free, c_nodes, c_normal, c_fn, mu, alpha, Dt, c_out):
    """Friction impulse on the contact nodes, and the step's contact work.

    Parameters
    ----------
    v : ndarray, shape (n, 3)
        Velocities v^{n-1/2} [m/s].
    v_new : ndarray, shape (n, 3)
        Trial velocities v^{n+1/2} [m/s]; the friction impulse is applied in place.
    f_ext : ndarray, shape (n, 3)
        External nodal forces [N]; the friction force is added in place.
    mass : ndarray, shape (n,)
        Lumped nodal masses [kg].
    free : ndarray, shape (n,)
        1.0 for a free node, 0.0 for a constrained one (no friction impulse).
    c_nodes : ndarray of int, shape (s,)
        Contact (slave) nodes.
    c_normal : ndarray, shape (n, 3)
        Outward surface normal at each active contact node [-].
    c_fn : ndarray, shape (n,)
        Normal force magnitude [N] (zero when not in contact).
    mu : float
        Friction coefficient [-].
    alpha : float
        Mass-proportional damping [1/s].
    Dt : float
        Velocity-update step (dt^{n-1/2} + dt^{n+1/2}) / 2 [s].
    c_out : ndarray, shape (8,)
        Contact record; the friction reaction on the surface is added to c_out[:3] [N].

    Returns
    -------
    w_normal, w_friction : float
        Work of the normal and of the friction forces on the body in the step [J].
    """
    m_fac = 1.0 + 0.5 * alpha * Dt
    w_n = 0.0
    w_f = 0.0
    for s in range(c_nodes.shape[0]):
        n = c_nodes[s]
        fn = c_fn[n]
        if fn <= 0.0:
            continue
        n0 = c_normal[n, 0]
        n1 = c_normal[n, 1]
        n2 = c_normal[n, 2]
        if free[n] > 0.0 and mu > 0.0:
            vn = v_new[n, 0] * n0 + v_new[n, 1] * n1 + v_new[n, 2] * n2
            t0 = v_new[n, 0] - vn * n0
            t1 = v_new[n, 1] - vn * n1
            t2 = v_new[n, 2] - vn * n2
            vt = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
            if vt > 0.0:
                m_eff = mass[n] * m_fac
                scale = -min(mu * fn * Dt / m_eff, vt) / vt
                for i in range(3):
                    change = scale * (t0 if i == 0 else (t1 if i == 1 else t2))
                    v_new[n, i] += change
                    ff = change * m_eff / Dt
                    f_ext[n, i] += ff
                    c_out[i] -= ff
                    w_f += ff * 0.5 * (v[n, i] + v_new[n, i])
        for i in range(3):
            w_n += fn * (n0 if i == 0 else (n1 if i == 1 else n2)) * 0.5 * (v[n, i] + v_new[n, i])
    return Dt * w_n, Dt * w_f
