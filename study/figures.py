"""The study's figures, drawn from the libraries' results (the paper's Figs. 7, 10, 13, 14
analogues and the axes the other steps share): plotting belongs to the application, the
libraries return numbers."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the file-only backend)
import numpy as np  # noqa: E402


def axes(nrows=1, figsize=(7.5, 4.5)):
    """A figure of ``nrows`` axes stacked over a shared time axis.

    Parameters
    ----------
    nrows : int, optional
        Number of axes.
    figsize : tuple of float, optional
        Figure size [in].

    Returns
    -------
    tuple
        ``(figure, axes)`` as :func:`matplotlib.pyplot.subplots` returns them.
    """
    return plt.subplots(nrows, 1, figsize=figsize, sharex=True)


def plot_reaction_force(history):
    """Fig. 10 analogue: force on the object [N] against time [s], one line per alpha.

    Parameters
    ----------
    history : pandas.DataFrame
        Long history with alpha_per_s, time_s and reaction_force_N.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = axes()
    for a, h in history.groupby("alpha_per_s"):
        ax.plot(h.time_s, h.reaction_force_N, label=f"alpha = {a:g} 1/s")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("reaction force on the object [N]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def plot_stresses(history):
    """Fig. 14 analogue: (a) max finger von Mises [kPa], (b) max object von Mises [MPa],
    (c) reaction force [N] against time [s].

    Parameters
    ----------
    history : pandas.DataFrame
        Long history of :func:`ccedi.fea.cases.contact_study.sweep`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (a1, a2, a3) = axes(3, figsize=(7.5, 9))
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


def plot_contact_shapes(setup, shapes):
    """Fig. 13 analogue: finger centre lines at first and last contact for each alpha,
    with the object outline and the drum, in the drum plane [mm].

    Parameters
    ----------
    setup : ccedi.fea.contact.drum.DrumSetup
    shapes : dict
        {alpha: (first-contact positions (n, 3) [m], last-contact positions)}.

    Returns
    -------
    matplotlib.figure.Figure
    """
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


def plot_impulse_study(history, finger="SM-A finger"):
    """Tip displacement [mm] and max von Mises stress [kPa] against time [s], one line per alpha.

    Parameters
    ----------
    history : pandas.DataFrame
        The long history of :func:`ccedi.fea.cases.studies.impulse_study`.
    finger : str, optional
        The finger's name, for the title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    for a, h in history.groupby("alpha_per_s"):
        ax1.plot(h.time_s, 1e3 * h.tip_uy_m, label=f"alpha = {a:g} 1/s")
        ax2.plot(h.time_s, 1e-3 * h.max_von_mises_Pa)
    ax1.axhline(0.0, color="k", lw=0.5)
    ax1.set_ylabel("tip displacement y [mm]")
    ax2.set_ylabel("max von Mises stress [kPa]")
    ax2.set_xlabel("time [s]")
    ax1.legend()
    ax1.set_title(f"{finger}, tip impulse (paper Fig. 7 analogue)")
    fig.tight_layout()
    return fig
