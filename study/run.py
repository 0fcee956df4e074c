"""``ccedi study``: the design study of the configured finger, one step after another,
each writing its sub-report under the output directory, then ``index.html``.

The study is about the configured finger (a ``[finger] mesh``, or the generated
elliptical finger of ``[finger] impulse_length_in``); its steps (:data:`FINGER_STEPS`,
each the ``write_*`` function of a sub-command, :mod:`ccedi.study.commands`):

  finger        its mesh, stable step, tip stiffness, first frequency -> finger.json
  impulse       impulse responses for several alpha (Fig. 7)       -> impulse/
  contact       the drum contact sweep (Figs. 10, 13, 14)          -> contact/
                ([damping] kind; with paper, the paper's global damping)
  design        ROM surrogate, optimum, Pareto front, FEA re-check -> design/
  calibrate     close the loop on the bundled measured records     -> calibrate/<record>/
                (a record the declared finger cannot explain is reported, model_adequate:
                false in its JSON and in index.html, and the next record is calibrated)

The paper's reproduction is its own part, run with ``[study] paper = true`` or
``ccedi study --paper`` (what ``make demo`` runs; :data:`PAPER_STEPS`, functions of
:mod:`ccedi.study.paper_steps` and the table1 and damping-fits commands):

  table1        paper Table 1 (SM-A, SM-B, SM-C, DM)              -> table1.json
  steel_rod     CCEDI on the steel rod (Figs. 3, 4)                -> steel_rod/
  mesh          SM-A against SM-B and the DM at one alpha (Fig. 6) -> mesh/
  damping_fits  alpha_cr over finger lengths, Eq. (7)/(8) (Fig. 8) -> damping_fits/

``index.html`` reports the finger first, then the paper's reproduction when it ran.
The inputs are parsed and validated once; every step gets them as objects, and the
resolved inputs are written to ``config.toml`` first, for the record.

With a ``[finger] mesh`` every step that computes a finger runs on that mesh, and the
steps that need the generated elliptical finger at other lengths or meshes (mesh,
damping_fits, design: :func:`skipped_steps`) are skipped; their reasons go to
``study.json`` (``skipped``), stdout and ``index.html``.
Every output is written atomically, so an interrupted study (Ctrl-C) leaves the
finished steps' files and no partial ones; ``study.json`` records each finished step's
wall time [s] and validity warnings (:mod:`ccedi.fea.solvers.validity`; the index lists them).
"""
# Imports inside functions: each step loads its own library stack (its command, Dask) when it
# runs, in the process that runs it.
import json
import time
from pathlib import Path

from ccedi.errors import InputError, SolverError, ValidityWarning
from ccedi.outputs import write_json, write_text
from ccedi.progress import progress_bar

from . import paper_steps
from .config import CONFIG_NAME, SCHEMA, finger_inputs, to_toml
from .report import write_index
from .steps import FINGER_STEPS, LONGEST_FIRST, PAPER_STEPS, STEP_NAMES

QUICK = {"study": {"impulse_t_end_s": 0.05, "mesh_comparison_t_end_s": 0.03, "identification_lengths_in": [3.0, 4.5],
                   "contact_alphas_per_s": [600.0], "contact_t_end_s": 1.0, "design_fea_check": False,
                   "table1_stiffness": False, "detailed_model": False,
                   "calibration_fea_correction": False}}
"""Settings ``--quick`` overrides: a few-minute smoke run of every step."""


def steps(cfg, out, scheduler):
    """The study's steps with settings ``cfg`` writing under ``out``.

    Parameters
    ----------
    cfg : dict
        Validated inputs (:func:`ccedi.study.config.load`), parsed once and handed to
        every step as objects.
    out : Path
        Output directory of the study.
    scheduler : str
        ``serial``, ``local`` or a Dask scheduler address, for the steps' own sweeps.

    Returns
    -------
    list of (str, str, callable)
        (name, description, thunk) per step, in the study's order.
    """
    from ccedi.study.commands.design import options_from, write_designs
    from ccedi.study.commands.fea import (
        contact_setup,
        write_contact_sweep,
        write_finger,
        write_impulse,
        write_table1,
    )
    from ccedi.study.commands.rom import write_damping_fits

    f, s = cfg["finger"], cfg["study"]
    impulse = {"length_in": None if f["mesh"] else f["impulse_length_in"], "force_N": s["impulse_force_N"],
               "duration_s": s["impulse_duration_s"]}
    material, semi_axes = finger_inputs(cfg)
    records = [Path(r) for r in s["measured_records"]]
    design = options_from(cfg, fea_check=s["design_fea_check"])
    contact_damping = "global" if s["paper"] else cfg["damping"]["kind"]
    # The DM's stiffness is the one its dimensions were fitted to (validation/dm_fit.py); its
    # nonlinear solves at 2.8 mm would take tens of minutes, so the study leaves it out.
    return [
        ("finger", "the finger: stable step, stiffness, first frequency", lambda: write_finger(
            cfg, out / "finger.json", stiffness=s["table1_stiffness"])),
        ("table1", "paper Table 1", lambda: write_table1(cfg, f["impulse_length_in"], json_path=out / "table1.json",
                                                         stiffness=s["table1_stiffness"], detailed=s["detailed_model"],
                                                         detailed_stiffness=False)),
        ("steel_rod", "steel rod alpha_cr (Figs. 3, 4)", lambda: paper_steps.steel_rod(out / "steel_rod")),
        ("impulse", "impulse study (Fig. 7)", lambda: write_impulse(
            cfg, s["impulse_alphas_per_s"], out / "impulse", t_end_s=s["impulse_t_end_s"], scheduler=scheduler,
            **impulse)),
        ("mesh", "SM-A vs SM-B and the DM (Fig. 6)", lambda: paper_steps.mesh_comparison(
            out / "mesh", length_in=f["impulse_length_in"], alpha=s["mesh_comparison_alpha_per_s"],
            force_N=s["impulse_force_N"], duration_s=s["impulse_duration_s"], t_end_s=s["mesh_comparison_t_end_s"],
            scheduler=scheduler, material=material, semi_axes_m=semi_axes, detailed_model=s["detailed_model"])),
        ("damping_fits", "alpha_cr over lengths (Fig. 8)", lambda: write_damping_fits(
            cfg, s["identification_lengths_in"], out / "damping_fits", scheduler=scheduler)),
        ("contact", "drum contact sweep (Figs. 10, 13, 14)", lambda: write_contact_sweep(
            contact_setup(cfg), s["contact_alphas_per_s"], out / "contact", damping=contact_damping,
            t_end_s=s["contact_t_end_s"], scheduler=scheduler)),
        ("design", "design optimisation and FEA re-check, with the declared and the calibrated inputs",
         lambda: write_designs(cfg, design, s["design_calibration_record"], out=out / "design", scheduler=scheduler)),
        ("calibrate", "close the loop on measured records", lambda: calibrate_records(records, out / "calibrate")),
    ]


def skipped_steps(cfg):
    """The steps that do not apply to the configured finger, with the reason.

    Parameters
    ----------
    cfg : dict
        Validated inputs (:func:`ccedi.study.config.load`).

    Returns
    -------
    dict
        ``{step name: reason}``; empty for the generated finger.
    """
    if cfg["finger"]["mesh"] is None:
        return {}
    return {"mesh": "Fig. 6 compares the generated SM-A and SM-B meshes of the elliptical finger; the [finger] "
                    "mesh is one mesh (its stable step and stiffness are in Table 1)",
            "damping_fits": "Fig. 8 needs the finger at several lengths, and the [finger] mesh has one; its "
                            "alpha_cr: ccedi identify --alpha-cr --config FILE",
            "design": "design this finger with ccedi design --config FILE (alpha and the drum speed on the contact "
                      "ROM built on the mesh, the optimum verified by the mesh's full FEA, minutes per FE run); the "
                      "study's design step also re-designs with the calibrated inputs of a record of the generated "
                      "finger, which do not apply to this mesh"}


def calibrate_records(records, out):
    """Calibrate each measured record into ``out/RECORD.json`` and ``out/RECORD/``.

    A record whose declared finger cannot explain it is a result, not a failure of the
    study: its JSON and report say ``model_adequate: false`` with the evidence, one line
    says so on stdout, and the next record is calibrated.

    Parameters
    ----------
    records : sequence of Path
        Measured impulse records (CSV with a JSON sidecar beside each).
    out : Path
        Output directory of the calibrate step.

    Returns
    -------
    list of str
        The one-line messages of the records whose declared model is inadequate.
    """
    from ccedi.errors import ModelInadequate
    from ccedi.study.commands.calibrate import write_calibration

    inadequate = []
    for r in records:
        try:
            write_calibration(r, out / f"{r.stem}.json", report_dir=out / r.stem)
        except ModelInadequate as err:
            print(f"ccedi study: calibrate: {err}", flush=True)
            inadequate.append(str(err))
    return inadequate




def wanted_steps(cfg, only=None):
    """The names of the steps a study runs, in the study's order.

    Parameters
    ----------
    cfg : dict
        Validated inputs (:func:`ccedi.study.config.load`).
    only : sequence of str, optional
        Exactly these steps (a paper step named here runs without ``[study] paper``).

    Returns
    -------
    tuple of str
        :data:`FINGER_STEPS`, then :data:`PAPER_STEPS` with ``[study] paper``; or the
        names in ``only``, in that order.
    """
    if only is not None:
        return tuple(name for name in STEP_NAMES if name in only)
    return FINGER_STEPS + (PAPER_STEPS if cfg["study"]["paper"] else ())


def _run_step(name, cfg, out, scheduler):
    """Run the study step ``name`` (on a Dask worker or in this process): its wall time [s],
    the warnings it issued, recorded (:func:`ccedi.distributed.recording_warnings`), and
    the one-line message of the :class:`ccedi.errors.SolverError` that stopped it (None when
    it finished), so that one failed run does not cost the other steps their results; an
    :class:`ccedi.errors.InputError` raised inside a step (an input only that step reads)
    is a failed step too."""
    from ccedi.distributed import recording_warnings

    thunk = next(t for n, _, t in steps(cfg, out, scheduler) if n == name)
    t0 = time.perf_counter()
    try:
        _, recorded = recording_warnings(thunk)
    except (SolverError, InputError) as err:
        return time.perf_counter() - t0, [], str(err)
    return time.perf_counter() - t0, recorded, None


def _step_warnings(name, recorded):
    """Issue a finished step's recorded warnings here, a validity warning named by its
    step; returns the validity warnings' messages."""
    from ccedi.distributed import reissue_warnings

    validity = [str(m) for m, category, _, _ in recorded if issubclass(category, ValidityWarning)]
    reissue_warnings([(f"{name}: {m}", category, f, n) if issubclass(category, ValidityWarning) else (m, category, f, n)
                      for m, category, f, n in recorded])
    return validity


def _distributed(todo, cfg, out, scheduler):
    """Yield (name, wall time [s], recorded warnings, error or None) as the steps finish, each step a task on the cluster
    (its own sweeps go to the same cluster first, so the workers stay busy)."""
    from contextlib import ExitStack

    from dask.distributed import as_completed

    from ccedi.distributed import client

    with ExitStack() as stack:
        dask = client(stack, scheduler)
        futures = {dask.submit(_run_step, name, cfg, out, scheduler, key=f"ccedi-study-{name}", pure=False): name
                   for name, _, _ in todo}
        for future in as_completed(futures):
            yield futures[future], *future.result()


def _check_records(records, key="measured_records"):
    """Raise :class:`ccedi.errors.InputError` for the first measured record (or its JSON
    sidecar) that is not a readable file or whose contents do not validate
    (:func:`ccedi.calibrate.experiment.load_experiment`: columns, units, NaN, the sidecar's
    fields), before any step runs."""
    from ccedi.calibrate.experiment import load_experiment  # the calibration stack loads only when a record is set

    for record in map(Path, records):
        for path in (record, record.with_suffix(".json")):
            if not path.is_file():
                where = "" if path.is_absolute() else f" (relative to the working directory {Path.cwd()})"
                raise InputError(f"[study] {key}: {path}: no such file{where}")
        try:
            load_experiment(record)
        except InputError as err:
            raise InputError(f"[study] {key}: {err}") from None


def run_study(cfg, out, *, scheduler=None, quick=False, only=None):
    """Run the study's steps (:func:`wanted_steps`) and write ``out/index.html``.
    Serial: one step after another in this process. Otherwise every step is a task on the
    Dask cluster, longest first, and its runs are mapped over the same cluster. Returns
    the index path. The measured records are checked before any step runs.

    Parameters
    ----------
    cfg : dict
        Validated inputs (:func:`ccedi.study.config.load`).
    out : str or Path
        Output directory.
    scheduler : str, optional
        ``serial``, ``local`` or a Dask scheduler address (default: the config's).
    quick : bool, optional
        Apply :data:`QUICK`, a few-minute smoke run of every step.
    only : sequence of str, optional
        Run only these steps, then rewrite the index.

    Returns
    -------
    Path
        ``out/index.html``.

    Raises
    ------
    ccedi.errors.InputError
        A measured record or its sidecar is missing.
    ccedi.errors.SolverError
        A step's run failed (e.g. an element inverted); raised after every other step has
        run and the index is written, with the failed steps' messages in ``study.json``
        (``failed``) and on the page.
    """
    from ccedi.distributed import SERIAL
    from ccedi.outputs import remove_temporaries

    if quick:
        for section, keys in QUICK.items():
            for key, value in keys.items():
                if cfg[section][key] not in (value, SCHEMA[section][key].default):
                    print(f"ccedi study: --quick sets [{section}] {key} = {value!r} instead of the configured "
                          f"{cfg[section][key]!r}", flush=True)
        cfg = {sec: {**keys, **QUICK.get(sec, {})} for sec, keys in cfg.items()}
    out = Path(out)
    scheduler = scheduler or cfg["study"]["scheduler"]
    wanted = wanted_steps(cfg, only)
    skipped = {name: why for name, why in skipped_steps(cfg).items() if name in wanted}
    todo = sorted((st for st in steps(cfg, out, scheduler) if st[0] in wanted and st[0] not in skipped),
                  key=lambda st: wanted.index(st[0]))
    if any(name == "calibrate" for name, _, _ in todo):
        _check_records(cfg["study"]["measured_records"])
    if any(name == "design" for name, _, _ in todo) and cfg["study"]["design_calibration_record"]:
        _check_records([cfg["study"]["design_calibration_record"]], "design_calibration_record")
    write_text(out / CONFIG_NAME, to_toml(cfg))
    record = {"config": cfg, "quick": quick, "scheduler": scheduler, "wall_time_s": {}, "warnings": {},
              "skipped": {}, "failed": {}}
    if only is not None and (out / "study.json").exists():     # keep the other steps' timings and warnings
        before = json.loads((out / "study.json").read_text())
        record["wall_time_s"] = before["wall_time_s"]
        record["warnings"] = before.get("warnings", {})
        rerun = {n for n, _, _ in todo}
        record["skipped"] = {k: v for k, v in before.get("skipped", {}).items() if k not in rerun}
        record["failed"] = {k: v for k, v in before.get("failed", {}).items() if k not in rerun}
    record["skipped"].update(skipped)
    for name, why in skipped.items():
        record["wall_time_s"].pop(name, None)
        print(f"ccedi study: {name} skipped: {why}", flush=True)
    write_json(out / "study.json", record)
    t0 = time.perf_counter()
    finished = ((name, *_run_step(name, cfg, out, scheduler)) for name, _, _ in todo) if scheduler == SERIAL \
        else _distributed(sorted(todo, key=lambda st: LONGEST_FIRST.index(st[0])), cfg, out, scheduler)
    try:
        for name, wall, recorded, error in progress_bar(finished, total=len(todo), desc="ccedi study", unit="step"):
            record["warnings"][name] = _step_warnings(name, recorded)
            record["wall_time_s"][name] = wall
            record["elapsed_s"] = time.perf_counter() - t0
            if error is not None:
                record["failed"][name] = error
            write_json(out / "study.json", record)
            print(f"ccedi study: {name} " + (f"failed after {wall:.0f} s: {error}" if error else f"done in {wall:.0f} s"),
                  flush=True)
    except KeyboardInterrupt:
        remove_temporaries(out)
        raise
    index = write_index(out)
    if record["failed"]:
        raise SolverError(f"{len(record['failed'])} step(s) failed ({', '.join(record['failed'])}); {index} "
                          "shows the other steps' results and why")
    return index
