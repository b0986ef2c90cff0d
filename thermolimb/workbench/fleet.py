"""A fleet at once: every actuator and run of many logs fitted (and diagnosed) on its own, in parallel.

One row per actuator and run: the parameters with their standard errors,
the train and validation errors, the fit's flags and, with ``diagnose``,
what the diagnosis recommends and the error it brings.  Runs are fitted by
one module-level function (:func:`analyse_run`), so the serial loop, the
process pool and Ray tasks give identical rows.  A run that cannot be
identified gives a row with its ``error`` instead of stopping the fleet.
"""

from __future__ import annotations

import glob
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

from ..logs.formats import LOG_SUFFIXES, is_bag, is_log
from ..util.errors import ThermolimbError, UsageError
from ..util.parallel import Runner, one_blas_thread, run_jobs
from .excitation import refuse_unfittable
from .validation import RUNS, Scheme, validate_model

TABLE_COLUMNS = ("source", "actuator", "run", "samples", "duration_s")  # the first columns of a --table CSV


def expand_paths(items: Sequence[str | Path], notes: list[str] | None = None) -> list[Path]:
    """Log files from files, folders (their logs, a ROS 2 bag folder as one log) and quoted globs, in order.

    A file reached twice -- named twice, matched by two patterns, or through a
    symbolic link (a link loop included) -- is one log, kept where it first
    appears: a run counted twice would make drift call an actuator steady.
    A fleet table this suite wrote (``--table``) found in a folder or by a
    pattern is not a log: it is skipped, with a sentence in ``notes``.
    """
    notes = notes if notes is not None else []
    paths = _once(_expand(items, notes), notes)
    if not paths:
        raise UsageError(f"{', '.join(map(str, items))}: nothing but "
                         "fleet tables this suite wrote; expected logs")
    return paths


def _once(paths: list[Path], notes: list[str]) -> list[Path]:
    seen, out, again = set(), [], 0
    for path in paths:
        key = os.path.realpath(path)
        if key not in seen:
            seen.add(key)
            out.append(path)
        else:
            again += 1
    if again:
        notes.append(f"{again} path(s) led to a log already listed "
                     "(named twice, matched twice, or through a link): "
                     f"each log read once")
    return out


def _expand(items: Sequence[str | Path], notes: list[str]) -> list[Path]:
    out: list[Path] = []
    for item in items:
        text = str(item)
        if any(c in text for c in "*?["):
            found = [Path(p) for p in sorted(glob.glob(text, recursive=True))]
            found = [p for p in found if is_log(p)]
            if not found:
                raise UsageError(f"{text}: the pattern matches no log; expected files ending in "
                                 f"{', '.join(LOG_SUFFIXES)} or ROS 2 bag folders")
            out += _not_tables(found, notes)
            continue
        path = Path(text)
        if path.is_dir() and not is_bag(path):
            found = _logs_in(path)
            if not found:
                raise UsageError(f"{path}: the folder holds no log; expected files ending in "
                                 f"{', '.join(LOG_SUFFIXES)} or ROS 2 bag folders")
            out += _not_tables(found, notes)
        else:
            out.append(path)
    return out


def _not_tables(paths: list[Path], notes: list[str]) -> list[Path]:
    """``paths`` without the fleet tables this suite wrote (``--table`` into the logs' own folder)."""
    kept = []
    for path in paths:
        if is_fleet_table(path):
            notes.append(f"{path}: a fleet table (--table) this suite wrote, not a log: skipped")
        else:
            kept.append(path)
    return kept


def is_fleet_table(path: Path) -> bool:
    """Whether ``path`` is a CSV whose header is the one :func:`rows_table` writes."""
    if path.suffix.lower() != ".csv" or not path.is_file():
        return False
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            head = f.readline(4096)
    except OSError:
        return False
    return head.startswith(",".join(TABLE_COLUMNS) + ",")


def _logs_in(folder: Path) -> list[Path]:
    found = []
    for root, dirs, files in os.walk(folder):
        root_path = Path(root)
        if is_bag(root_path) and root_path != folder:
            found.append(root_path)
            dirs[:] = []
            continue
        dirs.sort()
        found += [root_path / f for f in sorted(files) if is_log(root_path / f)]
    return found


@dataclass(frozen=True)
class FleetJob:
    source: str
    actuator: str
    run: str
    series: object  # ActuatorSeries


def analyse_run(job: FleetJob, model: str, scheme: Scheme, method: str, diagnose: bool,
                datasheet: dict | None = None) -> dict:
    """One row: fit (and diagnose) one actuator's run, with one BLAS thread (:func:`.one_blas_thread`)."""
    with one_blas_thread():
        return _analyse(job, model, scheme, method, diagnose, datasheet)


UNREADABLE = "(file)"  # the actuator and run of a row that stands for a whole file that could not be read


def unreadable_row(path, err: Exception) -> dict:
    """A file that could not be read, as a row of the fleet's table: its source and why."""
    return {
        "source": str(path),
        "actuator": UNREADABLE,
        "run": Path(path).name,
        "samples": 0,
        "duration_s": 0.0,
        "error": f"not read: {err}",
    }


def _analyse(job: FleetJob, model: str, scheme: Scheme, method: str, diagnose: bool,
             datasheet: dict | None = None) -> dict:
    series = job.series
    row = {"source": job.source, "actuator": job.actuator, "run": job.run, "samples": int(series.n),
           "duration_s": float(series.duration_s)}
    try:
        refuse_unfittable([series], job.actuator)  # a slot nothing drives is said so, not "cannot identify"
        if diagnose:
            from .diagnosis import diagnose as run_diagnosis

            d = run_diagnosis([series], model, quiet=True, scheme=scheme, datasheet=datasheet)
            report = d.base
            best = d.recommended
            row["recommended"] = best.label if best else None
            row["recommended_rmse_K"] = float(best.rmse_K) if best else None
        else:
            report = validate_model([series], model, scheme, method=method, reduce=True, datasheet=datasheet)
    except ThermolimbError as err:
        return row | {"error": str(err)}
    record = report.to_json()
    return row | {
        "model": record["model"],
        "params": record["params"],
        "train_rmse_K": record["train"]["rmse_K"],
        "validation_rmse_K": record["validation"]["rmse_K"],
        "flags": record["flags"],
        "set_aside": record["set_aside"],
        "evidence": record["evidence"]["verdict"],
        "error": None,
    }


def fleet_jobs(logs, actuators: Sequence[str] | None = None) -> list[FleetJob]:
    """One job per actuator and run of every log (each log cut into runs at its pauses)."""
    jobs = []
    for log in logs:
        names = [a for a in log.actuators if actuators is None or a in actuators]
        for name in names:
            for k, run in enumerate(log.runs(name)):
                jobs.append(FleetJob(log.source, name, run.run or f"{Path(log.source).stem}#{k + 1}", run))
    return jobs


def _check(scheme: Scheme) -> None:
    if scheme.kind == RUNS:
        raise UsageError("--cv runs leaves a run out, but a fleet fits "
                         "each run on its own; use --cv K or --split")


def fit_fleet(
    logs,
    model: str,
    scheme: Scheme = Scheme(),
    method: str = "output_error",
    diagnose: bool = False,
    backend: str = "process",
    workers: int | None = None,
    address: str | None = None,
    actuators: Sequence[str] | None = None,
    datasheet: dict | None = None,
) -> list[dict]:
    """Rows for every actuator and run of logs in memory, computed on ``backend``; the same rows on every
    backend."""
    _check(scheme)
    jobs = fleet_jobs(logs, actuators)
    if not jobs:
        raise UsageError("the logs hold no run of the chosen actuators")
    workers = workers or os.cpu_count() or 1
    return run_jobs(analyse_run, [(job, model, scheme, method, diagnose, datasheet) for job in jobs], backend,
                    workers, address)


def analyse_file(path: str, read: dict, names: Sequence[str] | None, model: str, scheme: Scheme, method: str,
                 diagnose: bool, datasheet: dict | None = None) -> tuple[list[dict], list[str]]:
    """Read one log in the worker and analyse its actuators ``names`` (all when ``None``): ``(rows,
    notes)``."""
    from ..logs import read_log

    try:
        log = read_log(path, **read)
    except (ThermolimbError, OSError) as err:  # one bad file is a row with its error; the others go on
        return [unreadable_row(path, err)], []
    with one_blas_thread():
        rows = [_analyse(job, model, scheme, method, diagnose, datasheet) for job in fleet_jobs([log], names)]
    return rows, list(log.notes)


def fit_fleet_files(
    paths: Sequence[Path],
    read: dict,
    model: str,
    scheme: Scheme = Scheme(),
    method: str = "output_error",
    diagnose: bool = False,
    backend: str = "process",
    workers: int | None = None,
    address: str | None = None,
    actuators: Sequence[str] | None = None,
    runner: Runner | None = None,
    datasheet: dict | None = None,
) -> tuple[list[dict], list[str]]:
    """Rows for every actuator and run of the log files, each worker reading the files it analyses.

    Only file names and rows cross between processes, never the logs.  A
    file with fewer files than ``4 x workers`` is split by actuator, so that
    one file of many joints still spreads over the workers.  ``read``: the
    keyword arguments of :func:`thermolimb.logs.read_log`.  ``runner``: a
    backend already open (its backend and workers replace those given).
    """
    from ..logs import read_log

    _check(scheme)
    workers = runner.workers if runner else (workers or os.cpu_count() or 1)
    jobs = []
    chunks = max(1, -(-4 * workers // max(len(paths), 1)))
    for path in paths:
        names = list(actuators) if actuators else None
        if chunks > 1:
            try:
                names = names or list(read_log(path, **read).actuators)
            except (ThermolimbError, OSError):
                names = None  # the worker reads it again and reports it as a row
        if chunks > 1 and names:
            size = -(-len(names) // chunks)
            groups = [names[i:i + size] for i in range(0, len(names), size)]
        else:
            groups = [names]
        jobs += [(str(path), read, group, model, scheme, method, diagnose, datasheet) for group in groups]
    results = (
        runner.map(analyse_file, jobs) if runner else run_jobs(analyse_file, jobs, backend, workers, address)
    )
    rows = [row for part, _ in results for row in part]
    notes = list(dict.fromkeys(note for _, part in results for note in part))
    if not rows:
        raise UsageError("the logs hold no run of the chosen actuators")
    return rows, notes


def rows_table(rows: list[dict]) -> list[dict]:
    """Flat rows for a CSV: one column per parameter value and standard error (the first columns are
    :data:`TABLE_COLUMNS`, by which a later fleet recognises the table as none of its logs)."""
    flat = []
    for row in rows:
        out = {k: v for k, v in row.items() if k not in ("params", "flags", "model")}
        out["model"] = ",".join(row.get("model") or [])
        for name, p in (row.get("params") or {}).items():
            out[name] = p["value"]
            out[f"{name}_stderr"] = p["stderr"]
        out["flags"] = " | ".join(row.get("flags") or [])
        flat.append(out)
    return flat


def format_rows(rows: list[dict]) -> str:
    """A table for the terminal: one line per actuator and run."""
    params = []
    for row in rows:
        for name in row.get("params") or {}:
            if name not in params:
                params.append(name)
    head = f"{'actuator':12s} {'run':24s} {'val RMSE K':>10s}  " + "  ".join(f"{p:>22s}" for p in params)
    lines = [head]
    for row in rows:
        if row.get("error"):
            lines.append(f"{row['actuator']:12s} {row['run']:24s} {'':>10s}  error: {row['error']}")
            continue
        cells = []
        for p in params:
            v = (row.get("params") or {}).get(p)
            cells.append(f"{v['value']:11.4g} ± {v['stderr']:<8.2g}" if v else f"{'':>22s}")
        line = f"{row['actuator']:12s} {row['run']:24s} {row['validation_rmse_K']:10.3f}  " + "  ".join(cells)
        if "recommended" in row:
            line += f"  -> {row['recommended'] or 'nothing'}"
            if row["recommended"]:
                line += f" ({row['recommended_rmse_K']:.3f} K)"
        lines.append(line)
    return "\n".join(lines)
