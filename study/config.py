"""Study inputs as TOML, validated against a schema: the finger's material and section,
the drum test, and the study settings.

Every key carries its unit in its name (``length_in``, ``alpha_per_s``, ``t_end_s``);
a key whose unit suffix is not the schema's (``length_mm``) is unknown, and the error
names the key the schema expects. Any problem gives one :class:`ccedi.errors.InputError`
line naming the section and key, e.g. ``[finger] length_in = 20: must be in 1..12 (in)``.

``[finger] mesh`` names a finger mesh file (:mod:`ccedi.fea.mesh.readers`) to use instead of
the generated elliptical prism; a relative path is relative to the TOML file's directory,
and the validated inputs hold it resolved (absolute), so that ``OUT/config.toml`` loads
from anywhere. :func:`finger_mesh` gives its :class:`ccedi.fea.mesh.readers.FingerMeshSpec`.

Every sub-command that builds a finger takes the same file with ``--config``
(:func:`finger_inputs`, :func:`drum_setup`); ``ccedi study`` loads and validates its
inputs once, writes them to ``OUT/config.toml`` for the record and passes them to each
step as objects.
"""
import difflib
import json
import re
import tomllib
from dataclasses import dataclass, fields
from pathlib import Path

from ccedi.distributed import check_scheduler
from ccedi.errors import InputError, brief_repr, one_line
from ccedi.fea.contact.drum import DEFAULT_FINGER_LENGTH_M, DrumSetup
from ccedi.fea.material import RUBBER, NeoHookean
from ccedi.fea.mesh import SEMI_AXES
from ccedi.fea.mesh.readers import BENDING_DIRECTIONS, PLANES, UNITS, FingerMeshSpec
from ccedi.quantities import QUANTITIES, Quantity
from ccedi.units import inch_to_m, m_to_inch

_DRUM = {f.name: f.default for f in fields(DrumSetup)}
_BARE_KEY = re.compile(r"[A-Za-z0-9_-]{1,60}")


@dataclass(frozen=True)
class Key:
    """One input: type (float, int, bool, str, or list of float), unit, allowed range,
    default (None: not set), one-line help, the allowed values of a str (empty: any), and
    a further ``check(value, where)`` that raises InputError (None: none)."""

    kind: type
    unit: str
    lo: float | None
    hi: float | None
    default: object
    help: str
    is_list: bool = False
    min_items: int = 1
    max_items: int | None = None
    choices: tuple = ()
    check: object = None


def _key(quantity, default, help, *list_args):
    """A :class:`Key` whose unit and range are those of :data:`ccedi.quantities.QUANTITIES`."""
    q = QUANTITIES[quantity]
    return Key(float, q.unit, q.lo, q.hi, default, help, *list_args)


CONFIG_NAME = "config.toml"
"""The resolved inputs of a study, written to its output directory before any step."""

SCHEMA = {
    "material": {
        "E_Pa": _key("E_Pa", RUBBER.E, "finger Young's modulus (paper Table 1: 6.1 MPa rubber)"),
        "nu": _key("nu", RUBBER.nu, "finger Poisson's ratio (neo-Hookean, compressible)"),
        "rho_kg_m3": _key("rho_kg_m3", RUBBER.rho, "finger density"),
        "alpha_per_s": _key("alpha_per_s", None, "the finger's measured mass-proportional damping (ccedi calibrate "
                            "--write-config); ccedi design reports the design at it beside the optimum"),
    },
    "finger": {
        "impulse_length_in": _key("length_in", 4.5, "finger length of the impulse studies (Figs. 6, 7)"),
        "contact_length_in": _key("length_in", round(m_to_inch(DEFAULT_FINGER_LENGTH_M), 6),
                                  "finger length of the drum contact study (Figs. 10, 13, 14; not used with a mesh, "
                                  "whose own length holds)"),
        "section_semi_axes_m": _key("section_semi_axis_m", list(SEMI_AXES),
                                    "elliptical section semi-axes [a along x, b along y, the bending direction]",
                                    True, 2, 2),
        "contact_taper_ratio": _key("taper_ratio", 1.0,
                                    "the drum contact and design finger's tip semi-axes over its root's "
                                    "section_semi_axes_m, linear along the length (1: the prism; not with a mesh)"),
        "mesh": Key(str, "-", None, None, None,
                    "finger mesh file instead of the generated elliptical finger (Gmsh .msh, Abaqus .inp, .vtu, "
                    ".vtk, LS-DYNA .k; relative to this file): hexahedra or 4-/10-node tetrahedra, length along z"),
        "mesh_unit": Key(str, "-", None, None, "m", "unit of the mesh file's coordinates", choices=tuple(UNITS)),
        "clamp": Key(str, "-", None, None, "z_min",
                     f"the mesh's clamped root: a set / physical group name or a plane ({', '.join(PLANES)})"),
        "tip": Key(str, "-", None, None, "z_max", "the mesh's loaded tip face: a set name or a plane"),
        "bending_direction": Key(str, "-", None, None, "y",
                                 "the mesh axis the finger bends along (x: the mesh is turned +90 deg about z)",
                                 choices=BENDING_DIRECTIONS),
    },
    "drum": {
        "drum_radius_m": _key("drum_radius_m", _DRUM["drum_radius_m"], "drum radius (the finger root's radius)"),
        "omega_rad_s": _key("omega_rad_s", _DRUM["omega_rad_s"], "drum speed"),
        "theta0_rad": _key("angle_rad", _DRUM["theta0_rad"],
                           "initial finger angle (default calibrated: alpha = 7.5 1/s first touches at 0.32 s; "
                           "recalibrate with ccedi contact --calibrate after changing the set-up)"),
        "object_center_m": _key("object_position_m", list(_DRUM["object_center_m"]),
                                "elliptical object centre [x, y] in the drum frame", True, 2, 2),
        "object_semi_axes_m": _key("object_semi_axis_m", list(_DRUM["object_semi_axes_m"]),
                                   "elliptical object semi-axes [a, b]", True, 2, 2),
        "friction": _key("friction", _DRUM["friction"], "Coulomb friction coefficient finger-object"),
        "contact_damping_ratio": _key("contact_damping_ratio", _DRUM["contact_damping_ratio"],
                                      "normal contact damping, fraction of each contact spring's critical damping"),
        "objects_per_revolution": Key(float, "-", 1.0, 360.0, _DRUM["objects_per_revolution"],
                                      "objects the finger meets per drum revolution: the next object arrives "
                                      "2 pi / (omega n) after the first contact (1.5 s at the paper's 20 rpm)"),
        "cycle_time_s": Key(float, "s", 1e-3, 1e3, None,
                            "time from one object's first contact to the next one's, instead of "
                            "objects_per_revolution"),
    },
    "damping": {
        "kind": Key(str, "-", None, None, "relative",
                    "mass-proportional damping of the design and its FEA re-check: relative (on the velocity "
                    "relative to the turning drum; a finger turned in air) or global (on the absolute velocity, "
                    "a drag on the whole finger: LS-DYNA's *DAMPING_GLOBAL, the paper's; the study's contact step "
                    "reproduces the paper with it)", choices=("relative", "global")),
    },
    "requirements": {
        "max_object_force_N": Key(float, "N", 0.0, 1e4, 25.0,
                                  "largest transducer-filtered (100 Hz) force on the object (0: no limit)"),
        "max_object_stress_Pa": Key(float, "Pa", 0.0, 1e12, 0.0, "largest object von Mises stress (0: no limit)"),
        "allowable_root_stress_Pa": Key(float, "Pa", 0.0, 1e12, 2.0e6,
                                        "largest finger (root) von Mises stress over the whole cycle: the rubber's "
                                        "fatigue limit over a safety factor (0: no limit)"),
        "max_recovery_deviation_mm": Key(float, "mm", 0.0, 1e4, 5.0,
                                         "the tip's distance from its running position when the next object "
                                         "arrives (0: no limit)"),
        "max_ringing_amplitude_mm": Key(float, "mm", 0.0, 1e4, 5.0,
                                        "residual oscillation amplitude of the tip after breakaway (0: no limit)"),
        "front_side_first": Key(bool, "-", None, None, True, "the first contact on the object's front half"),
        "min_patch_from_root_mm": Key(float, "mm", 0.0, 1e4, 10.0,
                                      "closest approach of the contact to the finger's root (0: no limit)"),
        "min_contact_impulse_N_s": Key(float, "N s", 0.0, 1e4, 2.0,
                                       "contact impulse the task needs, integral of the force (0: no limit)"),
        "objective": Key(str, "-", None, None, "object_force",
                         "what the design minimises among the designs that meet the requirements: the "
                         "transducer-filtered peak object force, the object stress, the root stress, the recovery "
                         "deviation, the ringing, or the throughput (the time between objects, with the drum speed "
                         "as a design variable)", choices=("object_force", "object_stress", "root_stress",
                                                           "recovery", "ringing", "throughput")),
    },
    "study": {
        "paper": Key(bool, "-", None, None, False,
                     "also reproduce the paper on its own finger: Table 1 (SM-A, SM-B, SM-C, DM), the steel rod "
                     "(Figs. 3, 4), SM-A against SM-B and the DM (Fig. 6), alpha_cr over lengths (Fig. 8), and the "
                     "contact sweep with the paper's global damping (ccedi study --paper; make demo)"),
        "impulse_alphas_per_s": _key("alpha_per_s", [70.0, 120.0, 160.0, 180.0, 200.0],
                                     "alphas of the impulse study (Fig. 7)", True),
        "table1_stiffness": Key(bool, "-", None, None, True,
                                "solve the nonlinear static tip stiffness of the finger and, with paper, of every Table 1 model "
                                "(SM-C: minutes)"),
        "detailed_model": Key(bool, "-", None, None, True,
                              "add the detailed model DM (2.8 mm, ~27 000 nodes) to Table 1 and Fig. 6 (minutes)"),
        "impulse_force_N": _key("force_N", 1.0, "tip impulse force"),
        "impulse_duration_s": _key("pulse_duration_s", 0.01, "tip impulse duration"),
        "impulse_t_end_s": Key(float, "s", 1e-3, 2.0, 0.2, "simulated time of the impulse runs"),
        "mesh_comparison_t_end_s": Key(float, "s", 1e-3, 2.0, 0.1,
                                       "simulated time of the SM-A / SM-B comparison (Fig. 6)"),
        "mesh_comparison_alpha_per_s": _key("alpha_per_s", 180.0, "alpha of the Fig. 6 comparison"),
        "identification_lengths_in": Key(float, "in", 1.0, 12.0, [3.0, 4.5, 6.0],
                                         "finger lengths whose alpha_cr is found by CCEDI (Fig. 8)", True, 2),
        "contact_alphas_per_s": _key("alpha_per_s", [7.5, 180.0, 600.0],
                                     "alphas of the drum contact sweep (Figs. 10, 13, 14)", True),
        "contact_t_end_s": Key(float, "s", 1e-3, 5.0, 1.5, "simulated time of each contact run"),
        "design_fea_check": Key(bool, "-", None, None, True, "re-check the recommended designs with the full FEA"),
        "measured_records": Key(str, "-", None, None, ["data/measured/tip_mass+quadratic_damping_high.csv",
                                                       "data/measured/control_fea_solid.csv"],
                                "measured impulse records to close the loop on (CSV with a JSON sidecar; relative to "
                                "this file)", True),
        "design_calibration_record": Key(str, "-", None, None, "data/contact/friction_low.csv",
                                         "measured record (impulse or contact, CSV with a JSON sidecar; relative to "
                                         "this file) whose calibrated inputs the design is re-run with, beside the "
                                         "declared model's design (empty: none)"),
        "calibration_fea_correction": Key(bool, "-", None, None, False,
                                          "correct the contact ROM by one full FE run at the calibration's "
                                          "baseline and check the result with another (~2 x 2 minutes)"),
        "scheduler": Key(str, "-", None, None, "local",
                         "serial, local (2-worker Dask cluster) or a Dask scheduler address with its port",
                         check=check_scheduler),
    },
}


def _shown(key):
    """A key of the file as a message shows it: as written when bare, else quoted and escaped."""
    return key if _BARE_KEY.fullmatch(key) else brief_repr(key)


def _hint(section, key):
    """`` (did you mean KEY? ...)`` naming the schema key of ``section`` closest to ``key``."""
    near = difflib.get_close_matches(key, SCHEMA[section], n=1, cutoff=0.6)
    return f" (did you mean {near[0]}? units are part of the key)" if near else ""


def check_value(section, key, value, *, name=None):
    """Check one value against :data:`SCHEMA` (the TOML file's rule, for any source).

    Parameters
    ----------
    section, key : str
        The schema entry.
    value : object
        The value to check.
    name : str, optional
        How the message names the value (default ``[section] key``); the message reads
        ``NAME = VALUE: must be ...``.

    Returns
    -------
    object
        The value, floats for float keys.

    Raises
    ------
    InputError
        Wrong type or out of range, in one line.
    """
    return _check(section, key, SCHEMA[section][key], value, name)


def _check(section, key, spec, value, name=None):
    name = name or f"[{section}] {key}"
    where = f"{name} = {brief_repr(value)}"
    if spec.is_list:
        if not isinstance(value, list) or not spec.min_items <= len(value) <= (spec.max_items or len(value)):
            unit = f" ({spec.unit})" if spec.unit != "-" else ""
            count = (f"exactly {spec.min_items}" if spec.max_items == spec.min_items
                     else f"at least {spec.min_items}")
            raise InputError(f"{where}: must be a list of {count} {spec.kind.__name__}{unit}")
        return [_check(section, key, Key(spec.kind, spec.unit, spec.lo, spec.hi, None, spec.help), v, name)
                for v in value]
    number = spec.kind is float and isinstance(value, (int, float)) and not isinstance(value, bool)
    if not (number or isinstance(value, spec.kind)) or (spec.kind is int and isinstance(value, bool)):
        raise InputError(f"{where}: must be {spec.kind.__name__}" + (f" ({spec.unit})" if spec.unit != "-" else ""))
    if spec.lo is not None:         # before float(): an integer too large for a float is out of range
        Quantity(spec.unit, spec.lo, spec.hi).check(value, name)
    if spec.choices and value not in spec.choices:
        raise InputError(f"{where}: must be one of {', '.join(spec.choices)}")
    if spec.check is not None:
        spec.check(value, name)
    return float(value) if number else value


def validate(data, source="config", base_dir=None):
    """Check the parsed TOML ``data`` against :data:`SCHEMA`; returns {section: {key: value}}
    with every default filled in, and every path (``[finger] mesh``, ``[study]
    measured_records`` and ``design_calibration_record``) made absolute by one rule:
    relative to ``base_dir`` (the TOML file's directory; default the working directory),
    a default relative to :data:`INSTALL_DIR`."""
    out = {section: {k: spec.default for k, spec in keys.items()} for section, keys in SCHEMA.items()}
    for section, entries in data.items():
        if section not in SCHEMA:
            raise InputError(f"{source}: unknown section [{_shown(section)}] (known: {', '.join(SCHEMA)})")
        if not isinstance(entries, dict):
            raise InputError(f"{source}: [{section}] must be a table of keys, got {brief_repr(entries)}")
        for key, value in entries.items():
            if key not in SCHEMA[section]:
                raise InputError(f"[{section}] {_shown(key)}: unknown key{_hint(section, key)}")
            out[section][key] = _check(section, key, SCHEMA[section][key], value)
    if out["finger"]["mesh"] is not None:
        out["finger"]["mesh"] = _mesh_path(out["finger"]["mesh"], base_dir)
    given = data.get("study", {})
    study = out["study"]
    for k, record in enumerate(study["measured_records"]):
        if not record.strip():
            raise InputError(f"[study] measured_records: entry {k + 1} is an empty path; give the CSV file of "
                             f"a measured record (relative to the TOML file's folder) or remove the entry")
    study["measured_records"] = [_record_path(r, base_dir if "measured_records" in given else INSTALL_DIR)
                                 for r in study["measured_records"]]
    if study["design_calibration_record"]:
        study["design_calibration_record"] = _record_path(
            study["design_calibration_record"], base_dir if "design_calibration_record" in given else INSTALL_DIR)
    finger_mesh(out)
    if out["finger"]["mesh"] is None:
        for key in ("impulse_length_in", "contact_length_in"):
            check_section_fits(out, out["finger"][key], f"[finger] {key}")
    elif out["finger"]["contact_taper_ratio"] != 1.0:
        raise InputError(f"[finger] contact_taper_ratio = {out['finger']['contact_taper_ratio']:g}: the finger is the "
                         "mesh of [finger] mesh, whose shape is its own; a taper is for the generated finger (leave "
                         "it 1)")
    drum_setup(out)             # the set-up as a whole: the object must clear the drum, ...
    return out


def check_section_fits(cfg, length_in, name):
    """Refuse a generated finger whose ``[finger] section_semi_axes_m`` is as long as the
    finger or longer (a finger is a cantilever longer than its section).

    Parameters
    ----------
    cfg : dict
        ``{section: {key: value}}`` as :func:`load` returns it.
    length_in : float
        The finger's length [in].
    name : str
        Where the length came from (``--length-in``, ``[finger] impulse_length_in``).

    Raises
    ------
    InputError
        Naming both inputs and their values.
    """
    axes = cfg["finger"]["section_semi_axes_m"]
    if max(axes) >= inch_to_m(length_in):
        raise InputError(f"[finger] section_semi_axes_m = [{axes[0]:g}, {axes[1]:g}] m is as long as the "
                         f"{1e3 * inch_to_m(length_in):.4g} mm finger of {name} = {length_in:g} in or longer: a "
                         "finger is a cantilever longer than its section (units? the right length?)")


def changed_keys(cfg):
    """The keys whose value in the validated inputs ``cfg`` is not their default.

    Parameters
    ----------
    cfg : dict
        ``{section: {key: value}}`` as :func:`load` returns it.

    Returns
    -------
    list of tuple
        ``(section, key)`` in :data:`SCHEMA` order.
    """
    defaults = validate({})
    return [(s, k) for s, keys in SCHEMA.items() for k in keys if cfg[s][k] != defaults[s][k]]


def finger_inputs(cfg):
    """(material, section semi-axes [m]) of the finger in the validated inputs ``cfg``."""
    m = cfg["material"]
    return NeoHookean(E=m["E_Pa"], nu=m["nu"], rho=m["rho_kg_m3"]), tuple(cfg["finger"]["section_semi_axes_m"])


INSTALL_DIR = Path(__file__).resolve().parents[1]
"""Where ccedi's bundled ``data/`` lies: the default records resolve against it, so the
defaults (and the TOML ``ccedi init`` writes) work from any working directory."""


def _record_path(value, base_dir):
    """A record path as an absolute path: relative ones against ``base_dir`` (the TOML
    file's directory, as ``[finger] mesh``; the working directory without a file; the
    install directory for a default). Whether it exists is checked when a step will read
    it (:func:`ccedi.study.run.run_study`)."""
    try:
        return str((Path(base_dir or ".") / value).resolve())
    except (OSError, ValueError):                   # a name too long, a NUL character
        return str(value)


def _mesh_path(value, base_dir):
    """``[finger] mesh`` as an absolute path to an existing file, relative to ``base_dir``."""
    base = Path(base_dir or ".").resolve()
    try:
        path = (base / value).resolve()
        exists = bool(value) and path.is_file()
    except (OSError, ValueError):                   # a name too long, a NUL character
        exists = False
    if not exists:
        raise InputError(f"[finger] mesh = {brief_repr(value)}: no such file (relative to {base})")
    return str(path)


def finger_mesh(cfg):
    """The imported finger of the validated inputs ``cfg``, or None for the generated one.

    Parameters
    ----------
    cfg : dict
        ``{section: {key: value}}`` as :func:`load` returns it.

    Returns
    -------
    ccedi.fea.mesh.readers.FingerMeshSpec or None
        Path (absolute), mesh unit, clamp, tip and bending direction of ``[finger] mesh``
        (its ``load()`` reads the :class:`ccedi.fea.mesh.Mesh`), or None when no mesh is set.

    Raises
    ------
    InputError
        ``[finger] clamp`` or ``tip`` is empty.
    """
    f = cfg["finger"]
    for key in ("clamp", "tip"):
        if not f[key].strip():
            raise InputError(f"[finger] {key} = {brief_repr(f[key])}: must be a set name or one of {', '.join(PLANES)}")
    if f["mesh"] is None:
        return None
    return FingerMeshSpec(f["mesh"], f["mesh_unit"], f["clamp"], f["tip"], f["bending_direction"])


def refuse_mesh(cfg, command, why):
    """Stop ``command`` in one line when ``[finger] mesh`` is set and it works only on the
    generated finger (it would otherwise drop the mesh without a word).

    Parameters
    ----------
    cfg : dict
        ``{section: {key: value}}`` as :func:`load` returns it.
    command : str
        The command, as the user typed it.
    why : str
        Why it needs the generated finger, and what to run instead.

    Raises
    ------
    InputError
        ``[finger] mesh`` is set.
    """
    if cfg["finger"]["mesh"] is not None:
        raise InputError(f"[finger] mesh = {brief_repr(cfg['finger']['mesh'])}: {command} {why}")


def configured_mesh(cfg):
    """The imported finger mesh of the validated inputs ``cfg``, read now (so that a bad
    mesh stops a command before any run), or None when ``[finger] mesh`` is not set.

    Parameters
    ----------
    cfg : dict
        ``{section: {key: value}}`` as :func:`load` returns it.

    Returns
    -------
    ccedi.fea.mesh.Mesh or None
        The finger with node sets ``root`` and ``tip``.

    Raises
    ------
    InputError
        The mesh cannot be read or is not a valid finger (:func:`ccedi.fea.mesh.readers.read_finger_mesh`).
    """
    spec = finger_mesh(cfg)
    return None if spec is None else spec.load()


def requirements(cfg):
    """The designer's requirements of the validated inputs ``cfg`` (``[requirements]``;
    a limit of 0 is none).

    Parameters
    ----------
    cfg : dict
        ``{section: {key: value}}`` as :func:`load` returns it.

    Returns
    -------
    ccedi.design.requirements.Requirements
    """
    from ccedi.design.requirements import Requirements  # the design library, only for the commands that design

    r = cfg["requirements"]

    def limit(key, factor=1.0):
        return r[key] * factor if r[key] > 0.0 else None

    return Requirements(max_object_force_N=limit("max_object_force_N"),
                        max_object_stress_Pa=limit("max_object_stress_Pa"),
                        allowable_root_stress_Pa=limit("allowable_root_stress_Pa"),
                        max_recovery_deviation_m=limit("max_recovery_deviation_mm", 1e-3),
                        max_ringing_amplitude_m=limit("max_ringing_amplitude_mm", 1e-3),
                        front_side_first=r["front_side_first"],
                        min_patch_from_root_m=limit("min_patch_from_root_mm", 1e-3),
                        min_contact_impulse_N_s=limit("min_contact_impulse_N_s"))


def drum_setup(cfg, finger=None):
    """The :class:`ccedi.fea.contact.drum.DrumSetup` of the validated inputs ``cfg``: the generated
    finger of ``[finger] contact_length_in`` and ``contact_taper_ratio``, or the mesh ``finger`` (e.g.
    :func:`configured_mesh`), whose own length then holds and ``contact_length_in`` is not
    used. An inconsistent set-up is an InputError naming the [drum] section."""
    material, semi_axes = finger_inputs(cfg)
    d = cfg["drum"]
    length_m = None if finger is not None else inch_to_m(cfg["finger"]["contact_length_in"])
    taper = 1.0 if finger is not None else cfg["finger"]["contact_taper_ratio"]
    try:
        return DrumSetup(drum_radius_m=d["drum_radius_m"], omega_rad_s=d["omega_rad_s"], theta0_rad=d["theta0_rad"],
                         object_center_m=tuple(d["object_center_m"]), object_semi_axes_m=tuple(d["object_semi_axes_m"]),
                         friction=d["friction"], contact_damping_ratio=d["contact_damping_ratio"],
                         objects_per_revolution=d["objects_per_revolution"], cycle_time_s=d["cycle_time_s"],
                         finger_length_m=length_m, finger_material=material,
                         finger_semi_axes_m=semi_axes, finger_taper_ratio=taper, finger=finger)
    except InputError as err:
        raise InputError(f"[drum]: {err}") from None


def load(path):
    """Read and validate a study TOML file (``None``: all defaults)."""
    if path is None:
        return validate({})
    try:
        data = tomllib.loads(Path(path).read_text(encoding="utf-8-sig"))
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{path}: is a directory; expected a TOML file") from None
    except PermissionError:
        raise InputError(f"{path}: not readable") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a text file; expected TOML") from None
    except RecursionError:
        raise InputError(f"{path}: not valid TOML (arrays or tables nested too deeply)") from None
    except ValueError as err:                       # TOMLDecodeError, or an integer of too many digits
        raise InputError(f"{path}: not valid TOML ({one_line(err)})") from None
    return validate(data, str(path), Path(path).parent)


def _toml_value(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):                      # a TOML basic string: JSON's escapes, and DEL's
        return json.dumps(value, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    return repr(value)


def to_toml(cfg):
    """The inputs ``cfg`` ({section: {key: value}}) as a TOML file, every key commented with
    its help, unit and allowed range."""
    lines = ["# ccedi inputs. Units are part of every key name (SI unless the key says in).",
             "# Run: ccedi study --config THIS_FILE (or any sub-command's --config). Unknown keys and",
             "# out-of-range values are errors."]
    for section, keys in SCHEMA.items():
        lines += ["", f"[{section}]"]
        for key, spec in keys.items():
            rng = f", {spec.lo:g}..{spec.hi:g}" if spec.lo is not None else ""
            unit = f" [{spec.unit}{rng}]" if spec.unit != "-" or rng else ""
            allowed = f" [{' or '.join(spec.choices)}]" if spec.choices else ""
            value = cfg[section][key]
            example = '"my_finger.msh"' if key == "mesh" else "VALUE"
            line = (f"{key} = {_toml_value(value)}" if value is not None
                    else f'# {key} = {example}   (not set; uncomment to set it)')
            lines += [f"# {spec.help}{unit}{allowed}", line]
    return "\n".join(lines) + "\n"


def calibrated_config(result, record):
    """The calibrated inputs of a ``ccedi calibrate`` result as a TOML fragment that every
    ``--config`` command reads: ``[material]`` E_Pa (declared E x the final E factor), nu,
    rho_kg_m3 (as declared) and alpha_per_s (the final alpha), ``[finger]``
    section_semi_axes_m (as declared) and the record's finger length as
    ``impulse_length_in`` (an impulse record) or ``contact_length_in`` (a contact record),
    so that the studies run the calibrated finger; for a contact record ``[drum]`` (the declared set-up
    with the calibrated friction, drum speed, initial angle and object centre); the effects
    found, an ambiguity and an unexplained residual as comments.

    Parameters
    ----------
    result : dict
        The calibration JSON (:func:`ccedi.calibrate.loop.summary`).
    record : ccedi.calibrate.experiment.Experiment
        The calibrated experiment (its declared finger).

    Returns
    -------
    str
        The TOML text, checked by :func:`validate` (so that it loads where it is written).

    Raises
    ------
    InputError
        A calibrated value outside the schema's range.
    """
    f = record.finger
    cal = result["calibrated"]
    lines = [f"# Calibrated by ccedi calibrate from {result['source']}: final NRMSE {result['final_nrmse']:.4%}, "
             f"noise floor {result['noise_floor_nrmse']:.4%}.",
             f"# Declared E {f.E_Pa:.6g} Pa; calibrated E factor {result['final_params']['E_factor']:.5f}."]
    for e in result["effects_found"]:
        lines.append(f"# effect found (not a study input): {e['name']} "
                     + ", ".join(f"{k} = {v:.5g}" for k, v in e["params_final"].items()))
    if result.get("ambiguous"):
        a = result["ambiguous"]
        lines.append(f"# ambiguous, not added: {' or '.join(a['effects'])}; separate them by "
                     f"{a['separating_measurement']['measurement']}")
    if result.get("unexplained_residual"):
        lines.append(f"# unexplained residual: {result['sparse_term']['force']}")
    cfg = {"material": {"E_Pa": cal["E_Pa"], "nu": f.nu, "rho_kg_m3": f.rho_kg_m3, "alpha_per_s": cal["alpha_per_s"]},
           "finger": {"section_semi_axes_m": list(f.semi_axes_m),
                      f"{record.kind}_length_in": round(m_to_inch(f.length_m), 6)}}
    if "drum" in cal:
        cfg["drum"] = dict(cal["drum"])
    for section, keys in cfg.items():
        lines += ["", f"[{section}]"] + [f"{k} = {_toml_value(v)}" for k, v in keys.items()]
    text = "\n".join(lines) + "\n"
    validate(tomllib.loads(text), "calibrated config")
    return text


def example():
    """A commented TOML file holding every key at its default."""
    return to_toml(validate({}))
