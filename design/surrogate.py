"""A smooth surrogate of the contact ROM's design outputs over the design variables.

A contact model (:class:`ccedi.models.ContactModel`, built per finger length by a
``model_factory(setup)``; by default the ROM, :class:`ccedi.rom.contact_rom.ReducedContactModel`,
:func:`rom_factory`) is run on a tensor grid of the
design variables (:class:`Variable`: alpha log-spaced, length linear), with one damping
kind ("relative" or "global", :data:`ccedi.models.DAMPING_KINDS`); each output of
:data:`ccedi.design.outputs.OUTPUTS` is then interpolated by a tensor-product cubic
B-spline (casadi ``interpolant``, "bspline") in the unit coordinates

    u = 2 (z - z_lo) / (z_hi - z_lo) - 1 in [-1, 1],  z = ln(alpha) or L,

which passes through the grid values and is C2, so IPOPT gets exact first and second
derivatives. (A least-squares polynomial was tried first: it smeared the ROM's sharp
rise of the peak force of under-damped 4.5-5.5-in fingers over the whole alpha range
and predicted 10 N where the ROM gives 14.5 N.) A further set of ROM runs off the grid
measures the interpolation error (:func:`validation_errors`).

More variables (the section's semi-axes, :func:`section_space`; the taper,
:func:`taper_space`; the drum speed; the finger's Young's modulus, :func:`material_space`) only need another :class:`Variable` and a way to set them on the
:class:`ccedi.fea.contact.drum.DrumSetup` (:func:`ccedi.design.outputs.setup_at`).
"""
import hashlib
import itertools
import json
import time
from dataclasses import dataclass
from pathlib import Path

import casadi as ca
import numpy as np
import pandas as pd

import ccedi.fea as fea_package
import ccedi.rom as rom_package
from ccedi.errors import InputError
from ccedi.fea.contact.drum import DrumSetup, FullContactModel, ObjectStress
from ccedi.outputs import write_csv, write_json
from ccedi.rom.contact_rom import FINGER_KEYS, reduce_contact_model
from ccedi.rom.superelement import fitting_segments

from . import outputs as outputs_module
from .outputs import (
    OUTPUT_STEP_S,
    OUTPUTS,
    RECOVERY_WINDOW_S,
    VARIABLES,
    design_outputs,
    output_count,
    rom_segments,
    run_time_s,
    setup_at,
)


def _is_symbolic(x):
    return isinstance(x, (ca.SX, ca.MX))


@dataclass(frozen=True)
class Variable:
    """One design variable of the surrogate.

    Parameters
    ----------
    name : str
        Name with its SI unit, one of :data:`ccedi.design.outputs.VARIABLES`
        (``alpha_per_s``, ``length_m``, ``drum_speed_rad_s``).
    lo, hi : float
        Bounds in SI units, lo < hi.
    log : bool, optional
        The surrogate works in the logarithm of the variable.
    """

    name: str
    lo: float
    hi: float
    log: bool = False

    @property
    def label(self):
        """Name in reports (``alpha``, ``L``, ``drum speed``)."""
        return VARIABLES[self.name][0]

    @property
    def unit(self):
        """Unit shown in reports, the CLI and JSON (``1/s``, ``in``, ``rpm``)."""
        return VARIABLES[self.name][1]

    @property
    def key(self):
        """JSON key of the shown value (``alpha_per_s``, ``length_in``, ``drum_speed_rpm``)."""
        return VARIABLES[self.name][2]

    def shown(self, x):
        """The value(s) ``x`` (SI) in :attr:`unit`.

        Parameters
        ----------
        x : float or numpy.ndarray

        Returns
        -------
        Same type as ``x``.
        """
        return x / VARIABLES[self.name][3]

    def describe(self, x):
        """``"L = 4.183 in"`` for the value ``x`` (SI).

        Parameters
        ----------
        x : float

        Returns
        -------
        str
        """
        return f"{self.label} = {self.shown(x):.4g}" + ("" if self.unit == "-" else f" {self.unit}")

    def to_unit(self, x):
        """u in [-1, 1] for the value(s) ``x`` (numpy or casadi).

        Parameters
        ----------
        x : float, numpy.ndarray or casadi expression

        Returns
        -------
        Same type as ``x``.
        """
        f = (ca.log if _is_symbolic(x) else np.log) if self.log else (lambda v: v)
        return 2.0 * (f(x) - f(self.lo)) / (f(self.hi) - f(self.lo)) - 1.0

    def from_unit(self, u):
        """The value for unit coordinate(s) ``u`` (inverse of :meth:`to_unit`; numpy or casadi).

        Parameters
        ----------
        u : float, numpy.ndarray or casadi expression

        Returns
        -------
        Same type as ``u``.
        """
        u = u if _is_symbolic(u) else np.asarray(u, dtype=float)
        if self.log:
            exp = ca.exp if _is_symbolic(u) else np.exp
            return exp(np.log(self.lo) + 0.5 * (u + 1.0) * (np.log(self.hi) - np.log(self.lo)))
        return self.lo + 0.5 * (u + 1.0) * (self.hi - self.lo)

    def grid(self, n):
        """``n`` values from lo to hi, evenly spaced in the surrogate's coordinate.

        Parameters
        ----------
        n : int

        Returns
        -------
        numpy.ndarray
        """
        return self.from_unit(np.linspace(-1.0, 1.0, n))


DRUM_SPEED_BOUNDS_RPM = (10.0, 40.0)
"""Default drum speed range of a design over the drum speed [rpm]: half to twice the
paper's 20 rpm."""

CHECKED_ALPHA_PER_S = (7.5, 600.0)
"""The default design space's alpha range [1/s]: the paper's 7.5 to 600 1/s. The contact
ROM behind the surrogate is checked against the full FEA over 3 to 600 1/s
(``validation/design_rom_check.py``); below 7.5 1/s the finger's friction stick-slip grows
and the ROM's peak force falls 24-28 % below the FEA's at 3 1/s."""


def _variable(name, bounds, log=False):
    """The variable ``name`` between ``bounds`` given in its shown unit (0 < lo < hi)."""
    lo, hi = bounds
    label, unit, _, si = VARIABLES[name]
    if not 0.0 < lo < hi:
        raise InputError(f"{label} bounds must satisfy 0 < lo < hi [{unit}], got {tuple(bounds)}")
    return Variable(name, lo * si, hi * si, log=log)


def design_space(alpha_bounds_per_s=CHECKED_ALPHA_PER_S, length_bounds_in=(3.0, 8.0)):
    """The (alpha [1/s], L [m]) design variables (lengths given in inches).

    Parameters
    ----------
    alpha_bounds_per_s : tuple, optional
        (lo, hi) [1/s] (default :data:`CHECKED_ALPHA_PER_S`).
    length_bounds_in : tuple, optional
        (lo, hi) [in].

    Returns
    -------
    tuple of Variable

    Raises
    ------
    InputError
        Bounds not 0 < lo < hi.
    """
    return _variable("alpha_per_s", alpha_bounds_per_s, log=True), _variable("length_m", length_bounds_in)


def speed_space(alpha_bounds_per_s=CHECKED_ALPHA_PER_S, speed_bounds_rpm=DRUM_SPEED_BOUNDS_RPM):
    """The (alpha [1/s], drum speed [rad/s]) design variables (speeds given in rpm): the
    design of a finger whose geometry is given (a mesh).

    Parameters
    ----------
    alpha_bounds_per_s : tuple, optional
        (lo, hi) [1/s] (default :data:`CHECKED_ALPHA_PER_S`).
    speed_bounds_rpm : tuple, optional
        (lo, hi) [rpm] (default :data:`DRUM_SPEED_BOUNDS_RPM`).

    Returns
    -------
    tuple of Variable

    Raises
    ------
    InputError
        Bounds not 0 < lo < hi.
    """
    return _variable("alpha_per_s", alpha_bounds_per_s, log=True), _variable("drum_speed_rad_s", speed_bounds_rpm)


SECTION_BOUNDS_MM = {"semi_width_m": (6.0, 18.0), "semi_thickness_m": (4.0, 14.0)}
"""Default semi-axis range of a design over the section [mm]: about half to one and a half
of the paper's 12 x 8.45 mm (:func:`section_space`)."""


def section_space(alpha_bounds_per_s=CHECKED_ALPHA_PER_S, semi_axis="semi_thickness_m", bounds_mm=None):
    """The (alpha [1/s], one section semi-axis [m]) design variables (semi-axes given in
    mm): the design of the generated finger's section at a given length; ``semi_axis`` is
    "semi_thickness_m" (b, along the bending direction) or "semi_width_m" (a, across).

    Parameters
    ----------
    alpha_bounds_per_s : tuple, optional
        (lo, hi) [1/s] (default :data:`CHECKED_ALPHA_PER_S`).
    semi_axis : {"semi_thickness_m", "semi_width_m"}, optional
        The semi-axis varied.
    bounds_mm : tuple, optional
        Its (lo, hi) [mm] (default :data:`SECTION_BOUNDS_MM`).

    Returns
    -------
    tuple of Variable
        alpha (log-spaced) and the semi-axis.

    Raises
    ------
    InputError
        An unknown semi-axis, or bounds not 0 < lo < hi.
    """
    if semi_axis not in SECTION_BOUNDS_MM:
        raise InputError(f"section semi-axis must be one of {', '.join(SECTION_BOUNDS_MM)}, got {semi_axis!r}")
    return (_variable("alpha_per_s", alpha_bounds_per_s, log=True),
            _variable(semi_axis, bounds_mm or SECTION_BOUNDS_MM[semi_axis]))


TAPER_BOUNDS = (0.6, 1.0)
"""Default taper ratio range of a design over the taper [-]: from a tip 0.6 times the
root's semi-axes to the prism (:func:`taper_space`). Below 0.6 the full FE finger's tip
(SM-A's 5 x 5 section, scaled with it) is crushed by the contact beyond what its elements
hold: measured on the 5-in finger, at 0.4 (alpha 60 1/s) an element inverts and the run
stops, at 0.5 (alpha 250 1/s) the energy balance is off by 110 % with strains of 1.24;
at 0.6 (alpha 60 and 250 1/s) the runs keep every validity limit."""


def taper_space(alpha_bounds_per_s=CHECKED_ALPHA_PER_S, taper_bounds=TAPER_BOUNDS):
    """The (alpha [1/s], taper ratio [-]) design variables: the design of the generated
    finger's taper at a given length and root section.

    Parameters
    ----------
    alpha_bounds_per_s : tuple, optional
        (lo, hi) [1/s] (default :data:`CHECKED_ALPHA_PER_S`).
    taper_bounds : tuple, optional
        (lo, hi) of the tip's semi-axes over the root's [-] (default :data:`TAPER_BOUNDS`).

    Returns
    -------
    tuple of Variable
        alpha (log-spaced) and the taper ratio.

    Raises
    ------
    InputError
        Bounds not 0 < lo < hi.
    """
    return _variable("alpha_per_s", alpha_bounds_per_s, log=True), _variable("taper_ratio", taper_bounds)


def material_space(alpha_bounds_per_s, length_bounds_in, modulus_bounds_Pa):
    """The (alpha [1/s], L [m], E [Pa]) variables: the finger's Young's modulus a third
    variable, at the set-up's density (:data:`ccedi.design.outputs.DENSITY_SCALED` carries it
    to any density).

    Parameters
    ----------
    alpha_bounds_per_s, length_bounds_in, modulus_bounds_Pa : tuple
        (lo, hi) of alpha [1/s], the length [in] and E [Pa].

    Returns
    -------
    tuple of Variable
        alpha (log), L, E (log).

    Raises
    ------
    InputError
        Any bounds not 0 < lo < hi.
    """
    return (*design_space(alpha_bounds_per_s, length_bounds_in),
            _variable("youngs_modulus_Pa", tuple(b / VARIABLES["youngs_modulus_Pa"][3] for b in modulus_bounds_Pa),
                      log=True))


def _fill_undefined(V, U):
    """``V`` (grid values, NaN where undefined) with each NaN replaced by the value at
    the nearest defined grid point (distance in unit coordinates); all-NaN -> zeros."""
    ok = np.isfinite(V)
    if not ok.any():
        return np.zeros_like(V)
    if ok.all():
        return V
    pts = np.stack([u.ravel() for u in U], axis=1)
    d = ((pts[~ok.ravel(), None, :] - pts[None, ok.ravel(), :]) ** 2).sum(-1)
    out = V.ravel().copy()
    out[~ok.ravel()] = V.ravel()[ok.ravel()][np.argmin(d, axis=1)]
    return out.reshape(V.shape)


class Surrogate:
    """Cubic B-spline interpolants (casadi ``interpolant``, 'bspline') of the design
    outputs through the ROM grid, in the unit coordinates of ``variables``.

    ``axes``: the grid's unit coordinates per variable; ``values[name]``: the grid values
    (shape of the grid; undefined entries, e.g. the contact start of a run without
    contact, filled from the nearest defined grid point). An output that is nowhere
    negative on the grid (a force, an amplitude) is clamped at zero: the cubic B-spline
    overshoots below zero next to a kink such as the ringing amplitude's where the
    finger stops overshooting. :meth:`expressions` gives casadi
    expressions (exact first and second derivatives), :meth:`evaluate` numpy values.

    Parameters
    ----------
    variables : sequence of Variable
        The design variables, in grid-axis order.
    axes : sequence of array_like
        Unit coordinates (in [-1, 1]) of the grid along each variable.
    values : dict of str to numpy.ndarray
        Grid values of each output, shaped like the grid, no NaN.
    """

    def __init__(self, variables, axes, values):
        self.variables = tuple(variables)
        self.axes = [np.asarray(a, dtype=float) for a in axes]
        self.values = dict(values)
        self.outputs = tuple(self.values)
        self.interpolants = {name: ca.interpolant(name, "bspline", self.axes, V.ravel(order="F"))
                             for name, V in self.values.items()}
        self.nonnegative = frozenset(name for name, V in self.values.items() if np.all(V >= 0.0))
        self._compile()

    def _compile(self):
        """``self.function``: the outputs of :meth:`expressions` as one casadi function of x."""
        x = ca.SX.sym("x", len(self.variables))
        y = self.expressions([x[i] for i in range(len(self.variables))])
        self.function = ca.Function("surrogate", [x], [ca.vertcat(*y.values())], ["x"], ["y"])

    @classmethod
    def fit(cls, variables, grid: pd.DataFrame):
        """Interpolants of every output column of ``grid`` (all but the variables and
        ``wall_time_s``: :data:`OUTPUTS` and any user-defined ones) through ``grid``, which
        must be a full tensor grid of the variables (as :func:`grid_points` makes).

        Parameters
        ----------
        variables : tuple of Variable
        grid : pandas.DataFrame
            :func:`run_rom` rows.

        Returns
        -------
        Surrogate

        Raises
        ------
        InputError
            Not a full tensor grid with >= 4 values per variable.
        """
        levels = [np.unique(grid[v.name].to_numpy()) for v in variables]
        shape = tuple(len(lv) for lv in levels)
        if np.prod(shape) != len(grid) or min(shape) < 4:
            raise InputError(f"the ROM grid must be a full tensor grid with >= 4 values per variable, got {shape} "
                             f"for {len(grid)} runs")
        order = np.lexsort([grid[v.name].to_numpy() for v in reversed(variables)])
        axes = [v.to_unit(lv) for v, lv in zip(variables, levels)]
        U = np.meshgrid(*axes, indexing="ij")
        names = [c for c in grid.columns if c not in {v.name for v in variables} | {"wall_time_s"}]
        values = {name: _fill_undefined(grid[name].to_numpy(dtype=float)[order].reshape(shape), U) for name in names}
        return cls(variables, axes, values)

    def expressions(self, xs):
        """{output: expression} at the variable values ``xs`` (casadi or numpy scalars).

        Parameters
        ----------
        xs : sequence
            Variable values (SI).

        Returns
        -------
        dict
        """
        return self.unit_expressions([v.to_unit(x) for v, x in zip(self.variables, xs)])

    def unit_expressions(self, us):
        """{output: expression} at the unit coordinates ``us`` of the variables (clamped to
        [-1, 1]: the B-spline is zero outside its knots, and IPOPT may step 1e-8 beyond a
        bound).

        Parameters
        ----------
        us : sequence
            Unit coordinates.

        Returns
        -------
        dict
        """
        u = ca.fmin(ca.fmax(ca.vertcat(*us), -1.0), 1.0)
        return {name: ca.fmax(f(u), 0.0) if name in self.nonnegative else f(u)
                for name, f in self.interpolants.items()}

    def evaluate(self, X):
        """{output: values} at the points ``X`` (m, n_variables), SI units.

        Parameters
        ----------
        X : array_like
            (m, n_variables) points.

        Returns
        -------
        dict
            {output: (m,) values}.
        """
        X = np.atleast_2d(np.asarray(X, dtype=float))
        Y = np.array(self.function.map(len(X))(X.T)).reshape(len(self.outputs), len(X))
        return dict(zip(self.outputs, Y))


def rom_factory(setup: DrumSetup):
    """The design's default contact model: the full FE model of the set-up reduced
    (:func:`ccedi.rom.contact_rom.reduce_contact_model`) to a chain of
    :func:`ccedi.design.outputs.rom_segments` superelements for the set-up's finger length
    (on a finger mesh, as many of them as its elements allow,
    :func:`ccedi.rom.superelement.fitting_segments`). Any
    :class:`ccedi.models.ContactModel` factory can take its place (``model_factory``), the
    full model's included.

    Parameters
    ----------
    setup : DrumSetup
        The set-up at one design's finger length.

    Returns
    -------
    ccedi.rom.contact_rom.ReducedContactModel
    """
    n = rom_segments(setup.finger_length_m)
    return reduce_contact_model(FullContactModel(setup),
                                n_segments=n if setup.finger is None else fitting_segments(setup.finger, n))


def run_rom(setup: DrumSetup, points, *, damping="relative", progress=None, model_factory=rom_factory,
            extra_outputs=None, variables=None):
    """Design outputs of a contact model at design points (one model build per finger);
    each run lasts until the next object arrives (:func:`ccedi.design.outputs.run_time_s`).

    Parameters
    ----------
    setup : DrumSetup
        The base set-up (each point's variables are set on it,
        :func:`ccedi.design.outputs.setup_at`).
    points : list of tuple
        [(alpha [1/s], second variable [SI]), ...].
    damping : {"relative", "global"}, optional
        Damping kind of every run.
    progress : callable, optional
        ``progress(done, total)`` after every run.
    model_factory : callable, optional
        ``model_factory(setup) -> ccedi.models.ContactModel`` (default :func:`rom_factory`,
        the ROM; e.g. ``lambda s: FullContactModel(s, object_stress=False)`` for the FEA).
    extra_outputs : dict, optional
        User-defined outputs, ``{name: function(setup, history) -> float}``
        (:func:`ccedi.design.outputs.design_outputs`).
    variables : tuple of Variable, optional
        The design variables the points hold (default: alpha and the finger length,
        :func:`design_space`).

    Returns
    -------
    pandas.DataFrame
        One row per point: the variables (``alpha_per_s``, ``length_m`` or
        ``drum_speed_rad_s``), :data:`OUTPUTS` (NaN where undefined), the user-defined
        outputs, wall_time_s.
    """
    names = [v.name for v in (variables or design_space())]
    stress = ObjectStress(setup)
    rows, models = [], {}
    for point in points:
        key = tuple(float(x) for x in point[1:])
        if key not in models:
            s = setup_at(setup, names, point)
            models[key] = (s, _model_on(models, s, model_factory), run_time_s(s))
        s, rom, t_end = models[key]
        t0 = time.perf_counter()
        res = rom.run(point[0], damping=damping, t_end_s=t_end, n_outputs=output_count(t_end))
        row = {name: float(x) for name, x in zip(names, point)}
        out = design_outputs(s, res.history, stress, extra=extra_outputs)
        row.update({k: np.nan if out[k] is None else out[k] for k in (*OUTPUTS, *(extra_outputs or {}))})
        row["wall_time_s"] = time.perf_counter() - t0
        rows.append(row)
        if progress:
            progress(len(rows), len(points))
    return pd.DataFrame(rows).astype(float)


def _model_on(models, setup, model_factory):
    """The contact model for ``setup``: one already built for the same finger moved onto
    the new drum set-up (its ``on``, e.g. the ROM at another drum speed), else a new one."""
    for _, model, _ in models.values():
        if hasattr(model, "on") and model.setup.finger is setup.finger \
                and all(getattr(model.setup, k) == getattr(setup, k) for k in FINGER_KEYS):
            return model.on(setup)
    return model_factory(setup)


def grid_points(variables, shape):
    """Tensor grid of the variables, ``shape[i]`` values each (list of tuples).

    Parameters
    ----------
    variables : tuple of Variable
    shape : tuple of int

    Returns
    -------
    list of tuple
    """
    return list(itertools.product(*(v.grid(n) for v, n in zip(variables, shape))))


def validation_points(variables, n, seed=6):
    """``n`` points off the grid: uniform random in the unit coordinates (seeded).

    Parameters
    ----------
    variables : tuple of Variable
    n : int
    seed : int, optional

    Returns
    -------
    list of tuple
    """
    u = np.random.default_rng(seed).uniform(-0.95, 0.95, size=(n, len(variables)))
    return [tuple(float(v.from_unit(u[i, j])) for j, v in enumerate(variables)) for i in range(n)]


def model_source_sha256():
    """SHA-256 of the source of the contact models a design runs: every module of
    :mod:`ccedi.fea` and :mod:`ccedi.rom`, in path order.

    Returns
    -------
    str
        The hex digest.
    """
    digest = hashlib.sha256()
    for package in (fea_package, rom_package):
        root = Path(package.__file__).parent
        for path in sorted(root.rglob("*.py")):
            digest.update(path.relative_to(root).as_posix().encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()


def cached_rom_runs(setup: DrumSetup, points, path, *, damping="relative", progress=None, model_factory=rom_factory,
                    variables=None):
    """:func:`run_rom` results, cached in a CSV file.

    Read from the CSV ``path`` when its sidecar JSON records the same set-up (a finger
    mesh by the SHA-256 of its nodes and elements), variables, points, damping kind,
    outputs (names and the source of :mod:`ccedi.design.outputs` that defines them),
    model and the source of the models (:func:`model_source_sha256`: a change to the FE or
    the ROM code runs them again); otherwise run and written there (with the sidecar).

    Parameters
    ----------
    setup : DrumSetup
        The base set-up.
    points : list of tuple
        [(alpha [1/s], second variable [SI]), ...].
    path : pathlib.Path
        CSV file.
    damping : {"relative", "global"}, optional
        Damping kind of every run.
    progress : callable, optional
        ``progress(done, total)`` after every run.
    model_factory : callable, optional
        ``model_factory(setup) -> ccedi.models.ContactModel`` (default :func:`rom_factory`).
    variables : tuple of Variable, optional
        The variables the points hold (default :func:`design_space`).

    Returns
    -------
    tuple
        (DataFrame of :func:`run_rom`, True when read from the cache).
    """
    variables = tuple(variables or design_space())
    mesh = setup.finger
    finger = None if mesh is None else hashlib.sha256(b"".join(
        np.ascontiguousarray(a).tobytes() for a in (mesh.nodes, mesh.hexes, mesh.tets4, mesh.tets10))).hexdigest()
    meta = {"setup": repr(setup), "finger_mesh_sha256": finger, "variables": [v.name for v in variables],
            "points": [list(map(float, p)) for p in points], "damping": damping,
            "output_step_s": OUTPUT_STEP_S, "outputs": list(OUTPUTS), "recovery_window_s": RECOVERY_WINDOW_S,
            "outputs_source_sha256": hashlib.sha256(Path(outputs_module.__file__).read_bytes()).hexdigest(),
            "model_source_sha256": model_source_sha256(),
            "model_factory": f"{getattr(model_factory, '__module__', '')}."
                             f"{getattr(model_factory, '__qualname__', repr(model_factory))}"}
    sidecar = path.with_suffix(".json")
    if path.exists() and sidecar.exists() and json.loads(sidecar.read_text()) == meta:
        return pd.read_csv(path), True
    frame = run_rom(setup, points, damping=damping, progress=progress, model_factory=model_factory, variables=variables)
    write_csv(path, frame)
    write_json(sidecar, meta)
    return frame, False


def validation_errors(surrogate: Surrogate, runs: pd.DataFrame):
    """Surrogate against model runs off the grid, per output: the largest and the RMS
    error, in the output's unit and relative to the output's range over the grid (many
    outputs pass through zero, e.g. the ringing of a finger that stops overshooting, so
    an error relative to the value itself would mean nothing there).

    Parameters
    ----------
    surrogate : Surrogate
    runs : pandas.DataFrame
        :func:`run_rom` rows off the grid.

    Returns
    -------
    dict
        {output: {max_abs_error, rms_abs_error, max_error_of_range, n_runs}}.
    """
    X = runs[[v.name for v in surrogate.variables]].to_numpy()
    pred = surrogate.evaluate(X)
    out = {}
    for name in surrogate.outputs:
        r = runs[name].to_numpy(dtype=float)
        ok = np.isfinite(r)
        err = np.abs(pred[name][ok] - r[ok])
        span = float(np.ptp(surrogate.values[name])) or 1.0
        out[name] = {"max_abs_error": float(err.max()) if ok.any() else None,
                     "rms_abs_error": float(np.sqrt(np.mean(err**2))) if ok.any() else None,
                     "max_error_of_range": float(err.max() / span) if ok.any() else None,
                     "n_runs": int(ok.sum())}
    return out
