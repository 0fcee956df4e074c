"""``ccedi calibrate`` (:mod:`ccedi.calibrate`): close the loop on a measured record.

  calibrate DATA.csv [--meta DATA.json] --json OUT.json [--report DIR] [--effects NAME ...]
            [--write-config OUT.toml] [--fea-correction] [--predict-contact CONTACT.csv|CONTACT.json]
            [--add-compound NAME [--compounds CATALOGUE.csv]]

``--predict-contact`` predicts the same finger's contact record from the impulse record's
calibrated E and alpha (:mod:`ccedi.calibrate.prediction`): contact start, end, duration and
filtered peak force, each with its 95 % interval, against the record's own when a record
(CSV with its sidecar) is given, not only its sidecar; the JSON gets a ``prediction`` block
and the report a table and ``prediction.png``.

``--add-compound NAME`` (impulse records) catalogues the record's finger as compound NAME
(:func:`ccedi.design.compounds.identified_compound`): the calibrated alpha and E (+- 2
standard errors), the finger's length, and tan delta = alpha / omega_1 at its first mode,
added to (or replacing NAME in) the catalogue ``--compounds`` (default ``compounds.csv`` in
the current directory; the bundled ``data/compounds.csv`` only when named there).

``--write-config`` writes the calibrated inputs (:func:`ccedi.study.config.calibrated_config`)
as a TOML fragment that ``ccedi study --config`` and every other ``--config`` command read.

Everything is loaded, validated and computed before the first file is written, and each
file is written atomically, so bad data leaves no output behind. A declared finger that
cannot explain the record (:mod:`ccedi.calibrate.adequacy`) is not bad data: the JSON
(``model_adequate: false``, the evidence, no effect) and the report are written in full,
then :class:`ccedi.errors.ModelInadequate` gives exit status 3.
"""
# Imports inside functions: building the parser imports no library, so that `ccedi --help`
# answers at once (tests/conventions/test_layout.py); each command loads what it runs.
from dataclasses import asdict
from pathlib import Path

from ccedi.errors import InputError, ModelInadequate
from ccedi.study.commands.arguments import add_command, add_output_argument


def add_parsers(sub):
    """Register calibrate on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-command registry of the ``ccedi`` parser.
    """
    from ccedi.calibrate.effects import CATALOGUE, CONTACT_CATALOGUE

    c = add_command(sub, "calibrate", help="fit the declared finger to a measured impulse or contact record, find "
                       "the effects its residual points to, report the error before and after")
    c.add_argument("csv", help="measured record: impulse (sidecar kind \"impulse\") time_s, tip_displacement_m"
                               "[, force_N]; contact (kind \"contact\") time_s, reaction_force_N")
    c.add_argument("--meta", help="JSON sidecar describing the experiment (default: DATA.json beside DATA.csv)")
    add_output_argument(c, "--json", "file", required=True, help="write the result as JSON to this path")
    add_output_argument(c, "--report", "dir", help="directory for plots, residuals.csv and report.md")
    add_output_argument(c, "--write-config", "file", help="write the calibrated inputs ([material] E_Pa, "
                        "alpha_per_s, ...; a contact record's [drum] too) as a TOML file for --config")
    c.add_argument("--effects", nargs="+", choices=sorted(set(CATALOGUE) | set(CONTACT_CATALOGUE)), metavar="EFFECT",
                   help=f"candidate effects (default: the record kind's whole catalogue; impulse: "
                        f"{', '.join(CATALOGUE)}; contact: {', '.join(CONTACT_CATALOGUE)})")
    c.add_argument("--fea-correction", action="store_true",
                   help="contact record: correct the reduced chain by one or two full explicit FE runs (~2 minutes "
                        "each) and check the result against the full FEA")
    c.add_argument("--predict-contact", metavar="CONTACT",
                   help="impulse record: predict the same finger's contact record from the calibrated E and alpha "
                        "(contact start, duration, filtered peak force with 95 %% intervals); CONTACT.csv (a contact "
                        "record, its sidecar beside it: measured against predicted) or CONTACT.json (a contact "
                        "sidecar alone: no record yet)")
    c.add_argument("--add-compound", metavar="NAME",
                   help="impulse record: add the calibrated finger to a compound catalogue as NAME (replacing a row "
                        "NAME): alpha, E +- 2 standard errors, the finger length and tan delta = alpha / omega_1 at its "
                        "first mode, alpha_source the record")
    add_output_argument(c, "--compounds", "file", metavar="CATALOGUE",
                        help="the compound catalogue CSV --add-compound writes to (default: compounds.csv in the "
                             "current directory)")
    c.set_defaults(func=cmd_calibrate)


def cmd_calibrate(args):
    """``ccedi calibrate``: :func:`write_calibration` of the parsed arguments."""
    write_calibration(args.csv, args.json, report_dir=args.report, meta=args.meta, effects=args.effects,
                      config_path=args.write_config, fea_correction=args.fea_correction,
                      predict_contact=args.predict_contact, add_compound=args.add_compound,
                      compounds_path=args.compounds)


def write_calibration(csv, json_path, *, report_dir=None, meta=None, effects=None, config_path=None,
                      fea_correction=False, predict_contact=None, add_compound=None, compounds_path=None):
    """Calibrate the declared finger on one measured impulse or contact record and write the result.

    Parameters
    ----------
    csv : str or Path
        Measured record (impulse: ``time_s``, ``tip_displacement_m``[, ``force_N``, ...];
        contact: ``time_s``, ``reaction_force_N``).
    json_path : str or Path
        Result JSON.
    report_dir : str or Path, optional
        Directory for plots, ``residuals.csv`` and ``report.md``.
    meta : str or Path, optional
        JSON sidecar (default: beside the CSV).
    effects : sequence of str, optional
        Candidate effects (default: the whole catalogue of the record's kind,
        :data:`ccedi.calibrate.effects.CATALOGUE` or ``CONTACT_CATALOGUE``).
    config_path : str or Path, optional
        Where to write the calibrated inputs as TOML (:func:`ccedi.study.config.calibrated_config`);
        not written when the declared model is inadequate.
    fea_correction : bool, optional
        Correct a contact record's chain by the full FEA at the baseline and check the
        final model with it (:func:`ccedi.calibrate.loop.calibrate`). Default False.
    predict_contact : str or Path, optional
        A contact record CSV (sidecar beside it) or a contact sidecar JSON of the impulse
        record's finger: its features are predicted from the calibration
        (:func:`ccedi.calibrate.prediction.predict_contact`; not when the declared model
        is inadequate). Default None.
    add_compound : str, optional
        Catalogue the calibrated finger as this compound (an impulse record only; not when
        the declared model is inadequate). Default None.
    compounds_path : str or Path, optional
        The catalogue ``add_compound`` writes to. Default ``compounds.csv`` in the current
        directory.

    Returns
    -------
    dict
        What the JSON holds.

    Raises
    ------
    ccedi.errors.InputError
        The record or its sidecar is invalid, or an effect is not in the record kind's
        catalogue, or the contact set-up to predict is invalid, not of a contact record,
        of another finger, or given with a contact record to calibrate, or a compound is to be
        added from a contact record, under an empty name or to an invalid catalogue, or a
        catalogue is named without a compound to add (nothing is written).
    ccedi.errors.ModelInadequate
        The declared finger cannot explain the record: raised after the JSON (with
        ``model_adequate: false``) and the report are written; its message is one line
        naming the failed checks and the record's own first-mode frequency.
    """
    import time

    from ccedi.calibrate.experiment import load_experiment
    from ccedi.calibrate.loop import calibrate, summary
    from ccedi.calibrate.prediction import check_same_finger, load_contact_setup
    from ccedi.calibrate.prediction import predict_contact as predict
    from ccedi.design.compounds import identified_compound, load_compounds, save_compound
    from ccedi.outputs import write_json, write_text
    from ccedi.study.calibration_report import write_report
    from ccedi.study.config import calibrated_config

    t0 = time.perf_counter()
    exp = load_experiment(csv, meta)
    if predict_contact is not None:
        if exp.kind != "impulse":
            raise InputError(f"--predict-contact: {csv} is a {exp.kind} record; a contact record is predicted from "
                             "an impulse record's calibration")
        try:
            contact, recorded = load_contact_setup(predict_contact)
        except InputError as err:
            raise InputError(f"--predict-contact: {err}") from None
        check_same_finger(exp, contact)
    if compounds_path is not None and add_compound is None:
        raise InputError("--compounds names the catalogue --add-compound writes to; give --add-compound NAME too")
    if add_compound is not None:
        if exp.kind != "impulse":
            raise InputError(f"--add-compound: {csv} is a {exp.kind} record; a compound's alpha is identified from "
                             "an impulse record")
        if not add_compound.strip():
            raise InputError("--add-compound: the compound name is empty")
        compounds_path = Path("compounds.csv") if compounds_path is None else Path(compounds_path)
        if compounds_path.exists():
            load_compounds(compounds_path)          # a bad catalogue is refused before the calibration
    cal = calibrate(exp, candidates=effects, fea_correction=fea_correction,
                    progress=lambda message: print(f"calibrate: {message}", flush=True))
    result = summary(cal) | {"wall_time_s": time.perf_counter() - t0}
    b, fin, err = result["baseline"], result["final_params"], result["final_stderr"]
    found = "; ".join(f"{e['name']} (" + ", ".join(f"{k} = {v:.4g} +- {e['stderr_final'][k]:.2g}"
                                                  for k, v in e["params_final"].items()) + ")"
                      for e in result["effects_found"]) or "no effect added"
    print(f"result: alpha = {fin['alpha_per_s']:.5g} +- {err['alpha_per_s']:.2g} 1/s, E = "
          f"{result['calibrated']['E_Pa']:.5g} Pa (declared x {fin['E_factor']:.4f} +- {err['E_factor']:.2g}); {found}")
    if result["chain_baseline"]:
        c = result["chain_baseline"]
        print(f"chain baseline: NRMSE {c['nrmse']:.3%}, alpha = {c['params']['alpha_per_s']:.4g} 1/s, "
              f"E x {c['params']['E_factor']:.4f}; corrected by the full FEA there")
    print(f"baseline (the declared finger, before any effect): NRMSE {b['nrmse']:.3%}, alpha = "
          f"{b['params']['alpha_per_s']:.4g} 1/s, E x {b['params']['E_factor']:.4f}")
    for e in result["effects_found"]:
        params = ", ".join(f"{k} = {v:.4g} +- {e['stderr'][k]:.2g}" for k, v in e["params"].items())
        print(f"+ {e['name']} as added ({params}): NRMSE {e['nrmse_after']:.3%}; {e['why']}")
    print(f"final NRMSE {result['final_nrmse']:.3%}, noise floor {result['noise_floor_nrmse']:.3%}; "
          f"{result['stop_reason']}")
    if result["ambiguous"]:
        a = result["ambiguous"]
        print(f"ambiguous: {' or '.join(a['effects'])} (neither added); separate them by "
              f"{a['separating_measurement']['measurement']}")
    if result["rejected_effects"]:
        r = result["rejected_effects"]
        print(f"not accepted: {'+'.join(r['effects'])} leave the residual at {r['rms_over_noise']:.3f} sigma "
              f"(the nearest catalogued stand-ins, not the missing physics)")
    if result["fea_check"]:
        f = result["fea_check"]
        print(f"full FEA (run of the last correction, {f['fea_runs']} run(s)): NRMSE {f['nrmse']:.3%} ({f['rms_over_noise']:.3f} x the noise std), "
              f"peak {f['peak_error']:+.2%}")
    if result["unexplained_residual"]:
        s = result["sparse_term"]
        print(f"unexplained residual: best sparse term {s['force']} removes {s['error_reduction']:.0%} of it")
    prediction = None
    if predict_contact is not None:
        if result["model_adequate"]:
            prediction = predict(cal, contact, recorded=recorded)
            print_prediction(prediction)
        else:
            print(f"no contact prediction: {result['adequacy']['message']}")
        result["prediction"] = None if prediction is None else prediction.summary()
    config_text = calibrated_config(result, exp) if config_path and result["model_adequate"] else None
    compound = None
    if add_compound is not None and result["model_adequate"]:
        f = exp.finger
        compound = identified_compound(add_compound.strip(), alpha_per_s=fin["alpha_per_s"],
                                       alpha_stderr_per_s=err["alpha_per_s"], E_Pa=result["calibrated"]["E_Pa"],
                                       E_stderr_Pa=f.E_Pa * err["E_factor"], rho_kg_m3=f.rho_kg_m3,
                                       length_m=f.length_m, semi_axes_m=f.semi_axes_m, nu=f.nu, source=str(csv))
        result["compound"] = {"catalogue": str(compounds_path)} | asdict(compound)
    elif add_compound is not None:
        print(f"no compound added: {result['adequacy']['message']}")
    if report_dir:
        for path in write_report(report_dir, cal, result, prediction=prediction):
            print(f"wrote {path}")
    write_json(json_path, result)
    print(f"wrote {json_path}")
    if config_text is not None:
        write_text(config_path, config_text)
        print(f"wrote {config_path}")
    if compound is not None:
        replaced = save_compound(compounds_path, compound)
        print(f"{'replaced' if replaced else 'added'} compound {compound.name} in {compounds_path}: alpha = "
              f"{compound.alpha_per_s:.5g} 1/s on the {compound.alpha_finger_length_in:.4g}-in finger, tan delta "
              f"{compound.tan_delta_min:.3g}..{compound.tan_delta_max:.3g} at its first mode "
              f"({compound.band_min_hz:.4g} Hz)")
    if not result["model_adequate"]:
        raise ModelInadequate(f"{csv}: {result['adequacy']['message']} (no effect added; {json_path} has "
                              f"model_adequate: false and the evidence)")
    return result


def print_prediction(prediction):
    """Print a contact prediction, one line per feature: predicted value, interval, unit and,
    with a record, the measured value and whether it lies inside.

    Parameters
    ----------
    prediction : ccedi.calibrate.prediction.ContactPrediction
        The prediction.
    """
    from ccedi.calibrate.prediction import FEATURE_NAMES, FEATURES, INTERVAL_PROBABILITY

    v = prediction.values
    print(f"contact prediction ({prediction.contact.record.source}) at E x {v['E_factor']:.4f} of its declared E, "
          f"alpha = {v['alpha_per_s']:.4g} 1/s:")
    for name, f in prediction.features.items():
        unit = FEATURES[name]
        lo, hi = f.interval
        line = (f"  {FEATURE_NAMES[name]}: predicted {f.predicted:.4g} {unit} ({INTERVAL_PROBABILITY:.0%} interval "
                f"{lo:.4g}..{hi:.4g} {unit})")
        if f.measured is not None:
            line += f"; measured {f.measured:.4g} {unit}: {'inside' if f.inside else 'OUTSIDE'}"
        print(line)
    if prediction.effects_not_carried:
        print(f"  (the impulse record's {'+'.join(prediction.effects_not_carried)} is not in the contact chain: the "
              "prediction is of the finger without it)")
