"""Elastomer compounds for a finger: the catalogue (``data/compounds.csv``) and how a
compound's loss factor becomes ccedi's Rayleigh alpha.

The conversion. ccedi damps a finger by mass-proportional Rayleigh damping, C = alpha M,
so that mode i has the damping ratio zeta_i = alpha / (2 omega_i) (paper Eq. 3b with
beta = 0). A material of loss factor eta = tan delta, vibrating at resonance, dissipates
what a viscous damper of ratio zeta = tan delta / 2 does. Asking the finger's first mode,
the one an impulse rings and the one that decides whether it overshoots, for that ratio::

    alpha = 2 zeta_1 omega_1 = tan delta x omega_1          (alpha_from_loss_factor)
    tan delta = alpha / omega_1                             (loss_factor_from_alpha)

with omega_1 the finger's first natural frequency (undamped, rad/s), here the clamped SM-A
finger's (:func:`ccedi.rom.finger_identification.finger_omega1`). Since the paper's
alpha_cr is close to 2 omega_1 (3525 / 4.5^2 = 174 1/s against 2 omega_1 = 179 1/s for
the 4.5-in finger), this is its under-damped rule alpha = zeta alpha_cr.

Its limits. (1) It matches one mode: the higher modes get zeta_i = alpha / (2 omega_i),
less damping than a constant loss factor gives them. (2) A loss factor is a material's
at a temperature, a strain amplitude and in a frequency band (the catalogue's columns);
the finger's omega_1 may lie outside it. (3) Published loss factors of solid rubbers, about
0.05-0.5 at 10-100 Hz, give damping ratios of 0.025-0.25: on the paper's 4.5-in finger
(omega_1 = 89.4 rad/s) alpha = 4.5-45 1/s, far below the alpha_cr of about 174 1/s and
the 180 1/s the paper matched to the over-damped response it measured. A loss factor is
therefore a first guess. A catalogue row can carry instead the alpha CCEDI identified
from a measured impulse record of a sample finger of that compound (``alpha_per_s``,
``alpha_finger_length_in``, ``alpha_source``; ``ccedi calibrate RECORD --add-compound NAME``
writes it), with its tan delta converted back at that finger's first mode (band_min_hz =
band_max_hz = that mode's frequency). Such an alpha belongs to that finger: the paper's
fingers show no single loss factor (alpha 600 and 180 1/s at 3 and 4.5 in are tan delta
3.0 and 2.0 at their first modes, the 6 and 8-in fingers' zeta 0.17 and 0.15 are 0.34 and
0.30).

Catalogue file (CSV, a header row, one compound a row; units in the column names)::

    name                     unique, non-empty
    E_min_Pa, E_max_Pa       Young's modulus range [Pa]
    rho_kg_m3                density [kg/m^3]
    tan_delta_min, _max      loss factor range [-]
    band_min_hz, _max        frequency band the loss factor holds for [Hz]
    source                   where the values come from (non-empty)
    temperature_C            optional: temperature of the loss factor [deg C]
    notes                    optional
    alpha_per_s              optional: alpha identified by CCEDI [1/s]
    alpha_finger_length_in   with alpha_per_s: the finger it was identified on [in]
    alpha_source             with alpha_per_s: the record or publication
"""
import csv
import io
import math
from dataclasses import dataclass, fields
from pathlib import Path

from ccedi.errors import InputError, brief_repr, one_line
from ccedi.fea.material import NeoHookean
from ccedi.fea.mesh import SEMI_AXES
from ccedi.outputs import write_text
from ccedi.quantities import QUANTITIES, Quantity
from ccedi.rom.finger_identification import finger_omega1
from ccedi.units import m_to_inch

CATALOGUE = Path(__file__).resolve().parents[1] / "data" / "compounds.csv"
"""The bundled catalogue."""

LOSS_FACTOR = Quantity("-", 0.0, 10.0)
"""Allowed loss factor tan delta (the identified rows of over-damped fingers exceed 1)."""
BAND_HZ = Quantity("Hz", 1e-3, 1e6)
"""Allowed frequency band edges."""
TEMPERATURE_C = Quantity("deg C", -150.0, 300.0)
"""Allowed temperature."""

RANGES = {"E_min_Pa": QUANTITIES["E_Pa"], "E_max_Pa": QUANTITIES["E_Pa"], "rho_kg_m3": QUANTITIES["rho_kg_m3"],
          "tan_delta_min": LOSS_FACTOR, "tan_delta_max": LOSS_FACTOR, "band_min_hz": BAND_HZ,
          "band_max_hz": BAND_HZ, "temperature_C": TEMPERATURE_C, "alpha_per_s": QUANTITIES["alpha_per_s"],
          "alpha_finger_length_in": QUANTITIES["length_in"]}
"""Numeric columns and their allowed ranges."""
REQUIRED = ("name", "E_min_Pa", "E_max_Pa", "rho_kg_m3", "tan_delta_min", "tan_delta_max", "band_min_hz",
            "band_max_hz", "source")
"""Columns every catalogue has."""
OPTIONAL = ("temperature_C", "notes", "alpha_per_s", "alpha_finger_length_in", "alpha_source")
"""Columns a catalogue may have (an empty cell: not given)."""
PAIRS = (("E_min_Pa", "E_max_Pa"), ("tan_delta_min", "tan_delta_max"), ("band_min_hz", "band_max_hz"))
"""(min, max) columns: min <= max."""


@dataclass(frozen=True)
class Compound:
    """One catalogue row (module docstring).

    Parameters
    ----------
    name : str
        Compound name, unique in its catalogue.
    E_min_Pa, E_max_Pa : float
        Young's modulus range [Pa].
    rho_kg_m3 : float
        Density [kg/m^3].
    tan_delta_min, tan_delta_max : float
        Loss factor range [-].
    band_min_hz, band_max_hz : float
        Frequency band the loss factor holds for [Hz].
    source : str
        Where the values come from.
    temperature_C : float or None, optional
        Temperature of the loss factor [deg C].
    notes : str, optional
        Free text.
    alpha_per_s : float or None, optional
        Mass-proportional damping identified by CCEDI on a finger of this compound [1/s].
    alpha_finger_length_in : float or None, optional
        Length of that finger [in].
    alpha_source : str, optional
        The record or publication ``alpha_per_s`` was identified from.
    """

    name: str
    E_min_Pa: float
    E_max_Pa: float
    rho_kg_m3: float
    tan_delta_min: float
    tan_delta_max: float
    band_min_hz: float
    band_max_hz: float
    source: str
    temperature_C: float | None = None
    notes: str = ""
    alpha_per_s: float | None = None
    alpha_finger_length_in: float | None = None
    alpha_source: str = ""

    @property
    def E_nominal_Pa(self):
        """Nominal Young's modulus, the middle of its range [Pa]."""
        return 0.5 * (self.E_min_Pa + self.E_max_Pa)

    @property
    def tan_delta_nominal(self):
        """Nominal loss factor, the middle of its range [-]: for a row identified by CCEDI
        (:func:`identified_compound`) the identified alpha over its finger's first mode."""
        return 0.5 * (self.tan_delta_min + self.tan_delta_max)


COLUMNS = tuple(f.name for f in fields(Compound))
"""Column order of a written catalogue."""


def alpha_from_loss_factor(tan_delta, omega_1_rad_s):
    """Mass-proportional alpha giving the first mode the damping ratio tan delta / 2.

    zeta_1 = alpha / (2 omega_1) and zeta = tan delta / 2 at resonance give
    alpha = tan delta x omega_1 (module docstring; a first guess, see its limits).

    Parameters
    ----------
    tan_delta : float or numpy.ndarray
        Loss factor [-].
    omega_1_rad_s : float or numpy.ndarray
        The finger's first natural frequency [rad/s].

    Returns
    -------
    float or numpy.ndarray
        alpha [1/s].
    """
    return tan_delta * omega_1_rad_s


def loss_factor_from_alpha(alpha_per_s, omega_1_rad_s):
    """The loss factor tan delta = alpha / omega_1 that mass-proportional ``alpha_per_s``
    gives the first mode (the inverse of :func:`alpha_from_loss_factor`).

    Parameters
    ----------
    alpha_per_s : float or numpy.ndarray
        Mass-proportional damping alpha [1/s].
    omega_1_rad_s : float or numpy.ndarray
        The finger's first natural frequency [rad/s].

    Returns
    -------
    float or numpy.ndarray
        tan delta = 2 zeta_1 [-].
    """
    return alpha_per_s / omega_1_rad_s


@dataclass(frozen=True)
class FingerDamping:
    """What a compound's loss factor gives one finger (:func:`finger_damping`).

    Parameters
    ----------
    compound : Compound
        The compound.
    length_in : float
        Finger length [in].
    omega_1_rad_s : tuple of float
        First natural frequency at E_min and at E_max [rad/s].
    alpha_per_s : tuple of float
        (tan_delta_min omega_1(E_min), tan_delta_max omega_1(E_max)) [1/s].
    zeta_1 : tuple of float
        First-mode damping ratio range (tan_delta_min / 2, tan_delta_max / 2) [-].
    in_band : bool
        Whether the first-mode frequencies lie within the compound's band.
    """

    compound: Compound
    length_in: float
    omega_1_rad_s: tuple
    alpha_per_s: tuple
    zeta_1: tuple
    in_band: bool

    @property
    def frequency_hz(self):
        """First-mode frequency range (at E_min, E_max) [Hz]."""
        return tuple(w / (2.0 * math.pi) for w in self.omega_1_rad_s)


def finger_damping(compound: Compound, length_in, *, semi_axes_m=SEMI_AXES, nu=0.49):
    """The alpha range a compound's loss factor gives the clamped SM-A finger of
    ``length_in`` (:func:`alpha_from_loss_factor` at its first mode).

    omega_1 is the FE finger's (:func:`ccedi.rom.finger_identification.finger_omega1`) at
    E_min; at E_max it is that times sqrt(E_max / E_min) (the linearised stiffness is
    proportional to E). The lower alpha pairs the lower loss factor with the softer
    compound, the upper the higher with the stiffer.

    Parameters
    ----------
    compound : Compound
        The compound (E range, density, loss factor range).
    length_in : float
        Finger length [in].
    semi_axes_m : tuple of float, optional
        Section semi-axes (a, b) [m], b along the bending direction. Default: the paper's.
    nu : float, optional
        Poisson's ratio [-]. Default 0.49.

    Returns
    -------
    FingerDamping
        omega_1, alpha and zeta_1 ranges, and whether omega_1 lies in the compound's band.

    Raises
    ------
    InputError
        A length, section or Poisson's ratio outside :data:`ccedi.quantities.QUANTITIES`.
    """
    length_in = QUANTITIES["length_in"].check(length_in, "length_in")
    nu = QUANTITIES["nu"].check(nu, "nu")
    w_lo = finger_omega1(length_in, material=NeoHookean(E=compound.E_min_Pa, nu=nu, rho=compound.rho_kg_m3),
                         semi_axes_m=tuple(semi_axes_m))
    w_hi = w_lo * math.sqrt(compound.E_max_Pa / compound.E_min_Pa)
    alpha = (alpha_from_loss_factor(compound.tan_delta_min, w_lo), alpha_from_loss_factor(compound.tan_delta_max, w_hi))
    in_band = all(compound.band_min_hz <= w / (2.0 * math.pi) <= compound.band_max_hz for w in (w_lo, w_hi))
    return FingerDamping(compound=compound, length_in=length_in, omega_1_rad_s=(w_lo, w_hi), alpha_per_s=alpha,
                         zeta_1=(compound.tan_delta_min / 2.0, compound.tan_delta_max / 2.0), in_band=in_band)


def identified_compound(name, *, alpha_per_s, E_Pa, rho_kg_m3, length_m, semi_axes_m, nu, source,
                        alpha_stderr_per_s=0.0, E_stderr_Pa=0.0):
    """A catalogue row from a CCEDI identification on a sample finger of the compound.

    E and tan delta are given as +-2 standard errors about the identified values; tan delta
    is alpha over the finger's first mode at the identified E (:func:`loss_factor_from_alpha`),
    and the band is that mode's frequency.

    Parameters
    ----------
    name : str
        Compound name.
    alpha_per_s : float
        Identified alpha [1/s].
    E_Pa : float
        Identified Young's modulus [Pa].
    rho_kg_m3 : float
        Density of the sample finger [kg/m^3].
    length_m : float
        Sample finger length [m].
    semi_axes_m : tuple of float
        Its section semi-axes (a, b) [m].
    nu : float
        Its Poisson's ratio [-].
    source : str
        The record alpha was identified from (``alpha_source``).
    alpha_stderr_per_s : float, optional
        Standard error of alpha [1/s]. Default 0.
    E_stderr_Pa : float, optional
        Standard error of E [Pa]. Default 0.

    Returns
    -------
    Compound
        The row (validated as :func:`load_compounds` validates a read one).

    Raises
    ------
    InputError
        An empty name, or a value outside its column's range.
    """
    length_in = m_to_inch(length_m)
    omega_1 = finger_omega1(length_in, material=NeoHookean(E=E_Pa, nu=nu, rho=rho_kg_m3),
                            semi_axes_m=tuple(semi_axes_m))
    tan_delta = [loss_factor_from_alpha(max(alpha_per_s + k * alpha_stderr_per_s, 0.0), omega_1) for k in (-2, 2)]
    f1 = omega_1 / (2.0 * math.pi)
    row = Compound(name=name, E_min_Pa=E_Pa - 2.0 * E_stderr_Pa, E_max_Pa=E_Pa + 2.0 * E_stderr_Pa,
                   rho_kg_m3=rho_kg_m3, tan_delta_min=tan_delta[0], tan_delta_max=tan_delta[1], band_min_hz=f1,
                   band_max_hz=f1, source=f"CCEDI calibration (ccedi calibrate) of {source}",
                   notes=f"identified on the record's {length_in:.4g}-in finger: alpha = {alpha_per_s:.5g} +- "
                         f"{alpha_stderr_per_s:.2g} 1/s, E = {E_Pa:.5g} +- {E_stderr_Pa:.2g} Pa",
                   alpha_per_s=alpha_per_s, alpha_finger_length_in=length_in, alpha_source=str(source))
    return _checked(row, "identified compound")


def _checked(row: Compound, where):
    """``row`` with every value in its column's range, min <= max and a name and source;
    InputError naming ``where`` and the column otherwise."""
    if not row.name.strip():
        raise InputError(f"{where}: column name is empty; every compound needs a name")
    at = f"{where} ({row.name})"
    if not row.source.strip():
        raise InputError(f"{at}: column source is empty; every compound cites where its values come from")
    for column, quantity in RANGES.items():
        value = getattr(row, column)
        if value is not None:
            quantity.check(value, f"{at}: {column}")
    for lo, hi in PAIRS:
        if getattr(row, lo) > getattr(row, hi):
            raise InputError(f"{at}: {lo} = {getattr(row, lo):g} is above {hi} = {getattr(row, hi):g}")
    if (row.alpha_per_s is None) != (row.alpha_finger_length_in is None):
        raise InputError(f"{at}: alpha_per_s and alpha_finger_length_in are given together or not at all")
    return row


def _number(cell, where):
    """``float(cell)``, None for an empty cell; InputError naming ``where`` otherwise."""
    if not cell.strip():
        return None
    try:
        value = float(cell)
    except ValueError:
        raise InputError(f"{where} = {brief_repr(cell)}: expected a number") from None
    if not math.isfinite(value):
        raise InputError(f"{where} = {brief_repr(cell)}: expected a finite number")
    return value


def load_compounds(path=None):
    """Read and validate a compound catalogue (format in the module docstring).

    Parameters
    ----------
    path : str or pathlib.Path, optional
        The CSV file. Default: the bundled catalogue :data:`CATALOGUE`.

    Returns
    -------
    dict
        {name: :class:`Compound`}, in file order.

    Raises
    ------
    InputError
        The file is missing or not a readable CSV, lacks a required column, names a column
        twice or one it does not know, or a row has a wrong number of fields, an empty
        required cell, a non-numeric or out-of-range value, a min above its max, an alpha
        without its finger length, or a name already used; the message names the file,
        the line, the compound and the value.
    """
    path = CATALOGUE if path is None else Path(path)
    if not path.is_file():
        raise InputError(f"compound catalogue not found: {path}")
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            reader = csv.reader(fh, strict=True)
            header = next(reader, None)
            rows = [(reader.line_num, row) for row in reader if any(cell.strip() for cell in row)]
    except (csv.Error, UnicodeDecodeError) as err:
        raise InputError(f"{path}: not a readable CSV ({one_line(err)})") from None
    if not header:
        raise InputError(f"{path}: no header row; expected the columns {', '.join(REQUIRED)}")
    header = [c.strip() for c in header]
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise InputError(f"{path}: missing column(s) {', '.join(missing)}; need {', '.join(REQUIRED)} (and "
                         f"optionally {', '.join(OPTIONAL)}), found {brief_repr(header)}")
    unknown = [c for c in header if c not in COLUMNS]
    if unknown:
        raise InputError(f"{path}: unknown column {brief_repr(unknown[0])}; the columns are {', '.join(COLUMNS)}")
    twice = [c for c in header if header.count(c) > 1]
    if twice:
        raise InputError(f"{path}: column {twice[0]} is there {header.count(twice[0])} times; expected once")
    compounds = {}
    for line, row in rows:
        if len(row) != len(header):
            raise InputError(f"{path}: line {line} has {len(row)} fields; the header has {len(header)}")
        cells = dict(zip(header, row))
        name = cells["name"].strip()
        at = f"{path}: line {line} ({name or 'no name'})"
        values = {}
        for column in COLUMNS:
            cell = cells.get(column, "")
            if column in RANGES:
                values[column] = _number(cell, f"{at}: {column}")
                if values[column] is None and column in REQUIRED:
                    raise InputError(f"{at}: column {column} is empty; expected a number")
            else:
                values[column] = cell.strip()
        compound = _checked(Compound(**values), f"{path}: line {line}")
        if compound.name in compounds:
            raise InputError(f"{at}: compound {compound.name!r} is already on an earlier line; names are unique")
        compounds[compound.name] = compound
    return compounds


def catalogue_text(compounds):
    """The CSV text of a catalogue (every column of :data:`COLUMNS`; None an empty cell).

    Parameters
    ----------
    compounds : iterable of Compound
        The rows, in order.

    Returns
    -------
    str
        Header and rows.
    """
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(COLUMNS)
    for c in compounds:
        writer.writerow(["" if getattr(c, k) is None else (repr(getattr(c, k)) if isinstance(getattr(c, k), float)
                                                            else getattr(c, k)) for k in COLUMNS])
    return out.getvalue()


def save_compound(path, compound: Compound):
    """Add ``compound`` to the catalogue at ``path``, replacing a row of the same name
    (a new file when there is none), atomically.

    Parameters
    ----------
    path : str or pathlib.Path
        The catalogue CSV.
    compound : Compound
        The row.

    Returns
    -------
    bool
        True when a row of that name was replaced, False when the row was added.

    Raises
    ------
    InputError
        An existing file at ``path`` is not a valid catalogue (:func:`load_compounds`).
    """
    rows = load_compounds(path) if Path(path).exists() else {}
    replaced = compound.name in rows
    rows[compound.name] = compound
    write_text(path, catalogue_text(rows.values()))
    return replaced
