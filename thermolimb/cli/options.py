"""Options shared by several subcommands: reading logs, choosing how to validate, printing."""

from __future__ import annotations

import json
import sys

from ..errors import UsageError
from ..evaluation import Scheme
from ..jsonutil import to_jsonable
from ..logs import VELOCITY_UNITS, ActuatorSeries, ThermalLog, parse_mapping, read_log
from ..logs.bags import is_bag
from .types import folds, fraction

SEPARATORS = {"comma": ",", "semicolon": ";", "tab": "\t", "bar": "|"}


def add_quiet(p):
    p.add_argument("--quiet", action="store_true", help="no progress bars")


def add_log_input(p):
    p.add_argument("logs", nargs="+", metavar="LOG",
                   help="log file(s): CSV, Parquet, ROS 1 bag or ROS 2 bag (.mcap, .db3 or its folder); several logs (runs) of the same actuators are fitted jointly, "
                        "each run simulated from its own first reading")
    p.add_argument("--map", default=None, metavar="CANONICAL=COLUMN,...",
                   help="read a wide file by naming its columns, e.g. effort=torque,temperature=stator_winding,"
                        "housing=case_temp (a second sensor); for one column per joint use {j} for the joint number "
                        "and * for any text: effort=Current_J{j},temperature=Temperature_*{j}; a column on a time base "
                        "of its own as COLUMN@TIME_COLUMN; for a bag, /topic.field "
                        "(effort=/joint_states.effort,temperature=/temperatures.temps; see thermolimb inspect)")
    p.add_argument("--velocity-unit", default="rad/s", choices=sorted(VELOCITY_UNITS),
                   help="unit of the velocity column (default rad/s); converted to rad/s")
    p.add_argument("--sep", default=None, choices=sorted(SEPARATORS),
                   help="CSV separator (default: found from the file)")
    p.add_argument("--decimal", default=None, choices=(".", ","),
                   help="decimal mark in a CSV (default: found from the file; ',' in ';'-separated files that use it)")
    p.add_argument("--drop-incomplete", action="store_true",
                   help="leave out samples with a missing value (and say how many) instead of refusing the file")
    p.add_argument("--actuator", default=None, metavar="NAME",
                   help="actuator to use (default: every actuator in the log); names the actuator of a wide "
                        "single-actuator file, so that several such files fit jointly")


def add_validation(p):
    p.add_argument("--split", type=fraction, default=0.7,
                   help="fraction of each run's time span used to fit (default 0.7)")
    p.add_argument("--cv", type=folds, default=None, metavar="K|runs",
                   help="blocked cross-validation over K contiguous folds, or 'runs': leave one run out")
    p.add_argument("--validate-on", nargs="+", default=None, metavar="LOG",
                   help="fit on the LOGs given first and validate on these runs (read with the same options)")
    p.add_argument("--restart-at-split", action="store_true",
                   help="restart the validation free run at the split from the measured temperature, hidden states "
                        "at rest (default: carried from each run's start through the training part)")


def scheme_of(args) -> Scheme:
    if args.validate_on and args.cv:
        raise UsageError("--validate-on and --cv are two ways to validate; give one")
    return Scheme(split=args.split, folds=args.cv if isinstance(args.cv, int) else None,
                  by_run=args.cv == "runs", restart_at_split=args.restart_at_split)


def _read(paths, args) -> list[ThermalLog]:
    mapping = parse_mapping(args.map)
    sep = SEPARATORS[args.sep] if args.sep else None
    name = args.actuator if mapping and "actuator" not in mapping else None
    return [read_log(path, mapping=mapping, velocity_unit=args.velocity_unit,
                     actuator_name=args.actuator if is_bag(path) else name, sep=sep,
                     decimal=args.decimal, drop_incomplete=args.drop_incomplete) for path in paths]


def read_logs(args) -> list[ThermalLog]:
    return _read(args.logs, args)


def _runs(logs: list[ThermalLog], name: str) -> list[ActuatorSeries]:
    runs = []
    for log in logs:
        runs += log.runs(name)
    return runs


def print_json(obj) -> None:
    json.dump(to_jsonable(obj), sys.stdout, indent=2)
    sys.stdout.write("\n")


def for_each_actuator(args, analyse) -> int:
    """Run ``analyse(name, runs, held_out_runs) -> (record, text)`` for the chosen actuator or every one.

    Prints what reading changed on standard error, each text, or with
    ``--json`` one record (a list when several actuators).
    """
    logs = read_logs(args)
    held = _read(args.validate_on, args) if getattr(args, "validate_on", None) else []
    names = [args.actuator] if args.actuator else list(logs[0].actuators)
    for log in logs + held:
        for note in log.notes:
            print(f"note: {note}", file=sys.stderr)
        for name in names:
            if name in log.actuators:
                gap = log.describe_gaps(name)
                if gap:
                    print(f"note: {gap}", file=sys.stderr)
    records = []
    for name in names:
        missing = [log.source for log in logs + held if name not in log.actuators]
        if missing:
            raise UsageError(f"{missing[0]}: no actuator {name!r}; the log has "
                             f"{', '.join(next(l for l in logs + held if l.source == missing[0]).actuators)}")
        record, text = analyse(name, _runs(logs, name), _runs(held, name))
        records.append(record)
        if not args.json:
            print(text)
    if args.json:
        print_json(records[0] if len(records) == 1 else records)
    return 0


def format_params(report, indent: str = "  ") -> list[str]:
    """Parameters with uncertainty and unit, one per line, then the report's flags."""
    lines = [f"{indent}{p.name:26s} {report.model.params[p.name]:12.5g} ± {report.stderr[p.name]:.2g} {p.unit}"
             for p in report.model.parameters]
    lines += [f"{indent}! {flag}" for flag in report.flags]
    return lines
