"""The chain's bias model: fitted to runs whose bias is known, it returns that bias, moved
with the contact and scaled with the peak; and it reads back what it writes."""
import numpy as np
import pytest

from ccedi.calibrate.chain_bias import ChainBias, fit_chain_bias, run_bias
from ccedi.errors import InputError

T = np.arange(1, 1501) / 1000.0


def _pulse(t_start, duration, peak):
    """A smooth contact force: a half-sine of the given start [s], duration [s] and peak [N]."""
    phase = (T - t_start) / duration
    return np.where((phase > 0) & (phase < 1), peak * np.sin(np.pi * np.clip(phase, 0, 1)), 0.0)


def _bias(chain, alpha, t_start, duration, peak):
    """A smooth bias tied to the contact, its size linear in ln alpha: a low impulse and an early rise."""
    phase = (T - t_start) / duration
    shape = -0.02 * (1 + 0.5 * np.log(alpha / 100.0)) * np.sin(np.pi * np.clip(phase, 0, 1)) ** 2
    return np.where((phase > 0) & (phase < 1), peak * shape, 0.0)


def _runs(alphas):
    runs = []
    for i, alpha in enumerate(alphas):
        t_s, dur, peak = 0.3 + 0.02 * i, 0.8 - 0.01 * i, 15.0 + i
        chain = _pulse(t_s, dur, peak)
        runs.append(("global", {"alpha_per_s": alpha, "E_factor": 1.0}, T, chain + _bias(chain, alpha, t_s, dur, peak),
                     chain))
    return runs


def test_the_fitted_bias_follows_the_contact_and_the_parameters():
    """Fitted on eight runs, the model predicts a ninth's bias (another alpha, contact start,
    duration and peak) to within 10 % of its RMS; a model that ignored the alpha
    dependence (its mean alone) misses by more."""
    model = fit_chain_bias(_runs([60, 80, 110, 150, 200, 280, 400, 550]))
    t_s, dur, peak, alpha = 0.41, 0.72, 19.0, 330.0
    chain = _pulse(t_s, dur, peak)
    truth = run_bias(T, chain + _bias(chain, alpha, t_s, dur, peak), chain)
    predicted = model.force_bias(T, chain, v={"alpha_per_s": alpha, "E_factor": 1.0}, damping="global")
    rms = np.sqrt(np.mean(truth**2))
    assert np.sqrt(np.mean((predicted - truth) ** 2)) < 0.1 * rms
    mean_only = ChainBias(mean=model.mean, shapes=model.shapes, weights=0 * model.weights, center=model.center,
                          scale=model.scale, residual_std=0.0, runs=8)
    assert np.sqrt(np.mean((mean_only.force_bias(T, chain, v={"alpha_per_s": alpha, "E_factor": 1.0}, damping="global")
                            - truth) ** 2)) > 0.15 * rms


def test_round_trip_and_bad_file(tmp_path):
    model = fit_chain_bias(_runs([60, 100, 200, 400, 700]), components=2)
    model.write(tmp_path / "bias.json")
    back = ChainBias.read(tmp_path / "bias.json")
    v = {"alpha_per_s": 150.0, "E_factor": 1.01}
    assert np.array_equal(back.shape(v, "relative"), model.shape(v, "relative"))
    (tmp_path / "bad.json").write_text("{}")
    with pytest.raises(InputError, match="bad.json"):
        ChainBias.read(tmp_path / "bad.json")
    with pytest.raises(InputError, match="3 design runs"):
        fit_chain_bias(_runs([60, 100, 200]))
