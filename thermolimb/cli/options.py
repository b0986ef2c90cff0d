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
