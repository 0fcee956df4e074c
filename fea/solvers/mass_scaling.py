"""Mass scaling: a few small elements no longer set the whole run's step.

A sliver where a hole meets the surface of an imported finger can have a stable step
several times shorter than the rest of the mesh, and central differences must take the
smallest element's step everywhere. Scaling the density of just the elements below a
target step, by ``s_e = (dt_target / dt_e)^2``, lifts each to the target (the stable step
of an element goes as ``L_e sqrt(rho_e / (lambda + 2 mu))``), at the price of mass added
where those elements are. Selective: only the elements below the target change, and the
added mass is reported, with the first natural frequencies before and after, so that a
user sees what the faster run costs in dynamics (a few small elements carry little mass:
the first modes barely move).

The tetrahedra's stable step comes from each element's largest eigenvalue with its own
lumped masses, scaled so that the smallest equals the assembled mesh's limit 2 /
omega_max (:func:`ccedi.fea.elements.tetra.time_step_length_factors`). Scaling some
elements changes omega_max, and with it that scale on every element; so the elements are
lifted to a threshold (each element below it scaled by ``(threshold / dt_e)^2``, dt_e
its step in the unscaled model), the scaled model is built anew
(:class:`ccedi.fea.model.Model` with ``element_mass_scale``) and its stable step
measured, and the threshold is raised from the target until the step reaches the target,
then bisected to the least threshold that does (least mass added). Hexahedra (the
generated fingers, whose elements are regular) are not scaled: a target above a
hexahedron's step is refused.
"""
from dataclasses import dataclass, replace

import numpy as np

from ccedi.errors import InputError, require_finite_positive
from ccedi.fea.model import Model
from ccedi.fea.solvers.explicit import element_stable_steps
from ccedi.fea.solvers.modal import natural_frequencies

THRESHOLD_GROWTH = 1.5
"""Factor by which the lifting threshold grows until the scaled model's step reaches the
target (module docstring)."""

MAX_THRESHOLD = 20.0
"""The threshold grows at most to this multiple of the target step."""

BISECTIONS = 6
"""Halvings (on a log scale) of the threshold's bracket: the least threshold that reaches
the target, within THRESHOLD_GROWTH ** (1 / 64), about 0.6 %."""

AUTO_STEP_FRACTION = 0.5
"""``dt_target_s="auto"`` lifts every element to this fraction of the mesh's median
element step: only elements much smaller than the typical one are scaled."""

MAX_ADDED_MASS_FRACTION = 0.02
"""Default most mass the scaling may add [-]: beyond it the first modes move by more than
about half that fraction, and the run is no longer the finger's."""

CHECKED_MODES = 3
"""Natural frequencies compared before and after scaling."""


@dataclass(frozen=True)
class MassScaling:
    """What mass scaling did to a model.

    Parameters
    ----------
    dt_target_s : float
        The least stable step asked for [s] (before the TSSFAC factor).
    dt_before_s, dt_after_s : float
        The model's smallest element step at rest before and after [s].
    scaled_elements : int
        Elements whose density was scaled.
    largest_factor : float
        The largest density factor [-].
    added_mass_kg : float
        Mass added [kg].
    added_mass_fraction : float
        Added over the model's mass [-].
    frequencies_before_hz, frequencies_after_hz : numpy.ndarray
        The first :data:`CHECKED_MODES` natural frequencies [Hz].
    """

    dt_target_s: float
    dt_before_s: float
    dt_after_s: float
    scaled_elements: int
    largest_factor: float
    added_mass_kg: float
    added_mass_fraction: float
    frequencies_before_hz: np.ndarray
    frequencies_after_hz: np.ndarray

    @property
    def speedup(self):
        """The stable step's gain, after over before [-]: how much fewer steps a run takes."""
        return self.dt_after_s / self.dt_before_s

    @property
    def frequency_change(self):
        """Largest relative change of the checked natural frequencies [-] (negative: lower)."""
        change = self.frequencies_after_hz / self.frequencies_before_hz - 1.0
        return float(change[np.argmax(np.abs(change))])

    def summary(self):
        """The figures as a flat dict with units in the keys (for a report or JSON).

        Returns
        -------
        dict
        """
        return {"mass_scaling_step_target_s": self.dt_target_s, "stable_step_before_s": self.dt_before_s,
                "stable_step_after_s": self.dt_after_s, "step_gain": self.speedup,
                "scaled_elements": self.scaled_elements, "largest_density_factor": self.largest_factor,
                "added_mass_kg": self.added_mass_kg, "added_mass_fraction": self.added_mass_fraction,
                "frequencies_before_hz": [float(f) for f in self.frequencies_before_hz],
                "frequencies_after_hz": [float(f) for f in self.frequencies_after_hz],
                "largest_frequency_change": self.frequency_change}


def step_target(model: Model, dt_target_s):
    """The target step of :func:`mass_scaled`: a number [s], or ``"auto"``
    (:data:`AUTO_STEP_FRACTION` of the median element step).

    Parameters
    ----------
    model : Model
        The model (with solid elements).
    dt_target_s : float or "auto"
        The step to lift every element to [s], > 0.

    Returns
    -------
    float
        The target [s].

    Raises
    ------
    InputError
        Neither a positive finite number nor ``"auto"``.
    """
    if isinstance(dt_target_s, str):
        if dt_target_s != "auto":
            raise InputError(f"mass scaling step = {dt_target_s!r}: must be a step in seconds (> 0) or 'auto'")
        return AUTO_STEP_FRACTION * float(np.median(element_stable_steps(model)))
    return require_finite_positive("mass scaling step (s)", dt_target_s)


def mass_scaled(model: Model, *, dt_target_s="auto", max_added_mass_fraction=MAX_ADDED_MASS_FRACTION):
    """The model with the density of its small tetrahedra scaled so that its stable step
    is at least ``dt_target_s`` (module docstring).

    Parameters
    ----------
    model : Model
        A model with solid elements (tetrahedra to scale).
    dt_target_s : float or "auto", optional
        The least stable step [s] (before the TSSFAC factor), or "auto"
        (:data:`AUTO_STEP_FRACTION` of the median element step). Default "auto".
    max_added_mass_fraction : float, optional
        The most mass the scaling may add, over the model's mass [-]. Default
        :data:`MAX_ADDED_MASS_FRACTION`.

    Returns
    -------
    scaled : Model
        The model with ``element_mass_scale`` set (the same model when its step already
        reaches the target).
    report : MassScaling
        Steps, added mass and natural frequencies before and after.

    Raises
    ------
    InputError
        A model without solid elements, a bad target, a hexahedron whose step is below
        the target (hexahedra are not scaled), or a target that needs more mass than
        ``max_added_mass_fraction``.
    """
    if model.mesh.n_elements == 0:
        raise InputError("mass scaling needs solid elements; this model has none")
    target = step_target(model, dt_target_s)
    steps = element_stable_steps(model)
    n_hex = len(model.mesh.hexes)
    if n_hex and steps[:n_hex].min() < target:
        k = int(np.argmin(steps[:n_hex]))
        raise InputError(f"mass scaling step {target:.4g} s: hexahedron element {k} has a step of "
                         f"{steps[k]:.4g} s; hexahedra are not scaled, choose a step of at most that")
    original = np.ones(model.mesh.n_elements) if model.element_mass_scale is None \
        else np.asarray(model.element_mass_scale, dtype=float)

    def lifted(threshold):
        """The model with every element below ``threshold`` lifted to it, and its step."""
        factor = original * np.maximum(1.0, (threshold / steps) ** 2)
        scaled = replace(model, element_mass_scale=factor)
        return scaled, float(element_stable_steps(scaled).min())

    scaled, step = model, float(steps.min())
    if step < target:
        low, high = None, target
        scaled, step = lifted(high)
        while step < target:
            if high > MAX_THRESHOLD * target:
                raise InputError(f"mass scaling step {target:.4g} s: not reached (the step is {step:.4g} s "
                                 f"with every element below {high:.4g} s lifted to it)")
            low, high = high, THRESHOLD_GROWTH * high
            scaled, step = lifted(high)
        for _ in range(BISECTIONS if low is not None else 0):
            middle = np.sqrt(low * high)
            candidate, candidate_step = lifted(middle)
            if candidate_step >= target:
                high, scaled, step = middle, candidate, candidate_step
            else:
                low = middle
    added = scaled.total_mass / model.total_mass - 1.0
    if added > max_added_mass_fraction:
        raise InputError(f"mass scaling step {target:.4g} s: reaching it adds {100 * added:.3g} % to the finger's mass "
                         f"(at most {100 * max_added_mass_fraction:.3g} % allowed): the dynamics would change; remesh "
                         f"the small elements or ask for a step nearer {steps.min():.4g} s")
    return scaled, _report(model, scaled, original=original, target=target, steps_before=steps, step_after=step)


def _report(model, scaled, *, original, target, steps_before, step_after):
    """The :class:`MassScaling` of ``scaled`` against ``model`` (whose density factors are
    ``original``), the stable steps already measured."""
    before = natural_frequencies(model, n_modes=CHECKED_MODES) / (2.0 * np.pi)
    after = before if scaled is model else natural_frequencies(scaled, n_modes=CHECKED_MODES) / (2.0 * np.pi)
    factor = original if scaled is model else scaled.element_mass_scale
    added = scaled.total_mass - model.total_mass
    return MassScaling(dt_target_s=target, dt_before_s=float(steps_before.min()), dt_after_s=step_after,
                       scaled_elements=int(np.sum(factor > original)), largest_factor=float((factor / original).max()),
                       added_mass_kg=float(added), added_mass_fraction=float(added / model.total_mass),
                       frequencies_before_hz=before, frequencies_after_hz=after)
