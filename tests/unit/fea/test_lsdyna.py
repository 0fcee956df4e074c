"""LS-DYNA deck: what we write, our parser reads back unchanged, and every card has the
field layout of the LS-DYNA Keyword User's Manual.

The layouts below (field names in column order, 10 columns each, 8 per line) are the
manual's, as transcribed field by field in Ansys PyDyna's keyword classes
(github.com/ansys/pydyna, src/ansys/dyna/core/keywords/keyword_classes/auto/<group>/<keyword>.py).
They are written out here, independently of the writer, and every card of an exported
deck is cut into its columns and checked field by field: ids that refer to other cards
must resolve, and values must be the model's.
"""
import numpy as np
import pytest

from ccedi.errors import InputError
from ccedi.fea.cases.studies import impulse_model
from ccedi.fea.contact.drum import DrumSetup, finger_on_drum
from ccedi.fea.elements.hex8 import BULK_VISCOSITY_C0, BULK_VISCOSITY_C1
from ccedi.fea.io.lsdyna import CLAMP_SET, keyword_blocks, keyword_lines, read_keyword, write_keyword
from ccedi.fea.mesh import Mesh
from ccedi.fea.mesh.gmsh_fingers import tapered_finger
from ccedi.fea.mesh.readers import read_finger_mesh
from ccedi.study import cli

LAYOUT = {
    "*CONTROL_TERMINATION": [["ENDTIM", "ENDCYC", "DTMIN", "ENDENG", "ENDMAS", "NOSOL"]],
    "*CONTROL_TIMESTEP": [["DTINIT", "TSSFAC", "ISDO", "TSLIMT", "DT2MS", "LCTM", "ERODE", "MS1ST"]],
    "*CONTROL_ENERGY": [["HGEN", "RWEN", "SLNTEN", "RYLEN", "IRGEN", "MATEN", "DRLEN", "DISEN"]],
    "*DATABASE_GLSTAT": [["DT", "BINARY", "LCUR", "IOOPT"]],
    "*DATABASE_NODOUT": [["DT", "BINARY", "LCUR", "IOOPT", "OPTION1", "OPTION2"]],
    "*DATABASE_RCFORC": [["DT", "BINARY", "LCUR", "IOOPT"]],
    "*DATABASE_SPCFORC": [["DT", "BINARY", "LCUR", "IOOPT"]],
    "*DATABASE_BINARY_D3PLOT": [["DT", "LCDT", "BEAM", "NPLTC", "PSETID"]],
    "*PART": [["HEADING"], ["PID", "SECID", "MID", "EOSID", "HGID", "GRAV", "ADPOPT", "TMID"]],
    "*PART_INERTIA": [["HEADING"], ["PID", "SECID", "MID", "EOSID", "HGID", "GRAV", "ADPOPT", "TMID"],
                      ["XC", "YC", "ZC", "TM", "IRCS", "NODEID"],
                      ["IXX", "IXY", "IXZ", "IYY", "IYZ", "IZZ"],
                      ["VTX", "VTY", "VTZ", "VRX", "VRY", "VRZ"]],
    "*SECTION_SOLID": [["SECID", "ELFORM", "AET"]],
    "*SECTION_SHELL": [["SECID", "ELFORM", "SHRF", "NIP", "PROPT", "QR/IRID", "ICOMP", "SETYP"],
                       ["T1", "T2", "T3", "T4", "NLOC", "MAREA", "IDOF", "EDGSET"]],
    "*HOURGLASS": [["HGID", "IHQ", "QM", "IBQ", "Q1", "Q2", "QB/VDC", "QW"]],
    "*MAT_ELASTIC": [["MID", "RO", "E", "PR", "DA", "DB", "K"]],
    "*MAT_RIGID": [["MID", "RO", "E", "PR", "N", "COUPLE", "M", "ALIAS"],
                   ["CMO", "CON1", "CON2", "SPCNID", "XSPC", "YSPC", "ZSPC"],
                   ["LCO/A1", "A2", "A3", "V1", "V2", "V3", "BNDLCO"]],
    "*DAMPING_GLOBAL": [["LCID", "VALDMP", "STX", "STY", "STZ", "SRX", "SRY", "SRZ"]],
    "*BOUNDARY_SPC_SET": [["NSID", "CID", "DOFX", "DOFY", "DOFZ", "DOFRX", "DOFRY", "DOFRZ"]],
    "*CONSTRAINED_EXTRA_NODES_SET": [["PID", "NSID", "IFLAG"]],
    "*BOUNDARY_PRESCRIBED_MOTION_RIGID": [["PID", "DOF", "VAD", "LCID", "SF", "VID", "DEATH", "BIRTH"]],
    "*INITIAL_VELOCITY_GENERATION": [["ID", "STYP", "OMEGA", "VX", "VY", "VZ", "IVATN", "ICID"],
                                     ["XC", "YC", "ZC", "NX", "NY", "NZ", "PHASE", "IRIGID"]],
    "*CONTACT_AUTOMATIC_NODES_TO_SURFACE": [["SSID", "MSID", "SSTYP", "MSTYP", "SBOXID", "MBOXID", "SPR", "MPR"],
                                            ["FS", "FD", "DC", "VC", "VDC", "PENCHK", "BT", "DT"],
                                            ["SFS", "SFM", "SST", "MST", "SFST", "SFMT", "FSF", "VSF"]],
}
"""Fixed cards: one list of field names per data line."""

REPEATED = {
    "*DATABASE_HISTORY_NODE": ([], ["ID1", "ID2", "ID3", "ID4", "ID5", "ID6", "ID7", "ID8"], 10),
    "*SET_NODE_LIST": ([["SID", "DA1", "DA2", "DA3", "DA4", "SOLVER"]],
                       ["NID1", "NID2", "NID3", "NID4", "NID5", "NID6", "NID7", "NID8"], 10),
    "*LOAD_NODE_SET": ([], ["NSID", "DOF", "LCID", "SF", "CID", "M1", "M2", "M3"], 10),
    "*DEFINE_CURVE": ([["LCID", "SIDR", "SFA", "SFO", "OFFA", "OFFO", "DATTYP", "LCINT"]], ["A", "O"], 20),
}
"""Cards with a repeated line: (leading lines, repeated line's fields, field width)."""

INTEGER_FIELDS = {"ENDCYC", "NOSOL", "BINARY", "LCUR", "IOOPT", "OPTION2", "LCDT", "BEAM", "NPLTC", "PSETID",
                  "PID", "SECID", "MID", "EOSID", "HGID", "GRAV", "ADPOPT", "TMID", "IRCS", "NODEID", "ELFORM",
                  "AET", "NIP", "PROPT", "ICOMP", "SETYP", "EDGSET", "IHQ", "IBQ", "LCID", "NSID", "CID",
                  "DOFX", "DOFY", "DOFZ", "DOFRX", "DOFRY", "DOFRZ", "IFLAG", "DOF", "VAD", "VID", "ID", "STYP",
                  "IVATN", "ICID", "PHASE", "IRIGID", "SSID", "MSID", "SSTYP", "MSTYP", "SID", "HGEN", "RWEN",
                  "SLNTEN", "RYLEN", "IRGEN", "MATEN", "DRLEN", "DISEN", "ISDO", "LCTM", "ERODE", "MS1ST",
                  "SPCNID", "BNDLCO", "SIDR", "DATTYP", "LCINT", "M1", "M2", "M3", "SBOXID", "MBOXID", "SPR", "MPR",
                  "EID", *(f"N{k}" for k in range(1, 11)),
                  *(f"ID{k}" for k in range(1, 9)), *(f"NID{k}" for k in range(1, 9))}
TEXT_FIELDS = {"HEADING", "ALIAS", "SOLVER"}
SOLID_ONE_LINE = ["EID", "PID", *(f"N{k}" for k in range(1, 9))]
SOLID_TEN_NODES = [["EID", "PID"], [f"N{k}" for k in range(1, 11)]]
"""*ELEMENT_SOLID, 8 columns a field: the one-line format (a tetrahedron as N1 N2 N3 N4 N4 N4
N4 N4), and the two-card ten-node format (Card 1 EID PID, Card 2 N1..N10), which PyDyna's
ElementSolid tells from the other by the number of fields on an element's first line."""
PAPER_ELFORM = {"hex8": 1, "tet4": 13, "tet10": 16}
"""*SECTION_SOLID ELFORM (manual): 1 constant stress solid, 13 one-point nodal pressure
tetrahedron, 16 4- or 5-point 10-noded tetrahedron."""
ROTATION_DOF_AXIS = {5: (1.0, 0.0, 0.0), 6: (0.0, 1.0, 0.0), 7: (0.0, 0.0, 1.0)}
"""*BOUNDARY_PRESCRIBED_MOTION DOF: EQ.5/6/7 x-, y-, z-rotational degree of freedom."""


def _cut(line, names, width):
    """{name: value} of one data line cut into ``width``-column fields; an empty field is
    None, an integer field must hold an integer, a real field a real number."""
    assert len(line) <= width * len(names) or names == ["HEADING"], f"{line!r}: text beyond {names[-1]}"
    if names == ["HEADING"]:
        return {"HEADING": line.strip()}
    out = {}
    for k, name in enumerate(names):
        text = line[k * width:(k + 1) * width].strip()
        assert " " not in text, f"{name}: {text!r} is not one field ({line!r})"
        if not text:
            out[name] = None
        elif name in TEXT_FIELDS:
            out[name] = text
        elif name in INTEGER_FIELDS:
            assert text.lstrip("-").isdigit(), f"{name} = {text!r} is not an integer ({line!r})"
            out[name] = int(text)
        else:
            out[name] = float(text)
    return out


def solid_cards(text):
    """(EID, PID, [N1, ...]) of every element of the *ELEMENT_SOLID cards, each line cut
    into the manual's 8-column fields (:data:`SOLID_ONE_LINE`, :data:`SOLID_TEN_NODES`)."""
    out = []
    for lines in keyword_blocks(text).get("*ELEMENT_SOLID", []):
        rows = iter(lines)
        for line in rows:
            if len(line.split()) > 2:
                row = _cut(line, SOLID_ONE_LINE, 8)
                names = SOLID_ONE_LINE[2:]
            else:
                head, row = _cut(line, SOLID_TEN_NODES[0], 8), _cut(next(rows), SOLID_TEN_NODES[1], 8)
                row.update(head)
                names = SOLID_TEN_NODES[1]
            out.append((row["EID"], row["PID"], [row[n] for n in names]))
    return out


def parse_deck(text):
    """{keyword: [occurrence: list of {field: value} per data line]} of every card in
    LAYOUT or REPEATED; a card with more lines than its layout fails."""
    cards = {}
    for key, occurrences in keyword_blocks(text).items():
        for lines in occurrences:
            if key in LAYOUT:
                layout = LAYOUT[key]
                assert len(lines) <= len(layout), f"{key}: {len(lines)} lines, the manual has {len(layout)}"
                rows = [_cut(line, names, 10) for line, names in zip(lines, layout)]
            elif key in REPEATED:
                lead, names, width = REPEATED[key]
                rows = ([_cut(line, n, 10) for line, n in zip(lines, lead)]
                        + [_cut(line, names, width) for line in lines[len(lead):]])
            else:
                continue
            cards.setdefault(key, []).append(rows)
    return cards


def _one(cards, key, **match):
    """The one occurrence of ``key`` whose first-line fields equal ``match``."""
    hits = [rows for rows in cards.get(key, []) if all(rows[0].get(f) == v for f, v in match.items())]
    assert len(hits) == 1, f"{key} {match}: {len(hits)} cards"
    return hits[0]


def _node_ids(text):
    return {int(line[:8]) for block in keyword_blocks(text).get("*NODE", []) for line in block}


def _set(cards, sid):
    rows = _one(cards, "*SET_NODE_LIST", SID=sid)
    return np.array(sorted(v for r in rows[1:] for v in r.values() if v is not None)) - 1


def _curve(cards, lcid):
    rows = _one(cards, "*DEFINE_CURVE", LCID=lcid)
    assert rows[0]["SFA"] in (None, 1.0) and rows[0]["SFO"] in (None, 1.0) and not rows[0]["OFFA"]
    return np.array([[r["A"], r["O"]] for r in rows[1:]])


def _integral(points, t):
    """Integral of a piecewise-linear curve from 0 to t."""
    a = np.union1d(points[:, 0][points[:, 0] < t], [0.0, t])
    o = np.interp(a, points[:, 0], points[:, 1])
    return float(np.sum(0.5 * (o[1:] + o[:-1]) * np.diff(a)))


def check_deck(text, model, t_end_s):
    """Every card field by field against the manual's layout and the model's values."""
    cards = parse_deck(text)
    nodes = _node_ids(text)
    assert _one(cards, "*CONTROL_TERMINATION")[0]["ENDTIM"] == t_end_s > 0
    assert _one(cards, "*CONTROL_TIMESTEP")[0]["TSSFAC"] == 0.9
    energy = _one(cards, "*CONTROL_ENERGY")[0]
    assert energy["HGEN"] == energy["RYLEN"] == energy["SLNTEN"] == 2     # 2: computed, in glstat
    ascii_files = ["*DATABASE_GLSTAT", "*DATABASE_NODOUT"] + (["*DATABASE_SPCFORC"] if len(model.fixed_nodes) else []) \
        + (["*DATABASE_RCFORC"] if model.contact is not None else [])
    for key in ascii_files:
        row = _one(cards, key)[0]
        assert row["DT"] == pytest.approx(t_end_s / 400, rel=1e-8) and row["DT"] > 0 and row["BINARY"] == 1, key
    assert ("*DATABASE_RCFORC" in cards) == (model.contact is not None)
    plot = _one(cards, "*DATABASE_BINARY_D3PLOT")[0]
    assert plot["DT"] == pytest.approx(t_end_s / 40, rel=1e-8) and plot["NPLTC"] is None
    history = [v for rows in cards["*DATABASE_HISTORY_NODE"] for r in rows for v in r.values() if v is not None]
    assert set(history) <= nodes
    np.testing.assert_array_equal(np.sort(history), np.sort(model.mesh.node_sets["tip"]) + 1)

    finger = _part(cards, "finger")
    mesh = model.mesh
    kind = mesh.element_type
    if kind == "hex8":
        hourglass = _one(cards, "*HOURGLASS", HGID=finger[1]["HGID"])[0]
        assert finger[1]["HGID"] is not None and hourglass["IHQ"] == 6
        assert hourglass["QM"] == model.hourglass_coefficient
        assert (hourglass["Q1"], hourglass["Q2"]) == (BULK_VISCOSITY_C0, BULK_VISCOSITY_C1)
    else:                                       # tetrahedra: no hourglass modes, no card
        assert finger[1]["HGID"] in (None, 0) and "*HOURGLASS" not in cards
    assert _one(cards, "*SECTION_SOLID", SECID=finger[1]["SECID"])[0]["ELFORM"] == PAPER_ELFORM[kind]
    solids = solid_cards(text)
    assert {pid for _, pid, _ in solids} == {finger[1]["PID"]}
    assert [eid for eid, _, _ in solids] == list(range(1, mesh.n_elements + 1))
    expected = {"hex8": mesh.hexes, "tet4": mesh.tets4[:, [0, 1, 2, 3, 3, 3, 3, 3]], "tet10": mesh.tets10}[kind]
    np.testing.assert_array_equal(np.array([n for _, _, n in solids]), expected + 1)
    mat = _one(cards, "*MAT_ELASTIC", MID=finger[1]["MID"])[0]
    m = model.material
    assert (mat["RO"], mat["E"], mat["PR"]) == (m.rho, m.E, m.nu)
    damping = _one(cards, "*DAMPING_GLOBAL")[0]
    assert damping["LCID"] == 0 and damping["VALDMP"] == model.alpha
    assert all(damping[f] == 1.0 for f in ("STX", "STY", "STZ", "SRX", "SRY", "SRZ"))

    if len(model.fixed_nodes):
        spc = _one(cards, "*BOUNDARY_SPC_SET")[0]
        np.testing.assert_array_equal(_set(cards, spc["NSID"]), np.sort(model.fixed_nodes))
        assert [spc[f] for f in ("DOFX", "DOFY", "DOFZ")] == [1, 1, 1]
    for pulse in model.pulses:
        total = np.zeros(3)
        for rows in cards["*LOAD_NODE_SET"]:
            for r in rows:
                curve = _curve(cards, r["LCID"])
                assert curve[:, 0].min() == 0.0 and curve[:, 0].max() >= t_end_s
                total[r["DOF"] - 1] += r["SF"] * curve[:, 1].max() * len(_set(cards, r["NSID"]))
        np.testing.assert_allclose(total, pulse.force_N, rtol=1e-12)

    if model.contact is not None:
        c = _one(cards, "*CONTACT_AUTOMATIC_NODES_TO_SURFACE")
        assert (c[0]["SSTYP"], c[0]["MSTYP"]) == (4, 3)             # node set -> part
        np.testing.assert_array_equal(_set(cards, c[0]["SSID"]), np.sort(model.contact.nodes))
        assert c[1]["FS"] == c[1]["FD"] == model.contact.surface.mu
        obj = _part(cards, "object (rigid)")
        assert obj[1]["PID"] == c[0]["MSID"]
        rigid = _one(cards, "*MAT_RIGID", MID=obj[1]["MID"])
        assert (rigid[1]["CMO"], rigid[1]["CON1"], rigid[1]["CON2"]) == (1.0, 7, 7)

    if model.rotating is not None:
        rot = model.rotating
        drum = _part(cards, "drum (rigid)", "*PART_INERTIA")
        pid = drum[1]["PID"]
        centre = np.array([drum[2]["XC"], drum[2]["YC"], drum[2]["ZC"]])
        off_axis = (centre - rot.center_m) - np.dot(centre - rot.center_m, rot.axis) * rot.axis
        assert np.linalg.norm(off_axis) == 0.0 and drum[2]["TM"] > 0 and drum[2]["IRCS"] == 0
        assert min(drum[3]["IXX"], drum[3]["IYY"], drum[3]["IZZ"]) > 0
        assert drum[4]["VRZ"] == rot.omega_rad_s and not any(drum[4][f] for f in ("VTX", "VTY", "VTZ", "VRX", "VRY"))
        rigid = _one(cards, "*MAT_RIGID", MID=drum[1]["MID"])
        assert (rigid[1]["CMO"], rigid[1]["CON1"], rigid[1]["CON2"]) == (1.0, 7, 4)   # only z rotation free
        extra = _one(cards, "*CONSTRAINED_EXTRA_NODES_SET")[0]
        assert extra["PID"] == pid
        np.testing.assert_array_equal(_set(cards, extra["NSID"]), np.sort(rot.nodes))
        motion = _one(cards, "*BOUNDARY_PRESCRIBED_MOTION_RIGID")[0]
        assert motion["PID"] == pid and motion["VAD"] == 0 and motion["DEATH"] in (None, 0.0)
        assert motion["SF"] is not None and motion["VID"] in (None, 0)     # VID: only for DOF 4 and 8
        np.testing.assert_array_equal(ROTATION_DOF_AXIS[motion["DOF"]], rot.axis)
        curve = _curve(cards, motion["LCID"])
        for t in np.linspace(0.0, t_end_s, 7):     # the drum angle omega t, t in 0..t_end
            assert motion["SF"] * _integral(curve, t) == pytest.approx(rot.omega_rad_s * t, rel=1e-12, abs=1e-15)
        start = _one(cards, "*INITIAL_VELOCITY_GENERATION")
        assert (start[0]["ID"], start[0]["STYP"]) == (finger[1]["PID"], 2)
        assert start[0]["OMEGA"] == rot.omega_rad_s
        np.testing.assert_array_equal([start[1][f] for f in ("XC", "YC", "ZC")], rot.center_m)
        np.testing.assert_array_equal([start[1][f] for f in ("NX", "NY", "NZ")], rot.axis)
    return cards


def _part(cards, heading, key="*PART"):
    hits = [rows for rows in cards.get(key, []) if rows[0]["HEADING"] == heading]
    assert len(hits) == 1, f"{key} {heading!r}: {len(hits)} cards"
    return hits[0]


@pytest.fixture(scope="module")
def impulse():
    model = impulse_model(length_in=4.5, alpha=180.0, force_N=1.0, duration_s=0.01)
    return model, "\n".join(keyword_lines(model, 0.2))


@pytest.fixture(scope="module")
def drum():
    model, _ = finger_on_drum(DrumSetup(), alpha=7.5)
    return model, "\n".join(keyword_lines(model, 1.5))


def test_impulse_deck_matches_the_manual_layouts(impulse):
    model, text = impulse
    cards = check_deck(text, model, 0.2)
    assert "*DATABASE_SPCFORC" in cards and "*PART_INERTIA" not in cards


def test_drum_deck_matches_the_manual_layouts(drum):
    model, text = drum
    cards = check_deck(text, model, 1.5)
    assert "*DATABASE_SPCFORC" not in cards and "*BOUNDARY_SPC_SET" not in cards


@pytest.mark.parametrize("card, occurrence, line, change", [
    ("*PART", 0, 1, lambda s: s[:40] + " " * 10 + s[40:]),               # the finger's HGID pushed into GRAV
    ("*HOURGLASS", 0, 0, lambda s: s[:10] + s[20:30] + s[10:20] + s[30:]),     # IHQ and QM swapped
    ("*DAMPING_GLOBAL", 0, 0, lambda s: s[10:]),                          # VALDMP read as LCID
    ("*CONTROL_TERMINATION", 0, 0, lambda s: " " * 3 + s),                # ENDTIM pushed out of its field
    ("*DATABASE_HISTORY_NODE", 0, 1, lambda s: s[:70] + "    999999"),   # a node that does not exist
    ("*DATABASE_GLSTAT", 0, 0, lambda s: s[:10] + "         2"),          # binout instead of the ASCII file
    ("*BOUNDARY_PRESCRIBED_MOTION_RIGID", 0, 0, lambda s: s[:10] + "         6" + s[20:]),   # y rotation
    ("*BOUNDARY_PRESCRIBED_MOTION_RIGID", 0, 0, lambda s: s[:20] + "         2" + s[30:]),   # VAD displacement
    ("*BOUNDARY_PRESCRIBED_MOTION_RIGID", 0, 0, lambda s: s[:40] + " " * 10 + "     2.095"),   # omega in VID
    ("*PART_INERTIA", 0, 2, lambda s: "    0.0001" + s[10:]),             # centre of mass off the axis
    ("*MAT_RIGID", -1, 1, lambda s: s[:20] + "         7"),               # the drum cannot turn
    ("*INITIAL_VELOCITY_GENERATION", 0, 1, lambda s: s[:30] + s[40:60] + s[30:40]),   # axis (0, 1, 0)
])
def test_a_misplaced_field_fails_the_layout_check(drum, card, occurrence, line, change):
    model, text = drum
    lines = text.splitlines()
    at = [i for i, s in enumerate(lines) if s == card][occurrence] + 1
    end = next(i for i in range(at, len(lines)) if lines[i].startswith("*"))
    data = [i for i in range(at, end) if not lines[i].startswith("$")][line]
    lines[data] = change(lines[data])
    check_deck(text, model, 1.5)
    with pytest.raises(AssertionError):
        check_deck("\n".join(lines), model, 1.5)


def test_sm_a_impulse_deck_round_trip(tmp_path):
    model = impulse_model(length_in=4.5, alpha=180.0, force_N=1.0, duration_s=0.01)
    path = write_keyword(model, tmp_path / "sm_a.k", t_end_s=0.2)
    deck = read_keyword(path)
    assert deck.nodes.shape == (1080, 3) and deck.hexes.shape == (725, 8)
    np.testing.assert_allclose(deck.nodes, model.mesh.nodes, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(deck.hexes, model.mesh.hexes)
    m = model.material
    assert deck.material == {"rho": m.rho, "E": m.E, "nu": m.nu}
    assert deck.alpha_per_s == 180.0 and deck.tssfac == 0.9 and deck.t_end_s == 0.2
    assert len(deck.spc_sets) == 1
    np.testing.assert_array_equal(np.sort(deck.node_sets[deck.spc_sets[0]]), np.sort(model.fixed_nodes))
    pulse = model.pulses[0]
    loaded = np.concatenate([ld["nodes"] for ld in deck.loads])
    np.testing.assert_array_equal(np.sort(loaded), np.sort(pulse.nodes))
    total = np.zeros(3)
    for ld in deck.loads:
        total[ld["dof"]] += ld["force_N"] * len(ld["nodes"])
        assert (ld["t_start_s"], ld["t_end_s"]) == (0.0, 0.01)
    np.testing.assert_allclose(total, pulse.force_N, rtol=1e-12)
    for ld in deck.loads:   # each node carries its own share of the pulse
        w = dict(zip(pulse.nodes.tolist(), pulse.weights))
        np.testing.assert_allclose([w[n] for n in ld["nodes"].tolist()], ld["force_N"], rtol=1e-12)


def test_contact_deck_round_trip(tmp_path):
    model, _ = finger_on_drum(DrumSetup(), alpha=7.5)
    deck = read_keyword(write_keyword(model, tmp_path / "drum.k", t_end_s=1.5))
    assert deck.contact["static_friction"] == 0.6
    np.testing.assert_array_equal(np.sort(deck.contact["nodes"]), np.sort(model.contact.nodes))
    np.testing.assert_allclose(deck.nodes, model.mesh.nodes, atol=1e-12)
    np.testing.assert_array_equal(deck.hexes, model.mesh.hexes)


def test_relative_damping_is_refused(tmp_path):
    model, _ = finger_on_drum(DrumSetup(), alpha=7.5, damping="relative")
    with pytest.raises(InputError, match="relative"):
        write_keyword(model, tmp_path / "x.k", t_end_s=1.0)


@pytest.mark.parametrize("kwargs, field", [
    ({"t_end_s": -1.0}, "t_end_s"), ({"t_end_s": float("nan")}, "t_end_s"), ({"t_end_s": 0.0}, "t_end_s"),
    ({"t_end_s": float("inf")}, "t_end_s"), ({"t_end_s": 0.2, "output_dt_s": 0.0}, "output_dt_s"),
    ({"t_end_s": 0.2, "output_dt_s": float("nan")}, "output_dt_s"),
    ({"t_end_s": 0.2, "output_dt_s": 0.5}, "output_dt_s"), ({"t_end_s": 0.2, "plot_dt_s": -0.1}, "plot_dt_s"),
])
def test_bad_times_are_refused_before_writing(tmp_path, impulse, kwargs, field):
    model, _ = impulse
    with pytest.raises(InputError, match=field) as err:
        write_keyword(model, tmp_path / "x.k", **kwargs)
    assert "\n" not in str(err.value)
    assert not (tmp_path / "x.k").exists()


@pytest.mark.parametrize("name, value", [("alpha", -1.0), ("alpha", float("nan")), ("alpha", float("inf")),
                                         ("beta", -1.0), ("hourglass_coefficient", 0.0)])
def test_damping_changed_after_construction_is_refused(tmp_path, name, value):
    model = impulse_model(length_in=3.0, alpha=180.0)
    setattr(model, name, value)
    with pytest.raises(InputError, match=name):
        write_keyword(model, tmp_path / "x.k", t_end_s=0.2)
    assert not (tmp_path / "x.k").exists()


@pytest.mark.parametrize("flag, value", [("--t-end-s", "-1"), ("--t-end-s", "nan"), ("--t-end-s", "0"),
                                         ("--t-end-s", "inf"), ("--alpha", "-1"), ("--alpha", "nan")])
def test_export_refuses_bad_values_in_one_line(tmp_path, capsys, flag, value):
    out = tmp_path / "deck.k"
    assert cli.main(["export", "--format", "lsdyna", flag, value, "--out", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and flag in err[0] and value in err[0], err
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_export_writes_a_checked_contact_deck(tmp_path, capsys):
    out = tmp_path / "drum.k"
    assert cli.main(["export", "--case", "contact", "--alpha", "180", "--t-end-s", "1.2", "--out", str(out)]) == 0
    model, _ = finger_on_drum(DrumSetup(), alpha=180.0)
    check_deck(out.read_text(), model, 1.2)


@pytest.fixture(scope="module")
def tet_fingers():
    """The tapered finger with a hole (not a prism), coarse, as 4- and 10-node tetrahedra."""
    return {kind: tapered_finger(0.012, order=order) for kind, order in (("tet4", 1), ("tet10", 2))}


@pytest.mark.parametrize("kind", ["tet4", "tet10"])
@pytest.mark.parametrize("case", ["impulse", "drum"])
def test_tetrahedral_decks_match_the_manual_and_read_back(tmp_path, tet_fingers, kind, case):
    """Impulse and drum decks of a tetrahedral finger: every card against the manual's
    layouts (ELFORM 13 / 16, the element cards), and both readers, :func:`read_keyword` and
    :func:`ccedi.fea.mesh.readers.read_finger_mesh` (the impulse deck: the drum deck's finger is
    turned onto the drum), give back the same nodes, elements and types."""
    mesh = tet_fingers[kind]
    model = (impulse_model(alpha=180.0, mesh=mesh) if case == "impulse"
             else finger_on_drum(DrumSetup(finger=mesh), alpha=7.5)[0])
    assert model.mesh.element_type == kind
    path = write_keyword(model, tmp_path / f"{case}.k", t_end_s=0.2)
    check_deck(path.read_text(), model, 0.2)
    deck = read_keyword(path)
    assert deck.elform == PAPER_ELFORM[kind] and deck.hexes.shape == (0, 8)
    np.testing.assert_allclose(deck.nodes, model.mesh.nodes, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(deck.tets4, model.mesh.tets4)
    np.testing.assert_array_equal(deck.tets10, model.mesh.tets10)
    if case == "drum":                          # turned onto the drum: not a finger along z
        return
    back = read_finger_mesh(path, clamp=str(CLAMP_SET))
    assert back.element_type == kind and back.n_nodes == model.mesh.n_nodes
    np.testing.assert_allclose(back.nodes, model.mesh.nodes, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(back.tets4, model.mesh.tets4)
    np.testing.assert_array_equal(back.tets10, model.mesh.tets10)
    np.testing.assert_array_equal(back.node_sets["root"], np.sort(model.mesh.node_sets["root"]))


def test_a_mixed_mesh_is_refused_in_one_line(tmp_path, tet_fingers):
    mesh = tet_fingers["tet4"]
    model = impulse_model(alpha=180.0, mesh=mesh)
    model.mesh = Mesh(nodes=mesh.nodes, tets4=mesh.tets4[1:], hexes=mesh.tets4[:1, [0, 1, 2, 3, 0, 1, 2, 3]],
                      node_sets=mesh.node_sets)
    with pytest.raises(InputError, match="element type 'mixed'"):
        write_keyword(model, tmp_path / "x.k", t_end_s=0.2)
    assert not (tmp_path / "x.k").exists()
