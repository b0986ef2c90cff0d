"""``thermolimb export``: a saved model carried into another simulator (MuJoCo's ``<dcmotor>`` thermal state)."""

from __future__ import annotations

import sys

from ..util.errors import ThermolimbError, UsageError
from .options import add_log_input, add_quiet, add_terms
from .output import print_json, say
from .reading import in_model_units, load_model_file, read_logs, runs_of
from .types import number, output_file


def add_parser(sub):
    p = sub.add_parser(
        "export", help="write a saved model as MuJoCo's dcmotor thermal attributes (an MJCF snippet)",
        description="Map each actuator's saved first-order model onto MuJoCo's <dcmotor> thermal state (MuJoCo 3.7 "
                    "or later): the time constant is RC, the heat gain maps through the motor constant, resistance "
                    "and gear, copper's coefficient where the model has it. What one thermal node cannot hold is "
                    "dropped and said; with a LOG (the model's calibration log), what dropping it costs is measured "
                    "and the exported actuator is run in MuJoCo itself against this suite's free run "
                    "(docs/travel.md).")
    p.add_argument("model_file", metavar="MODEL.json", help="a model file written by fit or diagnose with --save")
    p.add_argument("--mujoco", action="store_true", required=True, help="export to MuJoCo's dcmotor (the only target)")
    p.add_argument("--motor-const", dest="motor_const", type=number(0.0, 1e3, low_open=True, unit="N m/A"),
                   required=True, metavar="KT", help="the motor's torque constant (N m/A)")
    p.add_argument("--resistance", type=number(0.0, 1e4, low_open=True, unit="ohm"), required=True, metavar="R",
                   help="the winding's terminal resistance (ohm)")
    p.add_argument("--gear", type=number(0.0, 1e5, low_open=True), default=1.0, metavar="G",
                   help="the gear ratio from motor to joint (default 1): a joint torque is G times the motor's")
    p.add_argument("--out", type=output_file, default=None, metavar="FILE.xml",
                   help="write the snippet to FILE.xml instead of standard output")
    add_log_input(p, required=False)
    p.add_argument("--refit", action="store_true",
                   help="with a LOG, where terms are dropped: fit the one thermal node MuJoCo holds (heat gain, RC, "
                        "offset) again on the log and export that, not the saved model without them; without "
                        "--refit, what such a refit gives is said")
    add_terms(p)
    p.add_argument("--json", action="store_true", help="the attributes, what was dropped and the check as JSON")
    add_quiet(p)
    p.set_defaults(func=run, discovers=False)
    return p


def run(args) -> int:
    from ..mujoco_export import (
        EXPORT_MARK,
        Motor,
        cost_of_dropping,
        mjcf_snippet,
        refitted,
        run_in_mujoco,
        to_dcmotor,
    )

    if args.refit and not args.logs:
        raise UsageError("--refit fits the exported model again on a log: give the model's calibration LOG too")
    from ..util.atomic import holds, replaces

    replacing = bool(args.out) and replaces(args.out, holds(EXPORT_MARK.encode()), "--out")
    models = load_model_file(args)
    names = [args.actuator] if args.actuator else list(models.actuators)
    motor = Motor(args.motor_const, args.resistance, args.gear)
    exports = [to_dcmotor(models[name], motor) for name in names]
    logs = read_logs(args.logs, args) if args.logs else []
    records = []
    for k, export in enumerate(exports):
        saved = models[export.actuator]
        series = [in_model_units(saved, s, args.model_file) for s in runs_of(logs, export.actuator)]
        refit, refit_error = None, None
        if series and export.dropped:
            try:
                refit = refitted(saved, export, series)
            except ThermolimbError as exc:  # said beside the export; with --refit, the export's own error
                if args.refit:
                    raise
                refit_error = str(exc)
        if refit is not None and args.refit:
            export = exports[k] = refit
        record = {"actuator": export.actuator, "thermal": dict(zip(
            ("resistance_K_per_W", "capacitance_J_per_K", "timeconst_s", "tempcoef_per_K", "reftemp_C", "ambient_C"),
            (export.resistance_K_per_W, export.capacitance_J_per_K, export.timeconst_s, export.tempcoef_per_K,
             export.reftemp_C, export.ambient_C))), "dropped": list(export.dropped), "notes": list(export.notes)}
        if series:
            record["cost"] = cost_of_dropping(saved, export, series)
            if refit is not None:
                cost = record["cost"] if export is refit else cost_of_dropping(saved, refit, series)
                record["refit"] = {"exported": export is refit, "params": dict(refit.exported.params),
                                   "rmse_K": cost["exported_rmse_K"]}
            elif refit_error:
                record["refit"] = {"exported": False, "error": refit_error}
            record["check"] = _check(run_in_mujoco, export, series[0])
        _say(export, record, bool(logs))
        records.append(record)
    snippet = mjcf_snippet(exports)
    if args.out:
        from ..util.atomic import atomic_path

        with atomic_path(args.out) as tmp:
            tmp.write_text(snippet)
        print(f"{'replaced' if replacing else 'wrote'} {args.out}", file=sys.stderr)
    if args.json:
        print_json(records if len(records) > 1 else records[0])
    elif not args.out:
        sys.stdout.write(snippet)
    return 0


def _check(run_in_mujoco, export, series) -> dict | None:
    """MuJoCo's integration of the exported actuator against the suite's free run of the same model, on a run."""
    try:
        mujoco_C = run_in_mujoco(export, series.signals, float(series.temperature_C[0]))
    except ImportError:
        return None
    ours = export.exported.simulate(series.signals, float(series.temperature_C[0]))
    rise = float(ours.max() - ours.min())
    worst = float(abs(mujoco_C - ours).max())
    return {"max_difference_K": worst, "rise_K": rise, "share_of_rise": worst / rise if rise > 0 else None,
            "samples": int(series.n)}


def _say(export, record, have_log: bool) -> None:
    cost, refit = record.get("cost"), record.get("refit")
    if export.dropped:  # one sentence: the cost is of dropping them all
        dropped = (f"{export.actuator}: {' and '.join(export.dropped)} dropped (MuJoCo's dcmotor has one thermal "
                   f"node, heated by its current)")
        exported = "the exported one's, refitted on the log without them," if refit and refit["exported"] else \
            "the exported one's"
        if cost:
            say(f"{dropped}: on the log the saved model's free run is {cost['saved_rmse_K']:.3f} K RMSE from the "
                f"readings, {exported} {cost['exported_rmse_K']:.3f} K ({cost['between_K']:.3f} K between the "
                f"two, {cost['samples']} samples)"
                + (f"; refitted on the log without them, one node's would be {refit['rmse_K']:.3f} K (--refit "
                   f"exports it)" if refit and "rmse_K" in refit and not refit["exported"] else "")
                + (f"; one node could not be fitted again on the log: {refit['error']}" if refit and "error" in refit
                   else ""))
        else:
            say(f"{dropped}; give the calibration log to measure what that costs")
    for note in export.notes:
        say(f"{export.actuator}: {note}")
    check = record.get("check")
    if check:
        share = check["share_of_rise"]
        say(f"{export.actuator}: in MuJoCo, the exported actuator driven by the log's effort stays within "
            f"{check['max_difference_K']:.4f} K of this suite's free run of the same model"
            + (f" ({100 * share:.3f} % of its {check['rise_K']:.2f} K rise)" if share is not None else ""))
    elif have_log and "check" in record:
        say(f"{export.actuator}: not checked in MuJoCo: the mujoco package is not installed "
            f"(pip install 'thermolimb[mujoco]')")
