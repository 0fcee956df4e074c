"""A finite element model: mesh, material, Rayleigh damping, boundary conditions, loads.

Rayleigh damping, paper Eq. (2): ``C = alpha M + beta K`` with alpha [1/s] (mass
proportional) and beta [s] (stiffness proportional). Modal damping ratio, Eq. (3b):
``zeta_i = alpha / (2 omega_i) + beta omega_i / 2``.
"""
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ccedi.errors import InputError, require_finite_positive
from ccedi.fea.elements.hex8 import FACES, ElementGeometry, characteristic_length, element_geometry, hourglass_stiffness
from ccedi.fea.elements.hex8 import tangent_stiffness as hex_tangent
from ccedi.fea.elements.hex8_kernels import HexGroup, hex_group
from ccedi.fea.elements.rod import Rod, RodArrays, rod_arrays, rod_lumped_mass
from ccedi.fea.elements.tet4 import Tet4Group, tet4_group
from ccedi.fea.elements.tet4 import lumped_mass as tet4_lumped_mass
from ccedi.fea.elements.tet10 import Tet10Group, tet10_group
from ccedi.fea.elements.tet10 import lumped_mass as tet10_lumped_mass
from ccedi.fea.elements.tetra import CORNER_FACES, QUADRATIC_FACES, largest_frequency
from ccedi.fea.material import NeoHookean
from ccedi.fea.mesh import Mesh


@dataclass(frozen=True)
class ForcePulse:
    """A rectangular force pulse shared among a node set.

    The total force ``force_N`` is split among ``nodes`` in proportion to ``weights``
    and applied for ``t_start_s <= t < t_end_s``.

    Parameters
    ----------
    nodes : numpy.ndarray
        Loaded node ids (stored as int64).
    weights : numpy.ndarray
        Share of the force per node, one non-negative number per node, summing to 1.
    force_N : numpy.ndarray
        Total force, 3 finite components [N].
    t_start_s : float
        Pulse start [s], >= 0.
    t_end_s : float
        Pulse end [s], > ``t_start_s``.

    Raises
    ------
    InputError
        If the force is not 3 finite components, the times are not finite or not
        ordered, or the weights do not match the nodes or do not sum to 1.
    """

    nodes: np.ndarray
    weights: np.ndarray
    force_N: np.ndarray
    t_start_s: float
    t_end_s: float

    def __post_init__(self):
        force = np.asarray(self.force_N, dtype=float)
        if force.shape != (3,) or not np.all(np.isfinite(force)):
            raise InputError(f"force_N must be 3 finite components [N], got {self.force_N!r}")
        t0 = require_finite_positive("t_start_s (pulse start, s)", self.t_start_s, allow_zero=True)
        t1 = require_finite_positive("t_end_s (pulse end, s)", self.t_end_s)
        if t1 <= t0:
            raise InputError(f"t_end_s must exceed t_start_s ({t0} s), got {t1} s")
        w = np.asarray(self.weights, dtype=float)
        if len(w) != len(self.nodes) or not np.isclose(w.sum(), 1.0) or np.any(w < 0):
            raise InputError("weights must be one non-negative number per node, summing to 1")
        object.__setattr__(self, "force_N", force)
        object.__setattr__(self, "weights", w)
        object.__setattr__(self, "nodes", np.asarray(self.nodes, dtype=np.int64))


@dataclass(frozen=True)
class RotatingNodes:
    """Prescribed rigid rotation of a node set at constant angular velocity.

    x(t) = c + R(omega t) (X - c), a rotation about the axis through ``center_m``
    along ``axis``.

    Parameters
    ----------
    nodes : numpy.ndarray
        Driven node ids (stored as int64).
    center_m : numpy.ndarray
        A point c on the rotation axis, shape (3,) [m].
    axis : numpy.ndarray
        Axis direction, a non-zero 3-vector (stored normalised); the rotation is
        right-handed about it.
    omega_rad_s : float
        Angular velocity omega [rad/s], finite (negative turns the other way).

    Raises
    ------
    InputError
        If ``axis`` is not a non-zero finite 3-vector or ``omega_rad_s`` is not finite.
    """

    nodes: np.ndarray
    center_m: np.ndarray
    axis: np.ndarray
    omega_rad_s: float

    def __post_init__(self):
        axis = np.asarray(self.axis, dtype=float)
        norm = np.linalg.norm(axis)
        if axis.shape != (3,) or not np.isfinite(norm) or norm == 0.0:
            raise InputError(f"axis must be a non-zero 3-vector, got {self.axis!r}")
        if not np.isfinite(self.omega_rad_s):
            raise InputError(f"omega_rad_s must be finite, got {self.omega_rad_s!r}")
        object.__setattr__(self, "axis", axis / norm)
        object.__setattr__(self, "center_m", np.asarray(self.center_m, dtype=float))
        object.__setattr__(self, "nodes", np.asarray(self.nodes, dtype=np.int64))


@dataclass
class Model:
    """Everything the explicit solver needs: mesh, material, damping, constraints, loads.

    Construction validates the inputs and derives the element geometry of each solid
    group (hexahedra, 4-node and 10-node tetrahedra), the hourglass stiffness, rod arrays
    and lumped nodal masses.

    Parameters
    ----------
    mesh : Mesh
        Nodes [m], solid elements (hexahedra, 4- and 10-node tetrahedra) and node sets.
    material : NeoHookean or None
        Solid material; None only for a mesh without solid elements (rods and point
        masses only).
    alpha : float, optional
        Mass-proportional Rayleigh damping [1/s], >= 0. Default 0.
    beta : float, optional
        Stiffness-proportional Rayleigh damping [s], >= 0. Default 0.
    fixed_nodes : numpy.ndarray, optional
        Node ids with all displacements fixed (the clamped root). Default none.
    pulses : tuple of ForcePulse, optional
        External force pulses. Default none.
    rotating : RotatingNodes or None, optional
        Nodes driven in a prescribed rigid rotation (the drum). Default None.
    hourglass_coefficient : float, optional
        Q_hg, the scale on the physical hourglass stiffness of
        :func:`ccedi.fea.elements.hex8.hourglass_stiffness` [-], > 0. Default 1 (the
        incompatible-modes stiffness, LS-DYNA hourglass type 6 with QM = 1).
    rods : tuple of Rod, optional
        :class:`ccedi.fea.elements.rod.Rod` chains on mesh nodes (beam elements); they may
        share nodes with the solids. Default none.
    point_masses : dict, optional
        {node id: mass [kg]} lumped point-mass elements, masses > 0. Default none.
    contact : Contact or None, optional
        :class:`ccedi.fea.contact.penalty.Contact` of mesh nodes against a rigid surface.
        Default None.
    damping : {"global", "relative"}, optional
        Mass damping on the absolute velocity (LS-DYNA *DAMPING_GLOBAL) or on the
        velocity relative to the frame of ``rotating`` (*DAMPING_RELATIVE).
        Default ``"global"``.
    element_mass_scale : numpy.ndarray or None, optional
        Factor >= 1 on the density of each solid element (hexahedra, then 4-node, then
        10-node tetrahedra), shape (n_elements,) [-]: mass scaling
        (:mod:`ccedi.fea.solvers.mass_scaling`), for the tetrahedra only (the
        hexahedra's factors must be 1). It scales the element's lumped mass and its
        stable step (by the square root); the bulk viscosity keeps the material's
        density. Default None: no scaling.

    Attributes
    ----------
    geometry : ElementGeometry
        Reference geometry of the hexahedra.
    tet4 : Tet4Group
        Reference geometry of the 4-node tetrahedra (:mod:`ccedi.fea.elements.tet4`).
    tet10 : Tet10Group
        Reference geometry of the 10-node tetrahedra (:mod:`ccedi.fea.elements.tet10`).
    kappa : numpy.ndarray
        Hourglass stiffness K_hg per element, shape (e, 12, 12) [N/m].
    rod_arrays : RodArrays
        The rods packed for the kernels.
    mass : numpy.ndarray
        Lumped nodal masses, shape (n,) [kg].

    Raises
    ------
    InputError
        If a damping value or the hourglass coefficient is out of range, ``damping``
        is unknown (or ``"relative"`` without ``rotating``), ``element_mass_scale`` is
        not one factor >= 1 per solid element (1 on hexahedra), an element is inverted,
        the material is missing for solid elements, a rod or point mass refers to a
        node outside the mesh, a point mass is not > 0, or a free node has no mass.
    """

    mesh: Mesh
    material: NeoHookean | None
    alpha: float = 0.0
    beta: float = 0.0
    fixed_nodes: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    pulses: tuple = ()
    rotating: RotatingNodes | None = None
    hourglass_coefficient: float = 1.0
    rods: tuple = ()
    point_masses: dict = field(default_factory=dict)
    contact: object = None
    damping: str = "global"
    element_mass_scale: np.ndarray | None = None

    def __post_init__(self):
        self.alpha = require_finite_positive("alpha (mass-proportional damping, 1/s)", self.alpha, allow_zero=True)
        self.beta = require_finite_positive("beta (stiffness-proportional damping, s)", self.beta, allow_zero=True)
        self.hourglass_coefficient = require_finite_positive("hourglass_coefficient", self.hourglass_coefficient)
        self.fixed_nodes = np.asarray(self.fixed_nodes, dtype=np.int64)
        if self.damping not in ("global", "relative"):
            raise InputError(f"damping must be 'global' or 'relative', got {self.damping!r}")
        if self.damping == "relative" and self.rotating is None:
            raise InputError("damping = 'relative' needs a rotating frame (rotating nodes)")
        try:
            self.geometry: ElementGeometry = element_geometry(self.mesh.nodes, self.mesh.hexes)
        except ValueError as err:
            raise InputError(f"mesh: {err}") from None
        if self.material is None and self.mesh.n_elements:
            raise InputError("material is required when the mesh has solid elements")
        rho4, rho10 = self._tetrahedra_densities()
        try:
            self.tet4: Tet4Group = tet4_group(self.mesh.nodes, self.mesh.tets4, self.material, density=rho4)
            self.tet10: Tet10Group = tet10_group(self.mesh.nodes, self.mesh.tets10, self.material, density=rho10)
        except ValueError as err:
            raise InputError(f"mesh: {err}") from None
        mu, lam = (self.material.mu, self.material.lam) if self.material is not None else (0.0, 0.0)
        self.kappa = hourglass_stiffness(self.mesh.nodes, self.mesh.hexes, mu=mu, lam=lam,
                                         q_hg=self.hourglass_coefficient)
        self.rods = tuple(self.rods)
        if not all(isinstance(r, Rod) for r in self.rods):
            raise InputError("rods must be fea.rod.Rod objects")
        if any(r.nodes.max() >= self.mesh.n_nodes for r in self.rods):
            raise InputError("a rod refers to a node id beyond the mesh")
        self.rod_arrays: RodArrays = rod_arrays(self.mesh.nodes, self.rods)
        rho = self.material.rho if self.material is not None else 0.0
        self.mass = (lumped_mass(self.mesh, self.geometry, rho)
                     + tet4_lumped_mass(self.tet4, self.mesh.n_nodes, rho if rho4 is None else rho4)
                     + tet10_lumped_mass(self.mesh.nodes, self.tet10, rho if rho10 is None else rho10)
                     + rod_lumped_mass(self.mesh.nodes, self.rods))
        for node, m in dict(self.point_masses).items():
            if not 0 <= int(node) < self.mesh.n_nodes:
                raise InputError(f"point_masses: node {node} is not in the mesh (0..{self.mesh.n_nodes - 1})")
            self.mass[int(node)] += require_finite_positive(f"point_masses[{node}] (mass, kg)", m)
        free = np.ones(self.mesh.n_nodes, dtype=bool)
        free[self.fixed_nodes] = False
        if np.any(self.mass[free] <= 0.0):
            bad = int(np.flatnonzero(free & (self.mass <= 0.0))[0])
            raise InputError(f"node {bad} is free but has no mass (belongs to no element)")

    def _tetrahedra_densities(self):
        """The 4-node and the 10-node tetrahedra's densities [kg/m^3] under
        ``element_mass_scale`` (None for each: the material's), after checking it."""
        if self.element_mass_scale is None:
            return None, None
        n_hex, n_tet4 = len(self.mesh.hexes), len(self.mesh.tets4)
        s = np.asarray(self.element_mass_scale, dtype=float)
        if s.shape != (self.mesh.n_elements,) or not np.all(np.isfinite(s)) or np.any(s < 1.0):
            raise InputError(f"element_mass_scale must be one finite factor >= 1 per solid element, shape "
                             f"({self.mesh.n_elements},), got shape {s.shape}")
        if np.any(s[:n_hex] != 1.0):
            raise InputError("element_mass_scale: mass scaling is for tetrahedra; the hexahedra's factors must be 1")
        self.element_mass_scale = s
        rho = self.material.rho
        return rho * s[n_hex:n_hex + n_tet4], rho * s[n_hex + n_tet4:]

    @cached_property
    def hex_length_factor(self):
        """Scale s on the hexahedra's characteristic length V / A_max of paper Eq. (6) [-],
        so that at rest the stable step ``min_e s L_e / c`` is the real limit of central
        differences on this mesh, 2 / omega_max, with omega_max the largest natural
        frequency of the hexahedra alone (unconstrained tangent at the reference state,
        their lumped mass; Lanczos, :func:`ccedi.fea.elements.tetra.largest_frequency`). During a
        run L_e follows the deformation. Measured: s = 0.84 on a mesh of cubes (Eq. 6 alone
        would run at 1.07 of the limit and diverge), 0.9986 on SM-A, 0.962 on SM-B; 1 when
        there are no hexahedra or Lanczos does not converge."""
        if not len(self.mesh.hexes) or self.material is None:
            return 1.0
        K = hex_tangent(self.mesh.nodes, self.mesh.hexes, self.geometry, kappa=self.kappa, material=self.material)
        omega = largest_frequency(K, lumped_mass(self.mesh, self.geometry, self.material.rho))
        if not omega > 0.0:
            return 1.0
        Le = characteristic_length(self.mesh.nodes[self.mesh.hexes], self.geometry.volume)
        return float((2.0 / omega) / (Le.min() / self.material.wave_speed))

    @cached_property
    def hexahedra(self) -> HexGroup:
        """The hexahedra as the compiled kernel takes them (:func:`ccedi.fea.elements.hex8_kernels.hex_group`:
        reference arrays, element blocks, node-to-element slots)."""
        return hex_group(self.mesh.nodes, self.mesh.hexes, self.geometry, kappa=self.kappa,
                         length_factor=self.hex_length_factor)

    @property
    def solid_constants(self):
        """(mu [Pa], lam [Pa], rho [kg/m^3], wave speed [m/s]) of the solid material, zeros
        for a model without solid elements (the hexahedron kernel then has nothing to do).
        """
        m = self.material
        return (m.mu, m.lam, m.rho, m.wave_speed) if m is not None else (0.0, 0.0, 0.0, 0.0)

    @property
    def total_mass(self):
        """Total mass [kg]."""
        return float(self.mass.sum())


def lumped_mass(mesh, geometry, rho):
    """Diagonal (lumped) nodal masses of the hexahedra.

    Each element's mass rho V0 is split equally over its 8 nodes.

    Parameters
    ----------
    mesh : Mesh
        The mesh (connectivity and node count).
    geometry : ElementGeometry
        Reference geometry (element volumes V0 [m^3]).
    rho : float
        Density [kg/m^3].

    Returns
    -------
    numpy.ndarray
        Nodal masses, shape (n,) [kg]; zero on nodes of no solid element.
    """
    m = np.zeros(mesh.n_nodes)
    np.add.at(m, mesh.hexes, np.repeat((rho * geometry.volume / 8.0)[:, None], 8, axis=1))
    return m


def face_node_weights(mesh, node_set):
    """Area weights of the nodes of a node set, for a uniform traction on it.

    The traction acts on the element faces lying wholly in the set, with the consistent
    nodal loads of a uniform traction: a hexahedron's quadrilateral gives 1/4 of its area
    to each node, a 4-node tetrahedron's triangle 1/3 to each corner, and a 10-node
    tetrahedron's 6-node triangle 1/3 to each mid-side node and nothing to its corners
    (the integrals of its quadratic shape functions).

    Parameters
    ----------
    mesh : Mesh
        The mesh.
    node_set : numpy.ndarray
        Node ids (e.g. ``mesh.node_sets["tip"]``).

    Returns
    -------
    numpy.ndarray
        Weights, one per node of ``node_set`` in its order, summing to 1.

    Raises
    ------
    InputError
        If the node set contains no complete element face.
    """
    in_set = np.zeros(mesh.n_nodes, dtype=bool)
    in_set[node_set] = True
    faces = mesh.hexes[:, FACES].reshape(-1, 4)
    faces = faces[in_set[faces].all(axis=1)]
    triangles = mesh.tets4[:, CORNER_FACES].reshape(-1, 3)
    triangles = triangles[in_set[triangles].all(axis=1)]
    quadratic = mesh.tets10[:, QUADRATIC_FACES].reshape(-1, 6)
    quadratic = quadratic[in_set[quadratic].all(axis=1)]
    if len(faces) + len(triangles) + len(quadratic) == 0:
        raise InputError("node set contains no complete element face")
    p = mesh.nodes[faces]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1]), axis=-1)
    w = np.zeros(mesh.n_nodes)
    np.add.at(w, faces, np.repeat(area[:, None] / 4.0, 4, axis=1))
    for tri, mids in ((triangles, triangles), (quadratic[:, :3], quadratic[:, 3:])):
        p = mesh.nodes[tri]
        area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=-1)
        np.add.at(w, mids, np.repeat(area[:, None] / 3.0, 3, axis=1))
    return w[node_set] / w[node_set].sum()


def tip_pulse(mesh, force_N, duration_s, *, t_start_s=0.0):
    """The paper's impulse: a force pulse on the tip face, area-weighted over its nodes.

    Parameters
    ----------
    mesh : Mesh
        Mesh with a ``"tip"`` node set.
    force_N : array_like
        Total force, 3 components [N].
    duration_s : float
        Pulse duration [s], > 0.
    t_start_s : float, optional
        Pulse start [s], >= 0. Default 0.

    Returns
    -------
    ForcePulse
        Acting on the tip nodes for ``t_start_s <= t < t_start_s + duration_s``.

    Raises
    ------
    InputError
        If ``duration_s`` is not a finite number > 0 (and see :class:`ForcePulse`).
    """
    tip = mesh.node_sets["tip"]
    return ForcePulse(nodes=tip, weights=face_node_weights(mesh, tip),
                      force_N=np.asarray(force_N, dtype=float),
                      t_start_s=t_start_s, t_end_s=t_start_s + require_finite_positive("duration_s", duration_s))


def cantilever_model(mesh, material, *, alpha=0.0, beta=0.0, pulses=(), hourglass_coefficient=1.0):
    """A finger clamped at its root face (all ``"root"`` nodes fixed).

    Parameters
    ----------
    mesh : Mesh
        Mesh with a ``"root"`` node set.
    material : NeoHookean
        Solid material.
    alpha : float, optional
        Mass-proportional damping [1/s], >= 0. Default 0.
    beta : float, optional
        Stiffness-proportional damping [s], >= 0. Default 0.
    pulses : iterable of ForcePulse, optional
        External force pulses. Default none.
    hourglass_coefficient : float, optional
        Q_hg [-], > 0. Default 1.

    Returns
    -------
    Model
        The clamped cantilever.
    """
    return Model(mesh=mesh, material=material, alpha=alpha, beta=beta,
                 fixed_nodes=mesh.node_sets["root"], pulses=tuple(pulses),
                 hourglass_coefficient=hourglass_coefficient)
