"""``thermolimb inspect``: what a log holds, and the ``--map`` that reads it."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..logs import read_log
from ..logs.bags import inspect_bag, suggest_mapping
from ..logs.formats import is_bag
from ..logs.mapping import (
    REQUIRED,
    TIME_OF,
    UNITS,
    expand_joints,
    is_pattern,
    on_time,
    suggest_table_mapping,
)
from ..logs.plausible import fahrenheit_named
from ..logs.table import table_chunks
from ..logs.units import base_name, header_unit, split_unit
from ..logs.validate import apart, held_beside_temperature
from ..util.errors import LogError, ThermolimbError
from ..util.lazy import pandas as pd
from .template import Command, Outcome
from .types import names_list

READ_ROWS = 2_000_000  # a table of at most these rows is read with the map suggested, as fit would read it


class Inspect(Command):
    name = "inspect"
    help = "list a log's topics (bags) or columns (CSV, Parquet) and suggest a --map"
    description = ("For a ROS 1 or ROS 2 bag: every topic with its "
                    "message type, message count, mean rate (Hz), "
        "numeric fields and joint names, then a suggested --map for fit, compare and diagnose. For a CSV or "
        "Parquet file: its columns, how many values each holds, and its first values.")

    def add_options(self, p):
        p.add_argument("log", metavar="LOG", help="a ROS bag (.bag, .mcap, .db3 or a "
                                                  "ROS 2 bag folder), CSV or Parquet")
        p.add_argument("--columns", default=None, type=names_list, metavar="NAME,NAME,...",
                       help="the column names of a CSV file written without a header row, in the file's "
                       "order")
        p.add_argument("--json", action="store_true", help="print the listing as JSON")

    plots = None

    def work(self, args) -> Outcome:
        path = Path(args.log)
        if is_bag(path):
            infos = inspect_bag(path)
            mapping, reasons = suggest_mapping(infos)
            record = {"topics": [vars(i) for i in infos], "suggested_map": mapping, "ambiguous": reasons}
            lines = []
            lines.append(f"{path}: {len(infos)} topic(s)")
            lines.append(f"  {'topic':40s} {'type':46s} {'messages':>9s} {'rate Hz':>8s}")
            for i in infos:
                lines.append(f"  {i.topic:40s} {i.msgtype:46s} {i.count:9d} {i.rate_hz:8.2f}")
                if i.numeric_fields:
                    lines.append(f"      numeric fields: {', '.join(i.numeric_fields)}")
                if i.joint_names:
                    lines.append(f"      joints: {', '.join(i.joint_names)}")
            if mapping:
                text = ",".join(f"{k}={v}" for k, v in mapping.items())
                lines.append(f"suggested: --map {text}  (add --actuator NAME for one joint)")
            else:
                lines.append("no mapping suggested: " + "; ".join(reasons) + "; name the channels with "
                                                                      "--map channel=/topic.field")
            return Outcome(record, "\n".join(lines))
        rows, columns, first_line = _listing(path, args.columns)
        flat = {c["column"] for c in columns if c.get("flat")}
        mapping, reasons = suggest_table_mapping([c["column"] for c in columns],
                                                 {c["column"]: c["values"] for c in columns}, flat)
        if first_line is not None and not args.columns:
            reasons.insert(0, "the file has no header row (its first line, "
                           f"{first_line.strip()[:60]!r}, holds numbers): "
                           "its columns are listed as column1 to "
                           f"column{len(columns)}; name them with --columns "
                           f"NAME,NAME,... (in the file's order), here and in fit, diagnose and the others")
        left = _left_for(mapping, columns, flat)
        if left:
            reasons.append("effort: no column's name says torque, effort, "
                           f"current or power; if {' or '.join(left[:3])} "
                           "drives the heat (a torque, a current, a command "
                           f"or duty), add effort={left[0]} to the map")
        for name, column in list((mapping or {}).items()):
            if UNITS.get(name) == "degC" and fahrenheit_named(column) and header_unit(column) is None:
                mapping[name] = f"{column}:degF"
                reasons.append(f"{name}={column}: its name says degrees "
                               "Fahrenheit, so the suggestion reads it as such; "
                               f"write {column}:degC if it is Celsius")
        apart = _on_other_rows(path, mapping, {c["column"]: c["values"] for c in columns}, rows, args.columns)
        if apart:
            time = split_unit(mapping["time"])[0]
            mapping.update({k: on_time(v, time) for k, v in mapping.items() if k not in ("time", "actuator")})
            reasons.append(f"the temperature and the {apart[0]} are logged on different rows ({apart[1]} of "
                           f"the " f"temperature's rows hold the {apart[0]}): each " f"channel is read on "
                           f"its own samples (@{time}), " f"the inputs averaged over each temperature "
                           f"sample's interval")
        together = _times_agree(path, mapping, rows, args.columns)
        if together is not None:
            time, spread = together
            mapping.update({k: on_time(v, None) for k, v in mapping.items() if k not in ("time", "actuator")})
            mapping["time"] = time
            reasons = [r for r in reasons if not r.startswith("each channel has a time column of its own")]
            reasons.append("the channels' time columns agree on every "
                           f"row (to {1e3 * spread:.2g} ms, under a tenth "
                           f"of a step): the rows are samples of every channel, read on {time}")
        if mapping and _as_it_is(mapping):
            reasons.insert(0, "the columns carry the canonical names: fit, "
                              "compare and diagnose read the file as it is, "
                              "without --map")
        flags = []
        if mapping and rows <= READ_ROWS:
            # read as it would be with the words to add
            trial = {**mapping, "effort": left[0]} if left else mapping
            flags, read_notes = _read_with(path, trial, args.columns, left[0] if left else None)
            if "time" in mapping and split_unit(mapping["time"])[1] is None and any(
                    "if the time column counts milliseconds" in note for note in read_notes):
                mapping["time"] = trial["time"] = (
                    f"{mapping['time']}:ms"  # steps of hundreds of s over days: ms
                )
                reasons.append(f"time={split_unit(mapping['time'])[0]}: read "
                               "as seconds, its steps of hundreds span days; "
                               f"the suggestion reads it in ms (change it if the log did run for days)")
                flags, read_notes = _read_with(path, trial, args.columns, left[0] if left else None)
            reasons += read_notes
        record = {
            "rows": rows,
            "columns": columns,
            "suggested_map": mapping,
            "flags": flags,
            "notes": reasons,
        }
        lines = []
        shown = [c for c in columns if c["values"] > 0]
        empty = len(columns) - len(shown)
        lines.append(f"{path}: {rows} row(s), {len(columns)} column(s)"
              + (f" ({empty} without any value, not shown)" if empty else ""))
        for c in shown:
            lines.append(f"  {c['column']:40s} {c['values']:9d} values  first {c['first'][:30]}"
                  + ("  (never varies)" if c.get("flat") else ""))
        if mapping:
            text = ",".join(f"{k}={v}" for k, v in mapping.items())
            lines.append(f'suggested: --map "{text}"' + "".join(f" {f}" for f in flags)
                  + ("  (add --actuator NAME to read one joint)" if "{j}" in text else ""))
        for reason in reasons:
            lines.append(f"note: {reason}")
        return Outcome(record, "\n".join(lines))


add_parser = Inspect().add_parser


def _as_it_is(mapping: dict) -> bool:
    """Whether the suggested map names each channel by its canonical column (bare, or with its unit in the
    header: ``temperature [K]``), as a log is read without a map."""
    def canonical(name, value):
        column, unit = split_unit(value)
        return unit is None and (
            column == name or (header_unit(column) is not None and base_name(column) == name)
        )

    return set(REQUIRED) - {"actuator"} <= set(mapping) and all(canonical(k, v) for k, v in mapping.items())


def _left_for(mapping: dict, columns: list[dict], flat: set) -> list[str]:
    """Where no column was found for the effort: the numeric columns that vary and no channel takes (a
    command, a duty or a current the suggestion could not tell by its name), whose first is the word to
    add."""
    if "effort" in mapping or "temperature" not in mapping:
        return []
    taken = {split_unit(v)[0].partition(TIME_OF)[0] for v in mapping.values()}
    left = [
        c["column"]
        for c in columns
        if c["column"] not in taken and c["column"] not in flat and c["values"] > 0 and c.get("numeric")
    ]
    return left


def _read_with(
    path: Path, mapping: dict, names=None, effort: str | None = None
) -> tuple[list[str], list[str]]:
    """The file read with the suggested map, as ``fit`` would read it: the flags it needs
    (``--drop-incomplete`` where a channel misses readings: read so once, it says what it left out) and what
    reading it says (a temperature held between its updates, samples left out), or why it cannot be read
    so."""
    with_names = f" and {effort} as the effort" if effort else ""
    try:
        log = read_log(path, mapping=mapping, drop_incomplete=True, columns=names)
    except ThermolimbError as exc:  # whatever reading refuses, inspect says and still lists the file
        return [], [f"read with this map{with_names}, the file is refused: {exc}"]
    from ..logs.suspect import disturbed_spans

    notes = list(log.notes)
    for run in (r for name in log.actuators for r in log.runs(name)):
        spans = disturbed_spans(run.temperature_C, run.signals.effort)
        if spans:
            t = run.time_s
            notes.append(f"{run.run or run.actuator}: the readings jump "
                         f"up by {spans[0][3]:.1f} K as the effort steps "
                         f"down at {t[spans[0][1]]:g} s ({len(spans)} "
                         "driven interval(s) so): a sensor that reads low "
                         f"while driven; fit and diagnose refuse such readings")
    flags = ["--drop-incomplete"] if any("(--drop-incomplete)" in note for note in notes) else []
    flags += [f"--columns {','.join(names)}"] if names else []
    return flags, [f"read with this map{with_names}: {note.removeprefix(f'{path}: ')}" for note in notes]


def _listing(path: Path, names=None) -> tuple[int, list[dict], str | None]:
    """Rows; each column's count of values, first value, whether it holds numbers and whether they never vary
    (``flat``); and the first line of a file without a header row (else ``None``).  Read in pieces: a file of
    any size in the memory of one piece."""
    rows, counts, first, low, high, first_line = 0, {}, {}, {}, {}, None
    for chunk in table_chunks(path, names=names):
        rows += len(chunk)
        first_line = chunk.attrs.get("headerless") if not names else None
        for c in chunk.columns:
            present = chunk[c].dropna()
            counts[str(c)] = counts.get(str(c), 0) + len(present)
            if str(c) not in first and len(present):
                first[str(c)] = str(present.iloc[0])
            numbers = pd.to_numeric(present, errors="coerce").dropna()
            if len(numbers):
                low[str(c)] = min(low.get(str(c), np.inf), float(numbers.min()))
                high[str(c)] = max(high.get(str(c), -np.inf), float(numbers.max()))
    listing = [{"column": c, "values": k, "first": first.get(c, ""), "numeric": c in low,
                "flat": c in low and low[c] == high[c]} for c, k in counts.items()]
    return rows, listing, first_line


def _on_other_rows(path: Path, mapping: dict, values: dict, rows: int, names=None) -> tuple[str, int] | None:
    """Where the suggested temperature and an input share the time column but fewer than half of the
    temperature's rows hold the input (topics merged into one table), the first such input and how many rows
    hold both; else ``None``.  Read again in pieces, only when a mapped column misses values."""
    if (not mapping or "time" not in mapping or "temperature" not in mapping
            or any(TIME_OF in v for v in mapping.values())):
        return None
    columns = {k: split_unit(v)[0] for k, v in mapping.items() if k != "time"}
    if is_pattern(columns):  # the first joint's columns stand for every joint's
        try:
            columns = expand_joints(list(values), columns, str(path))[0][2]
        except LogError:
            return None
    columns.pop("actuator", None)
    if all(values.get(c, 0) == rows for c in columns.values()):
        return None
    held = dict.fromkeys(columns, 0)
    for chunk in table_chunks(path, names=names):
        channels = pd.DataFrame({k: chunk[c] for k, c in columns.items()})
        for k, n in held_beside_temperature(channels, list(columns)).items():
            held[k] += n
    thin = apart(held)
    return (thin, held[thin]) if thin else None


def _times_agree(path: Path, mapping: dict, rows: int, names=None) -> tuple[str, float] | None:
    """Where a suggestion reads each channel on a time column of its own and those columns hold a value on
    every row and agree within a tenth of the median step (the WidowX-200's bearing runs: within 5.4 ms of
    steps of 90 ms), the temperature's time column, which then reads every row as one sample, and the largest
    disagreement (s); else ``None``."""
    if not mapping or "time" in mapping or is_pattern(mapping):
        return None
    timed = {k: split_unit(v)[0].partition(TIME_OF)[2] for k, v in mapping.items() if k != "actuator"}
    if not all(timed.values()) or len(set(timed.values())) < 2:
        return None
    times = list(dict.fromkeys(timed.values()))
    parts = [chunk[times] for chunk in table_chunks(path, names=names)]
    frame = pd.concat(parts, ignore_index=True).apply(pd.to_numeric, errors="coerce")
    if len(frame) != rows or frame.isna().any().any() or rows < 3:
        return None
    values = frame.to_numpy(float)
    step = float(np.median(np.diff(values[:, times.index(timed["temperature"])])))
    spread = float(np.max(np.ptp(values, axis=1)))
    return (timed["temperature"], spread) if step > 0 and spread <= 0.1 * step else None
