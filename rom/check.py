"""Reduced models against the full FEA (``ccedi rom-check``).

Impulse cases (acceptance 1): the 4.5-in finger, a small tip pulse, the modal ROM with
``n_modes`` modes before and after its least-squares fit to the FE response.

Contact cases (acceptance 2): the 8-in finger on the drum, the full explicit FE model
(:class:`ccedi.fea.drum.FullContactModel`) against the superelement chain
(:class:`ccedi.rom.contact_rom.ReducedContactModel`), co-rotational and linear, through the
same ``run`` interface. Per case:

* ``nrmse``: NRMSE of the tip lag behind the rigidly turning finger
  (:func:`ccedi.fea.contact_study.tip_lag_series_m`) over the run [-];
* ``peak_force_error``: peak reaction force, ROM / FEA - 1 [-];
  ``smoothed_peak_force_error`` the same after a ``SMOOTHING_S`` moving average of both
  histories (the lightly damped FE finger chatters on the object: its sampled peak
  moves by +-10 % under last-bit changes, see README);
* ``contact_start_error_s``, ``contact_end_error_s``: ROM - FEA [s];
* ``max_stress_error``: largest finger von Mises stress, ROM / FEA - 1 [-];
* ``impulse_error``: contact impulse (time integral of the reaction force over the run,
  trapezoidal over the outputs), ROM / FEA - 1 [-]: the mean load the finger passes to
  the object, which the chatter of the lightly damped finger (alpha = 7.5 1/s: ~400 Hz,
  +-10 N about a 15 N mean) leaves well defined while it makes the sampled peak a draw;
* ``speedup``: FEA wall time / ROM wall time (the ROM's one-off build excluded and
  reported as ``rom_build_time_s``).
"""
import time

import numpy as np

from ccedi.fea.contact_study import tip_lag_series_m, window_mean
from ccedi.fea.drum import DrumSetup, FullContactModel
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import SEMI_AXES
from ccedi.fea.studies import impulse_model, impulse_response
from ccedi.fea.units import m_to_inch
from ccedi.rom.contact_rom import ReducedContactModel
from ccedi.rom.modal import fit_to_response, nrmse, tip_modal_rom

SMOOTHING_S = 0.025
"""Moving-average window [s] for ``smoothed_peak_force_error``."""


def compare_contact(setup: DrumSetup, fea, rom):
    """Metrics (module docstring) of a reduced :class:`ccedi.fea.drum.ContactResponse` ``rom``
    against the full one ``fea`` (same output times)."""
    hf, hr = fea.history, rom.history
    if not np.allclose(hf.time_s, hr.time_s):
        raise ValueError("the two responses must have the same output times")
    sf, sr = fea.summary, rom.summary
    t = hf.time_s.to_numpy()
    smooth_f = window_mean(t, hf.reaction_force_N.to_numpy(), SMOOTHING_S).max()
    smooth_r = window_mean(t, hr.reaction_force_N.to_numpy(), SMOOTHING_S).max()

    def diff(key):
        return None if sf[key] is None or sr[key] is None else sr[key] - sf[key]

    return {"nrmse": nrmse(tip_lag_series_m(setup, hr), tip_lag_series_m(setup, hf)),
            "peak_force_error": sr["peak_reaction_force_N"] / sf["peak_reaction_force_N"] - 1.0,
            "smoothed_peak_force_error": smooth_r / smooth_f - 1.0,
            "contact_start_error_s": diff("contact_start_s"), "contact_end_error_s": diff("contact_end_s"),
            "max_stress_error": sr["max_finger_stress_Pa"] / sf["max_finger_stress_Pa"] - 1.0,
            "impulse_error": (np.trapezoid(hr.reaction_force_N.to_numpy(), t)
                              / np.trapezoid(hf.reaction_force_N.to_numpy(), t) - 1.0),
            "speedup": sf["wall_time_s"] / sr["wall_time_s"]}


def _key_figures(summary):
    keep = ("contact_start_s", "contact_end_s", "peak_reaction_force_N", "max_finger_stress_Pa", "wall_time_s")
    return {k: summary[k] for k in keep}


def contact_cases(setup: DrumSetup, alphas=(7.5, 180.0, 600.0), damping="global", t_end_s=1.5, n_outputs=300,
                  progress=False, contact=None):
    """Full FEA vs both reduced models for every alpha: a list of case dicts. ``contact``:
    the ROM's contact model (:class:`ccedi.rom.contact_rom.ReducedContactModel`; None: its default)."""
    t0 = time.perf_counter()
    reduced = [ReducedContactModel(setup, nonlinear=True, contact=contact),
               ReducedContactModel(setup, nonlinear=False, contact=contact)]
    build = (time.perf_counter() - t0) / 2
    for r in reduced:
        r.run(alphas[0], damping, t_end_s=1e-3, n_outputs=1)          # compile outside the timing
    full = FullContactModel(setup)
    cases = []
    for alpha in alphas:
        ref = full.run(alpha, damping, t_end_s, n_outputs, progress=progress)
        for r in reduced:
            res = r.run(alpha, damping, t_end_s, n_outputs)
            cases.append({"case": f"contact, {m_to_inch(setup.finger_length_m):.3g}-in finger, alpha {alpha:g} 1/s, "
                                  f"{damping} damping",
                          "kind": "contact", "model": r.name, "alpha_per_s": float(alpha),
                          **compare_contact(setup, ref, res), "rom_build_time_s": build,
                          "fea": _key_figures(ref.summary), "rom": _key_figures(res.summary)})
    return cases


def impulse_cases(alphas=(20.0, 180.0), n_modes=6, force_N=0.1, duration_s=0.01, t_end_s=0.2, n_outputs=400,
                  material=RUBBER, semi_axes_m=SEMI_AXES):
    """Full FEA vs the modal ROM for the 4.5-in finger's tip pulse, per alpha (finger of
    ``material`` with section semi-axes ``semi_axes_m`` [m])."""
    finger = {"material": material, "semi_axes_m": semi_axes_m}
    impulse_response(t_end_s=1e-3, n_outputs=1)                       # compile outside the timing
    cases = []
    for alpha in alphas:
        fe = impulse_response(alpha=alpha, force_N=force_N, duration_s=duration_s, t_end_s=t_end_s,
                              n_outputs=n_outputs, **finger)
        t, y = fe.history.time_s.to_numpy(), fe.history.tip_uy_m.to_numpy()
        rom = tip_modal_rom(impulse_model(alpha=alpha, force_N=force_N, **finger), n_modes=n_modes)
        fit = fit_to_response(rom, t, y, force_N, duration_s)
        repeats = 200
        t0 = time.perf_counter()
        for _ in range(repeats):
            fit.rom.pulse_response(t, force_N, duration_s)
        per_eval = (time.perf_counter() - t0) / repeats
        share = (rom.gain / rom.omega_rad_s**2) / rom.static_flexibility
        cases.append({"case": f"impulse, 4.5-in finger, {force_N:g} N for {duration_s:g} s, alpha {alpha:g} 1/s",
                      "kind": "impulse", "model": f"modal-{n_modes}", "alpha_per_s": float(alpha),
                      "nrmse": fit.nrmse_after, "nrmse_before_fit": fit.nrmse_before,
                      "frequency_error": (fit.rom.omega_rad_s / rom.omega_rad_s - 1.0).tolist(),
                      "flexibility_share": share.tolist(),
                      "peak_force_error": None, "contact_start_error_s": None, "contact_end_error_s": None,
                      "speedup": fe.summary["wall_time_s"] / per_eval})
    return cases
