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
def pulse_forces(f_ext, loads, t):
    """External nodal forces of the pulses active at time ``t``, into ``f_ext``.

    Parameters
    ----------
    f_ext : ndarray, shape (n, 3)
        Overwritten with the pulse forces [N] (zero elsewhere).
    loads : PulseLoads
        The flattened pulses.
    t : float
        Time [s].
    """
    f_ext[:, :] = 0.0
    for p in range(loads.nodes.shape[0]):
        if loads.t_start[p] <= t and t < loads.t_end[p]:
            for i in range(3):
                f_ext[loads.nodes[p], i] += loads.forces[p, i]
