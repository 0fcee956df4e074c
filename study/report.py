"""``index.html`` (and ``index.pdf``) of a study directory, built only from the files the
study's steps wrote there: every number on the page is read from this run's JSON/CSV
outputs, and every figure is a PNG of this run. A step that did not run is listed as such.
"""
import html
import json
import tomllib
from datetime import datetime, timezone
from pathlib import Path

import pandas as pd

from ccedi.fea.cases.studies import PAPER_TABLE1, is_paper_finger
from ccedi.outputs import write_pdf_figures, write_text
from ccedi.study.config import SCHEMA, finger_inputs, validate

from .config import CONFIG_NAME
from .steps import PAPER_STEPS, STEP_NAMES

UNITS = (("_per_s", "1/s"), ("_rad_s", "rad/s"), ("_m_s", "m/s"), ("_N_s", "N s"), ("_N_per_m", "N/m"), ("_us", "us"),
         ("_cm3", "cm^3"), ("_rpm", "rpm"), ("_mm", "mm"), ("_Pa", "Pa"), ("_N", "N"), ("_in", "in"), ("_s", "s"), ("_m", "m"), ("_J", "J"))
"""Column/key suffix -> unit, longest match first."""

FIGURES = [
    ("steel_rod/fig3_steel_rod_alpha_cr.png", "Fig. 3 analogue: steel rod, initial guess and critical alpha"),
    ("steel_rod/fig4_steel_rod_decay.png", "Fig. 4 analogue: steel rod at alpha = zeta alpha_cr against the "
     "published decay (zeta 0.0055, 16.33 rad/s)"),
    ("mesh/fig6_mesh_comparison.png", "Fig. 6 analogue: SM-A and SM-B under the same impulse"),
    ("mesh/fig6_detailed_model.png", "Fig. 6 analogue: SM-A and the detailed model (modal ROMs), and the DM at "
     "the alpha nearest SM-A's response"),
    ("impulse/impulse_response.png", "Fig. 7 analogue: tip impulse response for several alpha"),
    ("damping_fits/alpha_cr_fit.png", "Fig. 8 analogue: alpha_cr and alpha against finger length, Eq. (7)/(8)"),
    ("contact/fig10_reaction_force_global.png", "Fig. 10 analogue: reaction force on the object (global damping)"),
    ("contact/fig13_contact_shapes_global.png", "Fig. 13 analogue: finger at first and last contact (global damping)"),
    ("contact/fig14_stresses_global.png", "Fig. 14 analogue: finger and object stresses, reaction force (global damping)"),
    ("contact/fig10_reaction_force_relative.png", "Fig. 10 analogue: reaction force on the object (relative damping)"),
    ("contact/fig13_contact_shapes_relative.png", "Fig. 13 analogue: finger at first and last contact (relative damping)"),
    ("contact/fig14_stresses_relative.png", "Fig. 14 analogue: finger and object stresses, reaction force (relative damping)"),
    ("design/feasible_region.png", "Design: the feasible region in (alpha, L or drum speed), each requirement's "
     "boundary"),
    ("design/pareto.png", "Design: Pareto front of the objective against the second output"),
]


def unit_of(key):
    """The unit a ccedi key or column name carries in its suffix ('-' if none)."""
    return next((u for suffix, u in UNITS if key.endswith(suffix)), "-")


def _fmt(v):
    if v is None or (isinstance(v, float) and v != v):
        return "n/a"
    if isinstance(v, bool) or isinstance(v, str):
        return html.escape(str(v))
    if isinstance(v, int):
        return f"{v:d}"
    if isinstance(v, float):
        return f"{v:.4g}"
    return html.escape(str(v))


def _table(rows, columns):
    """HTML table; ``columns`` are (header with unit, key or callable)."""
    head = "".join(f"<th>{html.escape(h)}</th>" for h, _ in columns)
    body = "".join("<tr>" + "".join(f"<td>{_fmt(k(r) if callable(k) else r.get(k))}</td>" for _, k in columns)
                   + "</tr>" for r in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def _col(key, label=None):
    unit = unit_of(key)
    return (f"{label or key} [{unit}]" if unit != "-" else (label or key), key)


def _load(out, name):
    path = out / name
    if not path.exists():
        return None
    return json.loads(path.read_text()) if path.suffix == ".json" else pd.read_csv(path)


def _missing(step):
    return f"<p class='missing'>Not in this run (study step <code>{step}</code> did not run).</p>"


def _inputs_of(out):
    """The validated inputs of the run (``config.toml``); the defaults for a run without one."""

    path = out / CONFIG_NAME
    return validate(tomllib.loads(path.read_text()) if path.exists() else {})


def _table1(out):

    t = _load(out, "table1.json")
    if t is None:
        return _missing("table1")
    cfg = _inputs_of(out)
    paper = is_paper_finger(cfg["finger"]["impulse_length_in"], *finger_inputs(cfg))
    rows = [{"model": f"{name} {src}", **vals} for name in t for src, vals in
            ((("paper", PAPER_TABLE1[name]),) if paper and name in PAPER_TABLE1 else ()) + (("ccedi", t[name]),)]
    cols = [("model", "model"), ("element type", "element_type"), _col("average_length_mm", "average length"),
            _col("volume_cm3", "volume"), ("nodes", "nodes"), ("elements", "elements"), _col("dt_us", "stable step"),
            ("steps to 0.2 s", "steps_to_0_2_s"), ("step ratio", "step_ratio"),
            _col("stiffness_N_per_m", "tip stiffness")]
    note = ("Paper rows are the paper's Table 1 (4.5-in finger)." if paper else
            "This run's finger is not the paper's (see the inputs), so the paper's Table 1 is not shown.")
    return _table(rows, cols) + f"<p>{note}</p>"


def _finger(out):
    f = _load(out, "finger.json")
    if f is None:
        return _missing("finger")
    limiting = f["step_set_by"]
    rows = [{"quantity": "mesh", "value": f"{f['nodes']} nodes, {f['elements']} {f['element_type']} elements"
             + (f" ({f['mesh_file']})" if f.get("mesh_file") else ""), "unit": "-"},
            {"quantity": "length", "value": 1e3 * f["length_m"], "unit": "mm"},
            {"quantity": "volume", "value": f["volume_cm3"], "unit": "cm^3"},
            {"quantity": "mass", "value": f["mass_kg"], "unit": "kg"},
            {"quantity": "stable time step", "value": f["dt_us"], "unit": "us"},
            {"quantity": "steps to 0.2 s", "value": f["steps_to_0_2_s"], "unit": "-"},
            {"quantity": "tip stiffness", "value": f.get("stiffness_N_per_m"), "unit": "N/m"},
            {"quantity": "first natural frequency", "value": f["f1_hz"], "unit": "Hz"},
            {"quantity": "2 omega_1 (alpha that damps the first mode critically)",
             "value": f["alpha_cr_first_mode_per_s"], "unit": "1/s"}]
    where = ", ".join(f"{round(1e3 * c, 2) + 0.0:g}" for c in limiting["centroid_m"])
    return (f"<p>{html.escape(f['name'])}.</p>" + _table(rows, [("quantity", "quantity"), ("value", "value"),
                                                                ("unit", "unit")])
            + f"<p>The stable step is set by {html.escape(limiting['element'])} at ({where}) mm, "
              f"{1e3 * limiting['length_m']:.3g} mm across (median element {1e3 * limiting['median_length_m']:.3g} "
              "mm). The tip stiffness is n/a when the study's table1_stiffness is off.</p>")


def _steel_rod(out):
    r = _load(out, "steel_rod/steel_rod.json")
    if r is None:
        return _missing("steel_rod")
    keys = ["alpha_guess_per_s", "alpha_cr_per_s", "paper_alpha_cr_per_s", "n_fe_runs", "alpha_per_s",
            "paper_alpha_per_s", "simulated_zeta", "published_zeta", "simulated_omega_d_rad_s",
            "published_omega1_rad_s"]
    return _table([{"quantity": k, "value": r[k], "unit": unit_of(k)} for k in keys],
                  [("quantity", "quantity"), ("value", "value"), ("unit", "unit")])


def _impulse(out):
    s = _load(out, "impulse/impulse_summary.json")
    if s is None:
        return _missing("impulse")
    rows = [{"alpha_per_s": float(a), **p} for a, p in s["peaks"].items()]
    keys = ["alpha_per_s", "peak_tip_uy_m", "time_of_peak_s", "min_tip_uy_after_peak_m", "peak_von_mises_Pa"]
    f = s["finger"]
    return (f"<p>{html.escape(f['name'])} ({f['nodes']} nodes, {f['elements']} {f['element_type']} elements, "
            f"{1e3 * f['length_m']:.1f} mm long), {s['force_N']:g} N for {s['duration_s']:g} s at the tip.</p>"
            + _table(rows, [_col(k) for k in keys]))


def _mesh(out):
    s = _load(out, "mesh/mesh_comparison.json")
    if s is None:
        return _missing("mesh")
    rows = [{"model": m, **v} for m, v in s["models"].items()]
    return (f"<p>alpha = {s['alpha_per_s']:g} 1/s, {s['t_end_s']:g} s simulated.</p>"
            + _table(rows, [("model", "model")] + [_col(k) for k in
                                                   ("peak_tip_uy_m", "peak_von_mises_Pa", "wall_time_s")]
                     + [("steps", "steps")]))


def _detailed_model(out):
    s = _load(out, "mesh/dm_comparison.json")
    if s is None:
        return ("<p>Not in this run (study step <code>mesh</code> did not run, or the finger is not the "
                "paper's, whose detailed model this is).</p>")
    rows = [{"model": m, **v} for m, v in s["models"].items()]
    keys = ("peak_tip_uy_m", "quasi_static_peak_von_mises_Pa", "omega1_rad_s")
    return (f"<p>The detailed model (DM, {s['dm_nodes']} nodes, {s['dm_elements']} 10-node tetrahedra) and "
            f"SM-A on their 6-mode modal ROMs, alpha = {s['alpha_per_s']:g} 1/s, {s['t_end_s']:g} s. The DM's "
            f"response is nearest SM-A's at alpha = {s['dm_matching_alpha_per_s']:.4g} 1/s (paper "
            f"{s['paper_dm_matching_alpha_per_s']:g} 1/s; relative RMS misfit "
            f"{s['match_relative_rms_error']:.3g}). Stresses: the linear static deflection scaled to each peak "
            "tip displacement (the ROM has no stresses); validation/dm_fig6.py checks the ROM against a full "
            "explicit run.</p>"
            + _table(rows, [("model", "model")] + [_col(k) for k in keys] + [("under-damped", "under_damped")]))


def _damping_fits(out):
    s = _load(out, "damping_fits/alpha_cr_fit.json")
    if s is None:
        return _missing("damping_fits")
    keys = ["length_in", "alpha_cr_per_s", "two_omega1_per_s", "paper_eq8_per_s", "n_runs"]
    p = s["power_law"]
    return (_table(s["alpha_cr"], [_col(k) for k in keys])
            + f"<p>Power-law fit alpha_cr = {p['coefficient']:.4g} x^{p['exponent']:.4g} [1/s], x in inches "
              f"(paper Eq. (8): {s['paper_eq8']['coefficient']:g} x^{s['paper_eq8']['exponent']:g}).</p>")


CONTACT_DAMPING = {
    "global": "The paper's reproduction: global mass damping (on the absolute velocity, LS-DYNA's *DAMPING_GLOBAL, "
              "as the paper ran it), a drag on the whole finger that bends it back before contact. The design uses "
              "relative damping ([damping] kind), the physical one for a finger turned in air.",
    "relative": "Relative mass damping ([damping] kind): on the finger's velocity relative to the turning drum, "
                "the physical model of a finger turned in air (it damps deformation, not the rigid turn).",
}
"""What the contact section says of each damping kind of the sweep."""


def _contact(out):
    parts = []
    for kind, text in CONTACT_DAMPING.items():
        t = _load(out, f"contact/contact_summary_{kind}.csv")
        if t is None:
            continue
        keys = ["alpha_per_s", "contact_start_s", "contact_end_s", "contact_duration_s", "first_contact_side",
                "peak_reaction_force_N", "max_finger_stress_Pa", "max_object_stress_Pa", "wall_time_s"]
        parts.append(f"<p>{text}</p>" + _table(t.to_dict("records"), [_col(k) for k in keys if k in t.columns]))
    return "".join(parts) or _missing("contact")


KEY_OUTPUTS = ("sensor_peak_force_N", "max_finger_stress_Pa", "recovery_deviation_m", "ringing_amplitude_m",
               "contact_impulse_N_s")
"""The design outputs the study's tables show."""


def _design(out):
    d = _load(out, "design/design.json")
    if d is None:
        return _missing("design")
    p = d["problem"]
    what = (f"<p>{html.escape(p['damping'])} damping; minimise {html.escape(p['objective_output'] or 'a weighted sum')}"
            f" subject to: {html.escape('; '.join(p['requirements']))}. The decision is explained in "
            "<code>design/design_report.md</code>.</p>")
    if not d["feasible"]:
        misses = "; ".join(f"{k}: {v['value']:.4g} against {v['bound']:.4g}" for k, v in d["misses"].items())
        return what + f"<p class='missing'>No design meets the requirements; the closest misses {html.escape(misses)}.</p>"
    keys = ["alpha_per_s", _second(d), *KEY_OUTPUTS]
    parts = [what, "<h3>Optimum (surrogate)</h3>", _table([d["optimum"]], [_col(k) for k in keys]),
             f"<p>binding: {html.escape(', '.join(d['binding']) or 'none')}"
             + (f"; FLAG: {html.escape(', '.join(d['on_bounds']))}" if d["on_bounds"] else "")
             + f"; surrogate built in {d['surrogate']['build_wall_time_s']:.4g} s "
             f"(grid from cache: {d['surrogate']['grid_from_cache']}).</p>"]
    err = d["surrogate"]["off_grid_error"]
    parts.append("<h3>Surrogate error on off-grid ROM runs</h3>" + _table(
        [{"output": k, **v} for k, v in err.items()],
        [("output", "output")] + [(f"{c}", c) for c in sorted({c for v in err.values() for c in v})]))
    parts.append(_fea_check(d, "Full-FEA re-check (relative error of the surrogate against the FEA)"))
    return "".join(parts) + _calibrated_design(out, d)


def _second(d):
    """JSON key of a design result's second variable (``length_in`` or ``drum_speed_rpm``)."""
    return d["problem"]["variables"][1]["key"]


def _fea_check(d, title):
    """The full-FEA re-check table of a design result."""
    if not d["fea_check"]:
        return "<p>FEA re-check skipped in this run.</p>"
    second = _second(d)
    rows = [{"alpha_per_s": c["alpha_per_s"], second: c[second], "wall_time_s": c["wall_time_s"],
             "meets the requirements": "FE run failed" if c.get("failed") else c["meets_requirements"],
             **{f"{k} error": c["relative_error"][k] for k in KEY_OUTPUTS}} for c in d["fea_check"]]
    return f"<h3>{html.escape(title)}</h3>" + _table(
        rows, [_col("alpha_per_s"), _col(second), ("FEA meets the requirements", "meets the requirements")]
        + [(f"{k} error [-]", f"{k} error") for k in KEY_OUTPUTS] + [_col("wall_time_s", "FEA wall time")])


def _calibrated_design(out, declared):
    """The design made with the calibrated inputs (``design/calibrated/``) beside the one
    made with the declared model, and the measured finger as built on the surrogate."""
    cal = _load(out, "design/calibrated/calibration.json")
    if cal is None:
        return ""
    source = html.escape(Path(cal["source"]).name)
    head = "<h3>Design with the calibrated inputs</h3>"
    calibrated = _load(out, "design/calibrated/design.json")
    if cal.get("model_adequate") is False or calibrated is None:
        why = html.escape(cal.get("adequacy", {}).get("message", "no calibrated design in this run"))
        return head + f"<p class='missing'>Not made: the declared finger cannot explain {source} ({why}).</p>"
    objectives = list(KEY_OUTPUTS)

    second = _second(declared)

    def row(name, d, design):
        drum = d.get("drum", {})
        return {"model": name, "E_Pa": d["finger_material"]["E_Pa"], "friction": drum.get("friction"),
                "omega_rad_s": drum.get("omega_rad_s"), **{k: design[k] for k in ["alpha_per_s", second, *objectives]}}

    if not declared["feasible"] or not calibrated["feasible"]:
        return head + "<p class='missing'>No design meets the requirements with the declared or the calibrated inputs.</p>"
    rows = [row("declared model: optimum", declared, declared["optimum"]),
            row(f"calibrated on {source}: optimum", calibrated, calibrated["optimum"])]
    if calibrated.get("measured_finger"):
        rows.append(row("calibrated: the measured finger as built", calibrated, calibrated["measured_finger"]))
    effects = ", ".join(e["name"] for e in cal["effects_found"]) or "none"
    notes = [f"effects found: {effects}"]
    if cal.get("ambiguous"):
        notes.append("ambiguous, not added: " + " or ".join(cal["ambiguous"]["effects"]))
    if cal.get("unexplained_residual"):
        notes.append("an unexplained residual remains")
    text = (f"<p>{source} calibrated ({'; '.join(html.escape(n) for n in notes)}; NRMSE {cal['baseline']['nrmse']:.3%} "
            f"-> {cal['final_nrmse']:.3%}, noise floor {cal['noise_floor_nrmse']:.3%}); its inputs "
            "(<code>design/calibrated/calibrated.toml</code>) re-ran the design.</p>")
    table = _table(rows, [("model", "model"), _col("E_Pa"), ("friction [-]", "friction"), _col("omega_rad_s"),
                          _col("alpha_per_s"), _col(second), *[_col(k) for k in objectives]])
    return head + text + table + _fea_check(calibrated, "Full-FEA re-check of the calibrated design")


def _calibrate(out):
    results = sorted((out / "calibrate").glob("*.json")) if (out / "calibrate").exists() else []
    if not results:
        return _missing("calibrate")
    rows, figs, inadequate = [], [], []
    for path in results:
        r = json.loads(path.read_text())
        adequacy = r.get("adequacy", {})          # absent in the results of a version without the check
        if r.get("model_adequate") is False:
            inadequate.append(f"<li><code>{html.escape(path.stem)}</code>: {html.escape(adequacy['message'])}; "
                              "no effect added</li>")
        rows.append({"record": path.stem,
                     "model adequate": {True: "yes", None: "not checked"}.get(
                         r.get("model_adequate"), "NO: " + ", ".join(adequacy.get("failed_checks", []))),
                     "record f1 [Hz]": adequacy.get("record_first_frequency_hz"),
                     "declared f1 [Hz]": adequacy.get("declared_first_frequency_hz"),
                     "alpha_per_s": r["final_params"].get("alpha_per_s"),
                     "E factor": r["final_params"].get("E_factor"),
                     "effects found": "; ".join(
                         f"{e['name']} ({', '.join(f'{k} = {v:.4g}' for k, v in e['params_final'].items())})"
                         for e in r["effects_found"]) or "none",
                     "baseline NRMSE": r["baseline"]["nrmse"],
                     "final NRMSE": r["final_nrmse"], "noise floor NRMSE": r["noise_floor_nrmse"],
                     "wall_time_s": r.get("wall_time_s")})
        if (out / "calibrate" / path.stem / "fit.png").exists():
            figs.append(_figure(f"calibrate/{path.stem}/fit.png", f"Calibrated model against {path.stem}"))
    cols = [("record", "record"), ("model adequate", "model adequate"), ("record f1 [Hz]", "record f1 [Hz]"),
            ("declared f1 [Hz]", "declared f1 [Hz]"), _col("alpha_per_s", "calibrated alpha"),
            ("calibrated E factor [-]", "E factor"), ("effects found (SI units as named)", "effects found"),
            ("baseline NRMSE [-]", "baseline NRMSE"), ("final NRMSE [-]", "final NRMSE"),
            ("noise floor NRMSE [-]", "noise floor NRMSE"), _col("wall_time_s")]
    warning = (f"<p class='missing'>The declared finger cannot explain {len(inadequate)} record(s) "
               f"(model_adequate: false):</p><ul>{''.join(inadequate)}</ul>" if inadequate else "")
    return warning + _table(rows, cols) + "".join(figs)


def _figure(src, caption):
    return (f"<figure><a href='{src}'><img src='{src}' alt='{html.escape(caption)}'></a>"
            f"<figcaption>{html.escape(caption)}</figcaption></figure>")


FINGER_SECTIONS = [("The finger: stable step, stiffness, first frequency", _finger, []),
                   ("Effect of alpha on the tip response (Fig. 7)", _impulse, FIGURES[4:5]),
                   ("Finger on the drum: contact (Figs. 10, 13, 14)", _contact, FIGURES[6:12]),
                   ("Design optimisation and FEA re-check", _design, FIGURES[12:13]),
                   ("Closing the loop on measured data (calibration)", _calibrate, [])]
"""The sections on the configured finger, first on the page: (title, section, figures)."""
PAPER_SECTIONS = [("Table 1: meshes, stable time step, tip stiffness", _table1, []),
                  ("Damping identification of the steel rod (Figs. 3, 4)", _steel_rod, FIGURES[0:2]),
                  ("Effect of the FE model (Fig. 6)", _mesh, FIGURES[2:3]),
                  ("The detailed model against SM-A (Fig. 6)", _detailed_model, FIGURES[3:4]),
                  ("CCEDI over finger lengths (Fig. 8)", _damping_fits, FIGURES[5:6])]
"""The paper's reproduction (``[study] paper``), after the finger: (title, section, figures)."""
PAPER_OUTPUTS = ("table1.json", "steel_rod/steel_rod.json", "mesh/mesh_comparison.json",
                 "damping_fits/alpha_cr_fit.json")
"""The files of the paper's steps."""

STYLE = ("body{font-family:sans-serif;max-width:1100px;margin:auto;padding:1em}table{border-collapse:collapse;"
         "margin:.5em 0}td,th{border:1px solid #bbb;padding:2px 8px;text-align:right}th{background:#eee}"
         "img{max-width:100%}figure{margin:1em 0}.missing{color:#a00}")


def _timings(out):
    s = _load(out, "study.json")
    if s is None:
        return ""
    rows = [{"step": k, "wall_time_s": v} for k, v in s["wall_time_s"].items()]
    if "elapsed_s" in s:
        rows.append({"step": "whole study (steps overlap on a cluster)", "wall_time_s": s["elapsed_s"]})
    return (f"<p>Scheduler: <code>{html.escape(str(s['scheduler']))}</code>; quick: {s['quick']}. A step's "
            "wall time runs from its start to its end, including waits for cluster workers.</p>"
            + _table(rows, [("step", "step"), _col("wall_time_s", "wall time")]))


def _step_list(out, key, heading):
    """The steps ``study.json`` lists under ``key`` ({step: reason}), under ``heading``."""
    s = _load(out, "study.json")
    if not s or not s.get(key):
        return ""
    items = "".join(f"<li><code>{html.escape(step)}</code>: {html.escape(why)}</li>" for step, why in s[key].items())
    return f"<p class='missing'>{heading}:</p><ul>{items}</ul>"


def _skipped(out):
    """The steps this run skipped, each with its reason (:func:`ccedi.study.run.skipped_steps`)."""
    return _step_list(out, "skipped", "Steps skipped for this finger")


def _failed(out):
    """The steps whose run failed, each with the solver's message."""
    return _step_list(out, "failed", "Steps that failed (their results are missing from this report)")


def _warnings(out):
    """The validity warnings every step recorded in ``study.json`` (:mod:`ccedi.fea.solvers.validity`)."""
    s = _load(out, "study.json")
    if s is None or "warnings" not in s:
        return ""
    found = [(step, w) for step, ws in s["warnings"].items() for w in ws]
    if not found:
        return ("<p>Validity warnings: none. Every run kept its energy balance, hourglass energy, strains and "
                "impulse tip deflection within the limits of <code>ccedi.fea.solvers.validity</code>.</p>")
    items = "".join(f"<li><b>{html.escape(step)}</b>: {html.escape(w)}</li>" for step, w in found)
    return (f"<p class='missing'>Validity warnings ({len(found)}): these numbers leave the models' range of "
            f"validity (<code>ccedi.fea.solvers.validity</code>); they are shown below as computed.</p><ul>{items}</ul>")


MESH_KEYS = ("mesh", "mesh_unit", "clamp", "tip", "bending_direction")
"""``[finger]`` keys of an imported mesh."""


def _ran(out):
    """The steps of this run that finished or failed (``study.json``); None without it."""
    s = _load(out, "study.json")
    return None if s is None else set(s["wall_time_s"]) | set(s.get("failed", {}))


def used_inputs(cfg, ran):
    """The finger, drum, damping and requirement inputs the steps ``ran`` read, each as
    ``(section, key, value)``.

    Parameters
    ----------
    cfg : dict
        Validated inputs (:func:`ccedi.study.config.load`).
    ran : set of str
        Names of the study's steps that ran (:data:`ccedi.study.steps.STEP_NAMES`).

    Returns
    -------
    list of tuple
        ``(section, key, value)``: the material; with a ``[finger] mesh``, the mesh's keys
        (and the generated finger's length and section only where a paper step ran on it);
        otherwise the generated finger's length of the impulse steps, its contact length
        and taper where the contact or design ran, its section; the drum where the contact or design
        ran; the damping kind and the requirements where the design ran (the damping kind
        also for a contact sweep that is not the paper's).
    """
    mesh = cfg["finger"]["mesh"] is not None
    paper = bool(ran & {"table1", "steel_rod", "mesh", "damping_fits"})
    drum = bool(ran & {"contact", "design"})
    finger = list(MESH_KEYS) if mesh else ["impulse_length_in"] + ["contact_length_in", "contact_taper_ratio"] * drum
    if paper or not mesh:
        finger += [k for k in ("impulse_length_in", "section_semi_axes_m") if k not in finger]
    material = [k for k in cfg["material"] if k != "alpha_per_s" or ("design" in ran and cfg["material"][k] is not None)]
    keys = [("material", material), ("finger", finger), ("drum", list(cfg["drum"]) if drum else []),
            ("damping", ["kind"] if "design" in ran or ("contact" in ran and not cfg["study"]["paper"]) else []),
            ("requirements", list(cfg["requirements"]) if "design" in ran else [])]
    return [(sec, key, cfg[sec][key]) for sec, names in keys for key in names]


def _inputs(out):
    """The inputs this run used (``config.toml``, :func:`used_inputs`), each with its unit."""

    if not (out / CONFIG_NAME).exists():
        return ""
    cfg = _inputs_of(out)
    ran = _ran(out)
    ran = set(STEP_NAMES) if ran is None else ran
    rows = [{"input": f"[{sec}] {key}", "value": ", ".join(f"{v:g}" for v in val) if isinstance(val, list) else val,
             "unit": SCHEMA[sec][key].unit} for sec, key, val in used_inputs(cfg, ran)]
    return (f"<p>The inputs the steps of this run used (from <code>{CONFIG_NAME}</code>, which holds every "
            "setting). Calibration uses each measured record's own finger (its JSON sidecar).</p>"
            + _table(rows, [("input", "input"), ("value", "value"), ("unit", "unit")]))


def _sections(out, sections):
    """The HTML of ``sections`` ((title, section, figures)) with this run's figures."""
    body = []
    for title, section, figures in sections:
        body += [f"<h2>{html.escape(title)}</h2>", section(out)]
        body += [_figure(src, cap) for src, cap in figures if (out / src).exists()]
    return body


def write_index(out):
    """Write ``out/index.html`` (and ``out/index.pdf`` of the figures) from the study's
    outputs: the run, the configured finger's sections, then the paper's reproduction when
    one of its steps ran.

    Parameters
    ----------
    out : str or Path
        The study's output directory.

    Returns
    -------
    Path
        ``out/index.html``.
    """
    out = Path(out)
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    finger = _load(out, "finger.json")
    name = f" of {html.escape(finger['name'])}" if finger else ""
    ran = _ran(out)
    paper = (ran is None or ran & set(PAPER_STEPS)) and any((out / f).exists() for f in PAPER_OUTPUTS)
    body = [f"<h1>ccedi design study{name}</h1><p>Generated {stamp} from the files in this directory. Units: SI "
            "unless a header says otherwise; every number below was computed by this run.</p>",
            "<h2>Run</h2>", _timings(out), _skipped(out), _failed(out), _warnings(out), _inputs(out)]
    body += _sections(out, FINGER_SECTIONS)
    if paper:
        body += ["<h1>Reproduction of the paper (Liu and Lee, 2012)</h1><p>The paper's own finger (4.5 in, its "
                 "rubber and section unless the inputs change them) and the steel rod.</p>"]
        body += _sections(out, PAPER_SECTIONS)
    page = (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>ccedi design study</title>"
            f"<style>{STYLE}</style></head><body>{''.join(body)}</body></html>\n")
    _write_pdf(out)
    return write_text(out / "index.html", page)


def _write_pdf(out):
    """index.pdf: one page per figure of this run, with its caption."""
    present = [(out / src, cap) for src, cap in FIGURES if (out / src).exists()]
    return write_pdf_figures(out / "index.pdf", present) if present else None
