"""Reduced model of the finger on the rotating drum.

:class:`ReducedContactModel` builds the superelement chain of the finger's FE mesh
(:mod:`ccedi.rom.superelement`), fits its bending stiffness to the full FE model's static tip
stiffness, and runs the chain's explicit dynamics in the drum's rotating frame
(:mod:`ccedi.rom.chain_dynamics`). It answers the same question as
:class:`ccedi.fea.contact.drum.FullContactModel`, through the same interface
(:class:`ccedi.models.ContactModel`: ``run(alpha, *, damping, t_end_s, n_outputs,
progress) -> ContactResponse``, with the same core history columns and summary keys), so a study
swaps one for the other with one argument.

``nonlinear=True`` is the co-rotational chain (large rotations exact, the nonlinear
enhancement); ``nonlinear=False`` the linear Craig-Bampton model in the drum frame.

Which fingers: any straight finger along z with a clamped root face and a flat tip face.
The generated elliptical finger of :class:`ccedi.fea.contact.drum.DrumSetup` is cut at node planes
z = const of its structured hexahedral mesh; a finger mesh given as ``DrumSetup(finger=...)``
(an imported or Gmsh finger, tetrahedra) at evenly spaced stations, the nodes its
neighbouring segments share moving as a rigid section
(:func:`ccedi.rom.superelement.chain_cuts`). The contact points sit on the faces at each
station's own half thickness (a tapered finger's follow its taper). The "face" contact
(points at every FE node plane, stiffness per length fitted on the FE face) needs the
node planes of the generated finger (:func:`require_generated_finger`).
"""
import copy
import time

import numpy as np
import pandas as pd

from ccedi.errors import InputError, SolverError, require_finite_positive
from ccedi.fea.contact.drum import DrumSetup, FullContactModel, finger_mesh, finger_on_drum
from ccedi.fea.contact.penalty import penalty_stiffness
from ccedi.fea.model import cantilever_model
from ccedi.fea.solvers.explicit import TSSFAC, critical_time_step
from ccedi.fea.solvers.static import static_solve
from ccedi.models import ContactResponse, contact_timing, validate_run_args
from ccedi.rom.chain_dynamics import (
    _FX,
    _FY,
    _NPTS,
    _PEN,
    _PX,
    _PY,
    ChainGroup,
    ChainOutputs,
    ChainState,
    ContactPoints,
    DrumFrame,
    chain_run,
    contact_omega,
    contact_point_stiffness,
    face_points,
    stable_step,
)
from ccedi.rom.superelement import (
    chain_frequencies,
    fe_tip_stiffness,
    finger_chain,
    fit_tip_stiffness,
    fitting_segments,
    linear_matrices,
    stress_recovery,
)

DEFAULT_SEGMENTS = 17
"""Superelements along the 8-in finger (three SM-A element layers, ~12 mm, each)."""
DEFAULT_CONTACT = "stations"
"""Contact model of :class:`ReducedContactModel` ("stations" or "face", see there)."""


FACE_PATCH_NODES = 1
"""Loaded FE apex nodes in the flattening solve of :func:`fe_face_stiffness_per_length`:
1, each ROM point's spring is its own FE node's compliance (the diagonal of the FE face's
contact compliance). The FE face is not a Winkler foundation: centre flattening per node
load is 51.5 / 30.6 / 54.7 / 52.2 / 68.6 um/N for 1 / 3 / 5 / 7 / 9 loaded nodes (the
FE's contact patch is 3 nodes, 8 mm, in the median at alpha = 7.5, 180 and 600 1/s)."""


def point_offsets(chain, seg, xi):
    """Face offsets [m] (+y, -y) of contact points at fractions ``xi`` of segments ``seg``:
    the chain's station offsets (:attr:`ccedi.rom.superelement.FingerChain.face_offsets_m`)
    interpolated linearly along the segment.

    Parameters
    ----------
    chain : ccedi.rom.superelement.FingerChain
    seg : (p,) int array_like
        Segment of each point.
    xi : (p,) array_like
        Fraction along the segment [-].

    Returns
    -------
    (p, 2) ndarray
    """
    seg, xi = np.asarray(seg, dtype=np.int64), np.asarray(xi, dtype=float)[:, None]
    h = chain.face_offsets_m
    return (1.0 - xi) * h[seg] + xi * h[seg + 1]


def require_generated_finger(setup: DrumSetup):
    """Refuse a set-up whose finger is a given mesh for the "face" contact (module
    docstring: its points sit at the node planes of the generated finger).

    Parameters
    ----------
    setup : DrumSetup
        The drum set-up.

    Raises
    ------
    InputError
        ``setup.finger`` is set.
    """
    if setup.finger is not None:
        raise InputError(f"the ROM's 'face' contact needs the generated elliptical finger (its points sit at the "
                         f"node planes of a structured hexahedral mesh); this finger is a given "
                         f"{setup.finger.element_type} mesh: use contact='stations'")


def fe_face_stiffness_per_length(setup: DrumSetup, patch_nodes=FACE_PATCH_NODES):
    """Contact stiffness per unit length of finger face [N/m^2] of the full FE model, for
    the ROM's rigid sections (fitted from the FEA).

    The FE face yields to a contact load twice: its nodes penetrate the object by
    f / k_pen, k_pen = (1/0.81 - 1) m_node (2 / dt_cfl)^2 (:func:`ccedi.fea.contact.penalty.penalty_stiffness`),
    and the section flattens (the loaded apex moves against the section's mean). The ROM
    section is rigid, so its springs must carry both::

        1 / k' = dz (1 / k_pen + d_flat)      [m^2 / N],   k' [N/m^2]

    d_flat [m/N]: apex displacement minus the section's mass-weighted mean displacement
    at the centre of a patch of ``patch_nodes`` apex nodes loaded by 1 N each (linear
    static FE solve of the clamped finger, load mid-finger); dz the layer spacing. On the
    finger's flat-on face only the apex row (x = 0, y = +b) touches: the next row, 3.3 mm
    to the side, sits 0.33 mm behind, beyond the 50 um the FE penetration reaches. On the
    8-in SM-A finger: k_pen / dz = 5.4e7 N/m^2 alone; with the flattening 4.5e6 (1 node),
    7.1e6 (3-node patch), 4.2e6 (5), 3.4e6 (9) N/m^2, against the station model's
    2.8e6 N/m^2.

    Parameters
    ----------
    setup : DrumSetup
        The finger (mesh, material).
    patch_nodes : int, optional
        Loaded apex nodes of the flattening solve (:data:`FACE_PATCH_NODES`).

    Returns
    -------
    float
        k' [N/m^2].

    Raises
    ------
    InputError
        ``setup`` has a finger mesh (:func:`require_generated_finger`).
    """
    require_generated_finger(setup)
    model, _ = finger_on_drum(setup, 0.0)
    local = finger_mesh(setup)
    zs = np.unique(local.nodes[:, 2])
    dz = float(np.median(np.diff(zs)))
    apex = _apex_nodes(local)
    z = local.nodes[apex, 2]
    inner = apex[(z > 0.0) & (z < zs[-1] - 1e-9 * zs[-1])]         # neither the clamp nor the tip face
    k_node = float(np.median(penalty_stiffness(model.mass[inner], critical_time_step(model))))
    d_flat = _face_flattening(local, setup.finger_material, int(patch_nodes))
    return 1.0 / (dz * (1.0 / k_node + d_flat))


def _apex_nodes(mesh):
    """Nodes of the finger face's apex row (x = 0, y = max y) of a straight finger ``mesh``."""
    X = mesh.nodes
    return np.flatnonzero((np.abs(X[:, 0]) < 1e-9) & (np.abs(X[:, 1] - X[:, 1].max()) < 1e-9))


def _face_flattening(mesh, material, patch_nodes):
    """Apex flattening [m/N] of the clamped finger ``mesh``: apex nodes (x = 0, y = y_max)
    of ``patch_nodes`` planes around mid-finger loaded by 1 N each along -y (linear static
    solve); the centre plane's apex displacement minus its nodes' mass-weighted mean."""
    X = mesh.nodes
    model = cantilever_model(mesh, material)
    zs = np.unique(X[:, 2])
    apex = _apex_nodes(mesh)
    mid = len(zs) // 2
    f = np.zeros_like(X)
    for p in range(mid - patch_nodes // 2, mid + patch_nodes // 2 + 1):
        f[apex[np.abs(X[apex, 2] - zs[p]) < 1e-9], 1] = -1.0
    u = static_solve(model, f, linear=True) - X
    plane = np.abs(X[:, 2] - zs[mid]) < 1e-9
    centre = apex[np.abs(X[apex, 2] - zs[mid]) < 1e-9]
    mean = (model.mass[plane] * u[plane, 1]).sum() / model.mass[plane].sum()
    return float(mean - u[centre, 1].mean())


FINGER_KEYS = ("finger_length_m", "finger_material", "finger_semi_axes_m", "finger_taper_ratio",
               "finger_section_elements", "finger_elements_along", "drum_radius_m")
"""The :class:`ccedi.fea.contact.drum.DrumSetup` fields a reduced model's chain is built on
(with its finger mesh): a set-up that changes one needs a new model
(:meth:`ReducedContactModel.on`)."""


class ReducedContactModel:
    """Superelement-chain ROM of :class:`ccedi.fea.contact.drum.DrumSetup`'s finger, a
    :class:`ccedi.models.ContactModel`.

    Parameters
    ----------
    setup : DrumSetup
        Geometry, speeds and materials.
    n_segments : int, optional
        Superelements along the finger.
    nonlinear : bool, optional
        Co-rotational (True) or linear (False) kinematics.
    fit : bool, optional
        Scale the bending stiffness to the FE tip stiffness.
    contact : str, optional
        "stations" or "face" (None: ``DEFAULT_CONTACT``), see below.
    k_per_length : float, optional
        Face contact stiffness per unit length [N/m^2] (default: the full FE model's).

    Raises
    ------
    InputError
        ``contact`` neither "face" nor "stations", "face" on a finger mesh
        (:func:`require_generated_finger`), or a mesh the chain cannot cut
        (:func:`ccedi.rom.superelement.chain_cuts`).

    Notes
    -----
    contact : "stations" (default, ``DEFAULT_CONTACT``): points at the stations only,
    penalty rule of :mod:`ccedi.fea.contact.penalty` for the station's effective mass, the chain's own
    step (points 12 mm apart, 2.8e6 N/m^2 per length). "face": contact points on both
    faces at every FE node plane,
    moved with the segment's cubic centre line (:func:`ccedi.rom.chain_dynamics._face_point`),
    penalty stiffness per unit length ``k_per_length`` [N/m^2] (default: the full FE
    model's, :func:`fe_face_stiffness_per_length`) times each point's tributary length;
    the step is the stable step of the chain with the contact springs engaged,
    TSSFAC x 2 / omega_c (:func:`ccedi.rom.chain_dynamics.contact_omega`). Against the full FEA
    (8-in finger, global damping) "face" matches the mean force as "stations" does, keeps
    the alpha = 180 and 600 peaks within 6 % at 13-51 segments (stations: +83 % / +51 % at
    34), costs ~2x the wall time, and with the 100 Hz transducer brings the alpha = 7.5 peak
    reading to +1.3 % of the FEA's (stations: -11.6 %); it is not the default because the
    contact calibration, which fits this chain, does worse with it (right effect in 6 of 13
    full-FEA records against 8, and a transducer bandwidth added to a clean control:
    ``validation/calibrate_contact_face.json``).
    """

    def __init__(self, setup: DrumSetup, *, n_segments=DEFAULT_SEGMENTS, nonlinear=True, fit=True, contact=None,
                 k_per_length=None):
        contact = DEFAULT_CONTACT if contact is None else contact
        if contact not in ("face", "stations"):
            raise InputError(f"contact must be 'face' or 'stations', got {contact!r}")
        if contact == "face":
            require_generated_finger(setup)
        self.setup = setup
        self.nonlinear = bool(nonlinear)
        self.name = "rom-corotational" if self.nonlinear else "rom-linear"
        mesh = finger_mesh(setup)
        chain = finger_chain(mesh, setup.finger_material, n_segments)
        if fit:
            chain = fit_tip_stiffness(chain, fe_tip_stiffness(mesh, setup.finger_material))
        self.chain = chain
        self.stress = stress_recovery(chain, setup.finger_material)
        self.omega_max_rad_s = float(chain_frequencies(chain)[-1])
        self.contact = contact
        if contact == "stations":
            self.pt_seg, self.pt_xi, _ = face_points(chain.station_z_m, chain.station_z_m, nonlinear=False)
            self.pt_k = contact_point_stiffness(chain.mass_kg, chain.inertia_kg_m2, chain.face_offsets_m.max(axis=1),
                                                omega_max=self.omega_max_rad_s)[1:]
            self.dt_s = stable_step(self.omega_max_rad_s)
            self.k_per_length = None
        else:
            self.k_per_length = fe_face_stiffness_per_length(setup) if k_per_length is None else float(k_per_length)
            self.pt_seg, self.pt_xi, trib = face_points(chain.station_z_m, np.unique(mesh.nodes[:, 2]), self.nonlinear)
            self.pt_k = self.k_per_length * trib
            K, M = linear_matrices(chain)
            self.omega_contact_rad_s = contact_omega(K, M, pt_seg=self.pt_seg, pt_xi=self.pt_xi, pt_k=self.pt_k,
                                                     pt_h=point_offsets(chain, self.pt_seg, self.pt_xi)[:, 0],
                                                     station_z_m=chain.station_z_m, nonlinear=self.nonlinear)
            self.dt_s = TSSFAC * 2.0 / self.omega_contact_rad_s
        self.pt_h = point_offsets(chain, self.pt_seg, self.pt_xi)

    def run(self, alpha, *, damping="global", t_end_s=1.5, n_outputs=300, progress=False):
        """Integrate the chain over the object.

        Parameters
        ----------
        alpha : float
            Mass-proportional damping coefficient [1/s].
        damping : str, optional
            "global" (on the absolute velocity) or "relative" (in the drum frame).
        t_end_s : float, optional
            Simulated time [s].
        n_outputs : int, optional
            Output times, equally spaced after 0.
        progress : bool, optional
            Accepted for the :class:`ccedi.models.ContactModel` interface; the chain shows
            no progress bar (a run takes about a second).

        Returns
        -------
        ccedi.models.ContactResponse
            History: the core columns (:data:`ccedi.models.CONTACT_CORE_COLUMNS`;
            ``contact_nodes`` counts the contact points in penetration); summary: the core
            keys and :data:`ccedi.models.ROM_CONTACT_EXTRA_SUMMARY`. ``warnings`` is
            empty: none of the checks of :mod:`ccedi.fea.solvers.validity` applies to the chain
            (it has no energy record, elements or impulse); its range is checked against
            the full model by ``ccedi rom-check``, and a chain that leaves it raises.

        Raises
        ------
        InputError
            Invalid arguments (:func:`ccedi.models.validate_run_args`).
        SolverError
            The chain diverged, or the stress recovery inverted an element.
        """
        alpha, t_end_s, n_outputs = validate_run_args(alpha, t_end_s, n_outputs, damping=damping)
        s, ch = self.setup, self.chain
        t_out = np.linspace(0.0, t_end_s, int(n_outputs) + 1)[1:]
        wall0 = time.perf_counter()
        P0, P_out, TH_out, C_out, steps = self._integrate(alpha, damping, t_out)
        stress = self._max_von_mises(P_out, TH_out)
        wall = time.perf_counter() - wall0
        if np.isnan(stress).any():
            raise SolverError(f"stress recovery inverts an element at t = {t_out[np.isnan(stress)][0]:.4g} s: "
                              "the deformation is beyond the reduced model's range")
        phi = s.theta0_rad + s.omega_rad_s * t_out
        tip = P_out[:, -1]
        tip_x = np.cos(phi) * tip[:, 0] - np.sin(phi) * tip[:, 1]
        tip_y = np.sin(phi) * tip[:, 0] + np.cos(phi) * tip[:, 1]
        x0 = np.cos(s.theta0_rad) * P0[-1, 0], np.sin(s.theta0_rad) * P0[-1, 0]
        history = pd.DataFrame({
            "time_s": t_out,
            "reaction_force_N": np.hypot(C_out[:, _FX], C_out[:, _FY]),
            "contact_force_x_N": C_out[:, _FX], "contact_force_y_N": C_out[:, _FY],
            "contact_nodes": C_out[:, _NPTS].astype(int),
            "contact_point_x_m": C_out[:, _PX], "contact_point_y_m": C_out[:, _PY],
            "max_penetration_m": C_out[:, _PEN], "max_von_mises_Pa": stress,
            "tip_ux_m": tip_x - x0[0], "tip_uy_m": tip_y - x0[1]})
        summary = {"model": self.name, "alpha_per_s": float(alpha), "damping": damping,
                   "wall_time_s": wall, "steps": int(steps), "warnings": [], "dt_s": self.dt_s,
                   "segments": ch.n_segments, "stiffness_scale": ch.stiffness_scale}
        summary.update(contact_timing(history))
        return ContactResponse(history=history, summary=summary)

    def on(self, setup: DrumSetup):
        """The same chain on another drum set-up (drum speed, initial angle, object,
        friction); the finger must be the same.

        Parameters
        ----------
        setup : DrumSetup
            The new set-up.

        Returns
        -------
        ReducedContactModel
            A copy sharing the chain, the contact points and the stress recovery.

        Raises
        ------
        InputError
            ``setup``'s finger (its mesh or its generator's inputs) or drum radius differs
        from this model's.
        """
        changed = [k for k in FINGER_KEYS if getattr(setup, k) != getattr(self.setup, k)]
        if setup.finger is not self.setup.finger:
            changed.append("finger mesh")
        if changed:
            raise InputError(f"the reduced model's finger and drum radius are fixed; the new set-up changes "
                             f"{', '.join(changed) or 'finger'}: build a new ReducedContactModel")
        other = copy.copy(self)
        other.setup = setup
        return other

    def reaction_force(self, alpha, time_s, *, damping="global", E_factor=1.0):
        """Force of the finger on the object at given times: the chain alone, without the
        stress recovery of :meth:`run` (the calibration's fast path).

        Young's modulus x ``E_factor`` scales the chain exactly: every section stiffness
        and contact spring by E_factor (the contact springs are set by the chain's or
        the FE face's stiffness, both linear in E), the step by 1 / sqrt(E_factor).

        Parameters
        ----------
        alpha : float
            Mass-proportional damping coefficient [1/s].
        time_s : array_like
            Increasing output times > 0 [s].
        damping : str, optional
            "global" or "relative".
        E_factor : float, optional
            Young's modulus over the model's [-], > 0.

        Returns
        -------
        numpy.ndarray
            (k, 2): force on the object, global x and y [N].

        Raises
        ------
        InputError
            Bad ``alpha``, ``damping``, ``E_factor`` or times.
        SolverError
            The chain diverged.
        """
        t_out = np.asarray(time_s, dtype=float)
        if t_out.ndim != 1 or len(t_out) == 0 or t_out[0] <= 0.0 or np.any(np.diff(t_out) <= 0.0):
            raise InputError("time_s must be increasing times > 0 s")
        alpha, _, _ = validate_run_args(alpha, float(t_out[-1]), len(t_out), damping=damping)
        C_out = self._integrate(alpha, damping, t_out, require_finite_positive("E_factor", E_factor))[3]
        return C_out[:, [_FX, _FY]]

    def _integrate(self, alpha, damping, t_out, E_factor=1.0):
        """Integrate the chain to the output times ``t_out`` (Young's modulus x
        ``E_factor``, :meth:`reaction_force`); returns (P0, P_out, TH_out, C_out, steps)."""
        s, ch = self.setup, self.chain
        n = len(ch.station_z_m)
        P = np.column_stack([s.drum_radius_m + ch.station_z_m, np.zeros(n)])
        TH, V, W = np.zeros(n), np.zeros((n, 2)), np.zeros(n)
        P0 = P.copy()
        P_out, TH_out = np.zeros((len(t_out), n, 2)), np.zeros((len(t_out), n))
        C_out = np.zeros((len(t_out), 6))
        obj = s.object_surface
        c = np.asarray(obj.center_m, dtype=float)
        obj_params = np.array([c[0], c[1], obj.a_m, obj.b_m, np.cos(obj.angle_rad), np.sin(obj.angle_rad)])
        status, steps = chain_run(ChainState(P, TH, V, W), self._chain_group(E_factor),
                                  DrumFrame(s.omega_rad_s, s.theta0_rad, float(alpha), damping == "relative"),
                                  points=ContactPoints(self.pt_seg, self.pt_xi, self.pt_h, E_factor * self.pt_k,
                                                       float(obj.damping_ratio), float(obj.mu), obj_params),
                                  dt=self.dt_s / np.sqrt(E_factor), outputs=ChainOutputs(t_out, P_out, TH_out, C_out))
        if status:
            raise SolverError(f"reduced model diverged (non-finite state) at step {steps + 1}")
        return P0, P_out, TH_out, C_out, steps

    def _chain_group(self, E_factor=1.0):
        """The chain as :data:`ccedi.rom.chain_dynamics.ChainGroup` (stiffness x ``E_factor``)."""
        ch = self.chain
        return ChainGroup(ch.mass_kg, ch.inertia_kg_m2, ch.segment_length_m, E_factor * ch.natural_stiffness,
                          ch.half_thickness_m, self.nonlinear)

    def _max_von_mises(self, P_out, TH_out):
        """Finger stress [Pa] per output from the station states, zone by zone."""
        e = self.stress.deformations(P_out, TH_out, self.chain.station_z_m, nonlinear=self.nonlinear)
        return self.stress.max_von_mises(e, nonlinear=self.nonlinear)


def reduce_contact_model(full: FullContactModel, *, n_segments=None, nonlinear=True, fit=True, contact=None):
    """The reductor of the contact model: the superelement chain of a full FE contact
    model's finger, with the same run signature and response type (pyMOR's way: a
    reductor takes the full model and returns the reduced one, so a study swaps one for
    the other with one argument).

    The chain is cut from the full model's own finger mesh and material (the generated
    prism or any mesh, :func:`ccedi.rom.superelement.chain_cuts`), its bending stiffness
    fitted to that mesh's FE tip stiffness, and it runs on the full model's drum, object
    and friction.

    Parameters
    ----------
    full : ccedi.fea.contact.drum.FullContactModel
        The full model to reduce.
    n_segments : int, optional
        Superelements along the finger (default: :data:`DEFAULT_SEGMENTS`, or on a finger
        mesh as many as its elements allow up to it,
        :func:`ccedi.rom.superelement.fitting_segments`).
    nonlinear : bool, optional
        Co-rotational (True) or linear (False) kinematics.
    fit : bool, optional
        Scale the bending stiffness to the FE tip stiffness.
    contact : str, optional
        "stations" or "face" (:class:`ReducedContactModel`).

    Returns
    -------
    ReducedContactModel

    Raises
    ------
    InputError
        ``full`` is not a full contact model, or the chain cannot be built
        (:class:`ReducedContactModel`).
    """
    if not isinstance(full, FullContactModel):
        raise InputError(f"reduce_contact_model reduces a FullContactModel, got {type(full).__name__}")
    setup = full.setup
    if n_segments is None:
        n_segments = DEFAULT_SEGMENTS if setup.finger is None else fitting_segments(setup.finger, DEFAULT_SEGMENTS)
    return ReducedContactModel(setup, n_segments=n_segments, nonlinear=nonlinear, fit=fit, contact=contact)
