"""External loads of the explicit solver: force pulses held on nodes over a time window."""
from collections import namedtuple

import numba as nb
import numpy as np

from ccedi.fea.elements.fastmath import FASTMATH

PulseLoads = namedtuple("PulseLoads", "nodes forces t_start t_end")
PulseLoads.__doc__ = """Force pulses flattened to one row per loaded node (built by :func:`pulse_loads`).

Row p applies ``forces[p]`` to node ``nodes[p]`` while ``t_start[p] <= t < t_end[p]``
(:func:`pulse_forces`); a node loaded by several pulses has several rows.

Attributes
----------
nodes : (p,) int ndarray
    Loaded node of each row.
forces : (p, 3) ndarray
    Force on that node while the pulse is on [N].
t_start : (p,) ndarray
    Time the pulse switches on [s] (inclusive).
t_end : (p,) ndarray
    Time the pulse switches off [s] (exclusive).
"""


def pulse_loads(pulses):
    """Flatten :class:`ccedi.fea.model.ForcePulse` objects into :data:`PulseLoads`.

    Parameters
    ----------
    pulses : sequence of ForcePulse
        Each with ``nodes``, ``weights`` (per node, [-]), ``force_N`` (3,) [N],
        ``t_start_s`` and ``t_end_s`` [s].

    Returns
    -------
    PulseLoads
        One row per loaded node, its force the pulse force times the node's weight [N].
    """
    nodes, forces, t0, t1 = [], [], [], []
    for p in pulses:
        nodes.append(p.nodes)
        forces.append(p.weights[:, None] * p.force_N[None, :])
        t0.append(np.full(len(p.nodes), p.t_start_s))
        t1.append(np.full(len(p.nodes), p.t_end_s))
    if not nodes:
        return PulseLoads(np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros(0), np.zeros(0))
    return PulseLoads(np.concatenate(nodes), np.concatenate(forces), np.concatenate(t0), np.concatenate(t1))


@nb.njit(cache=True, fastmath=FASTMATH)
def pulse_forces(t, x, v, loads, f_ext):
    """External nodal forces of the pulses active at time ``t``, added to ``f_ext`` (the
    external force term of :mod:`ccedi.fea.solvers.force_terms`).

    Parameters
    ----------
    t : float
        Time [s].
    x, v : ndarray, shape (n, 3)
        Nodal positions [m] and velocities [m/s] (not used: the pulses are given forces).
    loads : PulseLoads
        The flattened pulses.
    f_ext : ndarray, shape (n, 3)
        External nodal forces [N]; the pulse forces are ADDED to it.
    """
    for p in range(loads.nodes.shape[0]):
        if loads.t_start[p] <= t and t < loads.t_end[p]:
            for i in range(3):
                f_ext[loads.nodes[p], i] += loads.forces[p, i]
