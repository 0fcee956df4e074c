"""A nested fit (the current model plus one effect) never ends worse than the model it
extends: it restarts from that model, the effect where it vanishes, when its own starts end
in a worse local minimum."""
import numpy as np
import pytest
from conftest import ROOT

from ccedi.calibrate.effects import CATALOGUE, CONTACT_CATALOGUE, ContactScales, Parameter, Scales
from ccedi.calibrate.experiment import load_experiment
from ccedi.calibrate.fit import fit, fit_baseline, holdout_mask
from ccedi.calibrate.loop import calibration_model


class _Experiment:
    def __init__(self, time_s, signal):
        self.time_s, self.signal = time_s, signal


class SineModel:
    """A toy calibration model with a local minimum: amplitude (the baseline) times
    sin(2 pi (f0 + df) t), the effect a frequency shift df whose absent value is 0."""

    catalogue = {"shift": None}

    def __init__(self, true_shift_hz=0.0, seed=0):
        self.f0 = 10.0
        t = np.linspace(0.0, 2.0, 2000)
        noise = 0.01 * np.random.default_rng(seed).standard_normal(t.size)
        self.exp = _Experiment(t, 1.0 * np.sin(2 * np.pi * (self.f0 + true_shift_hz) * t) + noise)

    def parameters(self, effects):
        spec = [(Parameter("amplitude_m", 0.01, 10.0), 0.5)]
        if "shift" in effects:
            spec.append((Parameter("shift_hz", -6.0, 6.0, log=False, absent=0.0), 4.0))
        return spec

    def predict(self, values):
        return values["amplitude_m"] * np.sin(2 * np.pi * (self.f0 + values.get("shift_hz", 0.0)) * self.exp.time_s)


def training_rss(model, f):
    train = ~holdout_mask(len(model.exp.signal))
    return float(np.sum((f.prediction - model.exp.signal)[train] ** 2))


def test_a_nested_fit_from_a_far_start_ends_no_worse_than_its_parent():
    """From a start 4 Hz off the sine sticks in a side minimum far worse than the
    parent (no shift); given the parent, it ends at the parent's fit or better."""
    model = SineModel()
    parent = fit(model, ())
    stuck = fit(model, ("shift",))
    assert training_rss(model, stuck) > 10.0 * training_rss(model, parent)      # the trap is real
    nested = fit(model, ("shift",), parent=parent)
    assert training_rss(model, nested) <= training_rss(model, parent) * (1.0 + 1e-9)
    assert abs(nested.values["shift_hz"]) < 0.01


def test_a_nested_fit_that_converges_is_not_restarted():
    """Where the effect is real and the start reaches it, the parent does not change the fit."""
    model = SineModel(true_shift_hz=3.5)
    parent = fit(model, ())
    assert fit(model, ("shift",), parent=parent).values == fit(model, ("shift",)).values


@pytest.mark.parametrize("effect", ["tip_mass", "root_compliance", "coulomb_friction", "time_delay"])
def test_nested_fits_of_a_record_never_end_worse_than_the_baseline(effect):
    """On a bundled impulse record, the baseline plus each effect started at its far bound
    ends no worse than the baseline, within what the effect's model leaves at its absent
    value (a tip mass at its smallest bound, a root spring at its stiffest: 1e-4 of the
    training RSS here, 0.1 of BIC)."""
    model = calibration_model(load_experiment(ROOT / "data" / "measured" / "control_high.csv"))
    baseline = fit_baseline(model)
    added = [p for p, _ in CATALOGUE[effect].parameters(model.scales)]
    far = {p.name: p.upper if p.absent is None or p.absent <= p.lower else p.lower for p in added}
    nested = fit(model, (effect,), start=baseline.values | far, parent=baseline)
    assert training_rss(model, nested) <= training_rss(model, baseline) * (1.0 + 1e-3)


def test_every_catalogue_effect_says_where_it_vanishes():
    """Each effect has a parameter whose absent value switches it off (the others may then
    be irrelevant: a Prony time without a Prony weight), inside the bounds once clipped."""
    scales = Scales(**{name: 1.0 for name in Scales.__dataclass_fields__})
    contact = ContactScales(peak_force_N=1.0, duration_s=1.0, omega_rad_s=1.0, friction=0.3, sensor_hz=500.0,
                            sensor_damping_ratio=0.7)
    for catalogue, s in ((CATALOGUE, scales), (CONTACT_CATALOGUE, contact)):
        for effect in catalogue.values():
            params = [p for p, _ in effect.parameters(s)]
            assert any(p.absent is not None for p in params), effect.name
            for p in params:
                if p.absent is not None:
                    lo, hi = p.z_bounds()
                    assert lo <= p.absent_z() <= hi, (effect.name, p.name)
