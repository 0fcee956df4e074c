"""The contact chain's model error against the full FEA, measured: the discrepancy's
Gaussian process (:mod:`ccedi.calibrate.discrepancy`) fitted to the bundled FE runs and
checked on runs left out.

For every cached full-FEA run of the bundled contact set (data/contact/fe/, ten runs: three
controls at alpha 80-600 1/s and one per physical effect), the discrepancy is the FE run's
noiseless transducer reading (:func:`ccedi.calibrate.contact_synthetic.reading`) less the
chain's reading at the run's TRUE parameters (E, alpha and the effect's), on the record's
samples. The kernel's amplitudes and length scales maximise the likelihood of all ten
(Nelder-Mead in their logarithms, each run on its contact envelope; the timing term's
y'(t) is the chain's reading's rate); then each run is left
out in turn, the kernel refitted on the other nine, and the left-out run's chi-square per
sample d^T C^-1 d / n computed: about 1 when the kernel's variance is right for a run it
has not seen (its spread over runs: the discrepancy is one smooth draw per run).

Run: ``.venv/bin/python benchmarks/contact_discrepancy.py`` (about 5 minutes); writes
benchmarks/contact_discrepancy.json.
"""
import json
import time
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.optimize import minimize

from ccedi.calibrate.contact_model import DrumContactModel
from ccedi.calibrate.contact_synthetic import bundled_set, reading
from ccedi.calibrate.discrepancy import DiscrepancyKernel, contact_envelope, log_likelihood
from ccedi.calibrate.experiment import load_experiment

DATA = Path(__file__).parents[1] / "data" / "contact"
OUT = Path(__file__).with_suffix(".json")
START = DiscrepancyKernel(amplitudes=(0.018, 0.016), length_scales_s=(0.0035, 0.39), timing_std_s=0.003,
                          timing_length_s=0.1)


def discrepancies():
    """{run name: (t [s], chain reading [N], discrepancy [N], noise std [N])} of every cached FE run."""
    out = {}
    for name, truth in bundled_set().items():
        if truth.fe_run is not None or not (DATA / "fe" / f"{name}.csv").exists():
            continue
        exp = load_experiment(DATA / f"{name}.csv")
        model = DrumContactModel(exp)
        values = {"alpha_per_s": truth.alpha_per_s, "E_factor": truth.E_factor}
        for params in truth.effects.values():
            values |= params
        chain = model.predict(values)
        t, fe = reading(truth, pd.read_csv(DATA / "fe" / f"{name}.csv"))
        out[name] = (t, chain, fe - chain, exp.noise_std_N)
    return out


def kernel_of(z):
    """The kernel of log-parameters z = ln(a_1, l_1, a_2, l_2, s_tau, l_tau)."""
    a1, l1, a2, l2, s_tau, l_tau = np.exp(z)
    return DiscrepancyKernel(amplitudes=(a1, a2), length_scales_s=(l1, l2), timing_std_s=s_tau,
                             timing_length_s=l_tau)


def z_of(kernel):
    """ln(a_1, l_1, a_2, l_2, s_tau, l_tau) of a kernel."""
    (a1, a2), (l1, l2) = kernel.amplitudes, kernel.length_scales_s
    return np.log([a1, l1, a2, l2, kernel.timing_std_s, kernel.timing_length_s])


def on_envelope(run):
    """A run restricted to its contact envelope (elsewhere the discrepancy and its variance are 0)."""
    t, chain, d, _ = run
    keep = contact_envelope(t, chain) > 0
    return t[keep], chain[keep], d[keep]


def fit_kernel(runs, start, max_evaluations=500):
    """The maximum-likelihood kernel over ``runs`` (each on its envelope)."""
    def cost(z):
        return -sum(log_likelihood(kernel_of(z), time_s=r[0], reading=r[1], discrepancy=r[2])[0] for r in runs)

    res = minimize(cost, z_of(start), method="Nelder-Mead",
                   options={"xatol": 1e-3, "fatol": 0.1, "maxfev": max_evaluations})
    return kernel_of(res.x), -float(res.fun)


def main():
    t0 = time.perf_counter()
    runs = discrepancies()
    env = {k: on_envelope(r) for k, r in runs.items()}
    kernel, lnl = fit_kernel(list(env.values()), START)
    print(f"kernel over {len(runs)} runs: amplitudes {np.round(kernel.amplitudes, 4)} of the peak, "
          f"length scales {np.round(kernel.length_scales_s, 4)} s, timing std {kernel.timing_std_s:.4g} s over "
          f"{kernel.timing_length_s:.3g} s (ln L {lnl:.1f})", flush=True)
    per_run = {}
    for name, r in env.items():
        others = [v for k, v in env.items() if k != name]
        left_out, _ = fit_kernel(others, kernel, max_evaluations=150)
        t, chain, d, noise = runs[name]
        per_run[name] = {"rms_N": float(np.sqrt(np.mean(d**2))), "rms_over_noise": float(np.sqrt(np.mean(d**2)) / noise),
                         "rms_in_contact_N": float(np.sqrt(np.mean(r[2] ** 2))),
                         "max_abs_N": float(np.max(np.abs(d))), "peak_reading_N": float(np.max(chain)),
                         "chi2_per_sample": log_likelihood(kernel, time_s=r[0], reading=r[1], discrepancy=r[2])[1],
                         "held_out_chi2_per_sample": log_likelihood(left_out, time_s=r[0], reading=r[1], discrepancy=r[2])[1],
                         "held_out_kernel": left_out.summary()}
        print(f"{name:22s} RMS {per_run[name]['rms_N']:.3f} N ({per_run[name]['rms_over_noise']:.2f} noise std), "
              f"chi2/n {per_run[name]['chi2_per_sample']:.2f}, held out {per_run[name]['held_out_chi2_per_sample']:.2f}",
              flush=True)
    held = [p["held_out_chi2_per_sample"] for p in per_run.values()]
    result = {"what": "the contact chain's reading less the full FEA's at the true parameters, on the bundled FE runs",
              "kernel": kernel.summary(), "log_likelihood": lnl, "runs": per_run,
              "held_out_chi2_per_sample_median": float(np.median(held)),
              "held_out_chi2_per_sample_range": [float(min(held)), float(max(held))],
              "wall_time_s": time.perf_counter() - t0}
    OUT.write_text(json.dumps(result, indent=2) + "\n")
    print(f"held-out chi2 per sample: median {np.median(held):.2f}, range {min(held):.2f}..{max(held):.2f}; "
          f"wrote {OUT} ({result['wall_time_s']:.0f} s)")


if __name__ == "__main__":
    main()
