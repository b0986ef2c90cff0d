"""``thermolimb inspect``: what a log holds, and the ``--map`` that reads it."""

from __future__ import annotations

from pathlib import Path

from ..logs.bags import inspect_bag, is_bag, suggest_mapping
from ..logs.mapping import UNITS, suggest_table_mapping
from ..logs.plausible import fahrenheit_named
from ..logs.table import table_chunks
from ..logs.units import header_unit
from .options import add_quiet
from .output import print_json


def add_parser(sub):
    p = sub.add_parser(
        "inspect", help="list a log's topics (bags) or columns (CSV, Parquet) and suggest a --map",
        description="For a ROS 1 or ROS 2 bag: every topic with its message type, message count, mean rate (Hz), "
        "numeric fields and joint names, then a suggested --map for fit, compare and diagnose. For a CSV or "
        "Parquet file: its columns, how many values each holds, and its first values.",
    )
    p.add_argument("log", metavar="LOG", help="a ROS bag (.bag, .mcap, .db3 or a ROS 2 bag folder), CSV or Parquet")
    p.add_argument("--json", action="store_true", help="print the listing as JSON")
    add_quiet(p)
    p.set_defaults(func=run)


def run(args) -> int:
    path = Path(args.log)
    if is_bag(path):
        infos = inspect_bag(path)
        mapping, reasons = suggest_mapping(infos)
        if args.json:
            print_json({"topics": [vars(i) for i in infos], "suggested_map": mapping, "ambiguous": reasons})
            return 0
        print(f"{path}: {len(infos)} topic(s)")
        print(f"  {'topic':40s} {'type':46s} {'messages':>9s} {'rate Hz':>8s}")
        for i in infos:
            print(f"  {i.topic:40s} {i.msgtype:46s} {i.count:9d} {i.rate_hz:8.2f}")
            if i.numeric_fields:
                print(f"      numeric fields: {', '.join(i.numeric_fields)}")
            if i.joint_names:
                print(f"      joints: {', '.join(i.joint_names)}")
        if mapping:
            text = ",".join(f"{k}={v}" for k, v in mapping.items())
            print(f"suggested: --map {text}  (add --actuator NAME for one joint)")
        else:
            print("no mapping suggested: " + "; ".join(reasons) + "; name the channels with --map channel=/topic.field")
        return 0
    rows, columns = _listing(path)
    mapping, reasons = suggest_table_mapping([c["column"] for c in columns],
                                             {c["column"]: c["values"] for c in columns})
    for name, column in list((mapping or {}).items()):
        if UNITS.get(name) == "degC" and fahrenheit_named(column) and header_unit(column) is None:
            mapping[name] = f"{column}:degF"
            reasons.append(f"{name}={column}: its name says degrees Fahrenheit, so the suggestion reads it as such; "
                           f"write {column}:degC if it is Celsius")
    if args.json:
        print_json({"rows": rows, "columns": columns, "suggested_map": mapping, "notes": reasons})
        return 0
    shown = [c for c in columns if c["values"] > 0]
    empty = len(columns) - len(shown)
    print(f"{path}: {rows} row(s), {len(columns)} column(s)"
          + (f" ({empty} without any value, not shown)" if empty else ""))
    for c in shown:
        print(f"  {c['column']:40s} {c['values']:9d} values  first {c['first'][:30]}")
    if mapping:
        text = ",".join(f"{k}={v}" for k, v in mapping.items())
        print(f'suggested: --map "{text}"' + ("  (add --actuator NAME to read one joint)" if "{j}" in text else ""))
    for reason in reasons:
        print(f"note: {reason}")
    return 0


def _listing(path: Path) -> tuple[int, list[dict]]:
    """Rows, and each column's count of values and first value, read in pieces: a file of any size in the
    memory of one piece."""
    rows, counts, first = 0, {}, {}
    for chunk in table_chunks(path):
        rows += len(chunk)
        for c in chunk.columns:
            present = chunk[c].dropna()
            counts[str(c)] = counts.get(str(c), 0) + len(present)
            if str(c) not in first and len(present):
                first[str(c)] = str(present.iloc[0])
    return rows, [{"column": c, "values": k, "first": first.get(c, "")} for c, k in counts.items()]
