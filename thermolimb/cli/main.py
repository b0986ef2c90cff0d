"""``thermolimb``: the command line.  Each subcommand lives in its own module."""

from __future__ import annotations

import argparse
import contextlib
import difflib
import importlib
import os
import signal
import sys
import threading

from .. import __version__
from ..util.errors import WRITE_FAULTS, ThermolimbError, bounded
from ..util.interrupts import Terminated, ignore_further, install, restore

# the commands, each a module of this package, in the order --help lists them; a command line imports only the
# one it runs (the others' imports, the plant's and the audit's among them, cost a diagnosis a third of a
# second)
COMMANDS = ("inspect", "simulate", "fit", "compare", "diagnose", "plan", "predict", "monitor", "export",
            "audit", "strategies", "demo")
# the commands named otherwise than their module
MODULE_OF = {"compare-strategies": "strategies", "report": "demo"}
# Errors a user can act on: one sentence, no traceback, exit status 2.  Anything else is a bug in the
# suite and keeps its traceback.
USER_ERRORS = (ThermolimbError,)


class Parser(argparse.ArgumentParser):
    """argparse, with a usage mistake said in one line (``--help`` shows the usage) and exit status 2."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see --help)\n")


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The command line's parser: every command's, or (``only``, a command's name) that command's alone."""
    parser = Parser(prog="thermolimb", description="Thermal models of robot actuators: simulate a thermal "
                    "plant, identify models from " "logs, validate them, and run the demos.  Units: SI, "
                    "temperatures in degC.")
    parser.add_argument("--version", action="version", version=f"thermolimb {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    only = MODULE_OF.get(only, only)
    for name in (only,) if only in COMMANDS else COMMANDS:
        importlib.import_module(f"{__package__}.{name}").add_parser(sub)
    parser.commands = sub.choices  # each command's parser, by name
    return parser


# what the machine, not the input, can refuse a write for: said in one sentence naming what was not written


def main(argv=None) -> int:
    words = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(words[0] if words else None)  # a command first: only its parser (the rest: --help)
    args, unknown = parser.parse_known_args(argv)
    if unknown:
        refuse_unknown(parser, args.command, unknown)
    if not _main_thread():
        return _run(args)
    previous = install()  # Ctrl-C, SIGTERM, SIGHUP: deferred inside a held block, once only (util/interrupts)
    code = None
    try:
        code = _run(args)
        return code
    finally:
        # the command line is ending: further signals stay ignored until the process exits (restored, a second
        # Ctrl-C would kill it by the signal after its last words); a call with argv gets them back
        if argv is not None:
            restore(previous)
        else:
            ignore_further()


def refuse_unknown(parser: argparse.ArgumentParser, command: str, unknown: list[str]) -> None:
    """Arguments the command does not take, refused by the command's own parser, with the option meant where
    one is close (``--models`` for ``--model``)."""
    sub = parser.commands[command]
    options = [o for action in sub._actions for o in action.option_strings if o.startswith("--")]
    meant = [f"{close[0]} (not {word})" for word in (u.split("=")[0] for u in unknown if u.startswith("--"))
             for close in [difflib.get_close_matches(word, options, n=1, cutoff=0.8)] if close]
    sub.error(
        f"unrecognized arguments: {' '.join(unknown)}"
        + (f"; did you mean {', '.join(meant)}?" if meant else "")
    )


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


def _run(args) -> int:
    from .clobber import check_outputs

    try:
        check_outputs(args)
        code = int(args.func(args) or 0)
        sys.stdout.flush()  # a full disk or a closed pipe behind standard output shows here, not at exit
        return code
    except USER_ERRORS as exc:
        print(f"thermolimb {args.command}: error: {bounded(str(exc))}", file=sys.stderr)
        return 2
    # files being written are removed by their writers; earlier outputs stay intact
    except KeyboardInterrupt as exc:
        ignore_further()
        signum = exc.signum if isinstance(exc, Terminated) else signal.SIGINT
        what = {signal.SIGINT: "interrupted", signal.SIGTERM: "terminated"}.get(signum, "hung up")
        print(f"thermolimb {args.command}: {what}", file=sys.stderr)
        return 128 + int(signum)
    except BrokenPipeError:  # the reader went away (`| head`, `| true`): stop quietly, as Unix tools do
        _silence_stdout()
        return 141
    except OSError as exc:
        if exc.errno not in WRITE_FAULTS:
            raise
        what = exc.filename if exc.filename else "standard output"
        print(f"thermolimb {args.command}: error: could not write {bounded(str(what))}: "
              f"{WRITE_FAULTS[exc.errno]}", file=sys.stderr)
        _silence_stdout()
        return 1


def _silence_stdout() -> None:
    """Point standard output at /dev/null so that the interpreter's own flush at exit cannot fail again."""
    with contextlib.suppress(OSError, ValueError):  # no standard output to point anywhere: nothing to silence
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())


if __name__ == "__main__":
    sys.exit(main())
