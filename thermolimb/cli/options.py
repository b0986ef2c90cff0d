"""Options shared by several subcommands: reading logs, choosing how to validate, printing."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from ..logs import VELOCITY_UNITS, ActuatorSeries, LogError, ThermalLog, parse_mapping, read_log
from ..logs.bags import is_bag
from ..util.atomic import is_stream, write_text
from ..util.errors import UsageError, bounded
from ..util.jsonutil import to_jsonable
from ..util.parallel import BACKENDS, worker_limit
from ..workbench.validation import Scheme, set_aside_sentence
from .types import assignments, folds, fraction, integer, output_file

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
    p.add_argument("--velocity-unit", default=None, choices=sorted(VELOCITY_UNITS),
                   help="unit of the velocity column, converted to rad/s (default: the column header's, e.g. "
                        "'Speed [rpm]'; rad/s in the canonical format; else reported as not given)")
    p.add_argument("--effort-unit", default=None, metavar="UNIT",
                   help="unit of the effort column (e.g. 'N m', mA, A, W) when its header does not say "
                        "(also --map effort=COLUMN:UNIT); parameters are reported in it")
    p.add_argument("--sep", default=None, choices=sorted(SEPARATORS),
                   help="CSV separator (default: found from the file)")
    p.add_argument("--decimal", default=None, choices=(".", ","),
                   help="decimal mark in a CSV (default: found from the file; ',' in ';'-separated files that use it)")
    p.add_argument("--drop-incomplete", action="store_true",
                   help="leave out samples with a missing value (and say how many) instead of refusing the file")
    p.add_argument("--actuator", default=None, metavar="NAME",
                   help="actuator to use (default: every actuator in the log); names the actuator of a wide "
                        "single-actuator file, so that several such files fit jointly")


def add_terms(p):
    p.add_argument("--terms", nargs="+", default=None, metavar="FILE",
                   help="Python file(s) of model terms (classes decorated with @register_term, e.g. the file "
                        "diagnose --propose wrote), loaded before --model is read")


def load_terms(args) -> None:
    from ..model.generated import load_term_file

    for path in getattr(args, "terms", None) or ():
        load_term_file(path)


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
    p.add_argument("--datasheet", type=assignments, default={}, metavar="NAME=VALUE,...",
                   help="values from a datasheet (e.g. RC_s=600), held where the log cannot identify the parameter "
                        "or leaves it loose (standard error over half of it); the output says when one is held")


def scheme_of(args) -> Scheme:
    if args.validate_on and args.cv:
        raise UsageError("--validate-on and --cv are two ways to validate; give one")
    return Scheme(split=args.split, folds=args.cv if isinstance(args.cv, int) else None,
                  by_run=args.cv == "runs", restart_at_split=args.restart_at_split)


def datasheet_of(args, *models) -> dict[str, float]:
    """``--datasheet``, checked against the models' parameters before any log is read."""
    from ..model.terms import parse_model
    from ..workbench.validation import check_datasheet

    try:
        check_datasheet(args.datasheet, *(parse_model(m) for m in models))
    except LogError as exc:
        raise UsageError(str(exc)) from None
    return dict(args.datasheet)


def read_options(args, path) -> dict:
    """The keyword arguments of :func:`read_log` that the command line's options give for ``path``."""
    mapping = parse_mapping(args.map)
    name = args.actuator if mapping and "actuator" not in mapping else None
    return {"mapping": mapping, "velocity_unit": args.velocity_unit, "effort_unit": args.effort_unit,
            "actuator_name": args.actuator if is_bag(path) else name,
            "sep": SEPARATORS[args.sep] if args.sep else None, "decimal": args.decimal,
            "drop_incomplete": args.drop_incomplete,
            # one actuator of a canonical table: only its rows are read (and its neighbours' temperatures)
            "actuators": [args.actuator] if args.actuator and not mapping and not is_bag(path) else None,
            "neighbours": _reads_neighbours(args)}


def _reads_neighbours(args) -> bool:
    """Whether the command needs the neighbours' temperatures: a diagnosis may add their coupling; a fit or a
    comparison only when one of its models has it."""
    from ..model.terms import DEFAULT_MODEL, TERMS, parse_model

    if getattr(args, "discovers", True) or not hasattr(args, "model"):
        return True
    models = args.model if isinstance(args.model, list) else [args.model or DEFAULT_MODEL]
    return any("neighbors" in TERMS[name].columns for spec in models for name in parse_model(spec))


def _read(paths, args) -> list[ThermalLog]:
    return [read_log(path, **read_options(args, path)) for path in paths]


def read_logs(args) -> list[ThermalLog]:
    return _read(args.logs, args)


def _runs(logs: list[ThermalLog], name: str) -> list[ActuatorSeries]:
    runs = []
    for log in logs:
        runs += log.runs(name)
    return runs


def print_json(obj, file=None) -> None:
    file = file or sys.stdout
    json.dump(to_jsonable(obj), file, indent=2)
    file.write("\n")


def for_each_actuator(args, analyse, page=None) -> int:
    """Run ``analyse(name, runs, held_out_runs) -> (record, text)`` for the chosen actuator or every one.

    Prints what reading changed on standard error, each text, or with
    ``--json`` one record (a list when several actuators); writes ``page``
    (the ``--html`` page the analyses filled) at the end.
    """
    logs = read_logs(args)
    held = _read(args.validate_on, args) if getattr(args, "validate_on", None) else []
    names = [args.actuator] if args.actuator else list(logs[0].actuators)
    for log in logs + held:
        for note in log.notes:
            say(note)
        for name in names:
            if name in log.actuators:
                gap = log.describe_gaps(name)
                if gap:
                    say(gap)
    plot_dir = getattr(args, "plot", None)
    before = _files(plot_dir)
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
    if page is not None:
        page.write(args.html)
    after = _files(plot_dir)
    written = [path for path, stamp in after.items() if before.get(path) != stamp]
    written += [Path(args.html)] if page is not None else []
    for path in written:
        print(f"wrote {path}", file=sys.stderr)
    return 0


def _files(folder) -> dict:
    """``{path: (size, mtime)}`` of the files in ``folder`` (nothing when ``None`` or absent): what a run wrote is
    what changed."""
    if folder is None or not Path(folder).is_dir():
        return {}
    return {p: (p.stat().st_size, p.stat().st_mtime_ns) for p in sorted(Path(folder).iterdir()) if p.is_file()}


def format_params(report, indent: str = "  ", evidence: bool = True) -> list[str]:
    """What the validation rests on (unless ``evidence`` is false: said once elsewhere), the parameters with
    uncertainty and unit, one per line, then the report's flags and what was set aside."""
    lines = [f"{indent}{report.evidence.sentence()}"] if evidence else []
    lines += [f"{indent}{p.name:26s} {report.model.params[p.name]:12.5g} ± {report.stderr[p.name]:.2g} {report.unit(p)}"
             for p in report.model.parameters]
    lines += [f"{indent}! {flag}" for flag in report.flags]
    lines += [f"{indent}{set_aside_sentence(a)}" for a in report.set_aside]
    return lines


def add_html(p):
    p.add_argument("--html", type=output_file, default=None, metavar="FILE",
                   help="write an interactive page (zoomable, panels linked in time; self-contained, works offline)")


def html_page(args, title: str):
    """The interactive page ``--html`` asks for, or ``None``."""
    if not getattr(args, "html", None):
        return None
    from ..plotting.interactive import InteractivePage

    return InteractivePage(title, f"thermolimb {args.command} on {', '.join(map(str, args.logs))}.")


def add_fleet(p):
    g = p.add_argument_group("a fleet at once")
    g.add_argument("--fleet", action="store_true",
                   help="fit every actuator and run of the LOGs on its own (LOG may be a folder or a quoted glob): "
                        "one row per actuator and run, then each actuator's parameter drift across its runs "
                        "(--plot DIR writes DIR/drift.png)")
    g.add_argument("--backend", choices=BACKENDS, default="process",
                   help="with --fleet: a local process pool (default), Ray tasks (extra 'ray'), or serial")
    g.add_argument("--address", default=None, help="Ray cluster address (default: start a local Ray)")
    g.add_argument("--workers", type=integer(1, 1024), default=None,
                   help="processes of the local pool (default: one per core)")
    g.add_argument("--table", type=output_file, default=None, metavar="FILE",
                   help="with --fleet: write the rows to FILE (.csv, or .json with the drift records)")


def say(note: str) -> None:
    """A note on standard error, its over-long words (a name, a path) cut (:func:`~thermolimb.util.errors.bounded`)."""
    print(f"note: {bounded(note)}", file=sys.stderr)


def local_workers(args) -> int | None:
    """``--workers`` as this machine can run it (:func:`~thermolimb.util.parallel.worker_limit`), said when lowered."""
    if args.backend != "process" or args.workers is None:
        return args.workers
    count, why = worker_limit(args.workers)
    if why:
        say(why)
    return count


def run_fleet(args, diagnose: bool) -> int:
    """``--fleet``: rows for every actuator and run, the drift table, and the files asked for."""
    from ..plotting.drift import plot_drift
    from ..workbench.drift import drift, format_drift
    from ..workbench.fleet import expand_paths, fit_fleet_files, format_rows, rows_table

    table_kind = Path(args.table).suffix.lower() if args.table else None
    if args.table and is_stream(args.table) and table_kind != ".json":
        table_kind = ".csv"  # a pipe, a terminal or a device (/dev/stdout) takes the CSV unless named .json
    if args.table and table_kind not in (".csv", ".json"):
        raise UsageError(f"--table {args.table}: expected a .csv or .json file")
    skipped: list[str] = []
    paths = expand_paths(args.logs, skipped)
    for note in skipped:
        say(note)
    if len({is_bag(p) for p in paths}) > 1:
        raise UsageError("--fleet reads bags and tables with the same --map; give bags and tables in separate runs")
    datasheet = datasheet_of(args, args.model)
    rows, notes = fit_fleet_files(paths, read_options(args, paths[0]), args.model, scheme_of(args),
                                  method=getattr(args, "method", "output_error"), diagnose=diagnose,
                                  backend=args.backend, workers=local_workers(args), address=args.address,
                                  actuators=[args.actuator] if args.actuator and not args.map else None,
                                  datasheet=datasheet)
    for note in notes:
        say(note)
    records = drift(rows)
    if args.plot:
        plot_drift(records, Path(args.plot) / "drift.png")
    if args.table:
        if table_kind == ".json":
            write_text(args.table, json.dumps(to_jsonable({"rows": rows, "drift": records}), indent=2))
        else:
            import pandas as pd

            write_text(args.table, pd.DataFrame(rows_table(rows)).to_csv(index=False))
    if args.json:
        print_json({"rows": rows, "drift": records})
        return 0
    print(format_rows(rows))
    print()
    print(format_drift(records) if records else "drift: no actuator has two or more fitted runs")
    return 0
