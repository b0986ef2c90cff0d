"""Wide files onto the canonical long format: columns named by a mapping, a joint pattern over several
joints' columns, or channels on time bases of their own (:mod:`.align`)."""

from __future__ import annotations

from typing import Mapping

from ..util.errors import LogError
from ..util.lazy import pandas as pd
from . import extras
from .align import align, series_of
from .dialect import shown_names
from .mapping import EXTRA, REQUIRED, TIME_OF, expand_joints, is_pattern
from .table import first_stamp, time_seconds
from .units import KNOWN, split_unit


def split_units(mapping: Mapping[str, str] | None) -> tuple[dict[str, str], dict[str, str]]:
    """``{channel: "COLUMN:UNIT"}`` -> ``({channel: COLUMN}, {channel: UNIT})`` (see
    :func:`~.units.split_unit`)."""
    columns, units = {}, {}
    for key, value in (mapping or {}).items():
        columns[key], unit = split_unit(value)
        if unit:
            units[key] = unit
    return columns, units


def apply_mapping(frame: pd.DataFrame, mapping: Mapping[str, str], source: str, actuator_name: str,
                   drop_incomplete: bool = False) -> pd.DataFrame:
    if is_pattern(mapping):
        parts, notes = [], []
        timed = {k: v.partition(TIME_OF)[2] for k, v in mapping.items() if TIME_OF in v}
        plain = {k: v.partition(TIME_OF)[0] for k, v in mapping.items()}
        joints = expand_joints(frame.columns, plain, source, notes)
        per_joint, shared = extras.joint_extras(frame.columns, plain, [j for j, _, _ in joints])
        for j, name, cols in joints:
            # actuator=field.name{j}: a column names the joint
            if "actuator" in mapping and name in frame.columns:
                name = _joint_name(frame[name], name, source)
            if timed:  # each joint's channels on time bases of their own (topics merged on one time column)
                part = _aligned(frame,
                                {k: v + (TIME_OF + timed[k] if k in timed else "") for k, v in cols.items()},
                                source, name, drop_incomplete)
                notes += [n for n in part.attrs["notes"] if n not in notes]
                parts.append(part)
                continue
            part = pd.DataFrame({k: frame[v] for k, v in cols.items()})
            part.insert(1, "actuator", name)
            for stem, column in per_joint[j].items():
                part[EXTRA + stem] = frame[column].to_numpy()
            for column in shared:
                part[EXTRA + column] = frame[column].to_numpy()
            parts.append(part)
        out = pd.concat(parts, ignore_index=True)
        out.attrs["notes"] = notes
        return out
    if any(TIME_OF in v for v in mapping.values()):
        return _aligned(frame, mapping, source, actuator_name, drop_incomplete)
    absent = {
        k: v for k, v in mapping.items() if v not in frame.columns and not (k == "actuator" and "{" in v)
    }
    if absent:
        k, v = next(iter(absent.items()))
        column, sep, unit = str(v).rpartition(":")
        # a column of the file, and after its colon a unit this suite lacks
        if sep and column in frame.columns:
            raise LogError(f"{source}: --map {k}={v}: {unit!r} is not a unit this suite knows; known units: "
                           f"{', '.join(KNOWN)}")
        raise LogError(
            f"{source}: --map {k}={v} names column {v!r}, which the file does not have; "
            f"its columns are {shown_names(frame.columns)}"
        )
    unmapped = [c for c in REQUIRED if c != "actuator" and c not in mapping]
    if unmapped:
        raise LogError(
            f"{source}: --map does not name the column(s) for {', '.join(unmapped)}; add "
            f"{','.join(c + '=COLUMN' for c in unmapped)} with COLUMN among {shown_names(frame.columns)}"
        )
    out = pd.DataFrame({k: frame[v] for k, v in mapping.items()})
    for column in extras.unmapped(frame.columns, mapping):
        out[EXTRA + column] = frame[column]
    if "actuator" not in out.columns:
        out["actuator"] = actuator_name
    return out


def _others_message(frame: pd.DataFrame, key: str, column: str, time_column: str, targets: dict,
                    mapping: Mapping[str, str]) -> pd.Series:
    """Rows of a table of topics merged on one time column where ``column`` is blank and another channel on
    the same time column holds a value: another topic's message, not a missing reading."""
    mates = [c for k, (c, _, t) in targets.items() if k != key and (t or mapping.get("time")) == time_column
             and c in frame.columns and c != column]
    if not mates:
        return pd.Series(False, index=frame.index)
    return frame[column].isna() & frame[mates].notna().any(axis=1)


def _joint_name(column: pd.Series, header: str, source: str) -> str:
    """The one name a per-joint column holds (a ``rostopic echo -p`` export's ``field.name0``)."""
    names = column.dropna().astype(str).str.strip().unique()
    if len(names) != 1 or not names[0]:
        raise LogError(f"{source}: --map actuator= reads the joint's "
                       f"name from column {header!r}, which holds "
                       f"{len(names)} names "
                       f"({', '.join(names[:3])}{', ...' if len(names) > 3 else ''}); expected "
                       f"one name on every row")
    return names[0]


def _aligned(frame: pd.DataFrame, mapping: Mapping[str, str], source: str, actuator_name: str,
             drop_incomplete: bool) -> pd.DataFrame:
    """A wide file whose channels have time columns of their own, put on the temperature's samples."""
    if "temperature" not in mapping or ("time" not in mapping and TIME_OF not in mapping["temperature"]):
        raise LogError(f"{source}: with per-channel time columns, --map names temperature=COLUMN@TIME_COLUMN "
                       f"(or time=COLUMN for the channels without their own)")
    columns, notes = {}, []
    targets = {
        key: value.partition(TIME_OF) for key, value in mapping.items() if key not in ("time", "actuator")
    }
    stamps = [first_stamp(frame[t or mapping["time"]]) for _, _, t in targets.values()
              if (t or mapping.get("time")) in frame.columns]
    origin = min((s for s in stamps if s is not None), default=None)
    for key, (column, _, time_column) in targets.items():
        value = mapping[key]
        time_column = time_column or mapping.get("time")
        if time_column is None:
            raise LogError(f"{source}: --map {key}={value} has no time "
                           f"column; write {key}={column}@TIME_COLUMN or "
                           f"give time=COLUMN")
        for c in (column, time_column):
            if c not in frame.columns:
                raise LogError(f"{source}: --map {key}={value} names column "
                               f"{c!r}, which the file does not have; "
                               f"its columns are {shown_names(frame.columns)}")
        rows = frame[time_column].notna() & ~_others_message(
            frame, key, column, time_column, targets, mapping
        )
        if not rows.all() and (~rows & frame[time_column].notna()).any():
            notes.append(f"{source}: {key} read on the {int(rows.sum())} "
                         f"rows of {time_column} that hold it (the "
                         f"other {int((~rows & frame[time_column].notna()).sum())} "
                         "hold other channels' messages)")
        seconds = time_seconds(frame.loc[rows, time_column], source, time_column, origin, notes)
        columns[key] = series_of(seconds, pd.to_numeric(frame.loc[rows, column], errors="coerce"),
                                 source, key, drop_incomplete, notes)
    aligned, more = align(columns.pop("temperature"), columns, source)
    notes += more
    out = pd.DataFrame(aligned)
    out.insert(1, "actuator", actuator_name)
    out.attrs["notes"] = notes
    return out
