"""The design's figures and the report that explains the decision (``ccedi design``).

* :func:`feasible_region_figure`: the plane of the two design variables (alpha and the
  finger length, or alpha and the drum speed) with the objective's contours, each
  requirement's boundary (margin = 0, hatched on its failing side), the optimum, the
  Pareto points and the FEA-checked designs;
* :func:`pareto_figure`: the front of the objective against the second output, the
  designer's limit on the latter as a line;
* :func:`report_markdown`: the decision in words: the optimum, which requirements bind,
  what relaxing each buys, a variable on its bound, the model-error margins carried, and
  the FEA re-check output by output.
"""
import matplotlib
import matplotlib.pyplot as plt
import numpy as np

from ccedi.design.outputs import UNITS
from ccedi.units import INCH

matplotlib.use("Agg")                       # no screen: figures go to files

LABELS = {"sensor_peak_force_N": "peak object force (100 Hz transducer) [N]",
          "max_object_stress_Pa": "peak object von Mises stress [Pa]",
          "max_finger_stress_Pa": "peak root stress over the cycle [Pa]",
          "root_stress_before_contact_Pa": "root stress before contact [Pa]",
          "recovery_deviation_m": "tip deviation at the next arrival [m]",
          "ringing_amplitude_m": "ringing amplitude after breakaway [m]",
          "first_contact_front_m": "first contact ahead of the object's minor axis [m]",
          "contact_patch_from_root_m": "contact patch from the root [m]",
          "contact_impulse_N_s": "contact impulse [N s]",
          "cycle_time_s": "time between objects [s]"}
"""Axis label of each output, with its unit."""


def _label(name):
    return LABELS.get(name, f"{name} [{UNITS.get(name, '-')}]")


def feasible_region_figure(problem, optimum, *, front=(), checked=(), n=120):
    """The plane of the design variables (alpha [1/s] and L [in] or drum speed [rpm]):
    objective contours, each requirement's boundary.

    Parameters
    ----------
    problem : ccedi.design.optimise.DesignProblem
    optimum : ccedi.design.optimise.Design or None
    front : sequence of Design, optional
    checked : sequence of Design, optional
        The FEA-checked designs (ringed).
    n : int, optional
        Evaluation points per axis.

    Returns
    -------
    matplotlib.figure.Figure
    """
    va, vl = problem.surrogate.variables
    A, L = np.meshgrid(va.grid(n), vl.grid(n), indexing="ij")
    out = problem.surrogate.evaluate(np.column_stack([A.ravel(), L.ravel()]))
    Lin = vl.shown(L)
    fig, ax = plt.subplots(figsize=(8.5, 6))
    key = next(iter(problem.weights))
    J = (problem.J(out) if problem.objective == "weighted" else out[key]).reshape(A.shape)
    cs = ax.contourf(A, Lin, J, levels=20, cmap="viridis", alpha=0.75)
    fig.colorbar(cs, ax=ax, label="objective J (weighted, normalised)" if problem.objective == "weighted"
                 else _label(key))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    handles = []
    for i, (name, m) in enumerate(problem.constraint_margins(out, A.ravel(), L.ravel()).items()):
        M = np.asarray(m).reshape(A.shape)
        if M.min() >= 0.0:
            continue                                     # met everywhere: no boundary to draw
        c = colours[i % len(colours)]
        ax.contourf(A, Lin, M, levels=[M.min() - 1.0, 0.0], colors="none", hatches=["//"])
        if M.max() > 0.0:
            ax.contour(A, Lin, M, levels=[0.0], colors=[c], linewidths=2)
        handles.append(plt.Line2D([], [], color=c, lw=2, label=f"{name} (hatched: missed)"))
    for d in front:
        ax.plot(d.alpha_per_s, vl.shown(d.x), "w.", ms=6)
    for d in checked:
        ax.plot(d.alpha_per_s, vl.shown(d.x), "o", mfc="none", mec="k", ms=12)
    if optimum is not None:
        ax.plot(optimum.alpha_per_s, vl.shown(optimum.x), "r*", ms=18)
    handles += [plt.Line2D([], [], color="r", marker="*", ls="", ms=12, label="optimum"),
                plt.Line2D([], [], color="k", marker="o", mfc="none", ls="", ms=10, label="FEA re-checked"),
                plt.Line2D([], [], color="w", marker=".", mec="k", ls="", ms=8, label="Pareto front")]
    ax.set_xscale("log")
    ax.set_xlabel("mass-proportional damping alpha [1/s]")
    ax.set_ylabel({"length_m": "finger length L", "drum_speed_rad_s": "drum speed",
                   "semi_thickness_m": "section semi-axis b (bending direction)",
                   "semi_width_m": "section semi-axis a (across)"}.get(vl.name, vl.label) + f" [{vl.unit}]")
    ax.set_title("Feasible region on the surrogate (lines: each requirement's boundary)", fontsize=10)
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(0.0, -0.12), ncol=2)
    fig.tight_layout()
    return fig


def pareto_figure(problem, front, second, *, optimum=None, limit=None):
    """The objective against ``second`` along the front, coloured by alpha.

    Parameters
    ----------
    problem : ccedi.design.optimise.DesignProblem
    front : sequence of Design
    second : str
        The second output.
    optimum : Design, optional
    limit : float, optional
        The designer's limit on ``second`` (a dashed line).

    Returns
    -------
    matplotlib.figure.Figure
    """
    key = next(iter(problem.weights))
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    x = [d.outputs[second] for d in front]
    y = [problem.objective_value(d.outputs) for d in front]
    sc = ax.scatter(x, y, c=[d.alpha_per_s for d in front], cmap="plasma", norm=matplotlib.colors.LogNorm(), s=30)
    fig.colorbar(sc, ax=ax, label="alpha [1/s]")
    if optimum is not None:
        ax.plot(optimum.outputs[second], problem.objective_value(optimum.outputs), "r*", ms=16, label="optimum")
    if limit is not None:
        ax.axvline(limit, color="k", ls="--", lw=1, label="the requirement's limit")
    ax.set_xlabel(_label(second))
    ax.set_ylabel("objective J" if problem.objective == "weighted" else _label(key))
    ax.set_title("Pareto front: what less of the second output costs", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def _fmt(value, unit=""):
    if value is None:
        return "-"
    if unit == "m":
        return f"{value * 1e3:.4g} mm"
    if unit == "Pa":
        return f"{value / 1e6:.4g} MPa"
    return f"{value:.4g} {unit}".rstrip()


def _design(d, second):
    """``"alpha = 234.9 1/s, L = 4.183 in"`` of a design's JSON ``d``; ``second``: the
    problem's second variable (``result["problem"]["variables"][1]``)."""
    return f"alpha = {d['alpha_per_s']:.4g} 1/s, {second['label']} = {d[second['key']]:.4g} {second['unit']}"


def _verification(result, second):
    """Lines on the runs that verified the surrogate's optimum (:func:`ccedi.design.recheck.verified_optimum`):
    where the model run at a design missed a requirement, its bound was shifted by the
    surrogate's error there and the problem solved again."""
    steps = result.get("rom_verification") or []
    if not any(s["missed"] or s.get("failed") for s in steps):
        return []
    lines = ["", f"## Verification by the {result['problem'].get('verified_by', 'ROM')}", "",
             "The surrogate's optimum was run by the model; where it missed a requirement, that requirement's bound "
             "was shifted by the surrogate's error there and the problem solved again:", ""]
    for s in steps:
        lines.append(f"- {_design(s, second)}: " + (
            f"**the run failed** ({s['failed']}): the design below is the surrogate's, not verified" if s.get("failed")
            else "meets every requirement" if not s["missed"] else "misses " + "; ".join(s["missed"])))
    return lines


def _correction_lines(correction, held=""):
    """The report's paragraph on a surrogate corrected by the full FEA (none without one);
    ``held``: what the ratio is held across besides."""
    if not correction:
        return []
    ratios = {k: np.asarray(r, dtype=float) for k, r in correction["ratio_fea_over_model"].items()}
    n = max((r.size for r in ratios.values()), default=0)
    return ["", "## Surrogate corrected by the full FEA", "",
            f"The ROM runs were multiplied by the ratio FEA / ROM measured at {n} training designs (a tensor "
            f"grid of the design variables, bounds included; interpolated between, held at the edges{held}), so "
            "no model-error margin is carried: "
            + "; ".join(f"{_label(k).rsplit(' [', 1)[0]} {r.min():.3f}-{r.max():.3f}" for k, r in ratios.items())
            + "."]


def _fea_verdict(row):
    """What a :func:`ccedi.design.recheck.fea_check` row says, in one sentence."""
    if row.get("failed"):
        return f"**the FE run failed** ({row['failed']}); the design is not checked."
    if row["meets_requirements"]:
        return "meets every requirement."
    return "misses " + "; ".join(k for k, q in row["requirements"].items() if not q["met"]) + "."


def report_markdown(result):
    """The decision in words (Markdown), from the result ``ccedi design`` writes.

    Parameters
    ----------
    result : dict
        The design result (:func:`ccedi.study.commands.design.write_design`).

    Returns
    -------
    str
    """
    p = result["problem"]
    v = p["variables"][1]
    lines = ["# Finger design", "",
             f"Damping: **{p['damping']}** ({'on the velocity relative to the turning drum' if p['damping'] == 'relative' else 'on the absolute velocity, a drag on the whole finger (the paper, LS-DYNA *DAMPING_GLOBAL)'}). "
             f"Design space: alpha {p['alpha_bounds_per_s'][0]:g}-{p['alpha_bounds_per_s'][1]:g} 1/s, "
             f"{v['label']} {v['lo']:.4g}-{v['hi']:.4g} {v['unit']}. Objective: minimise "
             f"{p['objective_output'] or 'the weighted sum ' + str(p['weights'])}. Next object one cycle "
             f"({result['drum']['cycle_s']:.4g} s at the set-up's drum speed) after the first contact.", ""]
    if result.get("finger_mesh"):
        lines += [f"Finger: the given {result['finger_mesh']['element_type']} mesh `{result['finger_mesh']['path']}` "
                  f"({result['finger_mesh']['length_m'] * 1e3:.4g} mm long): its geometry is fixed, the design varies "
                  f"alpha and the drum speed on the contact ROM built on that mesh; the optimum is verified by "
                  f"the {p['verified_by']}.", ""]
    if not result["feasible"]:
        c = result["closest"]
        lines += ["## No design meets the requirements", "",
                  f"The closest design on the surrogate, {_design(c, v)}, misses:", "",
                  "| requirement | value | bound (with model-error margin) | short by |", "|---|---|---|---|"]
        for name, m in result["misses"].items():
            unit = UNITS.get(m["output"], "")
            lines.append(f"| {name} | {_fmt(m['value'], unit)} | {_fmt(m['bound'], unit)} | {_fmt(m['miss'], unit)} |")
        lines += _verification(result, v)
        lines += ["", "Relax the requirements above, widen the design space, or change the set-up."]
        return "\n".join(lines) + "\n"
    o = result["optimum"]
    lines += ["## Decision", "",
              f"**{_design(o, v)}** "
              f"({result['solver']['status']}).", ""]
    for flag in result["on_bounds"]:
        lines.append(f"- Flag: {flag}: the optimum may lie outside the design space; widen it to see.")
    lines += _verification(result, v)
    lines += ["", "## Requirements at the optimum", "",
              "| requirement | surrogate | margin | binds | FEA | FEA meets |", "|---|---|---|---|---|---|"]
    fea = result["fea_check"][0] if result["fea_check"] else None
    for name, margin in o["margins"].items():
        out = result["requirement_outputs"].get(name)
        unit = UNITS.get(out, "")
        f_row = fea["requirements"].get(name) if fea and not fea.get("failed") else None
        lines.append(f"| {name} | {_fmt(o.get(out), unit)} | {margin:+.3f} | {'yes' if name in result['binding'] else ''} "
                     f"| {_fmt(f_row['value'], unit) if f_row else '-'} | "
                     f"{('yes' if f_row['met'] else '**no**') if f_row else '-'} |")
    lines += ["", "Margins are normalised by each requirement's scale (its bound), >= 0 when met."]
    if result["model_error"]:
        lines += ["", "## Model-error margins carried", "",
                  "The ROM's measured error against the full FEA "
                  f"(`{result['model_error_source']}`, interpolated between the checked cases) tightens every "
                  "requirement on these outputs where the design lands:", ""]
        for name, e in result["model_error"].items():
            how = "of the FEA's value" if e["relative"] else "m"
            here = e.get("at_optimum")
            lines.append(f"- {name}: the ROM under-predicts by up to {e['largest_under']:.3g} {how} and over-predicts "
                         f"by up to {e['largest_over']:.3g} {how} over the design space"
                         + (f"; at the optimum {here['under']:.3g} and {here['over']:.3g}" if here else ""))
    lines += _correction_lines(result["surrogate"].get("fea_correction"))
    lines += ["", "## What relaxing each requirement buys", "",
              "Each requirement relaxed alone by 10 % of its scale, the problem solved again:", "",
              f"| requirement | binds | relaxed to | objective change | new alpha [1/s] | new {v['label']} [{v['unit']}] |",
              "|---|---|---|---|---|---|"]
    for name, s in result["sensitivities"].items():
        unit = UNITS.get(result["requirement_outputs"].get(name), "")
        lines.append(f"| {name} | {'yes' if s['binding'] else ''} | {_fmt(s['relaxed_to'], unit)} | "
                     f"{s['objective_change']:+.4g} | {s['alpha_per_s']:.4g} | {s[v['key']]:.4g} |")
    if result["fea_check"]:
        lines += ["", "## Full FEA re-check", ""]
        keys = [k for k in result["fea_check"][0]["surrogate"]]
        lines += ["| design | " + " | ".join(keys) + " |", "|---" * (len(keys) + 1) + "|"]
        for r in result["fea_check"]:
            name = _design(r, v)
            lines.append(f"| {name}: surrogate | " + " | ".join(_fmt(r["surrogate"][k], UNITS[k]) for k in keys) + " |")
            said = "**run failed**" if r.get("failed") else "meets" if r["meets_requirements"] else "misses"
            lines.append(f"| FEA ({said}{'' if r.get('failed') else ' the requirements'}) | "
                         + " | ".join(_fmt(r["fea"][k], UNITS[k]) for k in keys) + " |")
            lines.append("| error | " + " | ".join("-" if r["relative_error"][k] is None
                                                   else f"{r['relative_error'][k]:+.1%}" for k in keys) + " |")
    lines += ["", f"Figures: `feasible_region.png` (each requirement's boundary in the (alpha, {v['label']}) plane), "
              "`pareto.png` (the objective against the second output)."]
    return "\n".join(lines) + "\n"



def finger_drawing(length_m, semi_axes_m, *, drum_radius_m, taper_ratio=1.0, title=""):
    """The chosen finger drawn to scale: its side on the drum (length, thickness) and its
    elliptical section (width 2a, thickness 2b, b along the bending direction), in mm;
    a tapered finger's tip section dashed inside its root's.

    Parameters
    ----------
    length_m : float
        Finger length [m].
    semi_axes_m : tuple of float
        Section semi-axes (a, b) [m].
    drum_radius_m : float
        Drum radius [m] (the root sits on it).
    taper_ratio : float, optional
        The tip's semi-axes over the root's [-] (default 1, the prism).
    title : str, optional
        Figure title (the compound and its design).

    Returns
    -------
    matplotlib.figure.Figure
    """
    a, b = (1e3 * x for x in semi_axes_m)
    L, R = 1e3 * length_m, 1e3 * drum_radius_m
    fig, (side, section) = plt.subplots(1, 2, figsize=(10, 4.2), gridspec_kw={"width_ratios": [3, 1]})
    t = np.linspace(-0.35, 0.35, 60)
    side.plot(R * np.cos(t), R * np.sin(t), "k-", lw=2, label=f"drum, radius {R:.4g} mm")
    tip = taper_ratio * b
    h = max(b, tip)
    side.add_patch(matplotlib.patches.Polygon([(R, -b), (R + L, -tip), (R + L, tip), (R, b)], fc="tab:orange",
                                              ec="k", alpha=0.8, label="finger"))
    side.annotate("", xy=(R, -h - 6), xytext=(R + L, -h - 6), arrowprops={"arrowstyle": "<->"})
    side.text(R + L / 2, -h - 9, f"L = {L:.4g} mm ({L / 25.4:.4g} in)", ha="center", va="top")
    side.text(R + L + 3, 0, f"2b = {2 * b:.3g} mm" if taper_ratio == 1.0
              else f"root 2b = {2 * b:.3g} mm\ntip {2 * tip:.3g} mm\n(taper {taper_ratio:.3g})", va="center")
    side.set_aspect("equal")
    side.set_xlim(R * np.cos(0.35) - 5, R + L + 40)
    side.set_ylim(-h - 25, h + 15)
    side.set_xlabel("along the finger, from the drum axis [mm]")
    side.set_ylabel("bending direction [mm]")
    side.legend(fontsize=8, loc="upper right")
    s = np.linspace(0, 2 * np.pi, 200)
    section.fill(a * np.cos(s), b * np.sin(s), fc="tab:orange", ec="k", alpha=0.8)
    if taper_ratio != 1.0:
        section.plot(taper_ratio * a * np.cos(s), taper_ratio * b * np.sin(s), "k--", lw=1, label="tip")
        section.legend(fontsize=8, loc="lower right")
    section.set_aspect("equal")
    section.set_xlabel(f"width 2a = {2 * a:.3g} mm [mm]")
    section.set_ylabel(f"thickness 2b = {2 * b:.3g} mm (bending) [mm]")
    section.set_title("section" if taper_ratio == 1.0 else "root section", fontsize=9)
    fig.suptitle(title or "Chosen finger", fontsize=10)
    fig.tight_layout()
    return fig


def catalogue_report_markdown(result):
    """The compound ranking in words (Markdown), from the result ``ccedi design --compounds``
    writes (:func:`ccedi.study.commands.design.write_catalogue_design`).

    Parameters
    ----------
    result : dict
        The catalogue design result.

    Returns
    -------
    str
    """
    p, ranking = result["problem"], result["compounds"]
    output = ranking["objective_output"]
    unit = UNITS.get(output, "")
    shown = {"m": "mm", "Pa": "MPa"}.get(unit, unit)
    drum = any("fastest_drum_rpm" in r for r in ranking["table"])
    section = p.get("semi_thickness_bounds_mm")
    over = "" if section is None else (
        f" and the section's semi-thickness b {section[0]:.4g}-{section[1]:.4g} mm (along the bending direction; the "
        f"semi-width a = {p['semi_width_mm']:.4g} mm kept; no model-error margin is carried, the ROM's error was "
        "measured on the paper's section)")
    lines = ["# Compound design", "",
             f"Catalogue `{result['catalogue']}` ({len(ranking['table'])} compounds). Each compound is designed over "
             f"the finger length {p['length_bounds_in'][0]:.4g}-{p['length_bounds_in'][1]:.4g} in{over} at its "
             "nominal E (the middle of its range), its density and its damping alpha = tan delta x omega_1"
             f"({'L' if section is None else 'L, b'}) at its nominal loss factor; the objective: minimise "
             f"{_label(output)}. Damping: **{p['damping']}**. Requirements: " + "; ".join(p["requirements"]) + ".", "",
             "## Ranking", "",
             "Compounds that meet every requirement rank by "
             + ("their fastest drum, fastest first (ties by the objective)" if ranking.get("rank_by") == "fastest_drum"
                else "the objective")
             + ", the others after them by their largest shortfall (normalised). Robust margin: the smallest "
             "requirement margin over the compound's loss-factor range at the chosen length."
             + (" Fastest drum: the fastest drum speed at which the ROM of the compound's finger (its material, "
                "length and alpha) meets every requirement, and the requirement that fails on a faster drum "
                "(`ccedi.design.drum_speed.with_drum_speeds`)." if drum else ""), "",
             "| rank | compound | meets | E [MPa] | rho [kg/m^3] | tan delta | alpha [1/s] | L [in] | "
             + ("" if section is None else "b [mm] | ") + f"objective [{shown}] | binds (or missed) | shortfall | "
             "robust margin |" + (" fastest drum [rpm] | stops a faster drum |" if drum else ""),
             "|---" * (12 + 2 * drum + (section is not None)) + "|"]
    for r in ranking["table"]:
        lines.append(f"| {r['rank']} | {r['compound']} | {'yes' if r['feasible'] else '**no**'} | "
                     f"{r['E_Pa'] / 1e6:.4g} | {r['rho_kg_m3']:.4g} | {r['tan_delta']:.3g} | {r['alpha_per_s']:.4g} | "
                     f"{r['length_in']:.4g} | " + ("" if section is None else f"{r['semi_thickness_mm']:.4g} | ")
                     + f"{_fmt(r['objective'], unit).split(' ')[0]} | {r['binding'] or '-'} | "
                     f"{r['largest_shortfall']:.3g} | {r['robust_margin']:+.3f} |"
                     + (f" {_drum_cell(r)} |" if drum else ""))
    lines += _correction_lines(result["surrogate"].get("fea_correction"),
                               held="; on the set-up's own rubber, held across E' and the compounds; the "
                                    "compounds' optima are not verified by the ROM, which would undo it")
    win = ranking["winner"]
    if win is None:
        lines += ["", "## No compound meets the requirements", "",
                  f"The closest is **{ranking['table'][0]['compound']}**; relax the requirements above, widen the "
                  "length range, or add a compound to the catalogue."]
        return "\n".join(lines) + "\n"
    d = ranking["designs"][win]
    o = d["design"]
    lines += ["", "## Chosen compound", "",
              f"**{win}**: alpha = {o['alpha_per_s']:.4g} 1/s ({d['tie']}), L = {o['length_in']:.4g} in"
              + ("" if d.get("semi_thickness_mm") is None else f", b = {d['semi_thickness_mm']:.4g} mm") + ". "
              f"Robust margin {ranking['table'][0]['robust_margin']:+.3f} ({d['robust_limit']}).", ""]
    for flag in d["flags"]:
        lines.append(f"- Flag: {flag}.")
    fea = result.get("fea_check")
    lines += ["| output | surrogate | FEA | error |", "|---|---|---|---|"]
    for k in dict.fromkeys((output, *result["requirement_outputs"].values())):
        if k not in o:
            continue
        f_value = fea["fea"].get(k) if fea else None
        err = fea["relative_error"].get(k) if fea else None
        lines.append(f"| {_label(k).rsplit(' [', 1)[0]} | {_fmt(o[k], UNITS.get(k, ''))} | "
                     f"{_fmt(f_value, UNITS.get(k, ''))} | "
                     f"{'-' if err is None else f'{err:+.1%}'} |")
    if fea:
        lines += ["", "Error: (surrogate - FEA) / |FEA|, a length's over at least 5 mm "
                  "(`ccedi.design.model_error.output_error`)."]
        lines += ["", f"Full FEA at the compound's own E, rho and alpha ({fea['wall_time_s']:.0f} s): "
                  + _fea_verdict(fea)]
    if result.get("robust"):
        lines += _robust_lines(result, ranking, unit)
    if result.get("drum_speed"):
        lines += _drum_speed_lines(result["drum_speed"])
    lines += ["", "Figure: `finger_drawing.png` (the chosen finger's length on the drum and its section"
              + ("" if section is None else ", its chosen semi-thickness b") + ", in mm)."]
    return "\n".join(lines) + "\n"


def _drum_cell(row):
    """The ranking table's fastest drum [rpm] and the requirement that stops a faster one."""
    if not row["feasible"]:
        return "- | -"
    if row["fastest_drum_rpm"] is None or np.isnan(row["fastest_drum_rpm"]):
        return f"none | {row['drum_binding']} (even at the slowest speed run)"
    return f"{row['fastest_drum_rpm']:.3g} | {row['drum_binding'] or 'none up to the fastest speed run'}"


def _drum_speed_lines(check):
    """The chosen finger's fastest drum (:func:`ccedi.design.drum_speed.fastest_drum_speed`)."""
    lo, hi = check["speeds_rpm"][0], check["speeds_rpm"][-1]
    head = (f"The chosen finger ({check['compound']}, L = {check['length_m'] / INCH:.4g} in, alpha = "
            f"{check['alpha_per_s']:.4g} 1/s), its ROM run at {len(check['speeds_rpm'])} drum speeds over "
            f"{lo:.4g}-{hi:.4g} rpm: ")
    if check["fastest_rpm"] is None:
        text = f"misses {check['binding']} even at {lo:.4g} rpm."
    elif not check["binding"]:
        text = (f"meets every requirement up to the fastest run, {hi:.4g} rpm (an object every "
                f"{check['cycle_time_s']:.3g} s); widen --drum-speed-bounds-rpm to find its limit.")
    else:
        text = (f"meets every requirement up to **{check['fastest_rpm']:.3g} rpm** (an object every "
                f"{check['cycle_time_s']:.3g} s); faster, {check['binding']} fails.")
    return ["", "## Drum speed", "", head + text]


def _robust_lines(result, ranking, unit):
    """The robust designs' section of :func:`catalogue_report_markdown`: their ranking, the
    nominal and the robust winner side by side per requirement, the robust winner's FEA."""
    rb = result["robust"]
    p = rb["probability"]
    n = rb["designs"][0]["n_samples"] if rb["designs"] else 0

    def value(v):
        return _fmt(v, unit).split(" ")[0]

    lines = ["", "## Robust design", "",
             f"The inputs not known exactly: {rb['spread']}. Each compound's robust design is the length of least "
             f"objective (at its nominal inputs) where every requirement is met in at least {p:.0%} of {n} samples "
             "of its E and loss factor on the surrogate (the same samples at every length"
             + ("; the section's semi-thickness b held at the compound's nominal optimum" if
                result["problem"].get("semi_thickness_bounds_mm") else "")
             + "); compounds with no such "
             "length rank after, by their largest violation probability. Margins are normalised (>= 0: met); "
             f"*kept* is the margin met in {p:.0%} of the samples.", "",
             "| rank | compound | robust L [in] | objective | largest violation | nominal L [in] | objective | "
             "largest violation |", "|---|---|---|---|---|---|---|---|"]
    for k, d in enumerate(rb["designs"], start=1):
        r, nom = d["robust"], d["nominal"]
        lines.append(f"| {k} | {d['compound']} | {r['length_in']:.4g}{'' if d['feasible'] else ' (no robust length)'} | "
                     f"{value(d['objective'])} | {max(r['violation'].values(), default=0.0):.1%} | "
                     f"{nom['length_in']:.4g} | {value(d['nominal_objective'])} | "
                     f"{max(nom['violation'].values(), default=0.0):.1%} |")
    by_name = {d["compound"]: d for d in rb["designs"]}
    nominal_name = ranking["winner"] or ranking["table"][0]["compound"]
    robust_name = rb["winner"] or rb["designs"][0]["compound"]
    nom, rob = by_name[nominal_name]["nominal"], by_name[robust_name]["robust"]
    lines += ["", "### Nominal and robust design side by side", "",
              f"Nominal: **{nominal_name}**, L = {nom['length_in']:.4g} in. Robust: **{robust_name}**, "
              f"L = {rob['length_in']:.4g} in" + ("" if rb["winner"] else " (closest: no compound is robust)") + ".",
              "", "| requirement | nominal: margin | kept | violated | robust: margin | kept | violated |",
              "|---|---|---|---|---|---|---|"]
    for req in nom["violation"]:
        lines.append(f"| {req} | {nom['nominal_margin'][req]:+.3f} | {nom['margin_kept'][req]:+.3f} | "
                     f"{nom['violation'][req]:.1%} | {rob['nominal_margin'][req]:+.3f} | "
                     f"{rob['margin_kept'][req]:+.3f} | {rob['violation'][req]:.1%} |")
    fea = rb.get("fea_check")
    if fea:
        lines += ["", f"Full FEA of the robust design at its compound's nominal E, rho and alpha "
                  f"({fea['wall_time_s']:.0f} s): " + _fea_verdict(fea)]
    lines += ["", "The violation probabilities are the surrogate's; `benchmarks/robust_design_monte_carlo.py` checks "
              "them with a full-FEA Monte Carlo."]
    return lines
