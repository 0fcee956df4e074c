"""LS-DYNA keyword decks: write a ccedi :class:`ccedi.fea.model.Model` so that a user with LS-DYNA
can run the same model, and read back the cards ccedi writes (round-trip check).

Format: LS-DYNA's standard fixed-width fields, 10 characters per field except *NODE
(node id 8, coordinates 16 each), *ELEMENT_SOLID / *ELEMENT_SHELL (8 each) and the
*DEFINE_CURVE points (20 each). A real number is written in the shortest form that
round-trips exactly and fits the field less one character (so fields stay separated by
a blank); one that cannot fit keeps as many significant digits as fit (node coordinates
to about 1e-13 m on a finger). Ids are 1-based in the deck, 0-based in ccedi. The reader
also accepts comma-separated (free format) lines.

Cards written (SI units: m, kg, s, N, Pa):

* *NODE, *PART / *SECTION_SOLID (ELFORM 1, one-point hexahedron, as ccedi's element) /
  *ELEMENT_SOLID;
* *MAT_ELASTIC (E, nu, rho of the rubber: ccedi's neo-Hookean solid coincides with it at
  small strain; for large strain use *MAT_HYPERELASTIC_RUBBER with C10 = mu/2, D1 = 2/K);
* *DAMPING_GLOBAL with VALDMP = alpha (force d m v, the paper's mass-proportional term;
  beta, if any, is noted in a comment: LS-DYNA sets it per part with *DAMPING_PART_STIFFNESS);
* *CONTROL_TERMINATION, *CONTROL_TIMESTEP with TSSFAC 0.9;
* *SET_NODE_LIST + *BOUNDARY_SPC_SET for the clamped nodes;
* *SET_NODE_LIST + *LOAD_NODE_SET + *DEFINE_CURVE for each force pulse: nodes grouped by
  their share of the pulse (*LOAD_NODE_SET applies one force to every node), the curve
  holding the share, SF the force component [N] (per-node force = SF x curve);
* for a rotating root (the drum): *BOUNDARY_PRESCRIBED_MOTION_SET (DOF 11, rotation about
  z through the origin at constant rate) and *INITIAL_VELOCITY_GENERATION;
* for contact: the rigid elliptical object as a shell part (*MAT_RIGID, fully constrained)
  and *CONTACT_AUTOMATIC_NODES_TO_SURFACE from the finger's surface nodes, static and
  dynamic friction = mu.
"""
from dataclasses import dataclass, field

import numpy as np

from ccedi.errors import InputError

from .explicit import TSSFAC
from .outputs import write_text

FINGER_PART, OBJECT_PART = 1, 2
CLAMP_SET, CONTACT_SET, ROTATING_SET, FIRST_LOAD_SET = 1, 2, 3, 10
OBJECT_SHELLS_AROUND, OBJECT_SHELLS_THROUGH = 72, 4


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
    return "".join(v.rjust(width) if isinstance(v, str) else
                   (str(v).rjust(width) if isinstance(v, (int, np.integer)) else _num(v, width - 1).rjust(width))
                   for v in values)


def _node_line(i, xyz):
    """*NODE card of 0-based node ``i``: id in 8 characters, coordinates [m] in 16."""
    return f"{i + 1:8d}" + "".join(_num(c, 15).rjust(16) for c in xyz)


def _node_set(sid, nodes):
    lines = ["*SET_NODE_LIST", _card([sid])]
    ids = np.asarray(nodes, dtype=np.int64) + 1
    lines += [_card(list(ids[i:i + 8])) for i in range(0, len(ids), 8)]
    return lines


def _pulse_curve(lcid, share, t0, t1, t_end_s):
    """A rectangular pulse of height ``share`` (a node's share of the force, carried in the
    curve's 20-character ordinates so it stays exact) from t0 to t1 [s], as a *DEFINE_CURVE."""
    eps = 1e-9 * max(t1, 1.0)
    points = (([(0.0, 0.0), (max(t0 - eps, 0.0), 0.0)] if t0 > 0.0 else [])
              + [(t0, share), (t1, share), (t1 + eps, 0.0)])
    points.append((max(10.0 * t_end_s, t1 + 2 * eps), 0.0))
    return ["*DEFINE_CURVE", _card([lcid]), *[_card([t, f], 20) for t, f in points]]


def _object_shells(surface, first_node):
    """Quad shells on the lateral surface of the rigid elliptical cylinder."""
    ca, sa = np.cos(surface.angle_rad), np.sin(surface.angle_rad)
    th = np.linspace(0.0, 2 * np.pi, OBJECT_SHELLS_AROUND, endpoint=False)
    ex, ey = surface.a_m * np.cos(th), surface.b_m * np.sin(th)
    x = surface.center_m[0] + ca * ex - sa * ey
    y = surface.center_m[1] + sa * ex + ca * ey
    zs = np.linspace(surface.z_min_m, surface.z_max_m, OBJECT_SHELLS_THROUGH + 1)
    pts = np.array([[xi, yi, z] for z in zs for xi, yi in zip(x, y)])
    n = OBJECT_SHELLS_AROUND
    quads = [[k * n + i, k * n + (i + 1) % n, (k + 1) * n + (i + 1) % n, (k + 1) * n + i]
             for k in range(OBJECT_SHELLS_THROUGH) for i in range(n)]
    return pts, np.asarray(quads) + first_node


def keyword_lines(model, t_end_s, title="ccedi model"):
    """The LS-DYNA keyword deck of ``model`` as a list of lines (cards in the module docstring).

    Parameters
    ----------
    model : Model
        A solid model (no rods or point masses) with global damping; a rotating root
        must turn about the global z axis through the origin, and contact must be with
        the rigid elliptical object.
    t_end_s : float
        Termination time (*CONTROL_TERMINATION) [s].
    title : str, optional
        *TITLE text, truncated to 80 characters. Default ``"ccedi model"``.

    Returns
    -------
    list of str
        The deck, ``*KEYWORD`` to ``*END``, without line terminators.

    Raises
    ------
    InputError
        If the model has rods or point masses, relative damping, a rotation about
        another axis, contact with another surface, or a number that does not fit
        its fixed-width field.
    """
    if model.rods or model.point_masses:
        raise InputError("LS-DYNA export covers solid models; this model has rods or point masses")
    if model.damping != "global":
        raise InputError("LS-DYNA export writes *DAMPING_GLOBAL; relative damping is not exported")
    m, mesh = model.material, model.mesh
    lines = ["*KEYWORD", "*TITLE", title[:80],
             "$ units: m, kg, s, N, Pa. Written by ccedi (fea.lsdyna).",
             "*CONTROL_TERMINATION", _card([t_end_s]),
             "*CONTROL_TIMESTEP", "$    DTINIT    TSSFAC", _card([0.0, TSSFAC]),
             "*PART", "finger", _card([FINGER_PART, 1, 1]),
             "*SECTION_SOLID", _card([1, 1]),
             "*MAT_ELASTIC", "$       MID        RO         E        PR", _card([1, m.rho, m.E, m.nu]),
             "*DAMPING_GLOBAL", "$      LCID    VALDMP", _card([0, model.alpha])]
    if model.beta:
        lines.append(f"$ ccedi beta = {model.beta!r} s (not exported: use *DAMPING_PART_STIFFNESS)")
    lines += ["*NODE"] + [_node_line(i, xyz) for i, xyz in enumerate(mesh.nodes)]
    lines += ["*ELEMENT_SOLID"] + [_card([e + 1, FINGER_PART, *(h + 1)], 8) for e, h in enumerate(mesh.hexes)]
    if len(model.fixed_nodes):
        lines += _node_set(CLAMP_SET, model.fixed_nodes) + ["*BOUNDARY_SPC_SET", _card([CLAMP_SET, 0, 1, 1, 1, 1, 1, 1])]
    sid = FIRST_LOAD_SET
    for pulse in model.pulses:
        for w in np.unique(pulse.weights):
            lines += _pulse_curve(sid, w, pulse.t_start_s, pulse.t_end_s, t_end_s)
            lines += _node_set(sid, pulse.nodes[pulse.weights == w])
            lines += ["*LOAD_NODE_SET"] + [_card([sid, dof + 1, sid, f]) for dof, f in enumerate(pulse.force_N) if f]
            sid += 1
    lcid = sid
    if model.rotating is not None:
        rot = model.rotating
        if not (np.allclose(rot.axis, [0, 0, 1]) and np.allclose(rot.center_m, 0.0)):
            raise InputError("LS-DYNA export supports rotation about the global z axis through the origin only")
        lines += _node_set(ROTATING_SET, rot.nodes)
        lines += ["*DEFINE_CURVE", _card([lcid]), _card([0.0, 1.0], 20), _card([10.0 * t_end_s, 1.0], 20),
                  "*BOUNDARY_PRESCRIBED_MOTION_SET", _card([ROTATING_SET, 11, 0, lcid, rot.omega_rad_s]),
                  _card([0.0, 0.0]),
                  "*INITIAL_VELOCITY_GENERATION", _card([FINGER_PART, 2, rot.omega_rad_s, 0.0, 0.0, 0.0]),
                  _card([0.0, 0.0, 0.0, 0.0, 0.0, 1.0])]
    if model.contact is not None:
        surface = model.contact.surface
        if not hasattr(surface, "a_m"):
            raise InputError("LS-DYNA export writes contact with the rigid elliptical object only")
        pts, quads = _object_shells(surface, mesh.n_nodes)
        lines += ["*PART", "object (rigid)", _card([OBJECT_PART, 2, 2]),
                  "*SECTION_SHELL", _card([2, 2]), _card([1e-3, 1e-3, 1e-3, 1e-3]),
                  "*MAT_RIGID", _card([2, 2700.0, 69e9, 0.33]), _card([1.0, 7, 7]),
                  "*NODE"] + [_node_line(i, p) for i, p in enumerate(pts, mesh.n_nodes)]
        lines += ["*ELEMENT_SHELL"] + [_card([mesh.n_elements + k + 1, OBJECT_PART, *(q + 1)], 8)
                                       for k, q in enumerate(quads)]
        lines += _node_set(CONTACT_SET, model.contact.nodes)
        lines += ["*CONTACT_AUTOMATIC_NODES_TO_SURFACE", "$      SSID      MSID     SSTYP     MSTYP",
                  _card([CONTACT_SET, OBJECT_PART, 4, 3]), "$        FS        FD",
                  _card([surface.mu, surface.mu]), _card([1.0, 1.0])]
    lines.append("*END")
    return lines


def write_keyword(model, path, t_end_s, title="ccedi model"):
    """Write the LS-DYNA deck of ``model`` to ``path``, atomically.

    Parameters
    ----------
    model : Model
        The model (restrictions as in :func:`keyword_lines`).
    path : str or pathlib.Path
        Output ``.k`` file; parent directories are created.
    t_end_s : float
        Termination time [s].
    title : str, optional
        *TITLE text. Default ``"ccedi model"``.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    InputError
        If the model cannot be exported (see :func:`keyword_lines`).
    """
    return write_text(path, "\n".join(keyword_lines(model, t_end_s, title)) + "\n")


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


def _fields(line, width):
    if "," in line:
        return [f.strip() for f in line.split(",")]
    return [line[i:i + width].strip() for i in range(0, len(line), width)]


def _blocks(text):
    """{keyword: [list of data-line lists, one per occurrence]} without comments."""
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
        Nodes, elements, material, damping, controls, node sets, loads and contact.

    Raises
    ------
    InputError
        If a required card (*MAT_ELASTIC, *DAMPING_GLOBAL, *CONTROL_TIMESTEP,
        *CONTROL_TERMINATION) is missing.
    """
    blocks = _blocks(open(path).read())

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
    solids = [[int(v) for v in f] for f in (_fields(line, 8) for line in blocks["*ELEMENT_SOLID"][0])]
    hexes = np.asarray([s[2:10] for s in solids if s[1] == FINGER_PART], dtype=np.int64) - 1
    finger_nodes = np.unique(hexes)
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
                loads=loads, contact=contact)
