"""The paper's section 3.4 study: the finger on the drum sweeping over the object for
several alpha; time histories, summaries and the analogues of Figs. 10, 13 and 14."""
from functools import partial

import numpy as np
import pandas as pd

from ccedi.distributed import map_runs
from ccedi.errors import InputError
from ccedi.fea.contact.drum import PAPER_CONTACT, DrumSetup, contact_run, contact_summary, finger_mesh
from ccedi.fea.solvers.validity import run_label

PAPER_ALPHAS = (1.0, 7.5, 20.0, 50.0, 180.0, 600.0)
"""The six damping coefficients of the paper's section 3.4 [1/s]."""

WARNING_SEPARATOR = " | "
"""How the summaries table (a CSV) joins a run's validity warnings into one cell."""

HISTORY_COLUMNS = ["time_s", "reaction_force_N", "contact_force_x_N", "contact_force_y_N", "max_von_mises_Pa",
                   "max_object_von_mises_Pa", "contact_nodes", "contact_point_x_m", "contact_point_y_m",
                   "contact_patch_start_m", "contact_patch_end_m", "max_penetration_m", "tip_ux_m", "tip_uy_m",
                   "penalty_energy_J", "friction_work_J", "external_work_J", "kinetic_energy_J",
                   "internal_energy_J", "damping_energy_J"]


def _contact_case(alpha, setup, damping, t_end_s, n_outputs, progress):
    """One run of :func:`sweep`: (summary dict, history DataFrame, (first, last) contact
    positions or None)."""
    res, model = contact_run(setup, float(alpha), damping=damping, t_end_s=t_end_s, n_outputs=n_outputs,
                             progress=progress, snapshot_every=1)
    s = contact_summary(setup, res, model)
    h = res.history[HISTORY_COLUMNS].copy()
    h.insert(0, "alpha_per_s", float(alpha))
    shape = None
    if s["contact_start_s"] is not None:
        times = np.array([t for t, _ in res.snapshots])
        pick = [int(np.argmin(abs(times - s[k]))) for k in ("contact_start_s", "contact_end_s")]
        shape = tuple(res.snapshots[i][1] for i in pick)
    return s, h, shape


def sweep(setup: DrumSetup, *, alphas=PAPER_ALPHAS, damping="global", t_end_s=1.5, n_outputs=300, progress=False,
          scheduler="serial"):
    """Run every alpha, mapped through :func:`ccedi.distributed.map_runs` (``scheduler``).
    Returns (long history DataFrame with an alpha_per_s column, summaries DataFrame,
    {alpha: (first-contact positions, last-contact positions)}).

    Parameters
    ----------
    setup : DrumSetup
    alphas : sequence of float, optional
        Damping coefficients [1/s].
    damping : str, optional
        "global" or "relative".
    t_end_s : float, optional
        Simulated time [s].
    n_outputs : int, optional
        Output times.
    progress : bool, optional
        Progress bars (serial scheduler only).
    scheduler : str, optional
        :func:`ccedi.distributed.map_runs` scheduler.

    Returns
    -------
    tuple
        (history DataFrame of :data:`HISTORY_COLUMNS` with alpha_per_s, summaries
        DataFrame of :func:`ccedi.fea.contact.drum.contact_summary` (list values as text, the
        ``warnings`` joined by :data:`WARNING_SEPARATOR`, empty for a healthy run),
        shapes dict).
    """
    case = partial(_contact_case, setup=setup, damping=damping, t_end_s=t_end_s, n_outputs=n_outputs,
                   progress=progress and scheduler == "serial")
    runs = map_runs(case, alphas, scheduler=scheduler, label="contact runs")
    shapes = {float(a): shape for a, (_, _, shape) in zip(alphas, runs) if shape is not None}
    table = pd.DataFrame([{k: (WARNING_SEPARATOR.join(v) if k == "warnings" else str(v) if isinstance(v, list) else v)
                           for k, v in r.items()} for r, _, _ in runs])
    return pd.concat([h for _, h, _ in runs], ignore_index=True), table, shapes


def tip_drum_frame_displacement_m(setup: DrumSetup, history):
    """The tip's displacement from the rigidly turning finger's tip [m], in the finger's
    own turning directions: radial (along the undeformed finger, outward) and tangential
    (along the drum's motion), at every row of a contact history.

    Parameters
    ----------
    setup : DrumSetup
    history : pandas.DataFrame
        A contact history with the core columns time_s, tip_ux_m and tip_uy_m (the tip's
        displacement from its initial position; any :class:`ccedi.models.ContactModel`).

    Returns
    -------
    numpy.ndarray
        (n, 2): radial and tangential displacement [m] per row.
    """
    t = history.time_s.to_numpy()
    r_tip = setup.drum_radius_m + setup.finger_length_m
    th0 = setup.theta0_rad
    th = th0 + setup.omega_rad_s * t
    dx = r_tip * np.cos(th0) + history.tip_ux_m.to_numpy() - r_tip * np.cos(th)
    dy = r_tip * np.sin(th0) + history.tip_uy_m.to_numpy() - r_tip * np.sin(th)
    return np.column_stack([dx * np.cos(th) + dy * np.sin(th), -dx * np.sin(th) + dy * np.cos(th)])


def tip_lag_series_m(setup: DrumSetup, history):
    """How far the finger tip trails the rigidly turning finger [m] (positive = behind,
    along the drum's tangential direction) at every row of a contact history: minus the
    tangential part of :func:`tip_drum_frame_displacement_m`.

    Parameters
    ----------
    setup : DrumSetup
    history : pandas.DataFrame
        A contact history with the core columns time_s, tip_ux_m and tip_uy_m (any
        :class:`ccedi.models.ContactModel`).

    Returns
    -------
    numpy.ndarray
        Lag [m] per row.
    """
    return -tip_drum_frame_displacement_m(setup, history)[:, 1]


def window_mean(t, values, window_s):
    """Centred moving average of ``values`` over ``window_s`` [s] (outputs equally spaced at
    the step of ``t``; near the ends, the mean of the part of the window inside the record;
    a window longer than the record is cut to its length).

    Parameters
    ----------
    t : numpy.ndarray
        Times [s], equally spaced.
    values : numpy.ndarray
        Values at ``t``.
    window_s : float
        Window [s].

    Returns
    -------
    numpy.ndarray
        Averaged values.
    """
    n = min(len(values), max(1, int(round(window_s / float(np.median(np.diff(t)))))))   # a record shorter than the window
    kernel = np.ones(n)
    return np.convolve(values, kernel, mode="same") / np.convolve(np.ones_like(values), kernel, mode="same")


def tip_lag_m(setup: DrumSetup, history, t_s):
    """:func:`tip_lag_series_m` at the output nearest ``t_s`` [s].

    Parameters
    ----------
    setup : DrumSetup
    history : pandas.DataFrame
    t_s : float
        Time [s].

    Returns
    -------
    float
        Lag [m].
    """
    k = int(np.argmin(np.abs(history.time_s.to_numpy() - t_s)))
    return float(tip_lag_series_m(setup, history)[k])


def run_warnings(table):
    """The validity warnings of every run of a summaries table, named by alpha.

    Parameters
    ----------
    table : pandas.DataFrame or None
        Summaries of :func:`sweep` (or read back from its CSV, where a run without
        warnings has an empty cell), with alpha_per_s, damping and warnings.

    Returns
    -------
    list of str
        ``"alpha = 7.5 1/s: <warning>"`` per warning, in table order (none for None).
    """
    if table is None or "warnings" not in table:
        return []
    return [f"{run_label(float(r.alpha_per_s), r.damping)}: {w}" for _, r in table.iterrows()
            if isinstance(r.warnings, str) and r.warnings for w in r.warnings.split(WARNING_SEPARATOR)]


def validity_lines(global_table, relative_table=None):
    """Markdown list of the sweeps' validity warnings (:func:`run_warnings`), or a line
    saying there are none.

    Parameters
    ----------
    global_table : pandas.DataFrame
        Summaries of the global-damping sweep.
    relative_table : pandas.DataFrame, optional
        Summaries of the relative-damping sweep.

    Returns
    -------
    list of str
        Markdown lines.
    """
    if "warnings" not in global_table:
        return ["Not recorded: these summaries were written without the validity checks."]
    found = run_warnings(global_table) + run_warnings(relative_table)
    if not found:
        return ["None: every run kept its energy balance, hourglass energy and strains within the limits of "
                "`ccedi.fea.solvers.validity`."]
    return [f"- {w}" for w in found]


def _summary_lines(table, paper):
    """One Markdown row per run of a sweep summary, with the paper's contact timings in
    parentheses where ``paper`` (the global-damping sweep at the paper's alphas)."""
    lines = []
    for _, r in table.iterrows():
        a = float(r.alpha_per_s)
        p_first = PAPER_CONTACT["first_contact_s"].get(a) if paper else None
        p_dur = PAPER_CONTACT["contact_duration_s"].get(a) if paper else None
        last = r.last_contact_point_m if isinstance(r.last_contact_point_m, str) else "-"
        if last != "-":
            xy = [1e3 * float(v) for v in last.strip("[]").split(",")]
            last = f"({xy[0]:.1f}, {xy[1]:.1f})"
        if pd.isna(r.contact_start_s):
            lines.append(f"| {a:g} | no contact within the run | - | - | - | - | {r.peak_reaction_force_N:.2f} | "
                         f"{1e-6 * r.max_finger_stress_Pa:.3f} | - | - | {r.energy_balance_error:.4f} |")
            continue
        lines.append(f"| {a:g} | {r.contact_start_s:.3f}" + (f" ({p_first:g})" if p_first else "")
                     + f" | {r.first_contact_side} | {r.contact_end_s:.3f} | {r.contact_duration_s:.3f}"
                     + (f" ({p_dur:g})" if p_dur else "") + f" | {last} | {r.peak_reaction_force_N:.2f} | "
                     f"{1e-6 * r.max_finger_stress_Pa:.3f} | {1e-6 * r.max_object_stress_Pa:.3f} | "
                     f"{r.penetration_to_thickness:.4f} | {r.energy_balance_error:.4f} |")
    return lines


def contact_report(setup: DrumSetup, global_table, global_history, *, relative_table=None, relative_history=None):
    """Markdown of a contact sweep: the global-damping sweep against the paper (section
    3.4) and against relative damping, or the relative-damping sweep alone. Tables are the
    summaries of :func:`sweep`; histories the long frames.

    Parameters
    ----------
    setup : DrumSetup
    global_table, global_history : pandas.DataFrame or None
        Summaries and history of the global-damping sweep (None: not run).
    relative_table, relative_history : pandas.DataFrame, optional
        The same for relative damping.

    Returns
    -------
    str
        Markdown.

    Raises
    ------
    InputError
        Neither sweep is given.
    """
    if global_table is None and relative_table is None:
        raise InputError("contact_report needs the summary of a global or a relative damping sweep, got neither")
    finger = finger_mesh(setup)
    lines = ["# Finger on the rotating drum: contact study", "",
             f"Set-up: drum radius {1e3 * setup.drum_radius_m:g} mm, finger {1e3 * setup.finger_length_m:g} mm "
             f"({'SM-A' if setup.finger is None else 'given mesh'}, {finger.n_elements} {finger.element_type}), omega {setup.omega_rad_s:g} rad/s, object semi-axes "
             f"{1e3 * setup.object_semi_axes_m[0]:g} x {1e3 * setup.object_semi_axes_m[1]:g} mm at "
             f"({1e3 * setup.object_center_m[0]:g}, {1e3 * setup.object_center_m[1]:g}) mm, mu {setup.friction:g}, "
             f"initial angle {setup.theta0_rad:.5f} rad (calibrated: alpha = 7.5 1/s touches at 0.32 s). "
             "Object rigid in the dynamics; its stress from a linear static FE solve at each output.", ""]
    header = ["| alpha [1/s] | first contact [s]{} | side | last contact [s] | duration [s]{} | "
              "break-away point [mm] | peak force [N] | max finger stress [MPa] | max object stress [MPa] | "
              "penetration / thickness | energy error |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    if global_table is not None:
        lines += ["## Global damping (the paper's), against the paper", "",
                  header[0].format(" (paper)", " (paper)"), header[1], *_summary_lines(global_table, paper=True)]
    else:
        lines += ["## Relative damping (on the velocity relative to the drum: a finger turned in air)", "",
                  header[0].format("", ""), header[1], *_summary_lines(relative_table, paper=False)]
    lines += ["", "## Validity warnings", ""] + validity_lines(*[t for t in (global_table, relative_table)
                                                               if t is not None])
    if global_table is not None and relative_table is not None:
        lines += ["", "## Global against relative damping", "",
                  "Global mass damping acts on the absolute velocity, so it drags a turning finger back "
                  "(a load alpha rho A omega r per unit length); relative damping acts on the velocity in the "
                  "drum frame and leaves a rigidly turning finger alone. Tip lag behind the rigidly turning "
                  "finger at 0.3 s (before any contact), and the contact timings:", "",
                  "| alpha [1/s] | damping | tip lag at 0.3 s [mm] | first contact [s] | duration [s] | "
                  "peak force [N] |", "|---|---|---|---|---|---|"]
        for name, table, hist in (("global", global_table, global_history),
                                  ("relative", relative_table, relative_history)):
            for _, r in table.iterrows():
                if float(r.alpha_per_s) not in set(relative_table.alpha_per_s):
                    continue
                h = hist[hist.alpha_per_s == r.alpha_per_s]
                lines.append(f"| {r.alpha_per_s:g} | {name} | {1e3 * tip_lag_m(setup, h, 0.3):.2f} | "
                             f"{r.contact_start_s:.3f} | {r.contact_duration_s:.3f} | {r.peak_reaction_force_N:.2f} |")
    lines += ["", "Figures: `fig10_reaction_force_*.png` (force on the object), `fig13_contact_shapes_*.png` "
              "(finger at first and last contact), `fig14_stresses_*.png` (finger and object stress, force).", ""]
    return "\n".join(lines)
