"""The designer's requirements: limits on the outputs of a run (:mod:`ccedi.design.outputs`).

A requirement is a :class:`Limit` on one output, ``output <= bound`` (upper) or
``output >= bound`` (lower), in the output's SI unit. Its margin is relative to a scale
(the bound's size unless given):

    m = (bound - value) / scale   (upper),      m = (value - bound) / scale   (lower),

met when m >= 0; the optimiser works on margins, so that requirements in newtons,
pascals and millimetres weigh alike. :class:`Requirements` holds the designer's
requirements with their documented defaults, chosen from the paper's set-up (the 8-in
rubber finger on the 20 rpm drum, Table 2):

========================  ======================  =========================================
requirement               default                 why
========================  ======================  =========================================
object force              <= 25 N                 the paper's finger puts 15-20 N on its
                                                  object; 25 N leaves the force objective
                                                  room and stops a stiff, damped finger
object stress             none                    set it for a fragile object
root stress (whole cycle) <= 2.0 MPa              the paper's finger reaches 1.7-1.9 MPa at
                                                  its root; set your rubber's fatigue limit
                                                  over your safety factor
recovery at next arrival  <= 5 mm                 the finger back in shape (within a fifth
                                                  of its 24 mm width) when the next object
                                                  comes, one cycle after the first contact
ringing after breakaway   <= 5 mm                 a finger that whips after release startles
                                                  live birds (the paper's section 3.4)
first contact             on the front side       a drag-bent finger first touches the rear
contact patch from root   >= 10 mm                the object kept off the drum
contact impulse           >= 2 N s                the sweep must push the object; the
                                                  paper's finger gives 6-16 N s
========================  ======================  =========================================

Any limit can be switched off (None). User-defined outputs get their limits as extra
:class:`Limit` objects (``Requirements(extra=(Limit(...),))``).
"""
from dataclasses import dataclass, field, fields

import numpy as np

from ccedi.errors import InputError, require_finite_positive


@dataclass(frozen=True)
class Limit:
    """One requirement: ``output <= bound`` (``upper``) or ``output >= bound``.

    Parameters
    ----------
    output : str
        The output's name (:data:`ccedi.design.outputs.OUTPUTS` or a user-defined one).
    bound : float
        The limit, in the output's SI unit.
    upper : bool, optional
        True: the output must not exceed ``bound``; False: not fall below it.
    label : str, optional
        What the requirement is, for the report (default: the output's name).
    unit : str, optional
        How the report shows the bound: ``"N"``, ``"MPa"``, ``"mm"``, ... (default SI).
    scale : float, optional
        Normalisation of the margin, in the output's unit (default: |bound|).
    offset : float, optional
        A correction the surrogate's value must meet the requirement with: the margin is
        taken against ``bound + offset`` (:attr:`target`), e.g. the surrogate's error at the
        optimum against its own model (:func:`ccedi.design.recheck.verified_optimum`); the
        requirement as stated (:meth:`describe`) keeps ``bound``.

    Raises
    ------
    InputError
        A non-finite bound, or a zero bound without a scale.
    """

    output: str
    bound: float
    upper: bool = True
    label: str = ""
    unit: str = ""
    scale: float | None = None
    offset: float = 0.0

    def __post_init__(self):
        if not np.isfinite(self.bound):
            raise InputError(f"requirement on {self.output}: bound must be a finite number, got {self.bound!r}")
        if self.scale is None and self.bound == 0.0:
            raise InputError(f"requirement on {self.output}: a zero bound needs a scale")
        if self.scale is not None:
            require_finite_positive(f"requirement on {self.output}: scale", self.scale)

    @property
    def target(self):
        """The bound the margin is taken against, ``bound + offset``."""
        return self.bound + self.offset

    @property
    def norm(self):
        """The margin's scale, in the output's unit."""
        return float(self.scale if self.scale is not None else abs(self.bound))

    def margin(self, value, bound=None):
        """Normalised margin, >= 0 when met (numpy or casadi).

        Parameters
        ----------
        value : float, numpy.ndarray or casadi expression
            The output's value.
        bound : float, optional
            Another bound than :attr:`target` (e.g. tightened by a model-error margin).

        Returns
        -------
        Same type as ``value``.
        """
        b = self.target if bound is None else bound
        return ((b - value) if self.upper else (value - b)) / self.norm

    def describe(self):
        """The requirement in words, its bound in the limit's display unit.

        Returns
        -------
        str
            e.g. ``"object force (transducer) <= 25 N"``.
        """
        sign = "<=" if self.upper else ">="
        return f"{self.label or self.output} {sign} {self.shown(self.bound)}"

    def shown(self, value):
        """``value`` (the output's SI unit) in the limit's display unit.

        Parameters
        ----------
        value : float

        Returns
        -------
        str
            e.g. ``"25 N"``, ``"4.2 mm"``.
        """
        return f"{value / DISPLAY_UNITS.get(self.unit, 1.0):.4g} {self.unit}".rstrip()


DISPLAY_UNITS = {"mm": 1e-3, "MPa": 1e6, "kPa": 1e3, "N": 1.0, "N s": 1.0, "m": 1.0, "Pa": 1.0, "s": 1.0}
"""Display unit -> its size in SI."""


@dataclass(frozen=True)
class Requirements:
    """The designer's requirements (SI units; None switches one off). Defaults: the
    module docstring's table.

    Parameters
    ----------
    max_object_force_N : float or None
        Transducer-filtered peak force on the object [N].
    max_object_stress_Pa : float or None
        Peak object von Mises stress [Pa].
    allowable_root_stress_Pa : float or None
        Peak finger (root) von Mises stress over the whole cycle [Pa].
    max_recovery_deviation_m : float or None
        Tip's distance from its running position at the next arrival [m].
    max_ringing_amplitude_m : float or None
        Residual oscillation amplitude after breakaway [m].
    front_side_first : bool
        First contact on the object's front half.
    min_patch_from_root_m : float or None
        Closest approach of the contact to the finger's root [m].
    min_contact_impulse_N_s : float or None
        Contact impulse the task needs [N s].
    extra : tuple of Limit
        User-defined requirements (on any output, user-defined ones included).

    Raises
    ------
    InputError
        A limit that is not a finite positive number, or an ``extra`` that is not a Limit.
    """

    max_object_force_N: float | None = 25.0
    max_object_stress_Pa: float | None = None
    allowable_root_stress_Pa: float | None = 2.0e6
    max_recovery_deviation_m: float | None = 0.005
    max_ringing_amplitude_m: float | None = 0.005
    front_side_first: bool = True
    min_patch_from_root_m: float | None = 0.010
    min_contact_impulse_N_s: float | None = 2.0
    extra: tuple = field(default=())

    def __post_init__(self):
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in ("extra", "front_side_first") or value is None:
                continue
            require_finite_positive(f"requirement {f.name}", value)
        if not isinstance(self.front_side_first, bool):
            raise InputError(f"requirement front_side_first must be true or false, got {self.front_side_first!r}")
        if not all(isinstance(e, Limit) for e in self.extra):
            raise InputError("requirement extra must be a tuple of ccedi.design.requirements.Limit")

    @classmethod
    def from_limits(cls, limits):
        """Requirements made of ``limits`` alone (every named requirement off).

        Parameters
        ----------
        limits : sequence of Limit

        Returns
        -------
        Requirements
        """
        return cls(max_object_force_N=None, allowable_root_stress_Pa=None, max_recovery_deviation_m=None,
                   max_ringing_amplitude_m=None, front_side_first=False, min_patch_from_root_m=None,
                   min_contact_impulse_N_s=None, extra=tuple(limits))

    def limits(self):
        """The requirements as :class:`Limit` objects (those switched on, then ``extra``).

        Returns
        -------
        list of Limit
        """
        spec = (("max_object_force_N", "sensor_peak_force_N", True, "object force (transducer)", "N"),
                ("max_object_stress_Pa", "max_object_stress_Pa", True, "object stress", "MPa"),
                ("allowable_root_stress_Pa", "max_finger_stress_Pa", True, "root stress over the cycle", "MPa"),
                ("max_recovery_deviation_m", "recovery_deviation_m", True, "recovery at the next arrival", "mm"),
                ("max_ringing_amplitude_m", "ringing_amplitude_m", True, "ringing after breakaway", "mm"),
                ("min_patch_from_root_m", "contact_patch_from_root_m", False, "contact patch from the root", "mm"),
                ("min_contact_impulse_N_s", "contact_impulse_N_s", False, "contact impulse", "N s"))
        out = [Limit(output, getattr(self, name), upper, label, unit)
               for name, output, upper, label, unit in spec if getattr(self, name) is not None]
        if self.front_side_first:
            out.append(Limit("first_contact_front_m", 0.0, upper=False, label="first contact on the front side",
                             unit="mm", scale=0.01))
        return out + list(self.extra)


def met(limits, outputs):
    """{limit description: (value, margin, met)} of ``outputs`` against each requirement
    as stated (its ``bound``, no offset); a missing output, e.g. the contact side of a run
    without contact, is not met.

    Parameters
    ----------
    limits : sequence of Limit
    outputs : dict
        Output values by name.

    Returns
    -------
    dict
    """
    out = {}
    for lim in limits:
        value = outputs.get(lim.output)
        m = None if value is None else float(lim.margin(value, lim.bound))
        out[lim.describe()] = (value, m, m is not None and m >= 0.0)
    return out
