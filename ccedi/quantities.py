"""The allowed range of every physical input (the finger, its load, the sensor), whichever
way it comes (the study TOML, a command-line flag, a calibration sidecar, the Python API
through them): one table, one check, one message format,
``WHERE = VALUE: must be in LO..HI (UNIT)``."""
from dataclasses import dataclass

from ccedi.errors import InputError, brief_repr
from ccedi.units import INCH


@dataclass(frozen=True)
class Quantity:
    """A physical input: its unit and its allowed closed range.

    Parameters
    ----------
    unit : str
        Unit of ``lo`` and ``hi`` ("-" for a dimensionless number).
    lo, hi : float
        Smallest and largest allowed value, lo < hi.
    """

    unit: str
    lo: float
    hi: float

    def in_unit(self, factor, unit):
        """The same range in another unit.

        Parameters
        ----------
        factor : float
            Size of this quantity's unit in the new one (0.0254 from in to m).
        unit : str
            The new unit.

        Returns
        -------
        Quantity
        """
        return Quantity(unit, self.lo * factor, self.hi * factor)

    def check(self, value, where):
        """``float(value)`` when it is a finite number within the range.

        Parameters
        ----------
        value : object
            The value to check (a bool is not a number).
        where : str
            How the message names the value, e.g. ``"[material] nu"``.

        Returns
        -------
        float

        Raises
        ------
        InputError
            ``WHERE = VALUE: must be in LO..HI (UNIT)``, in one line (a long VALUE elided).
        """
        unit = f" ({self.unit})" if self.unit != "-" else ""
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not self.lo <= value <= self.hi:
            raise InputError(f"{where} = {brief_repr(value)}: must be in {self.lo:g}..{self.hi:g}{unit}")
        return float(value)


QUANTITIES = {
    "E_Pa": Quantity("Pa", 1e4, 1e12),
    "nu": Quantity("-", 0.0, 0.499),
    "rho_kg_m3": Quantity("kg/m^3", 1.0, 1e5),
    "length_in": Quantity("in", 1.0, 12.0),
    "section_semi_axis_m": Quantity("m", 1e-4, 0.1),
    "taper_ratio": Quantity("-", 0.2, 2.0),
    "E_tolerance": Quantity("-", 0.0, 0.9),
    "alpha_per_s": Quantity("1/s", 0.0, 1e4),
    "force_N": Quantity("N", 1e-4, 100.0),
    "pulse_duration_s": Quantity("s", 1e-4, 1.0),
    "pulse_start_s": Quantity("s", 0.0, 1e3),
    "noise_std_m": Quantity("m", 1e-9, 1e-2),
    "noise_std_N": Quantity("N", 1e-9, 1e3),
    "drum_radius_m": Quantity("m", 1e-3, 1.0),
    "omega_rad_s": Quantity("rad/s", 1e-3, 100.0),
    "angle_rad": Quantity("rad", -3.2, 3.2),
    "object_position_m": Quantity("m", -10.0, 10.0),
    "object_semi_axis_m": Quantity("m", 1e-3, 1.0),
    "friction": Quantity("-", 0.0, 2.0),
    "contact_damping_ratio": Quantity("-", 0.0, 0.2),
}
"""Finger material and geometry: Young's modulus, Poisson's ratio (neo-Hookean,
compressible), density, length, and each semi-axis of the elliptical section; the
relative tolerance of a declared E (E may lie in E (1 +- tolerance)); mass-proportional
damping; the tip load: force, how long it is held and when it starts; the standard
deviation of a displacement sensor's (and a force transducer's) white noise; and the drum test: drum radius and
speed, the finger's initial angle (and the object's rotation), each coordinate of the
object's centre (an object 10 m away takes no part), each semi-axis of the object, and
the Coulomb friction coefficient between finger and object, and the normal contact damping
as a fraction of critical (up to ccedi.fea.contact.penalty.MAX_DAMPING_RATIO, the explicit step's limit)."""

QUANTITIES["length_m"] = QUANTITIES["length_in"].in_unit(INCH, "m")
"""The finger length in metres: the same range as ``length_in``, for inputs given in SI."""

