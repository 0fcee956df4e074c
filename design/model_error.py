"""The surrogate's model against the full FEA: the error on each output, and the margin a
design carries where the error is larger than :data:`TOLERANCE`.

The check (``validation/design_rom_check.py``) runs the design's contact ROM and the full
explicit FEA on the same cases (finger length x alpha x damping kind) and keeps both
runs' outputs (:func:`ccedi.design.outputs.design_outputs`). The error of an output is

    e = (ROM - FEA) / |FEA|                    forces, stresses, impulse, times
    e = (ROM - FEA) / max(|FEA|, FLOOR_M)      lengths (recovery, ringing, contact side
                                               and patch), FLOOR_M = 5 mm

(a finger that has recovered to 1 um in one model and 0.2 mm in the other has recovered in
both: lengths are compared at the scale of the requirements on them). An output whose
|e| exceeds :data:`TOLERANCE` in any case inside the design space becomes a
:class:`ccedi.design.optimise.ModelError`: its under- and over-prediction at each checked
case (relative, or in metres for lengths), interpolated between the cases over
(ln alpha, L), tighten every requirement on it where the design lands.

Where the model's error is systematic, a few full FE runs can instead correct the
surrogate (:class:`FeaCorrection`): the ratio FEA / model of the outputs in force units
and of the recovery (:data:`CORRECTED`), measured at training designs on a tensor grid of
the design variables and interpolated between them, multiplies the model's grid runs
before the surrogate is fitted through them. The design's contact ROM carries the mean
load of a finger to the object but not the full FE finger's friction chatter, whose
ripple comes through the transducer: on the 5-in finger at alpha 40-60 1/s its peak force
reads 4-12 % below the FEA's, more the thinner the section, and 2-4 % at 250-600 1/s. An
over-damped finger creeps back at the rate omega_1^2 / alpha of its first mode, whose
omega_1^2 the chain has 1.1-1.7 % low: its recovery, exp(-omega_1^2 t / alpha) of its
deflection, reads high by a fraction (+15 % at 0.47 mm, +10 % at 4.5 mm). Both are ratios
(``validation/design_section_check.py``, which checks the corrected surrogate at designs
other than the training ones).
"""
import json
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.interpolate import RegularGridInterpolator

from ccedi.errors import InputError
from ccedi.units import INCH

from .optimise import ModelError
from .outputs import UNITS

TOLERANCE = 0.10
"""Largest |error| an output may show against the FEA without a margin."""

FLOOR_M = 0.005
"""Scale below which a length output's error is taken in absolute terms [m]."""


def output_error(name, rom, fea):
    """The error e of output ``name`` (module docstring); None where either is undefined.

    Parameters
    ----------
    name : str
        Output name (:data:`ccedi.design.outputs.UNITS` tells a length).
    rom, fea : float or None
        The two models' values.

    Returns
    -------
    float or None
    """
    if rom is None or fea is None or not np.isfinite(rom) or not np.isfinite(fea):
        return None
    if UNITS.get(name) == "m":
        return (rom - fea) / max(abs(fea), FLOOR_M)
    return None if fea == 0.0 else (rom - fea) / abs(fea)


def _inside(case, damping, alpha_bounds_per_s, length_bounds_in):
    lo_a, hi_a = alpha_bounds_per_s
    lo_l, hi_l = length_bounds_in
    return (case["damping"] == damping and lo_a * (1 - 1e-9) <= case["alpha_per_s"] <= hi_a * (1 + 1e-9)
            and lo_l - 1e-9 <= case["length_in"] <= hi_l + 1e-9)


def model_errors(cases, *, damping, alpha_bounds_per_s, length_bounds_in, tolerance=TOLERANCE):
    """``{output: ModelError}`` for the outputs whose error exceeds ``tolerance`` in a
    case inside the design space.

    Parameters
    ----------
    cases : list of dict
        ``{"damping", "alpha_per_s", "length_in", "rom": {...}, "fea": {...}}``.
    damping : str
        The design's damping kind.
    alpha_bounds_per_s, length_bounds_in : tuple
        The design space [1/s], [in].
    tolerance : float, optional
        Largest |error| without a margin.

    Returns
    -------
    dict
    """
    inside = [c for c in cases if _inside(c, damping, alpha_bounds_per_s, length_bounds_in)]
    out = {}
    for name in UNITS:
        rows = [c for c in inside if output_error(name, c["rom"].get(name), c["fea"].get(name)) is not None]
        if not rows or max(abs(output_error(name, c["rom"][name], c["fea"][name])) for c in rows) <= tolerance:
            continue
        relative = UNITS[name] != "m"

        def gap(c, sign, relative=relative, name=name):
            d = sign * (c["fea"][name] - c["rom"][name])
            return max(d / abs(c["fea"][name]) if relative else d, 0.0)

        alphas = np.unique([c["alpha_per_s"] for c in rows])
        lengths = np.unique([c["length_in"] for c in rows])
        tables = []
        for sign in (1.0, -1.0):
            table = np.zeros((len(alphas), len(lengths)))
            for j, length in enumerate(lengths):
                own = sorted((c["alpha_per_s"], gap(c, sign)) for c in rows if c["length_in"] == length)
                table[:, j] = np.interp(np.log(alphas), np.log([a for a, _ in own]), [g for _, g in own])
            tables.append(table)
        out[name] = ModelError(alphas, lengths * INCH, under=tables[0], over=tables[1], relative=relative)
    return out


def read_cases(path):
    """The cases of a ROM check file (JSON with a ``cases`` list).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    list of dict

    Raises
    ------
    InputError
        Missing, unreadable or without cases.
    """
    try:
        data = json.loads(Path(path).read_text())
        cases = data["cases"]
    except (OSError, ValueError, KeyError, TypeError) as err:
        raise InputError(f"model error file {path}: not a ROM check JSON with 'cases' ({type(err).__name__})") from None
    return cases


CORRECTED = ("sensor_peak_force_N", "max_object_stress_Pa", "max_finger_stress_Pa", "contact_impulse_N_s",
             "recovery_deviation_m")
"""The outputs :class:`FeaCorrection` corrects by default: those in force units that a
requirement bounds, and the recovery (module docstring). Not the ringing, which the ROM
follows within 1.2 % of its 5 mm scale at the training designs, nor the contact's place
and side, which it follows within 0.8 %; the root stress before contact is a few hundred
pascals of rounding."""

RATIO_FLOOR_M = 1e-4
"""A length output below this in either model is taken as zero there [m]: its ratio is 1
(a recovered finger's 1e-12-1e-6 m are rounding; 0.1 mm is 2 % of the 5 mm scale of the
requirements on lengths)."""


class FeaCorrection:
    """The surrogate's model corrected by the full FEA: per output, the ratio
    r = FEA / model measured at training designs on a tensor grid of the design
    variables (1 where a length is below :data:`RATIO_FLOOR_M` in either model),
    interpolated multilinearly in the variables' unit coordinates
    (:meth:`ccedi.design.surrogate.Variable.to_unit`: ln alpha, the second variable
    linear) and held at its edge values beyond the training grid; :meth:`apply` multiplies
    the model's runs by it.

    Parameters
    ----------
    variables : tuple of ccedi.design.surrogate.Variable
        The design variables, in the order of the training grid's axes.
    levels : sequence of numpy.ndarray
        The training grid's values of each variable [SI], increasing, at least two each.
    ratios : dict of str to numpy.ndarray
        {output: r on the training grid, shaped like it}.
    """

    def __init__(self, variables, levels, ratios):
        self.variables = tuple(variables)
        self.levels = [np.asarray(lv, dtype=float) for lv in levels]
        self.ratios = {k: np.asarray(v, dtype=float) for k, v in ratios.items()}
        self._interpolants = {k: RegularGridInterpolator([v.to_unit(lv) for v, lv in zip(self.variables, self.levels)],
                                                         r) for k, r in self.ratios.items()}

    @classmethod
    def fit(cls, variables, model_runs: pd.DataFrame, fea_runs: pd.DataFrame, *, outputs=CORRECTED):
        """The correction from model and full-FEA runs at the same training designs.

        Parameters
        ----------
        variables : tuple of ccedi.design.surrogate.Variable
            The design variables.
        model_runs, fea_runs : pandas.DataFrame
            :func:`ccedi.design.surrogate.run_rom` rows of the model and of the FEA
            (``model_factory=``:func:`ccedi.design.recheck.full_fea_factory`) at the same
            points, a full tensor grid of the variables with at least two values each.
        outputs : sequence of str, optional
            The outputs corrected (default :data:`CORRECTED`).

        Returns
        -------
        FeaCorrection

        Raises
        ------
        InputError
            The runs are not at the same points, not a full tensor grid with two values
            or more per variable, or an output is missing or not finite in either, or one
            in force units not positive.
        """
        names = [v.name for v in variables]
        X, Y = model_runs[names].to_numpy(dtype=float), fea_runs[names].to_numpy(dtype=float)
        if X.shape != Y.shape or not np.allclose(X, Y, rtol=1e-12, atol=0.0):
            raise InputError("FEA correction: the model and FEA runs must be at the same design points, in the same order")
        levels = [np.unique(X[:, i]) for i in range(len(names))]
        shape = tuple(len(lv) for lv in levels)
        if np.prod(shape) != len(X) or min(shape) < 2:
            raise InputError(f"FEA correction: the training designs must be a full tensor grid with >= 2 values per "
                             f"variable, got {shape} for {len(X)} runs")
        order = np.lexsort(X.T[::-1])
        ratios = {}
        for name in outputs:
            if name not in model_runs or name not in fea_runs:
                raise InputError(f"FEA correction: output {name!r} missing from the runs")
            m, f = model_runs[name].to_numpy(dtype=float), fea_runs[name].to_numpy(dtype=float)
            if UNITS.get(name) == "m":
                if not np.all(np.isfinite(m) & np.isfinite(f)):
                    raise InputError(f"FEA correction: output {name!r} must be finite in every run")
                large = (np.abs(m) >= RATIO_FLOOR_M) & (np.abs(f) >= RATIO_FLOOR_M)
                r = np.where(large, f / np.where(large, m, 1.0), 1.0)
            elif not (np.all(np.isfinite(m) & np.isfinite(f)) and np.all(m > 0.0) and np.all(f > 0.0)):
                raise InputError(f"FEA correction: output {name!r} must be finite and positive in every run")
            else:
                r = f / m
            ratios[name] = r[order].reshape(shape)
        return cls(variables, levels, ratios)

    def ratio(self, name, X):
        """r of output ``name`` at the designs ``X``.

        Parameters
        ----------
        name : str
            A corrected output.
        X : array_like
            (m, n_variables) designs [SI].

        Returns
        -------
        numpy.ndarray
            (m,) ratios FEA / model [-].
        """
        X = np.atleast_2d(np.asarray(X, dtype=float))
        U = np.column_stack([np.clip(v.to_unit(X[:, i]), v.to_unit(lv[0]), v.to_unit(lv[-1]))
                             for i, (v, lv) in enumerate(zip(self.variables, self.levels))])
        return self._interpolants[name](U)

    def apply(self, runs: pd.DataFrame):
        """Model runs with every corrected output multiplied by its ratio at the run's design.

        Parameters
        ----------
        runs : pandas.DataFrame
            :func:`ccedi.design.surrogate.run_rom` rows over the same variables.

        Returns
        -------
        pandas.DataFrame
            A corrected copy.
        """
        out = runs.copy()
        X = runs[[v.name for v in self.variables]].to_numpy(dtype=float)
        for name in self.ratios:
            out[name] = runs[name].to_numpy(dtype=float) * self.ratio(name, X)
        return out

    def as_dict(self):
        """The training grid (in each variable's shown unit) and the ratios, for a JSON report.

        Returns
        -------
        dict
            ``{variable key: [values], "ratio_fea_over_model": {output: nested list}}``.
        """
        return {**{v.key: [float(x) for x in v.shown(lv)] for v, lv in zip(self.variables, self.levels)},
                "ratio_fea_over_model": {k: r.tolist() for k, r in self.ratios.items()}}
