"""A compliant finger on a rotating drum sweeping over a fixed elliptical object (paper
sections 3.3-3.4, Table 2, Fig. 9).

Frame: the drum turns about the global z axis through the origin at omega = 20 rpm
(2.095 rad/s, counter-clockwise seen from +z); everything moves in the x-y plane.

Choices where Table 2 is ambiguous (all are :class:`DrumSetup` parameters):

* drum "82.55 (25)": radius 82.55 mm (3.25 in), 25 mm wide. The drum is rigid: the
  finger's root face turns with it (prescribed rotation).
* object "99.1, 67, 3(25)": an ellipse of semi-axes 99.1 mm (along x) and 67 mm (along
  y), a solid plate 25 mm thick centred on the finger's mid-plane, centre at
  (Dx, Dy) = (101.6, 184.15) mm; rigid for the dynamics. Read as full axes (semi-axes
  49.55 x 33.5 mm) the contact lasts 0.70 / 0.57 / 0.40 s for alpha = 7.5 / 180 / 600 1/s
  against the paper's 0.92 / 0.85 / 0.79 s; read as semi-axes, 0.93 / 0.845 / 0.775 s.
  So the table gives radii, like the drum's 82.55 mm.
* F/T sensor "20 (12.25)": a 20 mm diameter pad under the object's centre, where the
  object is clamped in the static stress solve (at least the 9 back-face nodes nearest
  the centre, when the pad holds fewer).
* finger: the 8-in SM-A finger (5 x 5 x 51 hexahedra, 1275 elements, 1872 nodes, as in
  Table 2), root on the drum surface, pointing radially out, soft (8.45 mm) direction
  tangential, 24 mm wide along the drum axis. At t = 0 it turns rigidly with the drum
  (initial velocity omega x r), the paper's "drum rotating at a constant speed".
  Any other finger mesh (hexahedra, 4- or 10-node tetrahedra, e.g. one read by
  :func:`ccedi.fea.mesh.readers.read_finger_mesh`) goes on the drum as ``DrumSetup(finger=mesh)``:
  length along z, bending along y, mounted by :func:`mounted_finger` (the centroid of its
  ``root`` set on the drum's radius, the root's lowest point on the drum surface); its
  root set turns with the drum, and every node of its outer surface is a contact node
  (:func:`ccedi.fea.contact.penalty.boundary_nodes`: for 10-node tetrahedra the corner and the
  mid-edge nodes of the boundary faces).
* initial angle theta0 (the one unknown): calibrated so that the alpha = 7.5 1/s finger
  first touches the object at t = 0.32 s (:func:`calibrate_initial_angle`).

Object stress: the object is rigid in the dynamics; at every output time a linear
static FE solve of the object (hexahedra, AL6061, clamped on the sensor pad) under the
finger's contact forces, each applied at the nearest node of the object's lateral
surface, gives its largest von Mises stress. Point-like loads make this maximum
mesh dependent (it grows under refinement); it is a comparative measure.
"""
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse.linalg as spla

from ccedi.errors import InputError, require_finite_positive
from ccedi.fea.contact.penalty import Contact, RigidEllipse, boundary_nodes
from ccedi.fea.elements.hex8 import deformation_gradient
from ccedi.fea.material import RUBBER, NeoHookean, max_von_mises_of
from ccedi.fea.mesh import SEMI_AXES, SM_A_ROOT_REFINEMENT, Mesh, elliptical_cantilever, sm_a_elements_along
from ccedi.fea.model import Model, RotatingNodes
from ccedi.fea.solvers.explicit import run
from ccedi.fea.solvers.rotating_frame import drum_to_object, frame_velocities
from ccedi.fea.solvers.static import free_dofs, tangent_stiffness
from ccedi.models import ContactResponse, contact_timing, validate_run_args
from ccedi.quantities import QUANTITIES

AL6061 = NeoHookean(E=69e9, nu=0.33, rho=2700.0)
"""Object and sensor material (Table 2)."""

CALIBRATED_THETA0_RAD = -0.012595
"""Initial finger angle [rad] from :func:`calibrate_initial_angle` with the default
:class:`DrumSetup` (alpha = 7.5 1/s first touches at 0.32 s, to the 1 ms output step;
rigid-finger estimate -0.035640 rad, then one FE correction). Recalibrate with
``ccedi contact --calibrate`` after changing the geometry."""

DEFAULT_FINGER_LENGTH_M = 0.2032
"""Length of the generated finger on the drum [m] (8 in, Table 2)."""

PAPER_CONTACT = {"first_contact_s": {7.5: 0.32, 600.0: 0.57},
                 "contact_duration_s": {7.5: 0.92, 180.0: 0.85, 600.0: 0.79}}
"""The paper's reported contact timings (section 3.4)."""


@dataclass(frozen=True)
class DrumSetup:
    """Geometry, speeds and materials of the rotating-finger test (SI units).

    Parameters
    ----------
    drum_radius_m : float
        Drum radius [m].
    finger_length_m : float or None
        Finger length [m]. None (the default): 8 in (:data:`DEFAULT_FINGER_LENGTH_M`),
        or the length of ``finger`` (the distance from its root face to the centroid of
        its ``tip`` set, :func:`finger_length_of`); set after construction.
    omega_rad_s : float
        Drum speed [rad/s], counter-clockwise seen from +z.
    object_center_m : tuple
        Object centre (x, y) [m].
    object_semi_axes_m : tuple
        Object semi-axes (along its x, along its y) [m].
    object_angle_rad : float
        Object rotation about z [rad].
    object_thickness_m : float
        Object plate thickness [m], centred on the finger's mid-plane.
    sensor_radius_m : float
        F/T sensor pad radius [m] (the object's clamp in the stress solve).
    friction : float
        Coulomb friction coefficient [-].
    contact_damping_ratio : float
        Normal contact damping, a fraction of each contact spring's critical damping [-]
        (:func:`ccedi.fea.contact.penalty.contact_damping`; 0: none).
    theta0_rad : float
        Initial finger angle [rad] (:func:`calibrate_initial_angle`).
    finger_material, object_material : NeoHookean
        Materials.
    finger_semi_axes_m : tuple
        Finger section semi-axes [m] (at the root).
    finger_taper_ratio : float
        The generated finger's tip semi-axes over its root's [-] (the section scales
        linearly along the length, :func:`ccedi.fea.mesh.elliptical_cantilever`); 1: the
        prism. Must be 1 with a ``finger`` mesh, whose shape is its own.
    finger_section_elements : int
        Elements across the finger section.
    finger_elements_along : int or None
        Elements along the finger (None: SM-A, ~4 mm).
    objects_per_revolution : float
        Objects the finger meets per drum revolution [-], >= 1 (:attr:`cycle_s`).
    cycle_time_s : float or None
        Time from one object's first contact to the next object's [s] (None: one
        revolution over ``objects_per_revolution``, :attr:`cycle_s`).
    finger : ccedi.fea.mesh.Mesh or None
        A finger mesh of any element type (hexahedra, 4- or 10-node tetrahedra) with node
        sets ``root`` and ``tip``, length along z, bending along y (None: the generated
        elliptical finger of ``finger_semi_axes_m``, ``finger_section_elements`` and
        ``finger_elements_along``, which are then not used). Stored as
        :func:`mounted_finger` places it; its length sets ``finger_length_m``.

    Raises
    ------
    InputError
        A non-positive or non-finite size, a bad element count, an object that overlaps
        the drum, a ``finger`` that is no valid finger mesh (:func:`mounted_finger`), or a
        ``finger_length_m`` other than such a finger's length.
    """
    drum_radius_m: float = 0.08255
    finger_length_m: float | None = None
    omega_rad_s: float = 2.095
    object_center_m: tuple = (0.1016, 0.18415)
    object_semi_axes_m: tuple = (0.0991, 0.067)
    object_angle_rad: float = 0.0
    object_thickness_m: float = 0.025
    sensor_radius_m: float = 0.010
    friction: float = 0.6
    contact_damping_ratio: float = 0.0
    theta0_rad: float = CALIBRATED_THETA0_RAD
    finger_material: NeoHookean = RUBBER
    finger_semi_axes_m: tuple = SEMI_AXES
    finger_taper_ratio: float = 1.0
    object_material: NeoHookean = AL6061
    finger_section_elements: int = 5
    finger_elements_along: int | None = None
    objects_per_revolution: float = 2.0
    cycle_time_s: float | None = None
    finger: Mesh | None = None

    def __post_init__(self):
        self._resolve_finger()
        q = QUANTITIES
        checks = {"drum_radius_m": q["drum_radius_m"], "omega_rad_s": q["omega_rad_s"], "friction": q["friction"],
                  "contact_damping_ratio": q["contact_damping_ratio"], "finger_length_m": q["length_m"], "theta0_rad": q["angle_rad"],
                  "object_angle_rad": q["angle_rad"], "finger_taper_ratio": q["taper_ratio"]}
        for name, quantity in checks.items():
            quantity.check(getattr(self, name), f"DrumSetup {name}")
        for name, quantity in (("object_center_m", q["object_position_m"]),
                               ("object_semi_axes_m", q["object_semi_axis_m"]),
                               ("finger_semi_axes_m", q["section_semi_axis_m"])):
            for value in _pair(getattr(self, name), name):
                quantity.check(value, f"DrumSetup {name}")
        for name in ("object_thickness_m", "sensor_radius_m"):
            require_finite_positive(f"DrumSetup {name}", getattr(self, name))
        for name in ("finger_section_elements", "finger_elements_along"):
            n = getattr(self, name)
            if n is not None and (int(n) != n or n < 1):
                raise InputError(f"{name} must be an integer >= 1, got {n!r}")
        n = self.objects_per_revolution
        if isinstance(n, bool) or not isinstance(n, (int, float)) or not 1.0 <= n <= 360.0:
            raise InputError(f"DrumSetup objects_per_revolution = {n!r}: must be a number in 1..360")
        if self.cycle_time_s is not None:
            require_finite_positive("DrumSetup cycle_time_s", self.cycle_time_s)
        c = np.hypot(*self.object_center_m)
        if c - max(self.object_semi_axes_m) <= self.drum_radius_m:
            raise InputError("the object overlaps the drum: move object_center_m or shrink it")

    def _resolve_finger(self):
        """Mount ``finger`` and set ``finger_length_m`` (None: the default or the finger's)."""
        length = self.finger_length_m
        if self.finger is None:
            object.__setattr__(self, "finger_length_m", DEFAULT_FINGER_LENGTH_M if length is None else length)
            return
        if self.finger_taper_ratio != 1.0:
            raise InputError(f"DrumSetup finger_taper_ratio = {self.finger_taper_ratio!r}: the finger is a given "
                             f"mesh, whose shape is its own; a taper is for the generated finger only (leave it 1)")
        mounted = mounted_finger(self.finger)
        object.__setattr__(self, "finger", mounted)
        own = finger_length_of(mounted)
        if length is not None and not np.isclose(length, own, rtol=1e-9, atol=0.0):
            raise InputError(f"DrumSetup finger_length_m = {length!r}: the finger mesh sets the length "
                             f"({own:.6g} m); leave finger_length_m unset")
        object.__setattr__(self, "finger_length_m", own)

    @property
    def cycle_s(self):
        """Time between two objects [s]: ``cycle_time_s`` if set, else one drum revolution
        over ``objects_per_revolution``, 2 pi / (omega n) (1.5 s for the paper's 20 rpm
        drum meeting two objects a revolution). The finger must be back in its running
        shape one cycle after it first touched an object."""
        if self.cycle_time_s is not None:
            return float(self.cycle_time_s)
        return 2.0 * np.pi / (self.omega_rad_s * self.objects_per_revolution)

    @property
    def finger_thickness_m(self):
        """The finger's thickness along its bending direction y [m]: 2 b of the generated
        finger's thickest section (the root's, or the tip's when it widens), the largest
        extent along y of a ``finger`` mesh."""
        if self.finger is None:
            return 2.0 * self.finger_semi_axes_m[1] * max(1.0, self.finger_taper_ratio)
        y = self.finger.nodes[:, 1]
        return float(y.max() - y.min())

    @property
    def object_surface(self):
        """The object as the contact's rigid ellipse (:class:`ccedi.fea.contact.penalty.RigidEllipse`)."""
        h = 0.5 * self.object_thickness_m
        return RigidEllipse(center_m=self.object_center_m, a_m=self.object_semi_axes_m[0],
                            b_m=self.object_semi_axes_m[1], angle_rad=self.object_angle_rad,
                            z_min_m=-h, z_max_m=h, mu=self.friction, damping_ratio=self.contact_damping_ratio)


def _pair(value, name):
    """``value`` as two numbers, or :class:`ccedi.errors.InputError` naming ``name``."""
    if not isinstance(value, (tuple, list, np.ndarray)) or len(value) != 2:
        raise InputError(f"DrumSetup {name} = {value!r}: must be a pair (x, y) of numbers")
    return tuple(value)


def finger_frame(theta):
    """Rotation taking finger mesh coordinates (x: wide, y: soft, z: along) to the drum
    frame at angle theta: z -> radial e_r, y -> tangential e_theta, x -> e_theta x e_r
    (along -z), a proper rotation.

    Parameters
    ----------
    theta : float
        Drum angle [rad].

    Returns
    -------
    numpy.ndarray
        (3, 3) rotation matrix.
    """
    er = np.array([np.cos(theta), np.sin(theta), 0.0])
    et = np.array([-np.sin(theta), np.cos(theta), 0.0])
    return np.column_stack([np.cross(et, er), et, er])


def mounted_finger(mesh):
    """A finger mesh placed for the drum: translated so that the centroid of its ``root``
    set lies on the z axis (the drum's radius) and the root's lowest point at z = 0 (the
    drum surface). A mesh already so placed is returned as it is.

    Parameters
    ----------
    mesh : ccedi.fea.mesh.Mesh
        Hexahedra, 4- or 10-node tetrahedra (one type), node sets ``root`` and ``tip``,
        length along +z, bending along y.

    Returns
    -------
    ccedi.fea.mesh.Mesh
        The translated mesh (same elements and node sets).

    Raises
    ------
    InputError
        Not a :class:`ccedi.fea.mesh.Mesh`, no single solid element type, a ``root`` or
        ``tip`` set missing or empty, or nodes below the root (inside the drum).
    """
    if not isinstance(mesh, Mesh):
        raise InputError(f"DrumSetup finger must be a ccedi.fea.mesh.Mesh, got {type(mesh).__name__}")
    if mesh.element_type not in ("hex8", "tet4", "tet10"):
        raise InputError(f"DrumSetup finger: element type {mesh.element_type!r}; must be one of hex8, tet4, tet10")
    for name in ("root", "tip"):
        if len(mesh.node_sets.get(name, ())) == 0:
            raise InputError(f"DrumSetup finger: node set {name!r} missing or empty (sets: {sorted(mesh.node_sets)})")
    root = mesh.nodes[mesh.node_sets["root"]]
    shift = np.array([-root[:, 0].mean(), -root[:, 1].mean(), -root[:, 2].min()])
    size = float(np.ptp(mesh.nodes, axis=0).max())
    nodes = mesh.nodes + shift if np.abs(shift).max() > 1e-12 * size else mesh.nodes
    below = -nodes[:, 2].min()
    if below > 1e-9 * size:
        raise InputError(f"DrumSetup finger: nodes reach {below:.3g} m below the root (inside the drum): "
                         "the root set must be the finger's end at the lowest z")
    if nodes is mesh.nodes:
        return mesh
    return Mesh(nodes=nodes, hexes=mesh.hexes, tets4=mesh.tets4, tets10=mesh.tets10, node_sets=dict(mesh.node_sets))


def finger_length_of(mesh):
    """Length of a mounted finger (:func:`mounted_finger`): the z of the centroid of its
    ``tip`` set [m] (the root's lowest point at z = 0).

    Parameters
    ----------
    mesh : ccedi.fea.mesh.Mesh
        A mounted finger.

    Returns
    -------
    float
        Length [m].
    """
    return float(mesh.nodes[mesh.node_sets["tip"], 2].mean())


def finger_mesh(setup: DrumSetup):
    """The finger's mesh in its own frame (root at z = 0): ``setup.finger`` if given, else
    SM-A (5 x 5 in the section, ~4 mm along, refined at the root as
    :func:`ccedi.fea.mesh.sm_a`) unless ``finger_section_elements`` /
    ``finger_elements_along`` say otherwise, tapered by ``finger_taper_ratio``.

    Parameters
    ----------
    setup : DrumSetup

    Returns
    -------
    ccedi.fea.mesh.Mesh
        Node sets ``root`` and ``tip``.
    """
    if setup.finger is not None:
        return setup.finger
    L = setup.finger_length_m
    n_along = setup.finger_elements_along or sm_a_elements_along(L)
    a, b = setup.finger_semi_axes_m
    return elliptical_cantilever(L, setup.finger_section_elements, n_along, a=a, b=b,
                                 root_refinement=SM_A_ROOT_REFINEMENT, taper_ratio=setup.finger_taper_ratio)


def finger_on_drum(setup: DrumSetup, alpha, damping="global"):
    """The finger model at angle ``setup.theta0_rad``: root face turning with the drum,
    contact of its surface nodes with the rigid object.

    Parameters
    ----------
    setup : DrumSetup
    alpha : float
        Mass-proportional damping [1/s].
    damping : str, optional
        "global" or "relative".

    Returns
    -------
    tuple
        (ccedi.fea.model.Model, v0: initial nodal velocities (n, 3) [m/s], rigid turning).
    """
    local = finger_mesh(setup)
    Q = finger_frame(setup.theta0_rad)
    nodes = (local.nodes + [0.0, 0.0, setup.drum_radius_m]) @ Q.T
    mesh = Mesh(nodes=nodes, hexes=local.hexes, tets4=local.tets4, tets10=local.tets10,
                node_sets=dict(local.node_sets))
    axis = np.array([0.0, 0.0, 1.0])
    rotating = RotatingNodes(nodes=mesh.node_sets["root"], center_m=np.zeros(3), axis=axis,
                             omega_rad_s=setup.omega_rad_s)
    contact = Contact(nodes=boundary_nodes(mesh), surface=setup.object_surface)
    model = Model(mesh=mesh, material=setup.finger_material, alpha=alpha, rotating=rotating, contact=contact,
                  damping=damping)
    v0 = frame_velocities(nodes, rotating.center_m, axis, setup.omega_rad_s)
    return model, v0


@dataclass
class ObjectStress:
    """Linear static stress of the object under the finger's contact forces.

    Parameters
    ----------
    setup : DrumSetup
        Object geometry, material and sensor pad.
    n_section : int, optional
        Elements across the object's section.
    n_thickness : int, optional
        Elements through its thickness.

    Attributes
    ----------
    model : ccedi.fea.model.Model
        The object's FE model, clamped on its sensor pad (built from ``setup``).
    """
    setup: DrumSetup
    n_section: int = 12
    n_thickness: int = 4
    model: Model = field(init=False)

    def __post_init__(self):
        s = self.setup
        a, b = s.object_semi_axes_m
        local = elliptical_cantilever(s.object_thickness_m, self.n_section, self.n_thickness, a=a, b=b)
        ca, sa = np.cos(s.object_angle_rad), np.sin(s.object_angle_rad)
        R = np.array([[ca, -sa, 0.0], [sa, ca, 0.0], [0.0, 0.0, 1.0]])
        nodes = local.nodes @ R.T + [s.object_center_m[0], s.object_center_m[1], -0.5 * s.object_thickness_m]
        back = local.node_sets["root"]
        r = np.hypot(*(local.nodes[back, :2].T))
        pad = back[r <= s.sensor_radius_m]
        if len(pad) < 9:                                    # coarse object mesh: the 9 nearest nodes
            pad = back[np.argsort(r)[:9]]
        mesh = Mesh(nodes=nodes, hexes=local.hexes, node_sets={"sensor": pad})
        self.model = Model(mesh=mesh, material=s.object_material, fixed_nodes=pad)
        K = tangent_stiffness(self.model)
        self._free = free_dofs(self.model)
        self._solve = spla.factorized(K[self._free][:, self._free].tocsc())
        on_side = boundary_nodes(mesh)
        r = np.hypot(*((local.nodes[on_side, :2] / [a, b]).T))
        self._side = on_side[r > 0.999]                     # the lateral (elliptical) surface

    def max_von_mises(self, points, forces):
        """Largest element von Mises stress [Pa] for contact ``forces`` (k, 3) [N] on the
        object at finger-node ``points`` (k, 3) [m] (each lumped to the nearest lateral
        surface node). Zero without forces.

        Parameters
        ----------
        points : numpy.ndarray
            (k, 3) contact points [m].
        forces : numpy.ndarray
            (k, 3) forces on the object [N].

        Returns
        -------
        float
            Largest von Mises stress [Pa].
        """
        if len(points) == 0:
            return 0.0
        side_xyz = self.model.mesh.nodes[self._side]
        nearest = self._side[np.argmin(((points[:, None, :] - side_xyz[None]) ** 2).sum(-1), axis=1)]
        f = np.zeros_like(self.model.mesh.nodes)
        np.add.at(f, nearest, forces)
        u = np.zeros(f.size)
        u[self._free] = self._solve(f.ravel()[self._free])
        x = self.model.mesh.nodes + u.reshape(-1, 3)
        F = deformation_gradient(x[self.model.mesh.hexes], self.model.geometry)
        mat = self.model.material
        return max_von_mises_of(F, mat.mu, mat.lam)


def contact_run(setup: DrumSetup, alpha, *, damping="global", t_end_s=1.5, n_outputs=300, progress=False,
                snapshot_every=0, object_stress=True, threads=None):
    """Run the finger over the object (the solver-level form of :class:`FullContactModel`).

    Parameters
    ----------
    setup : DrumSetup
    alpha : float
        Mass-proportional damping [1/s].
    damping : str, optional
        "global" or "relative".
    t_end_s : float, optional
        Simulated time [s].
    n_outputs : int, optional
        Output times.
    progress : bool, optional
        Progress bar.
    snapshot_every : int, optional
        Store nodal positions every this many outputs (0: none).
    object_stress : bool, optional
        Solve the object's stress at every output.
    threads : int, optional
        Threads of the run (:func:`ccedi.threads.thread_count`; default: the free
        cores).

    Returns
    -------
    tuple
        (ccedi.fea.solvers.explicit.RunResult, model). The history gains ``reaction_force_N``
        (magnitude of the force on the object) [N], ``max_object_von_mises_Pa`` [Pa] and
        the contact patch along the finger, ``contact_patch_start_m`` /
        ``contact_patch_end_m`` (distance from the root [m], NaN without contact).
    """
    model, v0 = finger_on_drum(setup, alpha, damping)
    nodes = model.contact.nodes
    along = (model.mesh.nodes[nodes] @ finger_frame(setup.theta0_rad))[:, 2] - setup.drum_radius_m
    stress = ObjectStress(setup) if object_stress else None

    def hook(t, x, f_ext):
        f = f_ext[nodes]
        active = np.abs(f).sum(axis=1) > 0.0
        out = {"max_object_von_mises_Pa": stress.max_von_mises(x[nodes][active], -f[active]) if stress else np.nan,
               "contact_patch_start_m": float(along[active].min()) if active.any() else np.nan,
               "contact_patch_end_m": float(along[active].max()) if active.any() else np.nan}
        return out

    result = run(model, t_end_s, n_outputs=n_outputs, v0=v0, progress=progress, snapshot_every=snapshot_every,
                 output_hook=hook, threads=threads)
    h = result.history
    h.insert(h.columns.get_loc("contact_force_z_N") + 1, "reaction_force_N",
             np.sqrt(h.contact_force_x_N**2 + h.contact_force_y_N**2 + h.contact_force_z_N**2))
    return result, model


def front_distance_m(setup: DrumSetup, point_xy):
    """Signed distance [m] of a point from the object's minor axis, positive on the front
    half: the half the sweep reaches first (the finger moves along e_theta, so it comes
    from the end of the major axis that points against e_theta at the centre).

    Parameters
    ----------
    setup : DrumSetup
    point_xy : array_like
        A point (x, y) [m].

    Returns
    -------
    float
        Distance along the major axis [m], > 0 on the front half, < 0 on the rear half.
    """
    c = np.asarray(setup.object_center_m, dtype=float)
    e_theta = np.array([-c[1], c[0]]) / np.hypot(*c)           # direction of finger motion at the object
    u_a = np.array([np.cos(setup.object_angle_rad), np.sin(setup.object_angle_rad)])
    along = float(np.dot(np.asarray(point_xy, dtype=float) - c, u_a))
    return -along if np.dot(e_theta, u_a) >= 0.0 else along


def object_side(setup: DrumSetup, point_xy):
    """"front" or "rear": the halves of the object on either side of its minor axis
    (:func:`front_distance_m`).

    Parameters
    ----------
    setup : DrumSetup
    point_xy : array_like
        A point (x, y) [m].

    Returns
    -------
    str
        "front" or "rear".
    """
    return "front" if front_distance_m(setup, point_xy) > 0.0 else "rear"


def _max_or_none(column):
    """Largest value of a history column, None when it holds no number (e.g. the object
    stress of a run without it)."""
    value = column.max()
    return None if np.isnan(value) else float(value)


def contact_summary(setup: DrumSetup, result, model):
    """The summary ``ccedi contact`` writes, from a :func:`contact_run`.

    Parameters
    ----------
    setup : DrumSetup
    result : ccedi.fea.solvers.explicit.RunResult
    model : ccedi.fea.model.Model
        The two of :func:`contact_run`.

    Returns
    -------
    dict
        The core keys of :data:`ccedi.models.CONTACT_CORE_SUMMARY` but ``model`` (which
        :class:`FullContactModel` adds) and :data:`ccedi.models.FE_CONTACT_EXTRA_SUMMARY`;
        the validity checks and ``warnings`` are the solver's
        (:func:`ccedi.fea.solvers.validity.run_checks`).
    """
    h = result.history
    summary = {"alpha_per_s": model.alpha, "damping": model.damping, "theta0_rad": setup.theta0_rad,
               "wall_time_s": result.summary["wall_time_s"], "steps": result.summary["steps"]}
    summary.update(contact_timing(h))
    if summary["contact_start_s"] is not None:
        summary.update({"first_contact_side": object_side(setup, summary["first_contact_point_m"]),
                        "last_contact_side": object_side(setup, summary["last_contact_point_m"]),
                        "max_object_stress_Pa": _max_or_none(h.max_object_von_mises_Pa),
                        "max_penetration_m": float(h.max_penetration_m.max())})
    else:
        summary.update({"first_contact_side": None, "last_contact_side": None, "max_object_stress_Pa": 0.0,
                        "max_penetration_m": 0.0})
    summary["penetration_to_thickness"] = summary["max_penetration_m"] / setup.finger_thickness_m
    for key in ("energy_balance_error", "hourglass_energy_fraction", "max_log_strain"):
        summary[key] = result.summary[key]
    summary["warnings"] = list(result.summary["warnings"])
    summary["friction_work_J"] = float(h.friction_work_J.iloc[-1])
    summary["max_penalty_energy_J"] = float(h.penalty_energy_J.max())
    return summary


class FullContactModel:
    """The full explicit FE model of the finger on the drum, a
    :class:`ccedi.models.ContactModel` (the reduced one is
    :class:`ccedi.rom.contact_rom.ReducedContactModel`).

    Parameters
    ----------
    setup : DrumSetup
        Geometry, speeds and materials.
    object_stress : bool, optional
        Compute the object's stress at every output (a static solve per output; the
        ``max_object_von_mises_Pa`` column is NaN without it).
    """
    name = "fea"

    def __init__(self, setup: DrumSetup, object_stress=True):
        self.setup = setup
        self.object_stress = object_stress

    def run(self, alpha, *, damping="global", t_end_s=1.5, n_outputs=300, progress=False):
        """Run the finger over the object (:func:`contact_run`).

        Parameters
        ----------
        alpha : float
            Mass-proportional damping coefficient [1/s].
        damping : str, optional
            "global" or "relative".
        t_end_s : float, optional
            Simulated time [s].
        n_outputs : int, optional
            Output times.
        progress : bool, optional
            Show a progress bar.

        Returns
        -------
        ccedi.models.ContactResponse
            History: the core columns and :data:`ccedi.models.FE_CONTACT_EXTRA_COLUMNS`;
            summary: ``model`` then :func:`contact_summary`.

        Raises
        ------
        InputError
            Invalid arguments (:func:`ccedi.models.validate_run_args`).
        SolverError
            The explicit solver cannot continue.
        """
        alpha, t_end_s, n_outputs = validate_run_args(alpha, t_end_s, n_outputs, damping=damping)
        result, model = contact_run(self.setup, alpha, damping=damping, t_end_s=t_end_s, n_outputs=n_outputs,
                                    progress=progress, object_stress=self.object_stress)
        summary = {"model": self.name, **contact_summary(self.setup, result, model)}
        return ContactResponse(history=result.history, summary=summary)


def first_contact_angle(setup: DrumSetup, samples=4000):
    """Drum angle change [rad] after which the undeformed finger, turning rigidly from
    ``setup.theta0_rad``, first touches the object (geometry only).

    Parameters
    ----------
    setup : DrumSetup
    samples : int, optional
        Angles tried over a full turn.

    Returns
    -------
    float
        Angle change [rad].

    Raises
    ------
    InputError
        The finger never reaches the object.
    """
    model, _ = finger_on_drum(setup, 0.0)
    pts = model.mesh.nodes[model.contact.nodes]
    s = setup.object_surface
    obj = s.params()[1]
    px, py = np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1])
    for dtheta in np.linspace(0.0, 2 * np.pi, samples):
        _, _, u, v = drum_to_object(px, py, np.cos(dtheta), np.sin(dtheta), obj)
        inside = (u / s.a_m) ** 2 + (v / s.b_m) ** 2 < 1.0
        inside &= (pts[:, 2] >= s.z_min_m) & (pts[:, 2] <= s.z_max_m)
        if inside.any():
            return float(dtheta)
    raise InputError("the finger never reaches the object: check the drum radius, finger length and object")


def calibrate_initial_angle(setup: DrumSetup, *, alpha=7.5, target_s=0.32, iterations=3, tol_s=0.004):
    """theta0 [rad] such that the finger with ``alpha`` first touches the object at
    ``target_s``: start from the rigid-finger geometry, then correct by FE runs
    (theta0 += omega (t_contact - target)).

    Parameters
    ----------
    setup : DrumSetup
    alpha : float, optional
        Damping of the calibration runs [1/s].
    target_s : float, optional
        Wanted first-contact time [s].
    iterations : int, optional
        FE corrections at most.
    tol_s : float, optional
        Accepted error of the contact time [s].

    Returns
    -------
    tuple
        (theta0 [rad], [(theta0 [rad], t_contact [s]), ...]).

    Raises
    ------
    InputError
        No contact within target_s + 0.1 s.
    """
    theta0 = setup.theta0_rad
    reach = first_contact_angle(replace(setup, theta0_rad=0.0))
    theta0 = reach - setup.omega_rad_s * target_s
    history = []
    for _ in range(iterations):
        trial = replace(setup, theta0_rad=theta0)
        res, _ = contact_run(trial, alpha, t_end_s=target_s + 0.1, n_outputs=int((target_s + 0.1) / 0.001),
                             object_stress=False)
        h = res.history
        on = h[h.contact_nodes > 0]
        if on.empty:
            raise InputError(f"no contact within {target_s + 0.1:.3g} s at theta0 = {theta0:.4f} rad")
        t_c = float(on.time_s.iloc[0])
        history.append((theta0, t_c))
        if abs(t_c - target_s) <= tol_s:
            break
        theta0 += setup.omega_rad_s * (t_c - target_s)
    return theta0, history
