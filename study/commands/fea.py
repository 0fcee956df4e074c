"""``ccedi`` sub-commands of the explicit FEA (:mod:`ccedi.fea`).

  table1         the paper's Table 1 for SM-A, SM-B, SM-C, DM and a [finger] mesh (nodes, elements, time step, stiffness)
  impulse        impulse response of the SM-A finger for several alpha (paper Fig. 7), CSV + plot
  contact        the finger on the drum over the object (paper 3.3-3.4), one alpha
  contact-sweep  the same for several alpha; paper Figs. 10, 13, 14 analogues
  contact-report contact_report.md from the CSVs a sweep wrote
"""
# Imports inside functions: building the parser imports no library, so that `ccedi --help`
# answers at once (tests/conventions/test_layout.py); each command loads what it runs.
import math
from pathlib import Path

from ccedi.errors import InputError
from ccedi.fea.solvers.budget import check_outputs
from ccedi.study.commands.arguments import (
    CONTACT_KEYS,
    IMPULSE_FINGER_KEYS,
    add_command,
    add_config_argument,
    add_output_argument,
    add_scheduler_argument,
    check_flag,
    load_config,
)


def _fmt(value):
    return value if isinstance(value, str) else (f"{value:d}" if isinstance(value, int) else f"{value:.4g}")


def write_table1(cfg, length_in, *, json_path=None, stiffness=True, detailed=True, detailed_stiffness=None,
                 detailed_omega1=True):
    """Print Table 1 of the configured finger (for the paper's finger, with the detailed
    model DM's row and the paper's values) and write it as JSON.

    Parameters
    ----------
    cfg : dict
        Validated inputs (:func:`ccedi.study.config.load`).
    length_in : float
        Finger length [in].
    json_path : str or Path, optional
        Where to write the table.
    stiffness : bool
        Also solve for the tip stiffness [N/m].
    detailed : bool
        Add the detailed model DM's row (for the paper's finger only).
    detailed_stiffness : bool or None
        Solve the DM's tip stiffness (None: as ``stiffness``; its nonlinear solves at
        2.8 mm take tens of minutes).
    detailed_omega1 : bool
        Solve the DM's first natural frequency (about 50 s).

    Returns
    -------
    dict
        ``{model name: {column: value}}``.
    """
    from ccedi.fea.cases.studies import PAPER_TABLE1, is_paper_finger, table1
    from ccedi.outputs import write_json
    from ccedi.study.config import configured_mesh, finger_inputs

    material, semi_axes = finger_inputs(cfg)
    finger = configured_mesh(cfg)
    paper_finger = is_paper_finger(length_in, material, semi_axes)
    result = table1(length_in=length_in, material=material, stiffness=stiffness, semi_axes_m=semi_axes,
                    finger=finger, detailed=detailed and paper_finger, detailed_stiffness=detailed_stiffness,
                    detailed_omega1=detailed_omega1, progress=lambda line: print(f"table1: {line}", flush=True))
    for name, row in result.items():
        paper = PAPER_TABLE1.get(name, {}) if paper_finger else {}
        print(f"{name}: " + ", ".join(
            f"{k} = {_fmt(v)}" + (f" (paper {_fmt(paper[k])})" if k in paper else "") for k, v in row.items()))
    if json_path:
        write_json(json_path, result)
        print(f"wrote {json_path}")
    return result


def write_finger(cfg, json_path, stiffness=True):
    """The configured finger's own row (the ``[finger] mesh``, or the generated finger of
    ``[finger] impulse_length_in``): its mesh, stable step, tip stiffness, first natural
    frequency and the element that sets its step, printed and written as JSON.

    Parameters
    ----------
    cfg : dict
        Validated inputs (:func:`ccedi.study.config.load`).
    json_path : str or Path
        Where to write the row.
    stiffness : bool, optional
        Also solve the nonlinear static tip stiffness [N/m].

    Returns
    -------
    dict
        The finger's description (:func:`finger_of`) and its Table 1 row
        (:func:`ccedi.fea.cases.studies.table1_row`, with ``omega1_rad_s``), plus
        ``f1_hz`` [Hz], ``mass_kg`` [kg], ``alpha_cr_first_mode_per_s`` (2 omega_1, the
        mass-proportional damping that makes the first mode critically damped [1/s]) and
        ``step_set_by`` (the element that sets the stable step: name, size [m], centroid [m]).
    """
    from ccedi.fea.cases.studies import table1_row
    from ccedi.fea.mesh import sm_a
    from ccedi.fea.model import cantilever_model
    from ccedi.fea.solvers.explicit import limiting_element
    from ccedi.outputs import write_json
    from ccedi.study.config import finger_inputs

    material, _ = finger_inputs(cfg)
    mesh, length_in, finger = finger_of(cfg)
    if mesh is None:
        mesh = sm_a(length_in=length_in, semi_axes_m=cfg["finger"]["section_semi_axes_m"])
    print("finger: the stable step, " + ("the tip stiffness (nonlinear static solves), " if stiffness else "")
          + "the first natural frequency (modal solve)", flush=True)
    row = table1_row(mesh, material, stiffness=stiffness, omega1=True)
    model = cantilever_model(mesh, material)
    limiting = limiting_element(model)
    omega1 = row["omega1_rad_s"]
    result = {**finger, **row, "f1_hz": omega1 / (2.0 * math.pi), "mass_kg": float(model.total_mass),
              "alpha_cr_first_mode_per_s": 2.0 * omega1,
              "step_set_by": {"element": limiting["element"], "length_m": limiting["length_m"],
                              "median_length_m": limiting["median_length_m"],
                              "centroid_m": [float(c) for c in limiting["centroid_m"]]}}
    print(f"finger: {finger['name']}: stable step {_fmt(row['dt_us'])} us, first frequency "
          f"{_fmt(result['f1_hz'])} Hz, 2 omega_1 = {_fmt(result['alpha_cr_first_mode_per_s'])} 1/s"
          + (f", tip stiffness {_fmt(row['stiffness_N_per_m'])} N/m" if stiffness else ""), flush=True)
    write_json(json_path, result)
    print(f"wrote {json_path}")
    return result


def write_impulse(cfg, alphas, out, *, length_in=None, force_N=1.0, duration_s=0.01, t_end_s=0.2, scheduler="serial"):
    """Impulse responses of the configured finger (the ``[finger] mesh`` of ``cfg``, or the
    SM-A finger of ``length_in``) for several alpha: writes
    ``impulse_response.csv``, ``.png`` and ``impulse_summary.json`` in ``out`` (each run's
    summary with its validity ``warnings``, and all of them, named by alpha, under the
    top-level ``warnings``).

    Parameters
    ----------
    cfg : dict
        Validated inputs (:func:`ccedi.study.config.load`).
    alphas : sequence of float
        Mass-proportional damping values [1/s].
    out : str or Path
        Output directory.
    length_in : float or None
        Length [in] of the SM-A finger (default 4.5); None with a ``[finger] mesh``.
    force_N : float
        Tip force [N], soft direction.
    duration_s : float
        Pulse duration [s].
    t_end_s : float
        Simulated time [s].
    scheduler : str
        ``serial``, ``local`` or a Dask scheduler address (:mod:`ccedi.distributed`).
    """
    import numpy as np

    from ccedi.fea.cases.studies import impulse_study
    from ccedi.fea.solvers.validity import run_label
    from ccedi.outputs import write_csv, write_figure, write_json
    from ccedi.study.config import finger_inputs
    from ccedi.study.figures import plot_impulse_study

    out = Path(out)
    material, semi_axes = finger_inputs(cfg)
    mesh, length_in, finger = finger_of(cfg, length_in)
    history, summaries = impulse_study(alphas=alphas, length_in=length_in, force_N=force_N,
                                       duration_s=duration_s, t_end_s=t_end_s, scheduler=scheduler,
                                       material=material, semi_axes_m=semi_axes, mesh=mesh)
    write_csv(out / "impulse_response.csv", history)
    write_figure(out / "impulse_response.png", plot_impulse_study(history, finger["name"]))
    peaks = {}
    for a, h in history.groupby("alpha_per_s"):
        i = int(np.argmax(h.tip_uy_m.values))
        peaks[f"{a:g}"] = {"peak_tip_uy_m": float(h.tip_uy_m.values[i]),
                           "time_of_peak_s": float(h.time_s.values[i]),
                           "min_tip_uy_after_peak_m": float(h.tip_uy_m.values[i:].min()),
                           "peak_von_mises_Pa": float(h.max_von_mises_Pa.max())}
    write_json(out / "impulse_summary.json", {
        "finger": finger, "force_N": force_N, "duration_s": duration_s,
        "warnings": [f"{run_label(s['alpha_per_s'])}: {w}" for s in summaries for w in s["warnings"]],
        "runs": summaries, "peaks": peaks})
    for s in summaries:
        print(f"alpha = {s['alpha_per_s']:g} 1/s: {s['steps']} steps, dt0 = {s['dt_initial_s'] * 1e6:.3f} us, "
              f"wall {s['wall_time_s']:.2f} s ({s['ns_per_element_cycle']:.0f} ns/element-cycle)")
    print(f"wrote {out}/impulse_response.csv, .png, impulse_summary.json")


def contact_setup(cfg, theta0_rad=None, calibrate=False):
    """The drum set-up of ``cfg`` (its ``[finger] mesh`` on the drum when set, read now),
    with the initial angle given or recalibrated.

    Parameters
    ----------
    cfg : dict
        Validated inputs (:func:`ccedi.study.config.load`).
    theta0_rad : float, optional
        Initial finger angle [rad] instead of the configured one.
    calibrate : bool
        Recalibrate theta0 so that alpha = 7.5 1/s first touches at t = 0.32 s
        (:func:`ccedi.fea.contact.drum.calibrate_initial_angle`; prints the iterations).

    Returns
    -------
    ccedi.fea.contact.drum.DrumSetup
    """
    from dataclasses import replace

    from ccedi.fea.contact.drum import calibrate_initial_angle
    from ccedi.study.config import configured_mesh, drum_setup

    setup = drum_setup(cfg, finger=configured_mesh(cfg))
    if theta0_rad is not None:
        setup = replace(setup, theta0_rad=theta0_rad)
    if calibrate:
        theta0, steps = calibrate_initial_angle(setup)
        for th, t_c in steps:
            print(f"theta0 = {th:.5f} rad: first contact at {t_c:.4f} s")
        setup = replace(setup, theta0_rad=theta0)
    return setup


def _setup_of(args):
    check_flag("--t-end-s", args.t_end_s, section="study", key="contact_t_end_s")
    check_outputs(args.n_outputs, "--n-outputs")
    check_flag("--theta0-rad", args.theta0_rad, section="drum", key="theta0_rad")
    return contact_setup(load_config(args), args.theta0_rad, args.calibrate)


def finger_of(cfg, length_in=None):
    """The finger a command runs: the ``[finger] mesh`` of ``cfg`` (read now), or the SM-A
    finger of ``length_in``.

    Parameters
    ----------
    cfg : dict
        Validated inputs (:func:`ccedi.study.config.load`).
    length_in : float or None
        ``--length-in`` [in] as given (None: not given; SM-A then has ``[finger]
        impulse_length_in``, 4.5 in by default).

    Returns
    -------
    tuple
        ``(mesh, length_in, finger)``: the imported mesh (None for SM-A), the SM-A length
        [in] (None with a mesh) and a JSON-ready description, ``name``, ``mesh_file``,
        ``element_type``, ``nodes``, ``elements``, ``length_m``.

    Raises
    ------
    InputError
        ``--length-in`` given beside a ``[finger] mesh`` (the mesh sets the length), or the
        mesh cannot be read.
    """
    from ccedi.fea.mesh import sm_a
    from ccedi.fea.solvers.validity import cantilever_length_m
    from ccedi.study.config import check_section_fits, configured_mesh

    mesh = configured_mesh(cfg)
    if mesh is not None and length_in is not None:
        raise InputError(f"--length-in {length_in:g}: the finger is [finger] mesh = {cfg['finger']['mesh']}, "
                         "whose length the mesh sets; drop --length-in")
    if mesh is None and length_in is not None:
        check_section_fits(cfg, length_in, "--length-in")
    length_in = None if mesh is not None else (cfg["finger"]["impulse_length_in"] if length_in is None else length_in)
    shown = mesh if mesh is not None else sm_a(length_in=length_in, semi_axes_m=cfg["finger"]["section_semi_axes_m"])
    finger = {"name": f"SM-A {length_in:g}-in finger" if mesh is None else Path(cfg["finger"]["mesh"]).name,
              "mesh_file": None if mesh is None else cfg["finger"]["mesh"], "element_type": shown.element_type,
              "nodes": shown.n_nodes, "elements": shown.n_elements, "length_m": cantilever_length_m(shown)}
    print(f"finger: {finger['name']}: {finger['nodes']} nodes, {finger['elements']} {finger['element_type']} "
          f"elements, length {1e3 * finger['length_m']:.1f} mm", flush=True)
    return mesh, length_in, finger


def _cmd_table1(args):
    from ccedi.study.config import check_section_fits

    check_flag("--length-in", args.length_in, section="finger", key="impulse_length_in")
    cfg = load_config(args)
    if args.length_in is not None:
        check_section_fits(cfg, args.length_in, "--length-in")
    stiffness = not args.no_stiffness and cfg["study"]["table1_stiffness"]
    detailed = not args.no_detailed_model and cfg["study"]["detailed_model"]
    print("table1: SM-A, SM-B and SM-C" + (" with their tip stiffness (nonlinear static solves, about 25 s here)"
                                           if stiffness else "")
          + ("" if not detailed else ", and the DM " + ("with its stiffness and first frequency (about "
                                                        "30 CPU-minutes more)" if args.detailed_model_solves
                                                        else "(its mesh and time step)")), flush=True)
    write_table1(cfg, cfg["finger"]["impulse_length_in"] if args.length_in is None else args.length_in,
                 json_path=args.json, stiffness=stiffness, detailed=detailed,
                 detailed_stiffness=args.detailed_model_solves, detailed_omega1=args.detailed_model_solves)


def _cmd_impulse(args):
    if args.alpha is not None:
        # every alpha before the first run
        check_flag("--alpha", list(args.alpha), section="study", key="impulse_alphas_per_s")
    check_flag("--length-in", args.length_in, section="finger", key="impulse_length_in")
    check_flag("--force-N", args.force_N, section="study", key="impulse_force_N")
    check_flag("--duration-s", args.duration_s, section="study", key="impulse_duration_s")
    check_flag("--t-end-s", args.t_end_s, section="study", key="impulse_t_end_s")
    cfg = load_config(args)
    s = cfg["study"]
    write_impulse(cfg, s["impulse_alphas_per_s"] if args.alpha is None else args.alpha, args.out,
                  length_in=args.length_in,
                  force_N=s["impulse_force_N"] if args.force_N is None else args.force_N,
                  duration_s=s["impulse_duration_s"] if args.duration_s is None else args.duration_s,
                  t_end_s=s["impulse_t_end_s"] if args.t_end_s is None else args.t_end_s, scheduler=args.scheduler)


def _cmd_contact(args):
    from ccedi.fea.contact.drum import contact_run, contact_summary
    from ccedi.fea.io.vtu import write_series
    from ccedi.outputs import write_csv, write_json

    check_flag("--alpha", [args.alpha], section="study", key="contact_alphas_per_s")
    setup = _setup_of(args)
    out = Path(args.out)
    print(f"contact: alpha = {args.alpha:g} 1/s, {args.damping} damping, {args.t_end_s:g} s simulated", flush=True)
    result, model = contact_run(setup, args.alpha, damping=args.damping, t_end_s=args.t_end_s,
                                n_outputs=args.n_outputs, progress=True, snapshot_every=5 if args.vtu else 0)
    summary = contact_summary(setup, result, model)
    stem = f"contact_alpha{args.alpha:g}_{args.damping}"
    write_csv(out / f"{stem}.csv", result.history)
    write_json(args.json or out / f"{stem}.json", summary)
    if args.vtu:
        print(f"wrote {write_series(args.vtu, model, result, stem=stem)}")
    for k in ("contact_start_s", "contact_end_s", "contact_duration_s", "first_contact_side",
              "peak_reaction_force_N", "max_finger_stress_Pa", "max_object_stress_Pa", "wall_time_s"):
        print(f"{k} = {summary.get(k)}")
    print(f"wrote {out / stem}.csv and the JSON summary")


def write_contact_sweep(setup, alphas, out, *, damping="global", t_end_s=1.5, n_outputs=300, scheduler="local"):
    """The contact run for several alpha: histories and summary CSVs, the Fig. 10, 13, 14
    analogues and ``contact_report.md`` in ``out``.

    Parameters
    ----------
    setup : ccedi.fea.contact.drum.DrumSetup
        The drum test.
    alphas : sequence of float
        Mass-proportional damping values [1/s].
    out : str or Path
        Output directory.
    damping : {"global", "relative"}
        Mass damping on the absolute velocity (the paper) or relative to the drum.
    t_end_s : float
        Simulated time [s].
    n_outputs : int
        Output times over the run.
    scheduler : str
        ``serial``, ``local`` or a Dask scheduler address.
    """
    from ccedi.fea.cases.contact_study import sweep
    from ccedi.outputs import write_csv, write_figure
    from ccedi.study.figures import plot_contact_shapes, plot_reaction_force, plot_stresses

    out = Path(out)
    history, table, shapes = sweep(setup, alphas=alphas, damping=damping, t_end_s=t_end_s,
                                   n_outputs=n_outputs, progress=True, scheduler=scheduler)
    write_csv(out / f"contact_histories_{damping}.csv", history)
    write_csv(out / f"contact_summary_{damping}.csv", table)
    write_figure(out / f"fig10_reaction_force_{damping}.png", plot_reaction_force(history))
    write_figure(out / f"fig14_stresses_{damping}.png", plot_stresses(history))
    write_figure(out / f"fig13_contact_shapes_{damping}.png", plot_contact_shapes(setup, shapes))
    print(table[["alpha_per_s", "contact_start_s", "contact_end_s", "contact_duration_s", "first_contact_side",
                 "peak_reaction_force_N", "max_object_stress_Pa"]].to_string(index=False))
    write_contact_report(setup, out)
    print(f"wrote {out}/")


def _cmd_contact_sweep(args):
    check_flag("--alphas", list(args.alphas), section="study", key="contact_alphas_per_s")
    write_contact_sweep(_setup_of(args), args.alphas, args.out, damping=args.damping, t_end_s=args.t_end_s,
                        n_outputs=args.n_outputs, scheduler=args.scheduler)


def write_contact_report(setup, out):
    """``contact_report.md`` from the summaries and histories in ``out`` (global and
    relative, either or both); nothing when neither sweep is there.

    Parameters
    ----------
    setup : ccedi.fea.contact.drum.DrumSetup
        The drum test the sweep ran.
    out : str or Path
        Directory holding the sweep CSVs.
    """
    import pandas as pd

    from ccedi.fea.cases.contact_study import contact_report
    from ccedi.outputs import write_text

    out = Path(out)

    def load(kind):
        s, h = out / f"contact_summary_{kind}.csv", out / f"contact_histories_{kind}.csv"
        return (pd.read_csv(s), pd.read_csv(h)) if s.exists() and h.exists() else (None, None)

    g_table, g_hist = load("global")
    r_table, r_hist = load("relative")
    if g_table is None and r_table is None:
        return
    write_text(out / "contact_report.md", contact_report(setup, g_table, g_hist, relative_table=r_table,
                                                                 relative_history=r_hist))


def _contact_arguments(p):
    p.add_argument("--damping", choices=("global", "relative"), default="global",
                   help="mass damping on the absolute velocity (global, the paper) or relative to the drum")
    p.add_argument("--t-end-s", type=float, default=1.5, help="simulated time [s]")
    p.add_argument("--n-outputs", type=int, default=300, help="number of output times")
    p.add_argument("--theta0-rad", type=float, help="initial finger angle [rad] (default: [drum] theta0_rad of "
                   "--config, else the calibrated one)")
    p.add_argument("--calibrate", action="store_true",
                   help="recalibrate theta0 so that alpha = 7.5 1/s first touches at t = 0.32 s")
    add_config_argument(p, CONTACT_KEYS)


def add_parsers(sub):
    """Register table1, impulse, contact, contact-sweep and contact-report on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-command registry of the ``ccedi`` parser.
    """
    t = add_command(sub, "table1", help="paper Table 1: nodes, elements, stable time step and tip stiffness "
                       "of SM-A, SM-B, SM-C, the detailed model DM and the --config's [finger] mesh")
    t.add_argument("--length-in", type=float, default=None,
                   help="finger length [in] (default: [finger] impulse_length_in of --config, 4.5)")
    add_output_argument(t, "--json", "file", help="write the table as JSON to this path")
    t.add_argument("--no-stiffness", action="store_true",
                   help="skip the static stiffness solves (also: [study] table1_stiffness = false in --config)")
    t.add_argument("--no-detailed-model", action="store_true",
                   help="leave out the detailed model DM, a 2.8 mm mesh of about 28 000 nodes (also: [study] "
                        "detailed_model = false in --config)")
    t.add_argument("--detailed-model-solves", action="store_true",
                   help="also solve the DM's tip stiffness and first frequency (nonlinear and modal solves at "
                        "2.8 mm: about 30 CPU-minutes, measured with SuperLU; without it the DM row has its nodes, elements "
                        "and time step; ccedi table1 then takes about 25 s here, most of it SM-B's and SM-C's "
                        "stiffness solves)")
    add_config_argument(t, IMPULSE_FINGER_KEYS + ("study.table1_stiffness", "study.detailed_model"))
    t.set_defaults(func=_cmd_table1)
    i = add_command(sub, "impulse", help="tip impulse response of the SM-A finger for several alpha "
                       "(paper Fig. 7): CSV, plot, JSON")
    i.add_argument("--alpha", type=float, nargs="+", default=None,
                   help="mass-proportional damping values [1/s] (default: [study] impulse_alphas_per_s of --config, "
                        "70 120 160 180 200)")
    i.add_argument("--length-in", type=float, default=None,
                   help="length of the SM-A finger [in] (default: [finger] impulse_length_in of --config, 4.5; not "
                        "with a [finger] mesh)")
    i.add_argument("--force-N", type=float, default=None,
                   help="tip force [N] (soft direction; default: [study] impulse_force_N, 1)")
    i.add_argument("--duration-s", type=float, default=None,
                   help="pulse duration [s] (default: [study] impulse_duration_s, 0.01)")
    i.add_argument("--t-end-s", type=float, default=None,
                   help="simulated time [s] (default: [study] impulse_t_end_s, 0.2)")
    add_output_argument(i, "--out", "dir", default="reports/impulse", help="output directory")
    add_scheduler_argument(i)
    add_config_argument(i, IMPULSE_FINGER_KEYS + ("study.impulse_alphas_per_s", "study.impulse_force_N",
                                                  "study.impulse_duration_s", "study.impulse_t_end_s"))
    i.set_defaults(func=_cmd_impulse)
    c = add_command(sub, "contact", help="finger on the rotating drum over the elliptical object (paper 3.3-3.4)")
    c.add_argument("--alpha", type=float, required=True, help="mass-proportional damping [1/s]")
    add_output_argument(c, "--json", "file", help="summary JSON path (default: OUT/contact_alpha<A>_<damping>.json)")
    add_output_argument(c, "--vtu", "dir", help="directory for a VTU/PVD animation of the finger")
    add_output_argument(c, "--out", "dir", default="reports/contact", help="output directory for the CSV history")
    _contact_arguments(c)
    c.set_defaults(func=_cmd_contact)
    w = add_command(sub, "contact-sweep", help="the contact run for several alpha; paper Figs. 10, 13, 14 analogues")
    w.add_argument("--alphas", type=float, nargs="+", default=[1.0, 7.5, 20.0, 50.0, 180.0, 600.0],
                   help="mass-proportional damping values [1/s], one contact run each")
    add_output_argument(w, "--out", "dir", default="reports/contact", help="output directory")
    add_scheduler_argument(w, default="local")
    _contact_arguments(w)
    w.set_defaults(func=_cmd_contact_sweep)
    r = add_command(sub, "contact-report", help="contact_report.md from the CSVs a contact-sweep wrote")
    r.add_argument("--out", default="reports/contact", help="directory holding the sweep CSVs")
    _contact_arguments(r)
    r.set_defaults(func=lambda args: write_contact_report(_setup_of(args), args.out))
