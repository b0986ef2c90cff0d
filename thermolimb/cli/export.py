"""``thermolimb export``: a saved model carried into another simulator (MuJoCo's ``<dcmotor>`` thermal
state)."""

from __future__ import annotations

import argparse

from ..util.errors import UsageError
from .options import add_log_input, add_terms
from .output import say
from .reading import in_model_units, load_model_file, read_logs, runs_of
from .template import Command, Outcome
from .types import number, output_file

FORMATS = ("mujoco",)  # what --to carries a model into


class Export(Command):
    name = "export"
    help = "write a saved model as MuJoCo's dcmotor thermal attributes (an MJCF snippet)"
    description = ("Map each actuator's saved first-order model onto "
                    "MuJoCo's <dcmotor> thermal state (MuJoCo 3.7 "
                    "or later): the time constant is RC, the heat "
                    "gain maps through the motor constant, resistance "
                    "and gear, copper's coefficient where the model "
                    "has it. What one thermal node cannot hold is "
                    "dropped and said; with a LOG (the model's "
                    "calibration log), what dropping it costs is measured "
                    "and the exported actuator is run in MuJoCo itself against this suite's free run "
                    "(docs/travel.md).")

    def add_options(self, p):
        p.add_argument("model_file", metavar="MODEL.json", help="a model file written by "
                                                                "fit or diagnose with --save")
        p.add_argument("--to", choices=FORMATS, default=FORMATS[0], help="the simulator to carry the model "
                       "into (default mujoco: its <dcmotor>, the one so far)")
        p.add_argument("--mujoco", dest="to", action="store_const", const="mujoco", help=argparse.SUPPRESS)
        p.add_argument("--motor-const", dest="motor_const",
                       type=number(0.0, 1e3, low_open=True, unit="N m/A"), required=True, metavar="KT",
                       help="the motor's torque constant (N m/A)")
        p.add_argument("--resistance", type=number(0.0, 1e4, low_open=True, unit="ohm"), required=True,
                       metavar="R", help="the winding's terminal resistance (ohm)")
        p.add_argument("--gear", type=number(0.0, 1e5, low_open=True), default=1.0, metavar="G",
                       help="the gear ratio from motor to joint (default "
                            "1): a joint torque is G times the motor's")
        p.add_argument("--out", type=output_file, default=None, metavar="FILE.xml",
                       help="write the snippet to FILE.xml instead of standard output")
        add_log_input(p, required=False)
        p.add_argument("--refit", action="store_true", help="with a LOG, where terms are dropped: fit the "
                       "one thermal node MuJoCo holds (heat gain, RC, "
                       "offset) again on the log and export that, not the saved model without them; without "
                       "--refit, what such a refit gives is said")
        add_terms(p)
        p.add_argument("--json", action="store_true", help="the attributes, what was "
                                                           "dropped and the check as JSON")

    plots = None

    def check(self, args):
        if args.refit and not args.logs:
            raise UsageError("--refit fits the exported model again on "
                             "a log: give the model's calibration LOG too")

    def outputs(self, args):
        return (args.out,)

    def work(self, args) -> Outcome:
        from ..mujoco_export import EXPORT_MARK, Motor, exported, mjcf_snippet, to_dcmotor
        from ..util.atomic import holds, replaces

        if args.out:
            replaces(args.out, holds(EXPORT_MARK.encode()), "--out")
        models = load_model_file(args)
        names = [args.actuator] if args.actuator else list(models.actuators)
        motor = Motor(args.motor_const, args.resistance, args.gear)
        for name in names:  # what cannot be exported is refused before any log is read
            to_dcmotor(models[name], motor)
        logs = read_logs(args.logs, args) if args.logs else []
        exports, records = [], []
        for name in names:
            saved = models[name]
            series = [in_model_units(saved, s, args.model_file) for s in runs_of(logs, name)]
            export, record = exported(saved, motor, series, args.refit)
            _say(export, record)
            exports.append(export)
            records.append(record)
        snippet = mjcf_snippet(exports)
        if args.out:
            from ..util.atomic import atomic_path

            with atomic_path(args.out) as tmp:
                tmp.write_text(snippet)
        # without --out the snippet is the product, on standard output
        text = "" if args.out else snippet.rstrip("\n")
        return Outcome(records if len(records) > 1 else records[0], text, (args.out,) if args.out else ())


add_parser = Export().add_parser


def _say(export, record) -> None:
    cost, refit = record.get("cost"), record.get("refit")
    if export.dropped:  # one sentence: the cost is of dropping them all
        dropped = (f"{export.actuator}: {' and '.join(export.dropped)} "
                   "dropped (MuJoCo's dcmotor has one thermal "
                   f"node, heated by its current)")
        exported = (
            "the exported one's, refitted on the log without them,"
            if refit and refit["exported"]
            else "the exported one's"
        )
        if cost:
            say(
                f"{dropped}: on the log the saved model's free run "
                f"is {cost['saved_rmse_K']:.3f} K RMSE from the "
                f"readings, {exported} {cost['exported_rmse_K']:.3f} "
                f"K ({cost['between_K']:.3f} K between the "
                f"two, {cost['samples']} samples)"
                + (
                    "; refitted on the log without them, one node's "
                    f"would be {refit['rmse_K']:.3f} K (--refit "
                    f"exports it)"
                    if refit and "rmse_K" in refit and not refit["exported"]
                    else ""
                )
                + (
                    f"; one node could not be fitted again on the log: {refit['error']}"
                    if refit and "error" in refit
                    else ""
                )
            )
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
    elif "check" in record:
        say(f"{export.actuator}: not checked in MuJoCo: the mujoco package is not installed "
            f"(pip install 'thermolimb[mujoco]')")
