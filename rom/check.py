"""Reduced models against the full FEA (``ccedi rom-check``).

Impulse cases (acceptance 1): the 4.5-in finger, a small tip pulse, the modal ROM with
``n_modes`` modes before and after its least-squares fit to the FE response.

Contact cases (acceptance 2): the 8-in finger on the drum, the full explicit FE model
(:class:`ccedi.fea.contact.drum.FullContactModel`) against the superelement chain
(:class:`ccedi.rom.contact_rom.ReducedContactModel`), co-rotational and linear, through the
same ``run`` interface. Per case:

* ``nrmse``: NRMSE of the tip lag behind the rigidly turning finger
  (:func:`ccedi.fea.cases.contact_study.tip_lag_series_m`) over the run [-];
* ``sensor_peak_force_error``: peak of the reaction force as the force transducer reads
  it (:class:`ccedi.rom.sensor.Transducer`, default a 100 Hz second-order low-pass, applied
  to both histories), ROM / FEA - 1 [-]: the acceptance figure of the peak force;
* ``peak_force_error``: peak of the raw (sampled) reaction force, ROM / FEA - 1 [-];
  ``smoothed_peak_force_error`` the same after a ``SMOOTHING_S`` moving average of both
  histories (the lightly damped FE finger chatters on the object: its sampled peak
  moves by +-10 % under last-bit changes, see docs/validation.md);
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

from ccedi.fea.cases.contact_study import tip_lag_series_m, window_mean
from ccedi.fea.cases.studies import finger_impulse_model
from ccedi.fea.contact.drum import DrumSetup, FullContactModel
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import SEMI_AXES
from ccedi.rom.contact_rom import DEFAULT_SEGMENTS, reduce_contact_model
from ccedi.rom.modal import fit_to_response, nrmse, reduce_impulse_model
from ccedi.rom.sensor import Transducer
from ccedi.units import m_to_inch

SMOOTHING_S = 0.025
"""Moving-average window [s] for ``smoothed_peak_force_error``."""


def compare_contact(setup: DrumSetup, fea, rom, *, transducer=None):
    """Metrics (module docstring) of a reduced contact response against the full one.

    Reads only the core columns and keys of :class:`ccedi.models.ContactResponse`, so any
    two contact models compare.

    Parameters
    ----------
    setup : DrumSetup
        The set-up both ran.
    fea, rom : ccedi.models.ContactResponse
        Full and reduced responses at the same output times.
    transducer : ccedi.rom.sensor.Transducer, optional
        The force transducer both forces are read through (default ``Transducer()``).

    Returns
    -------
    dict
        ``sensor_peak_force_error``, ``nrmse``, ``peak_force_error``,
        ``smoothed_peak_force_error``, ``contact_start_error_s``, ``contact_end_error_s``,
        ``max_stress_error``, ``impulse_error``, ``speedup``.

    Raises
    ------
    ValueError
        The output times differ.
    """
    hf, hr = fea.history, rom.history
    if not np.allclose(hf.time_s, hr.time_s):
        raise ValueError("the two responses must have the same output times")
    sf, sr = fea.summary, rom.summary
    t = hf.time_s.to_numpy()
    smooth_f = window_mean(t, hf.reaction_force_N.to_numpy(), SMOOTHING_S).max()
    smooth_r = window_mean(t, hr.reaction_force_N.to_numpy(), SMOOTHING_S).max()

    def diff(key):
        return None if sf[key] is None or sr[key] is None else sr[key] - sf[key]

    sensor = transducer or Transducer()
    sensor_f = sensor.measured(t, hf.reaction_force_N.to_numpy()).max()
    sensor_r = sensor.measured(t, hr.reaction_force_N.to_numpy()).max()
    return {"sensor_peak_force_error": sensor_r / sensor_f - 1.0,
            "nrmse": nrmse(tip_lag_series_m(setup, hr), tip_lag_series_m(setup, hf)),
            "peak_force_error": sr["peak_reaction_force_N"] / sf["peak_reaction_force_N"] - 1.0,
            "smoothed_peak_force_error": smooth_r / smooth_f - 1.0,
            "contact_start_error_s": diff("contact_start_s"), "contact_end_error_s": diff("contact_end_s"),
            "max_stress_error": sr["max_finger_stress_Pa"] / sf["max_finger_stress_Pa"] - 1.0,
            "impulse_error": (np.trapezoid(hr.reaction_force_N.to_numpy(), t)
                              / np.trapezoid(hf.reaction_force_N.to_numpy(), t) - 1.0),
            "speedup": sf["wall_time_s"] / sr["wall_time_s"]}


def _key_figures(response, transducer):
    keep = ("contact_start_s", "contact_end_s", "peak_reaction_force_N", "max_finger_stress_Pa", "wall_time_s")
    h = response.history
    measured = transducer.measured(h.time_s.to_numpy(), h.reaction_force_N.to_numpy())
    return {k: response.summary[k] for k in keep} | {"sensor_peak_reaction_force_N": float(measured.max())}


def contact_cases(setup: DrumSetup, *, alphas=(7.5, 180.0, 600.0), damping="global", t_end_s=1.5, n_outputs=3000,
                  progress=False, contact=None, full=None, reduced=None, transducer=None, forces=False):
    """Full contact model against reduced ones for every alpha.

    Parameters
    ----------
    setup : DrumSetup
        The set-up.
    alphas : sequence of float, optional
        Damping coefficients [1/s].
    damping : str, optional
        "global" or "relative".
    t_end_s : float, optional
        Simulated time [s].
    n_outputs : int, optional
        Output times (3000 over 1.5 s: 0.5 ms, which resolves the FE finger's ~400 Hz
        friction chatter before the transducer filters it).
    progress : bool, optional
        Progress bar of the full model.
    contact : str or sequence of str, optional
        The default ROMs' contact model(s) ("stations" and/or "face"; None: its default);
        each gets a co-rotational and a linear ROM, all against the same full runs.
    full : ccedi.models.ContactModel, optional
        The reference (default :class:`ccedi.fea.contact.drum.FullContactModel` of ``setup``).
    reduced : sequence of ccedi.models.ContactModel, optional
        The models checked (default: the co-rotational and the linear
        :class:`ccedi.rom.contact_rom.ReducedContactModel` with ``contact``).
    transducer : ccedi.rom.sensor.Transducer, optional
        The force transducer (default ``Transducer()``).
    forces : bool, optional
        Add ``forces`` to each case: ``time_s``, ``fea_N`` and ``rom_N``, the raw
        reaction forces (lists).

    Returns
    -------
    list of dict
        One case per alpha and reduced model: ``case``, ``kind``, ``model``, ``contact``
        (the ROM's contact model, None for given models), ``alpha_per_s``, the
        :func:`compare_contact` metrics, ``rom_build_time_s`` [s] (the default ROMs' mean
        build time; None for given models), ``fea`` and ``rom`` key figures (with
        ``sensor_peak_reaction_force_N`` [N]).
    """
    build = None
    transducer = transducer or Transducer()
    full = FullContactModel(setup) if full is None else full
    if reduced is None:
        contacts = [contact] if contact is None or isinstance(contact, str) else list(contact)
        t0 = time.perf_counter()
        reduced = [reduce_contact_model(full, n_segments=DEFAULT_SEGMENTS, nonlinear=nl, contact=c)
                   for c in contacts for nl in (True, False)]
        build = (time.perf_counter() - t0) / len(reduced)
    for r in reduced:
        r.run(alphas[0], damping=damping, t_end_s=1e-3, n_outputs=1)  # compile outside the timing
    cases = []
    for alpha in alphas:
        ref = full.run(alpha, damping=damping, t_end_s=t_end_s, n_outputs=n_outputs, progress=progress)
        for r in reduced:
            res = r.run(alpha, damping=damping, t_end_s=t_end_s, n_outputs=n_outputs)
            case = {"case": f"contact, {m_to_inch(setup.finger_length_m):.3g}-in finger, alpha {alpha:g} 1/s, "
                            f"{damping} damping",
                    "kind": "contact", "model": r.name, "contact": getattr(r, "contact", None),
                    "alpha_per_s": float(alpha), **compare_contact(setup, ref, res, transducer=transducer),
                    "rom_build_time_s": build, "fea": _key_figures(ref, transducer),
                    "rom": _key_figures(res, transducer)}
            if forces:
                case["forces"] = {"time_s": ref.history.time_s.tolist(),
                                  "fea_N": ref.history.reaction_force_N.tolist(),
                                  "rom_N": res.history.reaction_force_N.tolist()}
            cases.append(case)
    return cases


def impulse_cases(alphas=(20.0, 180.0), *, n_modes=6, force_N=0.1, duration_s=0.01, t_end_s=0.2, n_outputs=400,
                  material=RUBBER, semi_axes_m=SEMI_AXES, full=None):
    """Full FE impulse model against its modal ROM (before and after the fit), per alpha.

    Parameters
    ----------
    alphas : sequence of float, optional
        Damping coefficients [1/s].
    n_modes : int, optional
        Modes of the ROM.
    force_N : float, optional
        Tip pulse force [N] (small: the ROM is linear).
    duration_s : float, optional
        Pulse length [s].
    t_end_s : float, optional
        Simulated time [s].
    n_outputs : int, optional
        Output times.
    material : ccedi.fea.material.NeoHookean, optional
        Finger material (of the default full model).
    semi_axes_m : tuple, optional
        Section semi-axes [m] (of the default full model).
    full : ccedi.fea.cases.studies.FullImpulseModel, optional
        The full model (default: the 4.5-in finger of ``material`` and ``semi_axes_m``
        under ``force_N`` for ``duration_s``); reduced per alpha by
        :func:`ccedi.rom.modal.reduce_impulse_model`.

    Returns
    -------
    list of dict
        One case per alpha: ``case``, ``kind``, ``model``, ``alpha_per_s``, ``nrmse`` (after
        the fit), ``nrmse_before_fit``, ``frequency_error``, ``flexibility_share``,
        ``speedup`` (FE wall time over one ROM evaluation) and None contact metrics.
    """
    if full is None:
        full = finger_impulse_model(force_N=force_N, duration_s=duration_s, material=material,
                                    semi_axes_m=semi_axes_m)
    full.run(0.0, 1e-3, 1)                                            # compile outside the timing
    cases = []
    for alpha in alphas:
        fe = full.run(alpha, t_end_s, n_outputs)
        t, y = fe.tip_signal()
        rom = reduce_impulse_model(full, n_modes=n_modes, alpha=alpha).rom
        fit = fit_to_response(rom, t, y, force_N=full.force_N, duration_s=full.duration_s)
        repeats = 200
        t0 = time.perf_counter()
        for _ in range(repeats):
            fit.rom.pulse_response(t, full.force_N, full.duration_s)
        per_eval = (time.perf_counter() - t0) / repeats
        share = (rom.gain / rom.omega_rad_s**2) / rom.static_flexibility
        cases.append({"case": f"impulse, 4.5-in finger, {full.force_N:g} N for {full.duration_s:g} s, "
                              f"alpha {alpha:g} 1/s",
                      "kind": "impulse", "model": f"modal-{n_modes}", "alpha_per_s": float(alpha),
                      "nrmse": fit.nrmse_after, "nrmse_before_fit": fit.nrmse_before,
                      "frequency_error": (fit.rom.omega_rad_s / rom.omega_rad_s - 1.0).tolist(),
                      "flexibility_share": share.tolist(),
                      "peak_force_error": None, "contact_start_error_s": None, "contact_end_error_s": None,
                      "speedup": fe.summary["wall_time_s"] / per_eval})
    return cases
