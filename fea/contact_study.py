"""The paper's section 3.4 study: the finger on the drum sweeping over the object for
several alpha; time histories, summaries and the analogues of Figs. 10, 13 and 14."""
import numpy as np
import pandas as pd

from .drum import DrumSetup, contact_run, contact_summary

PAPER_ALPHAS = (1.0, 7.5, 20.0, 50.0, 180.0, 600.0)
"""The six damping coefficients of the paper's section 3.4 [1/s]."""

HISTORY_COLUMNS = ["time_s", "reaction_force_N", "contact_force_x_N", "contact_force_y_N", "max_von_mises_Pa",
                   "max_object_von_mises_Pa", "contact_nodes", "contact_point_x_m", "contact_point_y_m",
                   "contact_patch_start_m", "contact_patch_end_m", "max_penetration_m", "tip_ux_m", "tip_uy_m",
                   "penalty_energy_J", "friction_work_J", "external_work_J", "kinetic_energy_J",
                   "internal_energy_J", "damping_energy_J"]


def sweep(setup: DrumSetup, alphas=PAPER_ALPHAS, damping="global", t_end_s=1.5, n_outputs=300, progress=False):
    """Run every alpha. Returns (long history DataFrame with an alpha_per_s column,
    summaries DataFrame, {alpha: (first-contact positions, last-contact positions)})."""
    frames, rows, shapes = [], [], {}
    for a in alphas:
        res, model = contact_run(setup, float(a), damping=damping, t_end_s=t_end_s, n_outputs=n_outputs,
                                 progress=progress, snapshot_every=1)
        s = contact_summary(setup, res, model)
        rows.append(s)
        h = res.history[HISTORY_COLUMNS].copy()
        h.insert(0, "alpha_per_s", float(a))
        frames.append(h)
        if s["contact_start_s"] is not None:
            times = np.array([t for t, _ in res.snapshots])
            pick = [int(np.argmin(abs(times - s[k]))) for k in ("contact_start_s", "contact_end_s")]
            shapes[float(a)] = tuple(res.snapshots[i][1] for i in pick)
    table = pd.DataFrame([{k: (str(v) if isinstance(v, list) else v) for k, v in r.items()} for r in rows])
    return pd.concat(frames, ignore_index=True), table, shapes


def _axes(nrows=1, figsize=(7.5, 4.5)):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt.subplots(nrows, 1, figsize=figsize, sharex=True)


def plot_reaction_force(history):
    """Fig. 10 analogue: force on the object [N] against time [s], one line per alpha."""
    fig, ax = _axes()
    for a, h in history.groupby("alpha_per_s"):
        ax.plot(h.time_s, h.reaction_force_N, label=f"alpha = {a:g} 1/s")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("reaction force on the object [N]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def plot_stresses(history):
    """Fig. 14 analogue: (a) max finger von Mises [kPa], (b) max object von Mises [MPa],
    (c) reaction force [N] against time [s]."""
    fig, (a1, a2, a3) = _axes(3, figsize=(7.5, 9))
    for a, h in history.groupby("alpha_per_s"):
        a1.plot(h.time_s, 1e-3 * h.max_von_mises_Pa, label=f"alpha = {a:g} 1/s")
        a2.plot(h.time_s, 1e-6 * h.max_object_von_mises_Pa)
        a3.plot(h.time_s, h.reaction_force_N)
    a1.set_ylabel("finger max von Mises [kPa]")
    a2.set_ylabel("object max von Mises [MPa]")
    a3.set_ylabel("reaction force [N]")
    a3.set_xlabel("time [s]")
    a1.legend(fontsize=8)
    fig.tight_layout()
    return fig


def plot_contact_shapes(setup: DrumSetup, shapes, model_hexes=None):
    """Fig. 13 analogue: finger centre lines at first and last contact for each alpha,
    with the object outline and the drum, in the drum plane [mm]."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 5.5), sharex=True, sharey=True)
    th = np.linspace(0, 2 * np.pi, 200)
    a, b = setup.object_semi_axes_m
    ca, sa = np.cos(setup.object_angle_rad), np.sin(setup.object_angle_rad)
    ox = setup.object_center_m[0] + a * np.cos(th) * ca - b * np.sin(th) * sa
    oy = setup.object_center_m[1] + a * np.cos(th) * sa + b * np.sin(th) * ca
    for ax, k, title in ((axes[0], 0, "first contact"), (axes[1], 1, "last contact")):
        ax.fill(1e3 * ox, 1e3 * oy, color="0.85", label="object")
        ax.plot(1e3 * setup.drum_radius_m * np.cos(th), 1e3 * setup.drum_radius_m * np.sin(th), "k-", lw=0.8)
        for alpha, pair in shapes.items():
            x = pair[k]
            ax.plot(1e3 * x[:, 0], 1e3 * x[:, 1], ".", ms=1.5, label=f"alpha = {alpha:g} 1/s")
        ax.set_title(title)
        ax.set_aspect("equal")
        ax.set_xlabel("x [mm]")
    axes[0].set_ylabel("y [mm]")
    axes[0].legend(fontsize=8, markerscale=6)
    fig.tight_layout()
    return fig
