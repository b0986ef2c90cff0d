"""The command line's options: the groups several subcommands share, and what they mean (a validation
scheme).  Reading the logs they name is :mod:`.reading`'s; printing, :mod:`.output`'s."""

from __future__ import annotations

import argparse

from ..logs import VELOCITY_UNITS
from ..model.terms import DEFAULT_MODEL, TERMS
from ..util.errors import UsageError
from ..util.parallel import BACKENDS
from ..workbench.validation import PARTS, Scheme
from .types import (
    TEMPERATURE_C,
    assignments,
    folds,
    fraction,
    integer,
    names_list,
    output_dir,
    output_file,
)

DEFAULT_SPLIT = 0.7


class Once(argparse.Action):
    """An option given at most once: a second ``--actuator`` would silently win over the first."""

    def __call__(self, parser, namespace, values, option_string=None):
        if getattr(namespace, f"_given_{self.dest}", False):
            parser.error(f"{option_string} given twice "
                         f"({getattr(namespace, self.dest)!r} and {values!r}); give one "
                         f"(to fit several actuators, leave it out: every actuator is fitted)")
        setattr(namespace, f"_given_{self.dest}", True)
        setattr(namespace, self.dest, values)


SEPARATORS = {"comma": ",", "semicolon": ";", "tab": "\t", "bar": "|"}


def add_quiet(p):
    p.add_argument("--quiet", action="store_true", help="no progress bars")


def add_log_input(p, required: bool = True, positional: bool = True):
    """The logs (``positional``) and the options they are read with, alike for every command that reads
    logs."""
    if positional:
        p.add_argument("logs", nargs="+" if required else "*", metavar="LOG",
                       help="log file(s): CSV, Parquet, ROS 1 bag or ROS "
                            "2 bag (.mcap, .db3 or its folder); several "
                            "logs (runs) of the same actuators are fitted "
                            "jointly, each run simulated from its own "
                            "first reading")
    p.add_argument("--map", default=None, metavar="CANONICAL=COLUMN,...",
                   help="read a wide file by naming its columns, e.g. "
                        "effort=torque,temperature=stator_winding,"
                        "housing=case_temp (a second sensor); for one "
                        "column per joint use {j} for the joint number "
                        "(or its name) and * for any text: "
                        "effort=Current_J{j},temperature=Temperature_*{j}; a column "
                        "on a time base "
                        "of its own as COLUMN@TIME_COLUMN; for a bag, /topic.field "
                        "(effort=/joint_states.effort,temperature=/temperatures.temps; "
                        "see thermolimb inspect)")
    p.add_argument("--velocity-unit", default=None, choices=sorted(VELOCITY_UNITS),
                   help="unit of the velocity column, converted to rad/s (default: the column header's, e.g. "
                        "'Speed [rpm]'; rad/s in the canonical format; else reported as not given)")
    p.add_argument("--effort-unit", default=None, metavar="UNIT",
                   help="unit of the effort column (e.g. 'N m', mA, A, W) when its header does not say "
                        "(also --map effort=COLUMN:UNIT); parameters are reported in it")
    p.add_argument("--sep", default=None, choices=sorted(SEPARATORS),
                   help="CSV separator (default: found from the file)")
    p.add_argument("--decimal", default=None, choices=(".", ","),
                   help="decimal mark in a CSV (default: found from the "
                        "file; ',' in ';'-separated files that use it)")
    p.add_argument("--columns", default=None, type=names_list, metavar="NAME,NAME,...",
                   help="the column names of a CSV file written without "
                        "a header row, in the file's order (read "
                        "without them, its columns are column1, column2, ...)")
    p.add_argument("--drop-incomplete", action="store_true",
                   help="leave out samples with a missing value (and "
                        "say how many) instead of refusing the file")
    p.add_argument("--actuator", default=None, metavar="NAME", action=Once,
                   help="actuator to use (default: every actuator in the log); names the actuator of a wide "
                        "single-actuator file, so that several such files fit jointly")


def add_terms(p):
    p.add_argument("--terms", nargs="+", default=None, metavar="FILE",
                   help="Python file(s) of model terms (classes decorated with @register_term, e.g. the file "
                        "diagnose --propose wrote), loaded before --model is read")


def add_models(p, help: str, repeated: bool = False):
    """``--model``: one model (default: the model fit and diagnose start from), or with ``repeated``
    several."""
    if repeated:
        p.add_argument("--model", action="append", default=None, metavar="TERMS",
                       help=f"{help} (repeat the option; default "
                            f"{','.join(DEFAULT_MODEL)}, the model fit and "
                            f"diagnose start from); terms: {', '.join(TERMS)}")
    else:
        p.add_argument("--model", default=",".join(DEFAULT_MODEL), metavar="TERMS",
                       help=f"{help} (default {','.join(DEFAULT_MODEL)}); known terms: {', '.join(TERMS)}")


def add_validation(p):
    p.add_argument("--split", type=fraction, default=None,
                   help="fit on this fraction of each run's time span "
                        f"and validate on the rest (e.g. {DEFAULT_SPLIT}; "
                        f"default: leave one run out with several runs, a {DEFAULT_SPLIT} split of one run)")
    p.add_argument("--cv", type=folds, default=None, metavar="K|runs|interleaved|parts",
                   help="blocked cross-validation over K contiguous "
                        "folds; 'runs': leave one run out; 'interleaved': "
                        "blocks 2, 5 and 8 of 10 of each run held out; "
                        "'parts': each third of each run held out in turn")
    p.add_argument("--validate-on", nargs="+", default=None, metavar="LOG",
                   help="fit on the LOGs given first and validate on these runs (read with the same options, "
                        "but --validate-map)")
    p.add_argument("--validate-map", default=None, metavar="MAP",
                   help="the --map of the --validate-on logs where "
                        "they are written otherwise (another export, a "
                        "bag beside a CSV: \"\" lets a bag suggest its own); default: --map")
    p.add_argument("--restart-at-split", action="store_true",
                   help="restart the validation free run at the split "
                        "from the measured temperature, hidden states "
                        "at rest (default: carried from each run's start through the training part)")
    p.add_argument("--datasheet", type=assignments, default={}, metavar="NAME=VALUE,...",
                   help="values from a datasheet (e.g. RC_s=600), held "
                        "where the log cannot identify the parameter "
                        "or leaves it loose (standard error over "
                        "half of it); the output says when one is held")


def scheme_of(args) -> Scheme:
    if args.validate_on and args.cv:
        raise UsageError("--validate-on and --cv are two ways to validate; give one")
    if args.validate_map is not None and not args.validate_on:
        raise UsageError("--validate-map maps the --validate-on logs; give those logs with it")
    if args.split is not None and args.cv:
        raise UsageError("--split and --cv are two ways to validate (a split, or folds); give one")
    if args.cv == "runs":
        return Scheme.leave_one_run_out()
    if args.cv == "interleaved":
        return Scheme.interleaved()
    if args.cv == "parts":
        return Scheme(PARTS)
    if isinstance(args.cv, int):
        return Scheme.in_blocks(args.cv, args.restart_at_split)
    if args.split is not None or args.restart_at_split:
        return Scheme.at_split(DEFAULT_SPLIT if args.split is None else args.split, args.restart_at_split)
    return Scheme()  # leave one run out with several runs, a split of one run


def add_outputs(p, json_help: str, plot_help: str):
    """``--json``, ``--plot DIR`` and ``--html FILE``."""
    p.add_argument("--json", action="store_true", help=json_help)
    p.add_argument("--plot", type=output_dir, default=None, metavar="DIR", help=plot_help)
    p.add_argument("--html", type=output_file, default=None, metavar="FILE",
                   help="write an interactive page (zoomable, panels "
                        "linked in time; self-contained, works offline)")


def add_temperature(p, flag: str, help_text: str) -> None:
    """A winding's temperature option (``--limit-C``, ``--start-C``): degC within the model file's range,
    default ``None``, stored under the flag's name (``limit_C``)."""
    p.add_argument(flag, dest=flag[2:].replace("-", "_"), type=TEMPERATURE_C, default=None, metavar="C",
                   help=help_text)


def add_save(p, help_text: str):
    """``--save MODEL.json`` and the limit it stores, ``--limit-C``."""
    p.add_argument("--save", type=output_file, default=None, metavar="MODEL.json", help=help_text)
    add_temperature(p, "--limit-C", "with --save: the actuator's winding limit (degC), stored in the model "
                    "file; predict and monitor use it when no --threshold is given")


def add_fleet(p):
    g = p.add_argument_group("a fleet at once")
    g.add_argument("--fleet", action="store_true",
                   help="fit every actuator and run of the LOGs on its "
                        "own (LOG may be a folder or a quoted glob): "
                        "one row per actuator and run, then each actuator's parameter drift across its runs "
                        "(--plot DIR writes DIR/drift.png)")
    g.add_argument("--backend", choices=BACKENDS, default="process",
                   help="with --fleet: a local process pool (default), Ray tasks (extra 'ray'), or serial")
    g.add_argument("--address", default=None, help="Ray cluster address (default: start a local Ray)")
    g.add_argument("--workers", type=integer(1, 1024), default=None,
                   help="processes of the local pool (default: one per core)")
    g.add_argument("--table", type=output_file, default=None, metavar="FILE",
                   help="with --fleet: write the rows to FILE (.csv, or .json with the drift records)")
