"""Options shared by several subcommands."""

from __future__ import annotations

import json
import sys

from ..jsonutil import to_jsonable
from ..logs import VELOCITY_UNITS, ThermalLog, parse_mapping, read_log


def add_quiet(p):
    p.add_argument("--quiet", action="store_true", help="no progress bars")


def add_log_input(p):
    p.add_argument("logs", nargs="+", metavar="LOG",
                   help="log file(s), CSV or Parquet; several logs of one actuator are fitted jointly")
    p.add_argument("--map", default=None, metavar="CANONICAL=COLUMN,...",
                   help="read a wide single-actuator file by naming its columns, e.g. "
                        "effort=torque,temperature=stator_winding,velocity=motor_speed,ambient=coolant")
    p.add_argument("--velocity-unit", default="rad/s", choices=sorted(VELOCITY_UNITS),
                   help="unit of the velocity column (default rad/s); converted to rad/s")
    p.add_argument("--actuator", default=None, metavar="NAME",
                   help="actuator to use (default: every actuator in the log)")


def read_logs(args) -> list[ThermalLog]:
    mapping = parse_mapping(args.map)
    return [read_log(path, mapping=mapping, velocity_unit=args.velocity_unit) for path in args.logs]


def print_json(obj) -> None:
    json.dump(to_jsonable(obj), sys.stdout, indent=2)
    sys.stdout.write("\n")


def for_each_actuator(args, analyse) -> int:
    """Run ``analyse(name, series) -> (record, text)`` for the chosen actuator or every one.

    Prints each text, or with ``--json`` one record (a list when several actuators).
    """
    logs = read_logs(args)
    names = [args.actuator] if args.actuator else list(logs[0].actuators)
    records = []
    for name in names:
        record, text = analyse(name, [log.series(name) for log in logs])
        records.append(record)
        if not args.json:
            print(text)
    if args.json:
        print_json(records[0] if len(records) == 1 else records)
    return 0
