"""``thermolimb monitor``: follow a running robot's log with a saved model and publish what it estimates."""

from __future__ import annotations

from ..util.errors import UsageError
from ..util.interrupts import ignore_further
from .options import add_log_input, add_temperature, add_terms
from .output import existing, say, say_written
from .reading import load_model_file
from .template import Command, Outcome
from .types import integer, number, output_file


class Monitor(Command):
    name = "monitor"
    help = "follow a log as it is written: winding estimates, time to the limit, derating, live"
    description = ("Follow a log while another program writes it "
                    "-- a CSV read as fit reads it (the canonical "
                    "columns, or a wide file with --map) or an MCAP "
                    "/ ROS 2 bag being recorded (--map); a line that "
                    "cannot be read is said and skipped, a pause "
                    "starts a new run; for each actuator run the saved "
                    "model with a Kalman filter on "
                    "its readings (the winding temperature and its "
                    "uncertainty), the time to the limit at the "
                    "current effort and the protection's derating; "
                    "publish them as ROS 2 messages to an MCAP, live "
                    "to Foxglove, or as JSON lines. Ends on Ctrl-C, "
                    "SIGTERM or --idle-exit, every output complete. "
                    "Topics and messages: docs/model-file.md.")

    def add_options(self, p):
        p.add_argument("model_file", metavar="MODEL.json", help="a model file written by "
                                                                "fit or diagnose with --save")
        p.add_argument("--follow", required=True, metavar="LOG",
                       help="the log to follow: a CSV (waited for if it "
                            "does not exist yet), or an MCAP (or a ROS 2 bag "
                            "folder) being recorded")
        add_log_input(p, positional=False)
        add_terms(p)
        add_temperature(p, "--limit-C",
                        "the winding limit of every actuator (default: each model's stored limit)")
        p.add_argument("--measurement-std-K", dest="measurement_std_K", type=number(0.0, 10.0, low_open=True),
                       default=0.1, metavar="K", help="the thermistor's noise, 1 sigma, "
                                                      "quantisation included (default 0.1)")
        p.add_argument("--mcap", type=output_file, default=None, metavar="OUT.mcap",
                       help="write sensor_msgs/Temperature per actuator "
                            "and diagnostic_msgs/DiagnosticArray to OUT.mcap")
        p.add_argument("--foxglove", type=integer(0, 65535), nargs="?", const=8765, default=None,
                       metavar="PORT", help="serve the same channels live on Foxglove's "
                       "WebSocket protocol (default port 8765; extra " "'live')")
        p.add_argument("--layout", type=output_file, default=None, metavar="FILE",
                       help="also write a Foxglove layout for these actuators' "
                            "channels to FILE (import it in Foxglove)")
        p.add_argument("--json-lines", action="store_true", help="one JSON object per "
                                                                 "publication on standard output")
        p.add_argument("--publish-hz", type=number(0.0, 10000.0, low_open=True), default=20.0, metavar="HZ",
                       help="at most this many publications per second of log time (default 20)")
        p.add_argument("--poll-s", type=number(0.001, 60.0), default=0.05, metavar="S",
                       help="how often the log is checked for new rows (default 0.05 s)")
        p.add_argument("--idle-exit", type=number(0.0, 1e6, low_open=True), default=None, metavar="S",
                       help="end when the log has not grown for S seconds")

    plots = None

    def check(self, args):
        if not (args.mcap or args.foxglove is not None or args.json_lines):
            raise UsageError("monitor needs somewhere to publish: --mcap "
                             "OUT.mcap, --foxglove [PORT] or --json-lines")

    def work(self, args) -> Outcome:
        from ..monitor import Session, follow
        from ..monitor.outputs import FoxgloveOutput, JsonLinesOutput
        from ..monitor.recording import McapOutput

        models = load_model_file(args)
        names = list(models.actuators)
        limits = {n: args.limit_C for n in names} if args.limit_C is not None else {}
        if args.actuator is not None and args.actuator not in models.actuators:
            raise UsageError(f"--actuator {args.actuator}: the model file has no such actuator; it has "
                             f"{', '.join(models.actuators)}")
        follower = _follower(args)  # what cannot be followed is refused before any output is opened
        if args.layout:
            from ..monitor.layout import MARK, layout_text
            from ..util.atomic import atomic_path, holds, replaces

            replaces(args.layout, holds(MARK.encode()), "--layout")
            existed = existing(args.layout)
            with atomic_path(args.layout) as tmp:
                tmp.write_text(layout_text(names))
            say_written({}, None, (args.layout,), existed)  # now: the monitor runs until it is stopped
        outputs = []
        try:
            if args.mcap:
                outputs.append(McapOutput(args.mcap, names))
            if args.foxglove is not None:
                fox = FoxgloveOutput(args.foxglove, names)
                outputs.append(fox)
                say(f"Foxglove: open ws://127.0.0.1:{fox.port} (layout: {_layout()})")
            if args.json_lines:
                outputs.append(JsonLinesOutput())
        except BaseException:
            for out in outputs:
                out.close()
            raise
        session = Session(models, limits, outputs, args.measurement_std_K, 1.0 / args.publish_hz,
                          only=args.actuator)
        try:
            follow(session, follower, args.poll_s, args.idle_exit)
        # the monitor's usual end: its outputs are complete (a second signal changes nothing)
        except KeyboardInterrupt:
            ignore_further()
            say(f"stopped after {session.samples} samples; every output closed")
        return Outcome()


add_parser = Monitor().add_parser


def _follower(args):
    """The follower of ``--follow``: a CSV through the logs package's reading, or a recorded MCAP; what cannot
    be followed at all is one sentence."""
    from pathlib import Path

    from ..logs.follow import CsvFollower
    from ..logs.follow_mcap import McapFollower
    from ..logs.formats import followed_as
    from .reading import read_options

    path = Path(args.follow)
    if path.is_dir() and not any(path.glob("*.mcap")) and not any(path.glob("metadata.yaml")):
        raise UsageError(f"--follow {path}: a folder with no ROS 2 bag "
                         "in it; expected a CSV log, an MCAP, or a bag "
                         f"folder being recorded")
    if path.exists() and not path.is_file() and not path.is_dir():
        raise UsageError(f"--follow {path}: not a regular file (a device "
                         "or a pipe); expected a log file another "
                         f"program writes")
    kind = followed_as(path)
    if kind == "mcap":
        return McapFollower(path, args.map)
    if kind != "csv":
        raise UsageError(f"--follow {path}: a {kind} file is written "
                         "whole, not row by row; monitor follows a CSV or "
                         f"an MCAP as it is written (predict reads a finished {kind} log)")
    options = read_options(args, path)
    return CsvFollower(
        path,
        args.actuator,
        options["mapping"] or None,
        {k: options[k] for k in ("velocity_unit", "effort_unit", "sep", "decimal", "drop_incomplete")},
    )


def _layout() -> str:
    from importlib.resources import files

    return str(files("thermolimb.data").joinpath("foxglove_layout.json"))
