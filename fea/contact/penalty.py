"""Penalty contact of nodes against rigid, fixed surfaces, with Coulomb friction.

Surfaces (one per model, rigid and fixed in space):

* ``RigidPlane``: points p with (p - p0) . n < 0 are inside.
* ``RigidEllipse``: an elliptical cylinder (semi-axes a, b in its own x-y frame, rotated
  by ``angle_rad`` about the global z axis, centred at ``center_m``) between ``z_min_m``
  and ``z_max_m``; the object of the paper's section 3.3.

Normal contact (node-to-surface penalty): a slave node at penetration depth d > 0 (its
distance to the closest surface point) receives ``f_n = k d`` along the outward surface
normal, with a per-node penalty stiffness ``k`` [N/m]. ccedi chooses it from the node's
mass and the stable step so that the contact spring cannot shorten the step by more than
10 %: a node of mass m whose highest element frequency is w_max = 2 / dt_cfl stays below
w_max / 0.9 when ``k <= (1/0.81 - 1) m w_max^2`` (:func:`penalty_stiffness`); the solver
then runs at 0.9 x its usual step whenever contact is modelled.

The closest point on the ellipse is found by Newton's method on the boundary parameter
theta of q = (a cos theta, b sin theta), solving (q - p) . dq/dtheta = 0; the outward
normal is the ellipse gradient (q_x / a^2, q_y / b^2), normalised.

Friction (Coulomb, coefficient mu) is applied in the velocity update as an impulse, so
it needs no regularisation and cannot reverse the sliding direction within a step: the
tangential trial velocity v_t is reduced by at most ``mu f_n Dt / m_eff`` (slip); if
that would stop it, it is set to zero (stick). See :func:`ccedi.fea.solvers.explicit.run`.
"""
from collections import namedtuple
from dataclasses import dataclass

import numba as nb
import numpy as np

from ccedi.errors import InputError, require_finite_positive
from ccedi.fea.elements.fastmath import FASTMATH
from ccedi.fea.elements.hex8 import FACES
from ccedi.fea.elements.tetra import CORNER_FACES, QUADRATIC_FACES
from ccedi.fea.solvers.rotating_frame import rotate, rotate_back

PLANE, ELLIPSE = 0, 1
NEWTON_ITERATIONS = 12
STEP_SHRINK = 0.9
"""The stable step is multiplied by this factor when contact is modelled."""
MAX_DAMPING_RATIO = 0.2
"""Largest normal contact damping ratio (:func:`contact_damping`): at 0.9 x the contact
step, 0.436 zeta <= (1 - 0.9^2) / (2 x 0.9) = 0.106 keeps the damped step limit."""


@dataclass(frozen=True)
class RigidPlane:
    """Rigid, fixed half-space: points p with (p - p0) . n < 0 are inside.

    Parameters
    ----------
    point_m : tuple of 3 float
        A point p0 on the plane [m].
    normal : tuple of 3 float
        Outward normal n (away from the solid side) [-]; normalised by :meth:`params`.
    mu : float, optional
        Coulomb friction coefficient [-], >= 0. Default 0 (frictionless).
    damping_ratio : float, optional
        Normal contact damping as a fraction of each contact spring's critical damping
        [-], in [0, MAX_DAMPING_RATIO] (:func:`contact_damping`). Default 0.

    Raises
    ------
    InputError
        If ``mu`` is negative or not finite, ``damping_ratio`` is outside [0, MAX_DAMPING_RATIO], or
        ``normal`` is not a finite, non-zero 3-vector.
    """
    point_m: tuple
    normal: tuple
    mu: float = 0.0
    damping_ratio: float = 0.0

    def params(self):
        """Kernel form of the plane for :func:`contact_forces`.

        Returns
        -------
        kind : int
            :data:`PLANE`.
        params : (8,) ndarray
            ``p0`` (3) [m], unit normal ``n`` (3) [-], then two unused zeros.
        """
        n = np.asarray(self.normal, dtype=float)
        n = n / np.linalg.norm(n)
        p = np.asarray(self.point_m, dtype=float)
        return PLANE, np.array([*p, *n, 0.0, 0.0])

    def __post_init__(self):
        require_finite_positive("mu (friction coefficient)", self.mu, allow_zero=True)
        _check_damping_ratio(self.damping_ratio)
        n = np.asarray(self.normal, dtype=float)
        if n.shape != (3,) or not np.isfinite(n).all() or np.linalg.norm(n) == 0.0:
            raise InputError(f"normal must be a non-zero 3-vector, got {self.normal!r}")


@dataclass(frozen=True)
class RigidEllipse:
    """Rigid, fixed elliptical cylinder along global z.

    Points (x, y, z) with ``z_min_m <= z <= z_max_m`` and ``u^2/a^2 + w^2/b^2 < 1``, where
    (u, w) are the in-plane coordinates in the ellipse's own axes, are inside.

    Parameters
    ----------
    center_m : tuple of float
        Centre (x, y) of the ellipse [m] (further entries are ignored).
    a_m : float
        Semi-axis along the ellipse's own x axis [m], > 0.
    b_m : float
        Semi-axis along the ellipse's own y axis [m], > 0.
    angle_rad : float, optional
        Rotation of the a-axis from global x about global z [rad]. Default 0.
    z_min_m : float, optional
        Lower end of the cylinder [m]. Default -inf.
    z_max_m : float, optional
        Upper end of the cylinder [m], > ``z_min_m``. Default +inf.
    mu : float, optional
        Coulomb friction coefficient [-], >= 0. Default 0 (frictionless).
    damping_ratio : float, optional
        Normal contact damping as a fraction of each contact spring's critical damping
        [-], in [0, MAX_DAMPING_RATIO] (:func:`contact_damping`). Default 0.

    Raises
    ------
    InputError
        If a semi-axis is not finite and positive, ``mu`` is negative or not finite,
        ``damping_ratio`` is outside [0, MAX_DAMPING_RATIO], or ``z_min_m >= z_max_m``.
    """
    center_m: tuple
    a_m: float
    b_m: float
    angle_rad: float = 0.0
    z_min_m: float = -np.inf
    z_max_m: float = np.inf
    mu: float = 0.0
    damping_ratio: float = 0.0

    def __post_init__(self):
        require_finite_positive("a_m (ellipse semi-axis, m)", self.a_m)
        require_finite_positive("b_m (ellipse semi-axis, m)", self.b_m)
        require_finite_positive("mu (friction coefficient)", self.mu, allow_zero=True)
        _check_damping_ratio(self.damping_ratio)
        if not self.z_min_m < self.z_max_m:
            raise InputError(f"z_min_m must be below z_max_m, got {self.z_min_m}, {self.z_max_m}")

    def params(self):
        """Kernel form of the ellipse for :func:`contact_forces`.

        Returns
        -------
        kind : int
            :data:`ELLIPSE`.
        params : (8,) ndarray
            Centre x, y [m], semi-axes a, b [m], cos and sin of ``angle_rad`` [-],
            ``z_min_m``, ``z_max_m`` [m].
        """
        c = np.asarray(self.center_m, dtype=float)
        return ELLIPSE, np.array([c[0], c[1], self.a_m, self.b_m, np.cos(self.angle_rad),
                                  np.sin(self.angle_rad), self.z_min_m, self.z_max_m])


@dataclass(frozen=True)
class Contact:
    """Penalty contact of slave nodes against one rigid surface.

    Parameters
    ----------
    nodes : (s,) int ndarray
        Slave node indices.
    surface : RigidPlane or RigidEllipse
        The rigid, fixed surface.
    stiffness : (s,) ndarray or None, optional
        Penalty stiffness per slave node [N/m]. Default None: chosen by the solver
        from the nodal masses and the stable step (:func:`penalty_stiffness`).
    """
    nodes: np.ndarray
    surface: object
    stiffness: np.ndarray | None = None


ContactGroup = namedtuple("ContactGroup", "nodes k c kind params mu normal fn out")
ContactGroup.__doc__ = """Penalty contact as :func:`contact_forces` and
:func:`ccedi.fea.contact.friction.coulomb_friction` take it.

Attributes
----------
nodes : (s,) int ndarray
    Slave node indices (empty without contact).
k : (s,) ndarray
    Penalty stiffness per slave node [N/m].
c : (s,) ndarray
    Normal damping coefficient per slave node [N s/m] (:func:`contact_damping`).
kind : int
    Surface kind, :data:`ccedi.fea.contact.penalty.PLANE` or :data:`ccedi.fea.contact.penalty.ELLIPSE`.
params : (8,) ndarray
    Surface parameters (:meth:`ccedi.fea.contact.penalty.RigidPlane.params`,
    :meth:`ccedi.fea.contact.penalty.RigidEllipse.params`).
mu : float
    Coulomb friction coefficient [-].
normal : (n_nodes, 3) ndarray
    Work array: outward surface normal at each node in contact [-].
fn : (n_nodes,) ndarray
    Work array: normal contact force magnitude of each node [N].
out : (8,) ndarray
    Contact record of the last step (see :func:`ccedi.fea.contact.penalty.contact_forces`).
"""


def _check_damping_ratio(zeta):
    """:class:`ccedi.errors.InputError` unless 0 <= zeta <= MAX_DAMPING_RATIO."""
    if not (np.isfinite(zeta) and 0.0 <= zeta <= MAX_DAMPING_RATIO):
        raise InputError(f"damping_ratio (contact damping, fraction of critical) must be in [0, {MAX_DAMPING_RATIO:g}], "
                         f"got {zeta!r}")


def contact_damping(stiffness, mass, damping_ratio):
    """Normal damping coefficient of each contact spring, a fraction of its critical
    damping (the viscous contact damping of explicit codes, LS-DYNA's VDC)::

        c = 2 zeta sqrt(k m)

    The dashpot acts on the penetration rate while a node is in contact (a lossy object
    surface: energy lost in every contact closure and in the finger's chatter against it);
    the normal force stays compressive, f_n = max(k d + c d', 0). Stability at the
    contact step (0.9 x the step, :func:`penalty_stiffness`): the contact spring alone has
    w_c = sqrt(k / m) = 0.484 w_max, the node with it w_max / 0.9, and the dashpot damps
    that node at a ratio 0.436 zeta; central differences with damping ratio xi are stable
    below (2 / w)(sqrt(1 + xi^2) - xi), which stays above the step taken (0.9 of the
    undamped limit 2 / w at the default TSSFAC) for zeta <= :data:`MAX_DAMPING_RATIO`.

    Parameters
    ----------
    stiffness : (s,) array_like
        Penalty stiffness per slave node [N/m].
    mass : (s,) array_like
        Lumped mass per slave node [kg].
    damping_ratio : float
        Fraction of critical damping zeta [-], in [0, MAX_DAMPING_RATIO].

    Returns
    -------
    (s,) ndarray
        Damping coefficient per node [N s/m].
    """
    return 2.0 * damping_ratio * np.sqrt(np.asarray(stiffness, float) * np.asarray(mass, float))


def penalty_stiffness(mass, dt_cfl):
    """Per-node penalty stiffness that costs no more than the contact step margin.

    A node of mass m whose highest element frequency is ``w_max = 2 / dt_cfl`` keeps
    its frequency below ``w_max / STEP_SHRINK`` when::

        k = (1 / STEP_SHRINK^2 - 1) m (2 / dt_cfl)^2     (= (1/0.81 - 1) m w_max^2)

    so the solver running at ``STEP_SHRINK`` x its step stays stable (see the module
    docstring).

    Parameters
    ----------
    mass : float or (s,) array_like
        Lumped nodal masses [kg].
    dt_cfl : float
        Stable (Courant) time step of the mesh without contact [s].

    Returns
    -------
    float or (s,) ndarray
        Penalty stiffness per node [N/m].
    """
    return (1.0 / STEP_SHRINK**2 - 1.0) * np.asarray(mass) * (2.0 / dt_cfl) ** 2


def boundary_nodes(mesh):
    """Nodes on the outer surface of a solid mesh (hexahedra, 4- or 10-node tetrahedra).

    A face is on the boundary when it belongs to exactly one element (faces matched by
    their corner nodes). Every node of a boundary face is returned: the 4 corners of a
    hexahedron's quadrilateral, the 3 corners of a 4-node tetrahedron's triangle, and the
    3 corners and 3 mid-edge nodes of a 10-node tetrahedron's 6-node triangle. The
    node-to-surface penalty contact (:func:`contact_forces`) needs them all: a mid-edge
    node left out could sink into the object unresisted, and each node gets its own
    penalty stiffness from its own lumped mass (the HRZ masses of the 10-node element are
    all positive), so none is favoured.

    Parameters
    ----------
    mesh : ccedi.fea.mesh.Mesh
        The solid mesh (node orders of :class:`ccedi.fea.mesh.Mesh`).

    Returns
    -------
    (b,) int ndarray
        Sorted, unique indices of the nodes on boundary faces.
    """
    on_surface = [np.zeros(0, dtype=np.int64)]
    for cells, faces, corners in ((mesh.hexes, FACES, 4), (mesh.tets4, CORNER_FACES, 3),
                                  (mesh.tets10, QUADRATIC_FACES, 3)):
        if not len(cells):
            continue
        face_nodes = cells[:, faces].reshape(-1, faces.shape[1])
        key = np.sort(face_nodes[:, :corners], axis=1)
        _, index, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
        on_surface.append(face_nodes[index[counts == 1]].ravel())
    return np.unique(np.concatenate(on_surface))


@nb.njit(cache=True, fastmath=FASTMATH)
def _ellipse_gap(px, py, a, b):
    """Signed gap (negative inside) of point (px, py) to the ellipse x^2/a^2 + y^2/b^2 = 1
    in its own frame, and the outward unit normal (nx, ny) at the closest point."""
    th = np.arctan2(a * py, b * px)
    for _ in range(NEWTON_ITERATIONS):
        c = np.cos(th)
        s = np.sin(th)
        g = (b * b - a * a) * s * c + a * px * s - b * py * c
        dg = (b * b - a * a) * (c * c - s * s) + a * px * c + b * py * s
        if dg == 0.0:
            break
        step = g / dg
        if step > 0.5:
            step = 0.5
        elif step < -0.5:
            step = -0.5
        th -= step
    qx = a * np.cos(th)
    qy = b * np.sin(th)
    nx = qx / (a * a)
    ny = qy / (b * b)
    nn = np.sqrt(nx * nx + ny * ny)
    nx /= nn
    ny /= nn
    dist = np.sqrt((px - qx) ** 2 + (py - qy) ** 2)
    inside = (px / a) ** 2 + (py / b) ** 2 < 1.0
    return (-dist if inside else dist), nx, ny


@nb.njit(cache=True, fastmath=FASTMATH)
def contact_forces(x, v, contact, f_ext):
    """Penalty normal forces of slave nodes against a rigid surface, compiled.

    A slave node at penetration depth d = -gap > 0 (signed distance to the closest
    surface point, negative inside) receives ``f_n = max(k d + c d', 0)`` along the
    outward surface normal n, with d' = -v . n its penetration rate (the surface is
    fixed); the ellipse's closest point comes from Newton's method (module docstring).
    Nodes of an ellipse outside its z range, or outside it in plane, are skipped.

    Parameters
    ----------
    x : (n_nodes, 3) ndarray
        Current nodal coordinates [m].
    v : (n_nodes, 3) ndarray
        Nodal velocities [m/s] (the last half step's in the step loop).
    contact : ContactGroup
        Slave nodes, their penalty stiffness and damping, the surface; its work arrays
        receive the outputs: ``normal``, the outward unit normal [-] of each node in
        contact (other rows are left as they were); ``fn``, the normal force magnitude
        of each slave node [N] (zero when not in contact); ``out``, the total force on
        the surface (3) [N], the penalty energy sum k d^2 / 2 [J], the maximum
        penetration [m], the number of nodes in contact and the force-weighted contact
        point x, y [m] (0 when there is no contact).
    f_ext : (n_nodes, 3) ndarray
        External nodal forces [N]; the contact forces are ADDED to it.

    Returns
    -------
    float
        Sum of the normal force magnitudes [N].
    """
    nodes, stiffness, damping, kind, params = contact.nodes, contact.k, contact.c, contact.kind, contact.params
    normal, f_normal, out = contact.normal, contact.fn, contact.out
    for i in range(8):
        out[i] = 0.0
    fsum = 0.0
    for s in range(nodes.shape[0]):
        n = nodes[s]
        f_normal[n] = 0.0
        if kind == PLANE:
            gap = ((x[n, 0] - params[0]) * params[3] + (x[n, 1] - params[1]) * params[4]
                   + (x[n, 2] - params[2]) * params[5])
            n0 = params[3]
            n1 = params[4]
            n2 = params[5]
        else:
            if x[n, 2] < params[6] or x[n, 2] > params[7]:
                continue
            ca = params[4]
            sa = params[5]
            u, w = rotate_back(x[n, 0] - params[0], x[n, 1] - params[1], ca, sa)
            if (u / params[2]) ** 2 + (w / params[3]) ** 2 >= 1.0:
                continue                                    # outside: no contact, skip Newton
            gap, lx, ly = _ellipse_gap(u, w, params[2], params[3])
            n0, n1 = rotate(lx, ly, ca, sa)
            n2 = 0.0
        if gap >= 0.0:
            continue
        fn = -stiffness[s] * gap
        if damping[s] > 0.0:
            fn = max(fn - damping[s] * (v[n, 0] * n0 + v[n, 1] * n1 + v[n, 2] * n2), 0.0)
        f_ext[n, 0] += fn * n0
        f_ext[n, 1] += fn * n1
        f_ext[n, 2] += fn * n2
        normal[n, 0] = n0
        normal[n, 1] = n1
        normal[n, 2] = n2
        f_normal[n] = fn
        out[0] -= fn * n0
        out[1] -= fn * n1
        out[2] -= fn * n2
        out[3] += 0.5 * stiffness[s] * gap * gap
        out[4] = max(out[4], -gap)
        out[5] += 1.0
        out[6] += fn * x[n, 0]
        out[7] += fn * x[n, 1]
        fsum += fn
    if fsum > 0.0:
        out[6] /= fsum
        out[7] /= fsum
    return fsum
