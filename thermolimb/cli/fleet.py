"""``--fleet``: every actuator and run of many logs fitted on its own, the drift across runs, on a pool."""

from __future__ import annotations

import json
from pathlib import Path

from ..logs.formats import is_bag
from ..util.atomic import is_stream, write_text
from ..util.errors import UsageError
from ..util.jsonutil import to_jsonable
from ..util.parallel import worker_limit
from .options import scheme_of
from .output import print_json, say
from .reading import read_options


def local_workers(args) -> int | None:
    """``--workers`` as this machine can run it (:func:`~thermolimb.util.parallel.worker_limit`), said when
    lowered."""
    if args.backend != "process" or args.workers is None:
        return args.workers
    count, why = worker_limit(args.workers)
    if why:
        say(why)
    return count


def run_fleet(args, diagnose: bool, datasheet: dict[str, float]) -> int:
    """``--fleet``: rows for every actuator and run, the drift table, and the files asked for (``datasheet``:
    ``--datasheet``, already checked)."""
    from ..plotting.drift import plot_drift
    from ..workbench.drift import drift, format_drift
    from ..workbench.fleet import (
        UNREADABLE,
        expand_paths,
        fit_fleet_files,
        format_rows,
        rows_table,
    )

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
        raise UsageError("--fleet reads bags and tables with the same "
                         "--map; give bags and tables in separate runs")
    rows, notes = fit_fleet_files(paths, read_options(args, paths[0]), args.model, scheme_of(args),
                                  method=getattr(args, "method", "output_error"), diagnose=diagnose,
                                  backend=args.backend, workers=local_workers(args), address=args.address,
                                  actuators=[args.actuator] if args.actuator and not args.map else None,
                                  datasheet=datasheet)
    for note in notes:
        say(note)
    failed = [r for r in rows if r["actuator"] == UNREADABLE]
    if failed:
        say(f"{len(failed)} of {len(paths)} files could not be "
            f"read (rows marked {UNREADABLE}); the others were "
            f"analysed")
    rows_ok = [r for r in rows if r["actuator"] != UNREADABLE]
    if not rows_ok:
        raise UsageError(f"no log could be read: {failed[0]['source']}: {failed[0]['error']}")
    status = 1 if failed else 0
    records = drift(rows_ok)
    if args.plot:
        plot_drift(records, Path(args.plot) / "drift.png")
    if args.table:
        if table_kind == ".json":
            write_text(args.table, json.dumps(to_jsonable({"rows": rows, "drift": records}), indent=2))
        else:
            import pandas as pd

            write_text(args.table, pd.DataFrame(rows_table(rows)).to_csv(index=False))
    if args.json:
        print_json({"rows": rows, "drift": records, "files_failed": len(failed)})
        return status
    print(format_rows(rows))
    print()
    print(format_drift(records) if records else "drift: no actuator has two or more fitted runs")
    return status
