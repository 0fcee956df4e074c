"""The drum speed a chosen finger allows: the throughput a designer is paid for.

A compound's design (:func:`ccedi.design.catalogue_design.design_compounds`) fixes the
finger: its compound (E, rho), its length L (and, when designed, its section's
semi-thickness b) and its damping alpha = tan delta x omega_1(L). The drum speed is then a question about that finger alone: the faster the drum,
the shorter the time until the next object arrives (the cycle time, one revolution over
the objects per revolution) and the less the finger has recovered by then. The contact
ROM of the finger at its own material and length runs at ``n`` drum speeds over
``speed_bounds_rpm`` (one model build, moved onto each drum speed); every requirement's
margin at each speed carries the design's model-error tightening
(:meth:`ccedi.design.optimise.DesignProblem.constraint_margins`). The fastest drum is the
highest speed below which every requirement holds at every run speed, refined by linear
interpolation of the worst margin to its zero between that speed and the next; the
requirement that fails there binds.

Inside the compound ranking (:func:`with_drum_speeds`) every compound whose design meets the
requirements carries its fastest drum (``n`` ROM runs and one model build each), and the
ranking may order those compounds by it, fastest first (``rank_by="fastest_drum"``): the
throughput of the finger each compound's own design (its length at the least objective)
gives. That is not a throughput optimum over the length as well, which would need the drum
speed as a variable of the catalogue surrogate (one more axis of ROM runs); so
``--objective throughput`` stays refused for the compound design and ``--rank-by
fastest_drum`` asks for this ranking instead.

The answer is the ROM's; the full FEA re-check of the finger at that speed is the design's
usual check (:func:`ccedi.design.recheck.fea_check` with the drum speed as the variable).
"""
from dataclasses import dataclass, replace

import numpy as np

from ccedi.errors import InputError
from ccedi.units import RPM, m_to_inch

from .catalogue_design import CatalogueDesign, CompoundDesign, compound_setup
from .outputs import setup_for_length
from .surrogate import DRUM_SPEED_BOUNDS_RPM, run_rom, speed_space

N_SPEEDS = 9
"""Drum speeds the ROM runs at."""

RANK_BY = ("objective", "fastest_drum")
"""What orders the compounds that meet the requirements (:func:`with_drum_speeds`)."""


@dataclass(frozen=True)
class DrumSpeedCheck:
    """The fastest drum a finger allows (:func:`fastest_drum_speed`).

    Parameters
    ----------
    compound : str
        The compound's name.
    length_m : float
        The finger length [m].
    alpha_per_s : float
        Its damping [1/s].
    speeds_rpm : list of float
        The drum speeds run [rpm].
    worst_margin : list of float
        The smallest normalised requirement margin at each speed.
    limiting : list of str
        The requirement of that margin at each speed.
    fastest_rpm : float or None
        The fastest drum speed meeting every requirement [rpm] (None: not even the
        slowest; the highest speed run when every speed run meets them).
    cycle_time_s : float or None
        The time between objects at ``fastest_rpm`` [s].
    binding : str
        The requirement that stops a faster drum ("" when the fastest speed run holds).
    """

    compound: str
    length_m: float
    alpha_per_s: float
    speeds_rpm: list
    worst_margin: list
    limiting: list
    fastest_rpm: float | None
    cycle_time_s: float | None
    binding: str

    def as_dict(self):
        """JSON form.

        Returns
        -------
        dict
        """
        return {"compound": self.compound, "length_m": self.length_m, "alpha_per_s": self.alpha_per_s,
                "speeds_rpm": self.speeds_rpm, "worst_margin": self.worst_margin, "limiting": self.limiting,
                "fastest_rpm": self.fastest_rpm, "cycle_time_s": self.cycle_time_s, "binding": self.binding}


def fastest_drum_speed(design: CompoundDesign, setup, *, length_m=None, speed_bounds_rpm=DRUM_SPEED_BOUNDS_RPM,
                       n=N_SPEEDS, damping="relative", progress=None):
    """The fastest drum speed at which a compound's finger meets every requirement (module
    docstring).

    Parameters
    ----------
    design : CompoundDesign
        The compound's design (its compound, alpha tie and requirements).
    setup : ccedi.fea.contact.drum.DrumSetup
        The drum test (its objects per revolution; the compound's E and rho replace its
        finger material).
    length_m : float, optional
        The finger length [m] (default: the design's optimum; e.g. a robust length).
    speed_bounds_rpm : tuple of float, optional
        (lo, hi) drum speeds [rpm], 0 < lo < hi <= 120 (default
        :data:`ccedi.design.surrogate.DRUM_SPEED_BOUNDS_RPM`).
    n : int, optional
        Speeds run, >= 3.
    damping : {"relative", "global"}, optional
        Damping kind of the runs.
    progress : callable, optional
        ``progress(done, total)`` after every run.

    Returns
    -------
    DrumSpeedCheck

    Raises
    ------
    InputError
        Speed bounds outside 0 < lo < hi <= 120 rpm, or fewer than 3 speeds.
    """
    lo, hi = (float(v) for v in speed_bounds_rpm)
    if not 0.0 < lo < hi <= 120.0:
        raise InputError(f"drum speed bounds {lo!r}-{hi!r} rpm: must be 0 < lo < hi <= 120")
    if int(n) < 3:
        raise InputError(f"drum speeds run = {n!r}: at least 3 needed")
    c = design.compound
    L = float(design.design.x if length_m is None else length_m)
    alpha = float(design.tie(m_to_inch(L)))
    own = setup_for_length(compound_setup(setup, c, design.semi_thickness_m), L)
    speeds = np.linspace(lo, hi, int(n))
    runs = run_rom(own, [(alpha, w * RPM) for w in speeds], damping=damping, progress=progress,
                   variables=speed_space((alpha * 0.5, alpha * 2.0), (lo, hi)))
    outputs = {k: runs[k].to_numpy() for k in runs.columns}
    margins = design.problem.constraint_margins(outputs, np.full(len(speeds), alpha), np.full(len(speeds), L))
    names = list(margins)
    table = np.array([np.asarray(margins[k], dtype=float) for k in names])
    table = np.where(np.isnan(table), -np.inf, table)
    worst = table.min(axis=0)
    limiting = [names[int(k)] for k in table.argmin(axis=0)]
    ok = worst >= 0.0
    if not ok[0]:
        return DrumSpeedCheck(c.name, L, alpha, speeds.tolist(), worst.tolist(), limiting, None, None, limiting[0])
    if ok.all():
        fastest, binding = float(speeds[-1]), ""
    else:
        k = int(np.argmin(ok))                       # the first speed that misses a requirement
        a, b = worst[k - 1], worst[k]
        fastest = float(speeds[k - 1] + (speeds[k] - speeds[k - 1]) * a / (a - b)) if np.isfinite(b) else \
            float(speeds[k - 1])
        binding = limiting[k]
    cycle = replace(own, omega_rad_s=fastest * RPM).cycle_s
    return DrumSpeedCheck(c.name, L, alpha, speeds.tolist(), worst.tolist(), limiting, fastest, cycle, binding)


def with_drum_speeds(ranking: CatalogueDesign, setup, *, speed_bounds_rpm=DRUM_SPEED_BOUNDS_RPM, n=N_SPEEDS,
                     damping="relative", rank_by="objective", progress=None):
    """The ranking with every feasible compound's fastest drum (:func:`fastest_drum_speed` at
    its design's length), ordered by the objective as before or, with ``rank_by`` =
    "fastest_drum", the feasible compounds by their fastest drum, fastest first (ties, such
    as two fingers that hold up to the fastest speed run, and those that miss even the
    slowest, by the objective), the others after them as before (module docstring).

    Parameters
    ----------
    ranking : CatalogueDesign
        The compounds ranked (:func:`ccedi.design.catalogue_design.design_compounds`).
    setup : ccedi.fea.contact.drum.DrumSetup
        The drum test the ranking was made on.
    speed_bounds_rpm : tuple of float, optional
        (lo, hi) drum speeds [rpm] (:func:`fastest_drum_speed`).
    n : int, optional
        Speeds run per compound, >= 3.
    damping : {"relative", "global"}, optional
        Damping kind of the runs.
    rank_by : {"objective", "fastest_drum"}, optional
        What orders the feasible compounds (:data:`RANK_BY`).
    progress : callable, optional
        ``progress(done, total)`` after every compound.

    Returns
    -------
    CatalogueDesign
        A new ranking; its designs carry their check (``drum``).

    Raises
    ------
    InputError
        An unknown ``rank_by``, or bad speed settings (:func:`fastest_drum_speed`).
    """
    if rank_by not in RANK_BY:
        raise InputError(f"rank_by = {rank_by!r}: must be one of {', '.join(RANK_BY)}")
    feasible = [d for d in ranking.designs if d.feasible]
    checked = []
    for k, d in enumerate(feasible, start=1):
        checked.append(replace(d, drum=fastest_drum_speed(d, setup, speed_bounds_rpm=speed_bounds_rpm, n=n,
                                                          damping=damping)))
        if progress:
            progress(k, len(feasible))
    if rank_by == "fastest_drum":
        checked.sort(key=lambda d: (-(d.drum.fastest_rpm if d.drum.fastest_rpm is not None else -np.inf),
                                    d.objective_value))
    return replace(ranking, designs=checked + [d for d in ranking.designs if not d.feasible], rank_by=rank_by)
