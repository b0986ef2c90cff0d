"""``thermolimb``: the command line.  Each subcommand lives in its own module."""

from __future__ import annotations

import argparse
import sys

from ..errors import ThermolimbError
from . import compare, demo, diagnose, fit, inspect, simulate, strategies

COMMANDS = (inspect, simulate, fit, compare, diagnose, strategies, demo)
# Errors a user can act on: one sentence, no traceback, exit status 2.  Anything else is a bug in the
# suite and keeps its traceback.
USER_ERRORS = (ThermolimbError,)


class Parser(argparse.ArgumentParser):
    """argparse, with a usage mistake said in one line (``--help`` shows the usage) and exit status 2."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="thermolimb",
        description="Thermal models of robot actuators: simulate a thermal plant, identify models from "
        "logs, validate them, and run the demos.  Units: SI, temperatures in degC.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module in COMMANDS:
        module.add_parser(sub)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except USER_ERRORS as exc:
        print(f"thermolimb {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # files being written are removed by their writers; earlier outputs stay intact
        print(f"thermolimb {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
