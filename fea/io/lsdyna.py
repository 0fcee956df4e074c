"""LS-DYNA keyword decks: write a ccedi :class:`ccedi.fea.model.Model` so that a user with LS-DYNA
can run the same model as it is (``ls-dyna i=deck.k``), and read back the cards ccedi writes
(round-trip check).

Format: LS-DYNA's standard fixed-width fields, 10 characters per field, 8 per line, except
*NODE (node id 8, coordinates 16 each), *ELEMENT_SOLID / *ELEMENT_SHELL (8 each) and the
*DEFINE_CURVE points (20 each). A real number is written in the shortest form that
round-trips exactly and fits the field less one character (so fields stay separated by
a blank); one that cannot fit keeps as many significant digits as fit (node coordinates
to about 1e-13 m on a finger). Ids are 1-based in the deck, 0-based in ccedi. The reader
also accepts comma-separated (free format) lines.

Cards written (SI units: m, kg, s, N, Pa):

* *CONTROL_TERMINATION (ENDTIM), *CONTROL_TIMESTEP (TSSFAC 0.9), *CONTROL_ENERGY (hourglass,
  contact and damping energies computed, so that glstat balances like ccedi's energy terms);
* *DATABASE_GLSTAT, *DATABASE_NODOUT with *DATABASE_HISTORY_NODE on the ``tip`` node set
  (ccedi's tip displacement is their area-weighted mean, :func:`ccedi.fea.model.face_node_weights`),
  *DATABASE_SPCFORC for a clamp, *DATABASE_RCFORC for contact (ASCII files, every
  ``output_dt_s``), and *DATABASE_BINARY_D3PLOT (every ``plot_dt_s``);
* *NODE, *PART / *SECTION_SOLID / *ELEMENT_SOLID, the element formulation by element type
  (:data:`ELFORM`): hexahedra ELFORM 1 (one-point, as ccedi's) with *HOURGLASS
  (:data:`HOURGLASS_IHQ`, QM = ccedi's hourglass coefficient, Q1/Q2 = ccedi's bulk
  viscosity) linked by the part's HGID; 4-node tetrahedra ELFORM 13 (the one-point nodal
  pressure tetrahedron: ccedi's element averages the pressure the same way, and also
  takes 0.7 of its shear on node-smoothed strains, :mod:`ccedi.fea.elements.tet4`, which ELFORM 13
  does not: LS-DYNA's will be stiffer in bending), written in the 8-node
  format with N4 repeated (N1 N2 N3 N4 N4 N4 N4 N4); 10-node tetrahedra ELFORM 16 (the
  4-point 10-node tetrahedron, ccedi's integration), in the two-card format of
  *ELEMENT_SOLID (Card 1: EID PID; Card 2: N1 ... N10, corners then the mid-edge nodes of
  the edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4, which is VTK's and ccedi's order). Tetrahedra have
  no hourglass modes and carry no *HOURGLASS card (LS-DYNA's default bulk viscosity,
  Q1 = 1.5, Q2 = 0.06, is ccedi's);
* *MAT_ELASTIC (E, nu, rho of the rubber: ccedi's neo-Hookean solid coincides with it at
  small strain; for large strain use *MAT_HYPERELASTIC_RUBBER with C10 = mu/2, D1 = 2/K);
* *DAMPING_GLOBAL with VALDMP = alpha: the manual's nodal damping force f = -d m v is
  ccedi's mass-proportional term -alpha m v (beta, if any, is noted in a comment: LS-DYNA
  sets it per part with *DAMPING_PART_STIFFNESS);
* *SET_NODE_LIST + *BOUNDARY_SPC_SET for the clamped nodes;
* *SET_NODE_LIST + *LOAD_NODE_SET + *DEFINE_CURVE for each force pulse: nodes grouped by
  their share of the pulse (*LOAD_NODE_SET applies one force to every node), the curve
  holding the share, SF the force component [N] (per-node force = SF x curve); nodes of
  zero share (the corners of a 10-node tetrahedron's loaded face) are left out;
* for a rotating root (the drum): solid nodes have no rotational degrees of freedom, so the
  root nodes are made *CONSTRAINED_EXTRA_NODES_SET of a rigid drum part (*PART_INERTIA with
  its centre of mass on the axis, *MAT_RIGID with translations and the x, y rotations
  constrained), whose z-rotational degree of freedom (DOF 7) is prescribed at omega by
  *BOUNDARY_PRESCRIBED_MOTION_RIGID; *INITIAL_VELOCITY_GENERATION starts the finger turning
  rigidly (ccedi's v0 = omega x r);
* for contact: the rigid elliptical object as a shell part (*MAT_RIGID, fully constrained)
  and *CONTACT_AUTOMATIC_NODES_TO_SURFACE from the finger's surface nodes, static and
  dynamic friction = mu.

Card layouts (field order, columns, meaning) follow the LS-DYNA Keyword User's Manual
(Vol. I, the keyword's own page), as transcribed field by field in Ansys PyDyna's keyword
classes, which are generated from the manual
(https://github.com/ansys/pydyna, ``src/ansys/dyna/core/keywords/keyword_classes/auto/
<group>/<keyword>.py``); each card writer names its keyword page. ``tests/unit/fea/test_lsdyna.py``
checks every card field by field against those layouts.
"""
from dataclasses import dataclass, field

import numpy as np

from ccedi.errors import InputError, require_finite_positive
from ccedi.fea.elements.hex8 import BULK_VISCOSITY_C0, BULK_VISCOSITY_C1
from ccedi.fea.solvers.explicit import TSSFAC
from ccedi.outputs import write_text

FINGER_PART, OBJECT_PART, DRUM_PART = 1, 2, 3
ELFORM = {"hex8": 1, "tet4": 13, "tet10": 16}
"""*SECTION_SOLID element formulation written for each ccedi element type (module docstring)."""
HOURGLASS_ID = 1
CLAMP_SET, CONTACT_SET, ROTATING_SET, FIRST_LOAD_SET = 1, 2, 3, 10
OBJECT_SHELLS_AROUND, OBJECT_SHELLS_THROUGH = 72, 4
DRUM_SHELLS_AROUND = 36
RIGID_DENSITY, RIGID_E, RIGID_NU, RIGID_SHELL_T = 2700.0, 69e9, 0.33, 1e-3
"""Rigid object and drum: aluminium (Table 2); E and nu only set the contact stiffness of a
rigid part, the shell thickness [m] only its drawn mass."""
OUTPUTS_PER_RUN, OUTPUTS_PER_PLOT = 400, 10
"""Default history interval t_end / 400 (the rows of :func:`ccedi.fea.solvers.explicit.run`) and
d3plot interval 10 history intervals (the frames of ``ccedi export --format vtu``)."""

HOURGLASS_IHQ = 6
"""LS-DYNA hourglass type of ccedi's (:mod:`ccedi.fea.elements.hex8`), with QM = ccedi's Q_hg.

ccedi's hourglass control is a physical stiffness form: the hourglass stiffness of the
incompatible-modes element of each element's centre parallelepiped, scaled by Q_hg
(:func:`ccedi.fea.elements.hex8.hourglass_stiffness`), which is Belytschko & Bindeman's assumed-
strain stabilisation -- LS-DYNA's type 6. The manual (*HOURGLASS, QM): "For type 6 solid
element hourglass control, QM=1.0 gives an accurate coarse mesh bending stiffness that does
not lock in the incompressible limit", as ccedi's Q_hg = 1 (exact pure bending of a
parallelepiped at any aspect ratio, nu = 0.49 included). So QM = Q_hg.

* IHQ 1-3 are viscous forms (resisting hourglass velocities, not displacements); LS-DYNA
  uses one of them for a part without an *HOURGLASS card.
* IHQ 4 and 5 are the Flanagan-Belytschko stiffness form, scaled by the dilatational
  modulus lam + 2 mu (about 17 E at the rubber's nu = 0.49, stiff enough to lock in
  bending) with another QM normalisation.

Remaining differences: type 6 updates its hourglass forces incrementally in a co-rotational
frame, ccedi's are total, with the hourglass displacements pulled back by F^-1 (type 7,
"linear total strain form of type 6", is the total variant with the same QM meaning).
"""


def _num(value, width=10):
    """``value`` as text of at most ``width`` characters, exact if possible."""
    text = repr(float(value))
    digits = 17
    while len(text) > width and digits > 1:
        digits -= 1
        text = f"{float(value):.{digits}g}"
    if len(text) > width:
        raise InputError(f"{value!r} does not fit a {width}-character LS-DYNA field")
    return text


def _card(values, width=10):
    """One data line: ints and strings right-justified in ``width`` columns, reals by :func:`_num`."""
    return "".join(v.rjust(width) if isinstance(v, str) else
                   (str(v).rjust(width) if isinstance(v, (int, np.integer)) else _num(v, width - 1).rjust(width))
                   for v in values)


def _node_line(i, xyz):
    """*NODE card of 0-based node ``i``: id in 8 characters, coordinates [m] in 16."""
    return f"{i + 1:8d}" + "".join(_num(c, 15).rjust(16) for c in xyz)


def _node_set(sid, nodes):
    """*SET_NODE_LIST: SID (DA1..DA4, SOLVER defaulted), then node ids 8 per line."""
    lines = ["*SET_NODE_LIST", _card([sid])]
    ids = np.asarray(nodes, dtype=np.int64) + 1
    lines += [_card(list(ids[i:i + 8])) for i in range(0, len(ids), 8)]
    return lines


def _curve(lcid, points):
    """*DEFINE_CURVE: LCID (SIDR, SFA, SFO, OFFA, OFFO defaulted), then (A, O) pairs in 20 columns."""
    return ["*DEFINE_CURVE", _card([lcid]), *[_card([a, o], 20) for a, o in points]]


def _pulse_curve(lcid, share, t0, t1, t_end_s):
    """A rectangular pulse of height ``share`` (a node's share of the force, carried in the
    curve's 20-character ordinates so it stays exact) from t0 to t1 [s], as a *DEFINE_CURVE."""
    eps = 1e-9 * max(t1, 1.0)
    points = (([(0.0, 0.0), (max(t0 - eps, 0.0), 0.0)] if t0 > 0.0 else [])
              + [(t0, share), (t1, share), (t1 + eps, 0.0)])
    points.append((max(10.0 * t_end_s, t1 + 2 * eps), 0.0))
    return _curve(lcid, points)


def _ring_shells(center, radius, angle, z0, z1, n_around, n_through, first_node):
    """Nodes and 1-based quad connectivity of an elliptical cylinder's lateral surface:
    semi-axes ``radius`` = (a, b) turned by ``angle`` about z, centre (x, y), z0..z1."""
    ca, sa = np.cos(angle), np.sin(angle)
    th = np.linspace(0.0, 2 * np.pi, n_around, endpoint=False)
    ex, ey = radius[0] * np.cos(th), radius[1] * np.sin(th)
    x = center[0] + ca * ex - sa * ey
    y = center[1] + sa * ex + ca * ey
    zs = np.linspace(z0, z1, n_through + 1)
    pts = np.array([[xi, yi, z] for z in zs for xi, yi in zip(x, y)])
    n = n_around
    quads = [[k * n + i, k * n + (i + 1) % n, (k + 1) * n + (i + 1) % n, (k + 1) * n + i]
             for k in range(n_through) for i in range(n)]
    return pts, np.asarray(quads) + first_node + 1


def _rigid_shell_part(pid, heading, pts, quads, first_node, first_element, con2, inertia=()):
    """A rigid shell part: *PART (or *PART_INERTIA followed by the ``inertia`` cards),
    *SECTION_SHELL (ELFORM 2, thickness RIGID_SHELL_T), *MAT_RIGID (CMO = 1: CON1 = 7 fixes
    the translations, CON2 the rotations), *NODE and *ELEMENT_SHELL (EID, PID, N1..N4).

    Layouts: Keyword Manual *PART (Card 2: PID SECID MID EOSID HGID GRAV ADPOPT TMID),
    *SECTION_SHELL (Card 1: SECID ELFORM SHRF NIP ...; Card 2: T1 T2 T3 T4 ...), *MAT_RIGID
    (Card 1: MID RO E PR N COUPLE M ALIAS; Card 2: CMO CON1 CON2 ...; Card 3: LCO or A1 ...).
    """
    return ([f"*PART{'_INERTIA' if inertia else ''}", heading, _card([pid, pid, pid, 0, 0]), *inertia,
             "*SECTION_SHELL", "$     SECID    ELFORM", _card([pid, 2]), _card([RIGID_SHELL_T] * 4),
             "*MAT_RIGID", "$       MID        RO         E        PR", _card([pid, RIGID_DENSITY, RIGID_E, RIGID_NU]),
             "$       CMO      CON1      CON2", _card([1.0, 7, con2]), "$       LCO", _card([0.0]),
             "*NODE"] + [_node_line(i, p) for i, p in enumerate(pts, first_node)]
            + ["*ELEMENT_SHELL"] + [_card([first_element + k + 1, pid, *q], 8) for k, q in enumerate(quads)])


def _output_interval(name, value, default, t_end_s):
    """``value`` (``default`` when None) as a float in 0 < dt <= t_end_s, else InputError."""
    dt = require_finite_positive(name, default if value is None else value)
    if dt > t_end_s:
        raise InputError(f"{name} = {value!r}: must be in 0..{t_end_s:g} (s), > 0 and at most t_end_s")
    return dt


def _controls(t_end_s):
    """*CONTROL_TERMINATION (ENDTIM ENDCYC DTMIN ENDENG ENDMAS NOSOL), *CONTROL_TIMESTEP
    (DTINIT TSSFAC ...) and *CONTROL_ENERGY (HGEN RWEN SLNTEN RYLEN: 2 = computed and
    included in the energy balance; without it glstat has no hourglass or damping energy).
    Layouts: Keyword Manual *CONTROL_TERMINATION, *CONTROL_TIMESTEP, *CONTROL_ENERGY, Card 1."""
    return ["*CONTROL_TERMINATION", "$    ENDTIM", _card([t_end_s]),
            "*CONTROL_TIMESTEP", "$    DTINIT    TSSFAC", _card([0.0, TSSFAC]),
            "*CONTROL_ENERGY", "$      HGEN      RWEN    SLNTEN     RYLEN", _card([2, 2, 2, 2])]


def _databases(model, output_dt_s, plot_dt_s):
    """*DATABASE_GLSTAT, _NODOUT, _SPCFORC (clamped model), _RCFORC (contact): Card 1
    DT BINARY LCUR IOOPT, BINARY = 1 (ASCII file); *DATABASE_BINARY_D3PLOT: Card 1 DT LCDT
    BEAM NPLTC PSETID; *DATABASE_HISTORY_NODE: ID1..ID8 per line, the ``tip`` node set.
    Layouts: Keyword Manual *DATABASE_OPTION (ASCII files), *DATABASE_BINARY_OPTION,
    *DATABASE_HISTORY_OPTION."""
    ascii_ = ["GLSTAT", "NODOUT"] + (["SPCFORC"] if len(model.fixed_nodes) else []) \
        + (["RCFORC"] if model.contact is not None else [])
    lines = []
    for name in ascii_:
        lines += [f"*DATABASE_{name}", "$        DT    BINARY", _card([output_dt_s, 1])]
    lines += ["*DATABASE_BINARY_D3PLOT", "$        DT", _card([plot_dt_s])]
    tip = model.mesh.node_sets.get("tip")
    if tip is not None and len(tip):
        ids = np.sort(np.asarray(tip, dtype=np.int64)) + 1
        lines += ["*DATABASE_HISTORY_NODE", "$ the tip face: ccedi's tip_u* is their area-weighted mean"]
        lines += [_card(list(ids[i:i + 8])) for i in range(0, len(ids), 8)]
    return lines


def _finger_part(model, q_hg, alpha, beta):
    """*PART (PID SECID MID EOSID HGID), *SECTION_SOLID (SECID ELFORM, :data:`ELFORM` of the
    mesh's element type), for hexahedra *HOURGLASS (HGID IHQ QM IBQ Q1 Q2), *MAT_ELASTIC
    (MID RO E PR) and *DAMPING_GLOBAL (LCID VALDMP STX STY STZ SRX SRY SRZ: the scale
    factors written as 1 so every direction is damped).
    Layouts: Keyword Manual *PART, *SECTION_SOLID, *HOURGLASS, *MAT_ELASTIC (MAT_001),
    *DAMPING_GLOBAL, Card 1."""
    m = model.material
    kind = model.mesh.element_type
    hourglass = kind == "hex8"
    lines = ["*PART", "finger", "$       PID     SECID       MID     EOSID      HGID",
             _card([FINGER_PART, FINGER_PART, FINGER_PART, 0, HOURGLASS_ID if hourglass else 0]),
             "*SECTION_SOLID", "$     SECID    ELFORM", _card([FINGER_PART, ELFORM[kind]])]
    if hourglass:
        lines += ["*HOURGLASS", "$      HGID       IHQ        QM       IBQ        Q1        Q2",
                  _card([HOURGLASS_ID, HOURGLASS_IHQ, q_hg, 0, BULK_VISCOSITY_C0, BULK_VISCOSITY_C1])]
    lines += ["*MAT_ELASTIC", "$       MID        RO         E        PR", _card([FINGER_PART, m.rho, m.E, m.nu]),
              "*DAMPING_GLOBAL", "$      LCID    VALDMP       STX       STY       STZ       SRX       SRY       SRZ",
              _card([0, alpha, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0])]
    if beta:
        lines.append(f"$ ccedi beta = {beta!r} s (not exported: use *DAMPING_PART_STIFFNESS)")
    return lines


def _solid_elements(mesh):
    """*ELEMENT_SOLID of the finger (PID :data:`FINGER_PART`), 8-column fields: a hexahedron
    on one line (EID PID N1 ... N8), a 4-node tetrahedron likewise with N4 repeated, a
    10-node tetrahedron on two (EID PID; N1 ... N10). Layout: Keyword Manual *ELEMENT_SOLID
    (the one-line format and the two-card ten-node format)."""
    lines = ["*ELEMENT_SOLID"]
    lines += [_card([e + 1, FINGER_PART, *(h + 1)], 8) for e, h in enumerate(mesh.hexes)]
    lines += [_card([e + 1, FINGER_PART, *(t + 1), *([t[3] + 1] * 4)], 8) for e, t in enumerate(mesh.tets4)]
    for e, t in enumerate(mesh.tets10):
        lines += [_card([e + 1, FINGER_PART], 8), _card(list(t + 1), 8)]
    return lines


def solid_element_rows(block):
    """(EID, PID, node ids) of every element of one *ELEMENT_SOLID block, in the one-line
    format (EID PID N1 ... N8) or the two-card one (EID PID; N1 ... N10); ids as in the deck.

    Parameters
    ----------
    block : list of str
        The block's data lines (:func:`keyword_blocks`), 8-column fields or comma-separated.

    Returns
    -------
    list of tuple
        ``(eid, pid, [node ids])``, zero node ids dropped.

    Raises
    ------
    ValueError
        A field that is not an integer.
    StopIteration
        A two-card element without its node card.
    """
    rows = iter([int(v) for v in _fields(line.rstrip(), 8) if v] for line in block)
    out = []
    for row in rows:
        nodes = row[2:] if len(row) > 2 else next(rows)
        out.append((row[0], row[1], [n for n in nodes if n]))
    return out


def solid_kind(nodes):
    """The element type of one *ELEMENT_SOLID node list: ``"hex8"`` (8 distinct nodes),
    ``"tet4"`` (4 nodes, or 8 with N4 = N5 = ... = N8) or ``"tet10"`` (10 distinct nodes).

    Parameters
    ----------
    nodes : list of int
        Node ids, zeros dropped.

    Returns
    -------
    tuple
        ``(kind, node ids)`` with the repeated N4 dropped for a tetrahedron; ``(None, nodes)``
        for any other solid (a wedge, a pyramid, a 20-node hexahedron).
    """
    distinct = len(set(nodes))
    if len(nodes) == 8 and distinct == 4 and len(set(nodes[3:])) == 1:
        return "tet4", nodes[:4]
    if len(nodes) == distinct and len(nodes) in (4, 8, 10):
        return {4: "tet4", 8: "hex8", 10: "tet10"}[len(nodes)], nodes
    return None, nodes


def _drum(model, lcid, first_node, first_element, t_end_s):
    """The rigid drum carrying the rotating root nodes, turning at omega about z.

    The root nodes become *CONSTRAINED_EXTRA_NODES_SET (PID NSID) of a rigid shell ring
    (radius: the root nodes' nearest distance to the axis, width: their extent along it).
    A rigid body's computed mass properties include its extra nodes' masses (manual,
    *CONSTRAINED_EXTRA_NODES, IFLAG), which would move its centre of mass off the axis;
    *PART_INERTIA (Card 3: XC YC ZC TM IRCS NODEID; Card 4:
    IXX IXY IXZ IYY IYZ IZZ; Card 5: VTX VTY VTZ VRX VRY VRZ) puts it on the axis with the
    ring's own mass and inertia and the initial spin VRZ = omega. *MAT_RIGID constrains the
    translations (CON1 = 7) and the x and y rotations (CON2 = 4), and
    *BOUNDARY_PRESCRIBED_MOTION_RIGID (PID DOF VAD LCID SF VID DEATH BIRTH) drives the
    z-rotational degree of freedom (DOF 7, about the global z axis through the centre of
    mass) with velocity (VAD 0) SF x curve = omega [rad/s] for all t.
    *INITIAL_VELOCITY_GENERATION (ID STYP OMEGA VX VY VZ IVATN ICID; XC YC ZC NX NY NZ PHASE
    IRIGID) gives the finger part (STYP 2) the rigid spin omega about the drum's axis.

    Layouts: Keyword Manual *CONSTRAINED_EXTRA_NODES, *PART_INERTIA, *MAT_RIGID,
    *BOUNDARY_PRESCRIBED_MOTION (DOF: "EQ.7: z-rotational degree of freedom"; DOF 9-11, the
    nodal rotations, are "not applicable to rigid bodies" and leave the axial degree of
    freedom free), *INITIAL_VELOCITY_GENERATION.
    """
    rot = model.rotating
    if not (np.allclose(rot.axis, [0, 0, 1]) and np.allclose(rot.center_m, 0.0)):
        raise InputError("LS-DYNA export supports rotation about the global z axis through the origin only")
    root = model.mesh.nodes[rot.nodes]
    r = float(np.hypot(root[:, 0], root[:, 1]).min())
    z0, z1 = float(root[:, 2].min()), float(root[:, 2].max())
    if not r > 0.0 or not z1 > z0:
        raise InputError("LS-DYNA export: the rotating nodes must span a face off the axis")
    pts, quads = _ring_shells((0.0, 0.0), (r, r), 0.0, z0, z1, DRUM_SHELLS_AROUND, 1, first_node)
    width = z1 - z0
    mass = RIGID_DENSITY * RIGID_SHELL_T * 2 * np.pi * r * width
    i_axis, i_diam = mass * r ** 2, mass * (r ** 2 / 2 + width ** 2 / 12)
    omega = rot.omega_rad_s
    inertia = ["$        XC        YC        ZC        TM      IRCS", _card([0.0, 0.0, 0.5 * (z0 + z1), mass, 0]),
               "$       IXX       IXY       IXZ       IYY       IYZ       IZZ",
               _card([i_diam, 0.0, 0.0, i_diam, 0.0, i_axis]),
               "$       VTX       VTY       VTZ       VRX       VRY       VRZ", _card([0.0, 0.0, 0.0, 0.0, 0.0, omega])]
    lines = _rigid_shell_part(DRUM_PART, "drum (rigid)", pts, quads, first_node, first_element, 4, inertia)
    lines += _node_set(ROTATING_SET, rot.nodes)
    lines += ["*CONSTRAINED_EXTRA_NODES_SET", "$       PID      NSID", _card([DRUM_PART, ROTATING_SET])]
    lines += _curve(lcid, [(0.0, 1.0), (10.0 * t_end_s, 1.0)])
    lines += ["*BOUNDARY_PRESCRIBED_MOTION_RIGID", "$       PID       DOF       VAD      LCID        SF",
              _card([DRUM_PART, 7, 0, lcid, omega]),
              "*INITIAL_VELOCITY_GENERATION", "$        ID      STYP     OMEGA        VX        VY        VZ",
              _card([FINGER_PART, 2, omega, 0.0, 0.0, 0.0]),
              "$        XC        YC        ZC        NX        NY        NZ",
              _card([*rot.center_m, *rot.axis])]
    return lines


def keyword_lines(model, t_end_s, *, title="ccedi model", output_dt_s=None, plot_dt_s=None):
    """The LS-DYNA keyword deck of ``model`` as a list of lines (cards in the module docstring).

    Every value is checked before a line is built, so a refused model writes nothing.

    Parameters
    ----------
    model : Model
        A solid model (no rods or point masses) with global damping; a rotating root
        must turn about the global z axis through the origin, and contact must be with
        the rigid elliptical object.
    t_end_s : float
        Termination time (*CONTROL_TERMINATION ENDTIM) [s], finite and > 0.
    title : str, optional
        *TITLE text, truncated to 80 characters. Default ``"ccedi model"``.
    output_dt_s : float or None, optional
        Interval of the ASCII histories (glstat, nodout, spcforc, rcforc) [s], in
        0 < dt <= t_end_s. Default None: ``t_end_s / 400``.
    plot_dt_s : float or None, optional
        Interval of the d3plot states [s], in 0 < dt <= t_end_s. Default None: 10 history
        intervals.

    Returns
    -------
    list of str
        The deck, ``*KEYWORD`` to ``*END``, without line terminators.

    Raises
    ------
    InputError
        If ``t_end_s`` or an output interval is not finite and in range, alpha, beta or the
        hourglass coefficient is out of range, the model has rods or point masses, no single
        solid element type, relative damping, a rotation about another axis, contact with another surface, or a number
        does not fit its fixed-width field.
    """
    t_end_s = require_finite_positive("t_end_s (termination time, s)", t_end_s)
    output_dt_s = _output_interval("output_dt_s (history output interval, s)", output_dt_s,
                                   t_end_s / OUTPUTS_PER_RUN, t_end_s)
    plot_dt_s = _output_interval("plot_dt_s (d3plot interval, s)", plot_dt_s,
                                 min(OUTPUTS_PER_PLOT * output_dt_s, t_end_s), t_end_s)
    alpha = require_finite_positive("alpha (mass-proportional damping, 1/s)", model.alpha, allow_zero=True)
    beta = require_finite_positive("beta (stiffness-proportional damping, s)", model.beta, allow_zero=True)
    q_hg = require_finite_positive("hourglass_coefficient", model.hourglass_coefficient)
    if model.rods or model.point_masses:
        raise InputError("LS-DYNA export covers solid models; this model has rods or point masses")
    if model.damping != "global":
        raise InputError("LS-DYNA export writes *DAMPING_GLOBAL; relative damping is not exported")
    if model.contact is not None and not hasattr(model.contact.surface, "a_m"):
        raise InputError("LS-DYNA export writes contact with the rigid elliptical object only")
    mesh = model.mesh
    if mesh.element_type not in ELFORM:
        raise InputError(f"LS-DYNA export: element type {mesh.element_type!r}; one of {', '.join(ELFORM)} per model")
    lines = ["*KEYWORD", "*TITLE", title[:80],
             "$ units: m, kg, s, N, Pa. Written by ccedi (fea.lsdyna).",
             *_controls(t_end_s), *_databases(model, output_dt_s, plot_dt_s), *_finger_part(model, q_hg, alpha, beta)]
    lines += ["*NODE"] + [_node_line(i, xyz) for i, xyz in enumerate(mesh.nodes)]
    lines += _solid_elements(mesh)
    if len(model.fixed_nodes):
        lines += _node_set(CLAMP_SET, model.fixed_nodes) + ["*BOUNDARY_SPC_SET", _card([CLAMP_SET, 0, 1, 1, 1, 1, 1, 1])]
    sid = FIRST_LOAD_SET
    for pulse in model.pulses:
        for w in np.unique(pulse.weights[pulse.weights != 0.0]):     # a 10-node face's corners carry nothing
            lines += _pulse_curve(sid, w, pulse.t_start_s, pulse.t_end_s, t_end_s)
            lines += _node_set(sid, pulse.nodes[pulse.weights == w])
            lines += ["*LOAD_NODE_SET"] + [_card([sid, dof + 1, sid, f]) for dof, f in enumerate(pulse.force_N) if f]
            sid += 1
    n_nodes, n_elements = mesh.n_nodes, mesh.n_elements
    if model.contact is not None:
        s = model.contact.surface
        pts, quads = _ring_shells(s.center_m, (s.a_m, s.b_m), s.angle_rad, s.z_min_m, s.z_max_m,
                                  OBJECT_SHELLS_AROUND, OBJECT_SHELLS_THROUGH, n_nodes)
        lines += _rigid_shell_part(OBJECT_PART, "object (rigid)", pts, quads, n_nodes, n_elements, 7)
        n_nodes, n_elements = n_nodes + len(pts), n_elements + len(quads)
        lines += _node_set(CONTACT_SET, model.contact.nodes)
        lines += ["*CONTACT_AUTOMATIC_NODES_TO_SURFACE", "$      SSID      MSID     SSTYP     MSTYP",
                  _card([CONTACT_SET, OBJECT_PART, 4, 3]), "$        FS        FD",
                  _card([s.mu, s.mu]), _card([1.0, 1.0])]
    if model.rotating is not None:
        lines += _drum(model, sid, n_nodes, n_elements, t_end_s)
    lines.append("*END")
    return lines


def write_keyword(model, path, t_end_s, *, title="ccedi model", output_dt_s=None, plot_dt_s=None):
    """Write the LS-DYNA deck of ``model`` to ``path``, atomically; nothing is written when
    the model or a value is refused.

    Parameters
    ----------
    model : Model
        The model (restrictions as in :func:`keyword_lines`).
    path : str or pathlib.Path
        Output ``.k`` file; parent directories are created.
    t_end_s : float
        Termination time [s], finite and > 0.
    title : str, optional
        *TITLE text. Default ``"ccedi model"``.
    output_dt_s : float or None, optional
        ASCII history interval [s] (see :func:`keyword_lines`). Default ``t_end_s / 400``.
    plot_dt_s : float or None, optional
        d3plot interval [s]. Default 10 history intervals.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    InputError
        If the model or a value cannot be exported (see :func:`keyword_lines`).
    """
    lines = keyword_lines(model, t_end_s, title=title, output_dt_s=output_dt_s, plot_dt_s=plot_dt_s)
    return write_text(path, "\n".join(lines) + "\n")


@dataclass
class Deck:
    """What :func:`read_keyword` recovers from a deck (0-based ids, SI units).

    Parameters
    ----------
    nodes : numpy.ndarray
        Finger node coordinates, shape (n, 3) [m] (the rigid object's nodes dropped).
    hexes : numpy.ndarray
        Finger hexahedra, shape (e, 8), 0-based node ids.
    material : dict
        ``{"rho": kg/m^3, "E": Pa, "nu": -}`` from *MAT_ELASTIC.
    alpha_per_s : float
        VALDMP of *DAMPING_GLOBAL, the mass damping alpha [1/s].
    tssfac : float
        Time step scale factor of *CONTROL_TIMESTEP [-].
    t_end_s : float
        Termination time [s].
    node_sets : dict
        {set id: array of 0-based node ids} of every *SET_NODE_LIST.
    spc_sets : list of int
        Node set ids with a *BOUNDARY_SPC_SET.
    loads : list of dict, optional
        One per *LOAD_NODE_SET line: ``nodes``, ``dof`` (0, 1, 2), ``force_N``
        (force per node [N], SF times the curve's height), ``t_start_s``, ``t_end_s``.
    contact : dict or None, optional
        ``nodes``, ``static_friction``, ``dynamic_friction`` of the nodes-to-surface
        contact, or None.
    shells : numpy.ndarray or None, optional
        Shell connectivity of the rigid object; not filled by :func:`read_keyword`.
    tets4 : numpy.ndarray, optional
        Finger 4-node tetrahedra, shape (e4, 4), 0-based node ids.
    tets10 : numpy.ndarray, optional
        Finger 10-node tetrahedra, shape (e10, 10), 0-based node ids (ccedi's node order).
    elform : int or None, optional
        ELFORM of the finger part's *SECTION_SOLID.
    """

    nodes: np.ndarray
    hexes: np.ndarray
    material: dict
    alpha_per_s: float
    tssfac: float
    t_end_s: float
    node_sets: dict
    spc_sets: list
    loads: list = field(default_factory=list)
    contact: dict | None = None
    shells: np.ndarray | None = None
    tets4: np.ndarray = field(default_factory=lambda: np.zeros((0, 4), dtype=np.int64))
    tets10: np.ndarray = field(default_factory=lambda: np.zeros((0, 10), dtype=np.int64))
    elform: int | None = None


def _fields(line, width):
    if "," in line:
        return [f.strip() for f in line.split(",")]
    return [line[i:i + width].strip() for i in range(0, len(line), width)]


def keyword_blocks(text):
    """Split a keyword deck into its cards, comment (``$``) and blank lines dropped.

    Parameters
    ----------
    text : str
        The deck.

    Returns
    -------
    dict
        ``{keyword: [data lines of each occurrence, in order]}``, the keyword upper-cased
        with its ``*`` (``"*PART"``), each occurrence a list of the raw data lines.
    """
    blocks, current = {}, None
    for raw in text.splitlines():
        if raw.startswith("$") or not raw.strip():
            continue
        if raw.startswith("*"):
            current = []
            blocks.setdefault(raw.strip().upper(), []).append(current)
        elif current is not None:
            current.append(raw.rstrip("\n"))
    return blocks


def read_keyword(path):
    """Parse a deck written by :func:`write_keyword` into a :class:`Deck`.

    Reads the fixed-width fields ccedi writes and comma-separated (free format) lines.

    Parameters
    ----------
    path : str or pathlib.Path
        The keyword file.

    Returns
    -------
    Deck
        Nodes, elements (hexahedra, 4- and 10-node tetrahedra of the finger part, by
        :func:`solid_kind`), the finger's ELFORM, material, damping, controls, node sets,
        loads and contact.

    Raises
    ------
    InputError
        If a required card (*MAT_ELASTIC, *DAMPING_GLOBAL, *CONTROL_TIMESTEP,
        *CONTROL_TERMINATION) is missing.
    """
    blocks = keyword_blocks(open(path).read())

    def one(key, width=10):
        if key not in blocks:
            raise InputError(f"{path}: no {key} card")
        return [_fields(line, width) for line in blocks[key][0]]

    node_ids, coords = [], []
    for block in blocks.get("*NODE", []):
        for line in block:
            f = _fields(line, 8) if "," in line else [line[:8]] + [line[8 + 16 * k:24 + 16 * k] for k in range(3)]
            node_ids.append(int(f[0]) - 1)
            coords.append([float(c) for c in f[1:4]])
    coords = np.asarray(coords)[np.argsort(node_ids)]
    cells = {"hex8": [], "tet4": [], "tet10": []}
    for block in blocks["*ELEMENT_SOLID"]:
        for _, pid, nodes in solid_element_rows(block):
            kind, nodes = solid_kind(nodes)
            if pid == FINGER_PART and kind is not None:
                cells[kind].append(nodes)
    hexes, tets4, tets10 = (np.asarray(cells[k], dtype=np.int64).reshape(-1, n) - 1
                            for k, n in (("hex8", 8), ("tet4", 4), ("tet10", 10)))
    finger_nodes = np.unique(np.concatenate([hexes.ravel(), tets4.ravel(), tets10.ravel()]))
    section = one("*SECTION_SOLID") if "*SECTION_SOLID" in blocks else None
    mat = one("*MAT_ELASTIC")[0]
    sets = {}
    for block in blocks.get("*SET_NODE_LIST", []):
        rows = [_fields(line, 10) for line in block]
        sets[int(rows[0][0])] = np.asarray([int(v) for r in rows[1:] for v in r if v], dtype=np.int64) - 1
    curves = {}
    for block in blocks.get("*DEFINE_CURVE", []):
        rows = [_fields(line, 20) for line in block]
        pts = np.asarray([[float(v) for v in r[:2]] for r in rows[1:]])
        on = pts[pts[:, 1] != 0.0]
        curves[int(rows[0][0])] = (float(on[:, 0].min()), float(on[:, 0].max()), float(on[:, 1].max()))
    loads = []
    for block in blocks.get("*LOAD_NODE_SET", []):
        for f in (_fields(line, 10) for line in block):
            sid, dof, lcid = int(f[0]), int(f[1]), int(f[2])
            loads.append({"nodes": sets[sid], "dof": dof - 1, "force_N": float(f[3]) * curves[lcid][2],
                          "t_start_s": curves[lcid][0], "t_end_s": curves[lcid][1]})
    contact = None
    if "*CONTACT_AUTOMATIC_NODES_TO_SURFACE" in blocks:
        c = one("*CONTACT_AUTOMATIC_NODES_TO_SURFACE")
        contact = {"nodes": sets[int(c[0][0])], "static_friction": float(c[1][0]), "dynamic_friction": float(c[1][1])}
    return Deck(nodes=coords[: finger_nodes.max() + 1], hexes=hexes,
                material={"rho": float(mat[1]), "E": float(mat[2]), "nu": float(mat[3])},
                alpha_per_s=float(one("*DAMPING_GLOBAL")[0][1]), tssfac=float(one("*CONTROL_TIMESTEP")[0][1]),
                t_end_s=float(one("*CONTROL_TERMINATION")[0][0]), node_sets=sets,
                spc_sets=[int(f[0]) for f in (_fields(line, 10) for b in blocks.get("*BOUNDARY_SPC_SET", []) for line in b)],
                loads=loads, contact=contact, tets4=tets4, tets10=tets10,
                elform=int(section[0][1]) if section else None)
