"""Study steps that no other sub-command covers: the steel rod of the paper's section 2.2
(Figs. 3 and 4 analogues) and the SM-A / SM-B / detailed model comparison (Fig. 6 analogue)."""
# Imports inside functions: each step loads its own library stack (its command, Dask) when it
# runs, in the process that runs it.
from functools import partial

import numpy as np
import pandas as pd

from ccedi.outputs import write_csv, write_figure, write_json

from .figures import axes

FREE_PERIODS = 6
"""Free-vibration periods simulated after the steel rod's load for Fig. 4 [-]."""


def steel_rod(out):
    """CCEDI on the steel rod: alpha_cr by bisection from 2 omega_1, responses at the guess,
    at alpha_cr and, for contrast, at alpha_cr / 4 (Fig. 3), and at alpha = zeta alpha_cr against the published decay
    (Fig. 4).

    Every run goes through the rod's impulse model
    (:func:`ccedi.fea.cases.steel_rod.steel_rod_impulse_model`), 800 outputs per run; the
    Fig. 3 runs last :func:`ccedi.rom.finger_identification.run_length_s` (the load and
    12 / omega_1), the Fig. 4 run the load and ``FREE_PERIODS`` periods.

    Parameters
    ----------
    out : pathlib.Path
        Output directory; receives steel_rod.json, steel_rod_responses.csv,
        steel_rod_free_vibration.csv and the fig3/fig4 PNGs.

    Returns
    -------
    dict
        ``alpha_guess_per_s``, ``alpha_cr_per_s``, ``oscillating_bracket_per_s``,
        ``alpha_per_s``, the paper's values [1/s] and ``published_zeta`` [-],
        ``published_omega1_rad_s`` [rad/s], ``n_fe_runs``; the simulated free vibration's
        ``simulated_zeta`` [-], ``simulated_omega_d_rad_s`` [rad/s] and
        ``log_decrement_cycles``.
    """
    from ccedi.fea.cases.steel_rod import PAPER_ROD, STEEL_ROD, steel_rod_impulse_model
    from ccedi.rom.damping import log_decrement
    from ccedi.rom.finger_identification import rod_alpha_cr, run_length_s

    rod = steel_rod_impulse_model()
    omega1 = PAPER_ROD["omega1_rad_s"]
    n_outputs = 800
    crit = rod_alpha_cr(omega1_guess=omega1, model=rod, n_outputs=n_outputs)
    guess = 2.0 * omega1
    alpha = PAPER_ROD["zeta"] * crit.alpha_cr_per_s
    t_end = run_length_s(rod.duration_s, omega1)
    series = {name: rod.run(a, t_end, n_outputs).tip_signal()
              for name, a in (("initial_guess", guess), ("quarter_critical", 0.25 * crit.alpha_cr_per_s),
                              ("critical", crit.alpha_cr_per_s))}
    t = series["critical"][0]
    write_csv(out / "steel_rod_responses.csv",
              pd.DataFrame({"time_s": t, **{f"tip_uy_m_{k}": v[1] for k, v in series.items()}}))
    t_free, u_free = rod.run(alpha, STEEL_ROD["duration_s"] + FREE_PERIODS * 2 * np.pi / omega1,
                             n_outputs).tip_signal()
    write_csv(out / "steel_rod_free_vibration.csv", pd.DataFrame({"time_s": t_free, "tip_uy_m": u_free}))
    free = t_free > STEEL_ROD["duration_s"]
    dec = log_decrement(t_free[free], u_free[free], y_final=0.0)
    result = {"alpha_guess_per_s": guess, "alpha_cr_per_s": crit.alpha_cr_per_s, "n_fe_runs": crit.n_runs,
              "oscillating_bracket_per_s": crit.bracket_per_s[0],
              "alpha_per_s": alpha, "paper_alpha_cr_per_s": PAPER_ROD["alpha_cr_per_s"],
              "paper_alpha_per_s": PAPER_ROD["alpha_per_s"], "published_zeta": PAPER_ROD["zeta"],
              "published_omega1_rad_s": PAPER_ROD["omega1_rad_s"], "simulated_zeta": dec.zeta,
              "simulated_omega_d_rad_s": dec.omega_d_rad_s, "log_decrement_cycles": dec.n_cycles}
    fig, ax = axes(figsize=(7, 4.5))
    for name, label in (("initial_guess", f"initial guess 2 omega_1 = {guess:.4g} 1/s"),
                        ("quarter_critical", f"alpha_cr / 4 = {0.25 * crit.alpha_cr_per_s:.4g} 1/s (under-damped)"),
                        ("critical", f"alpha_cr = {crit.alpha_cr_per_s:.4g} 1/s (CCEDI, {crit.n_runs} runs)")):
        ax.plot(t, 1e3 * series[name][1], label=label)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set(xlabel="time [s]", ylabel="tip displacement [mm]",
           title="steel rod, 0.003 N for 0.2 s (paper Fig. 3 analogue)")
    ax.legend()
    write_figure(out / "fig3_steel_rod_alpha_cr.png", fig)
    fig, ax = axes(figsize=(7, 4.5))
    ax.plot(t_free, 1e3 * u_free, label=f"FEA, alpha = zeta alpha_cr = {alpha:.4g} 1/s")
    t0 = dec.peak_times_s[0]
    after = t_free >= t0
    env = dec.peak_amplitudes[0] * np.exp(-PAPER_ROD["zeta"] * PAPER_ROD["omega1_rad_s"] * (t_free[after] - t0))
    for sign in (1, -1):
        ax.plot(t_free[after], sign * 1e3 * env, "k--", lw=0.8,
                label="published decay, zeta = 0.0055 at 16.33 rad/s" if sign > 0 else None)
    ax.set(xlabel="time [s]", ylabel="tip displacement [mm]",
           title=f"steel rod free vibration (paper Fig. 4 analogue): log-decrement zeta = {dec.zeta:.4g}")
    ax.legend(loc="lower right")
    write_figure(out / "fig4_steel_rod_decay.png", fig)
    write_json(out / "steel_rod.json", result)
    return result


def _mesh_run(name, length_in, alpha, force_N, duration_s, t_end_s, material, semi_axes_m):
    from ccedi.fea.cases.studies import finger_impulse_model
    from ccedi.fea.mesh import sm_a, sm_b

    mesh = {"SM-A": sm_a, "SM-B": sm_b}[name](length_in=length_in, semi_axes_m=semi_axes_m)
    res = finger_impulse_model(force_N=force_N, duration_s=duration_s, material=material, mesh=mesh).run(
        alpha, t_end_s, 400)
    h = res.history[["time_s", "tip_uy_m", "max_von_mises_Pa"]].copy()
    h.insert(0, "model", name)
    return h, res.summary


def _mesh_model(name, length_in, alpha, force_N, duration_s, t_end_s, material, semi_axes_m, out):
    """One model of the Fig. 6 comparison: an explicit run of SM-A or SM-B (its history and
    summary, :func:`_mesh_run`), or the detailed model's comparison ("DM", its summary,
    :func:`dm_comparison`, which writes its own files in ``out``)."""
    if name == "DM":
        return dm_comparison(out, alpha=alpha, force_N=force_N, duration_s=duration_s, material=material)
    return _mesh_run(name, length_in, alpha, force_N, duration_s, t_end_s, material, semi_axes_m)


def mesh_comparison(out, *, length_in, alpha, force_N, duration_s, t_end_s, scheduler, material, semi_axes_m,
                    detailed_model=True):
    """Fig. 6 analogue: tip response and max von Mises stress of SM-A and SM-B (``material``,
    section semi-axes ``semi_axes_m`` [m]) under the same impulse at one alpha. Writes
    mesh_comparison.csv/.json and the figure; for the paper's finger, when
    ``detailed_model``, also the detailed model's half of Fig. 6 (:func:`dm_comparison`,
    summary under ``"detailed_model"``). The three are independent runs, mapped together over
    ``scheduler`` (the DM's first, the longest)."""
    from ccedi.distributed import map_runs
    from ccedi.fea.cases.studies import is_paper_finger

    run = partial(_mesh_model, length_in=length_in, alpha=alpha, force_N=force_N, duration_s=duration_s,
                  t_end_s=t_end_s, material=material, semi_axes_m=semi_axes_m, out=out)
    detailed = detailed_model and is_paper_finger(length_in, material, semi_axes_m)
    names = (["DM"] if detailed else []) + ["SM-B", "SM-A"]     # longest first: a cluster starts them in order
    results = dict(zip(names, map_runs(run, names, scheduler=scheduler, label="/".join(names))))
    runs = [results["SM-A"], results["SM-B"]]
    history = pd.concat([h for h, _ in runs], ignore_index=True)
    write_csv(out / "mesh_comparison.csv", history)
    fig, (a1, a2) = axes(2, figsize=(7, 7))
    summary = {"length_in": length_in, "alpha_per_s": alpha, "force_N": force_N, "duration_s": duration_s,
               "t_end_s": t_end_s, "models": {}}
    for (h, s), name in zip(runs, ("SM-A", "SM-B")):
        a1.plot(h.time_s, 1e3 * h.tip_uy_m, label=name)
        a2.plot(h.time_s, 1e-3 * h.max_von_mises_Pa, label=name)
        summary["models"][name] = {"peak_tip_uy_m": float(h.tip_uy_m.max()),
                                   "peak_von_mises_Pa": float(h.max_von_mises_Pa.max()),
                                   "wall_time_s": s["wall_time_s"], "steps": s["steps"]}
    a1.set(ylabel="tip displacement y [mm]",
           title=f"{length_in:g}-in finger, alpha = {alpha:g} 1/s (paper Fig. 6 analogue)")
    a2.set(xlabel="time [s]", ylabel="max von Mises stress [kPa]")
    a1.legend()
    write_figure(out / "fig6_mesh_comparison.png", fig)
    write_json(out / "mesh_comparison.json", summary)
    if detailed:
        summary["detailed_model"] = results["DM"]
    return summary


def dm_comparison(out, *, alpha, force_N, duration_s, material, t_end_s=0.2):
    """Fig. 6 with the detailed model: SM-A and the DM (2.8 mm,
    :func:`ccedi.fea.mesh.gmsh_fingers.detailed_model`) on their modal ROMs at ``alpha`` [1/s],
    and the DM's alpha whose response is nearest SM-A's
    (:func:`ccedi.rom.finger_identification.detailed_model_comparison`; the ROM against a
    full explicit run of the DM is ``validation/dm_fig6.py``). Writes dm_comparison.csv/.json
    and fig6_detailed_model.png in ``out``.

    Parameters
    ----------
    out : pathlib.Path
        Output directory.
    alpha : float
        Mass-proportional damping of the comparison [1/s].
    force_N, duration_s : float
        Tip pulse [N] along +y and how long it is held [s].
    material : ccedi.fea.material.NeoHookean
        Finger material.
    t_end_s : float, optional
        Simulated time [s]. Default 0.2.

    Returns
    -------
    dict
        ``alpha_per_s``, ``dm_matching_alpha_per_s`` (and the paper's), the relative RMS
        misfit of the match, whether each response is under-damped, per model
        ``peak_tip_uy_m`` [m], ``quasi_static_peak_von_mises_Pa`` [Pa], ``omega1_rad_s``,
        the DM's ``nodes`` and ``elements``, and ``wall_time_s``.
    """
    import time

    from ccedi.fea.mesh.gmsh_fingers import detailed_model
    from ccedi.rom.finger_identification import PAPER_FIG6, detailed_model_comparison

    t0 = time.perf_counter()
    dm = detailed_model()
    c = detailed_model_comparison(dm, alpha=alpha, force_N=force_N, duration_s=duration_s, t_end_s=t_end_s,
                                  material=material)
    a_m = c.match.alpha_per_s
    write_csv(out / "dm_comparison.csv", pd.DataFrame({"time_s": c.time_s, "sm_a_tip_uy_m": c.sm_a_tip_m,
                                                       "dm_tip_uy_m": c.dm_tip_m,
                                                       "dm_matched_tip_uy_m": c.dm_matched_tip_m}))
    fig, ax = axes(figsize=(7, 4.5))
    for y, label in ((c.sm_a_tip_m, f"SM-A, alpha = {alpha:g} 1/s"), (c.dm_tip_m, f"DM, alpha = {alpha:g} 1/s"),
                     (c.dm_matched_tip_m, f"DM, alpha = {a_m:.4g} 1/s (nearest SM-A)")):
        ax.plot(c.time_s, 1e3 * y, label=label)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set(xlabel="time [s]", ylabel="tip displacement y [mm]",
           title="4.5-in finger, SM-A and detailed model, 6-mode ROMs (paper Fig. 6 analogue)")
    ax.legend()
    write_figure(out / "fig6_detailed_model.png", fig)
    models = {name: {"peak_tip_uy_m": float(y.max()), "quasi_static_peak_von_mises_Pa": c.peak_stress_Pa[name],
                     "under_damped": u}
              for name, y, u in (("SM-A", c.sm_a_tip_m, c.sm_a_under_damped), ("DM", c.dm_tip_m, c.dm_under_damped),
                                 ("DM matched", c.dm_matched_tip_m, c.dm_matched_under_damped))}
    for name in ("SM-A", "DM"):
        models[name]["omega1_rad_s"] = c.omega1_rad_s[name]
    summary = {"alpha_per_s": alpha, "dm_matching_alpha_per_s": a_m,
               "paper_dm_matching_alpha_per_s": PAPER_FIG6["dm_matching_alpha_per_s"],
               "match_relative_rms_error": c.match.relative_rms_error, "t_end_s": t_end_s,
               "dm_nodes": dm.n_nodes, "dm_elements": dm.n_elements, "models": models,
               "wall_time_s": time.perf_counter() - t0}
    write_json(out / "dm_comparison.json", summary)
    return summary
