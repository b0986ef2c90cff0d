"""Channels a log carries beyond the model's inputs, kept for the diagnosis to try (``diagnose --discover``).

A fan's duty, a brake's state, a driver board's temperature, a supply
voltage: a heat path that rides on one of them is invisible to a model that
reads only effort, velocity and the canonical channels.  A log keeps every
extra numeric channel it has, named after its column without the unit
(``Voltage [V]`` -> ``Voltage`` in V), in the frame as ``extra.Voltage``:

* a canonical or single-actuator file: every column that is not a canonical one;
* a file mapped with joint patterns (``effort=Current_J{j}``): per-joint
  columns of the same form (``Voltage_J{j}`` -> ``Voltage_J`` of each
  joint) and the columns shared by every joint (``Tool_current``);
* a bag: every other numeric field of the topics the mapping reads
  (:func:`~thermolimb.logs.bags.auto_extras`), and those named as ``extra.NAME=/topic.field``;
* a file with per-channel time columns: the channels named as ``--map extra.NAME=COLUMN@TIME``.

Columns that are not numbers, are empty, never change, or count samples,
cycles or time (monotonic) are not channels and are left out; one with missing values is left
out with a note.  Booleans are read as 0 and 1.
"""

from __future__ import annotations

import re
from typing import Mapping

import numpy as np

from ..util.lazy import pandas as pd
from .dialect import shown_names
from .mapping import EXTRA, JOINT, NAME, NUMBER, OPTIONAL, REQUIRED, pattern_regex
from .units import header_unit

_HEADER_UNIT = re.compile(r"\s*[\[(][^\[\]()]*[\])]\s*$")
_PER_JOINT = re.compile(r"^(?P<stem>.*?\D)(?P<j>\d+)$")
_BOOLEAN = {"true": 1.0, "false": 0.0}


def extra_name(header: str) -> tuple[str, str | None]:
    """``Voltage [V]`` -> ``("Voltage", "V")``; a header without a unit is its own name."""
    header = str(header).strip()
    name = _HEADER_UNIT.sub("", header).strip().removeprefix(EXTRA)  # extra.ambient: a file's extra "ambient"
    return (name or header), header_unit(header)


def unmapped(columns, mapping: Mapping[str, str]) -> list[str]:
    """Columns of a single-actuator file that no ``--map`` entry uses (candidates for extra channels)."""
    used = set(mapping.values())
    return [str(c) for c in columns if str(c) not in used]


def joint_extras(columns, mapping: Mapping[str, str],
                 joints: list[int | str]) -> tuple[dict[int | str, dict[str, str]], list[str]]:
    """Per-joint extra columns (``{joint: {stem: column}}``, only stems every joint has) and shared ones, for
    a file mapped with joint patterns; columns the mapping uses are not extras.  Joints named in the columns
    (``/joint_states/FR_hip/position``) give stems without the name (``/joint_states/position``)."""
    named = any(isinstance(j, str) for j in joints)
    used = {str(c) for c in columns if any(_matches(c, t, named) for t in mapping.values())}
    per_stem: dict[str, dict[int | str, str]] = {}
    shared = []
    for c in (str(c) for c in columns):
        if c in used:
            continue
        joint, stem = _named_joint(c, joints) if named else _numbered_joint(c)
        if joint in joints:
            per_stem.setdefault(stem, {})[joint] = c
        elif joint is None:
            shared.append(c)
    complete = {stem: cols for stem, cols in per_stem.items() if set(joints) <= set(cols)}
    return {j: {stem: cols[j] for stem, cols in complete.items()} for j in joints}, shared


def _numbered_joint(column: str) -> tuple[int | None, str]:
    m = _PER_JOINT.match(column)
    return (int(m.group("j")), m.group("stem")) if m else (None, column)


def _named_joint(column: str, joints: list[str]) -> tuple[str | None, str]:
    """The longest of ``joints`` a column's name holds between separators, and the name without it."""
    for joint in sorted(joints, key=len, reverse=True):
        m = re.search(rf"(^|[^A-Za-z0-9]){re.escape(joint)}($|[^A-Za-z0-9])", column)
        if m:
            return joint, (column[:m.start()] + m.group(1) + column[m.end():]).strip("._- ")
    return None, column


def _matches(column, template: str, named: bool = False) -> bool:
    if JOINT not in template and "*" not in template:
        return str(column) == template
    return pattern_regex(template, NAME if named else NUMBER).match(str(column)) is not None


def collect(frame: pd.DataFrame, given: Mapping[str, str | None], explicit: Mapping[str, str],
            source: str) -> tuple[dict[str, np.ndarray], dict[str, str | None], list[str]]:
    """The frame's extra channels as float arrays by name, their units, and notes on what was left out.

    Extra columns are those of ``frame`` that are not canonical; a column
    named ``extra.NAME`` was mapped (``explicit``: NAME's mapped column, whose
    header may give the unit) or comes from a bag.  ``given`` holds units
    given with the mapping (``extra.NAME=COL:UNIT``).
    """
    values, units, missing, text = {}, {}, [], []
    groups = None  # each actuator's rows, found when a column is first tested for counting (_monotonic)
    for column in frame.columns:
        if column in REQUIRED + OPTIONAL:
            continue
        if column.startswith(EXTRA) and column in explicit:
            name, unit = column[len(EXTRA):], given.get(column) or header_unit(explicit[column])
        elif column.startswith(EXTRA):
            name, unit = extra_name(column[len(EXTRA):])
            unit = given.get(column) or unit
        else:
            name, unit = extra_name(column)
        if name in values:
            name = column  # two headers with one name and different units: keep the header
        x = _numeric(frame[column])
        if x is None:
            if frame[column].notna().any():
                text.append(name)
            continue
        finite = np.isfinite(x)
        if not finite.any() or np.nanmin(x) == np.nanmax(x):
            continue  # empty, or constant (it can explain nothing)
        if groups is None and "actuator" in frame.columns:
            groups = list(frame.groupby("actuator", sort=False, observed=True).indices.values())
        if _monotonic(x, groups):
            continue  # a sample counter or a clock
        if not finite.all():
            missing.append(f"{name} ({int((~finite).sum())})")
            continue
        values[name] = x
        units[name] = unit
    notes = []
    if missing:
        notes.append(f"{source}: extra channel(s) with missing values not kept: {', '.join(missing)} "
                     f"(fill them to use them)")
    if text:
        notes.append(f"{source}: column(s) holding text not kept as channels: {shown_names(text)}")
    return values, units, notes


def _numeric(column: pd.Series) -> np.ndarray | None:
    """The column as floats (booleans 0/1), or ``None`` when it holds text."""
    if pd.api.types.is_bool_dtype(column):
        return column.to_numpy(float)
    if column.dtype == object:
        lowered = column.dropna().astype(str).str.strip().str.lower()
        if len(lowered) and lowered.isin(list(_BOOLEAN)).all():
            return column.map(lambda v: _BOOLEAN.get(str(v).strip().lower(), np.nan)).to_numpy(float)
    converted = pd.to_numeric(column, errors="coerce")
    if converted.notna().sum() < column.notna().sum():
        return None
    return converted.to_numpy(float)


# a counter's changes are rises, but for the odd reset (the UR3's cycle count drops once)
COUNTER_RISES = 0.95


def _monotonic(x: np.ndarray, groups: list[np.ndarray] | None) -> bool:
    """A count or a clock: strictly monotonic, or whole numbers that take several values and change almost
    only upwards (a cycle counter, reset now and then), within each actuator's rows (a counter shared by every
    joint repeats per joint)."""
    def one(v: np.ndarray) -> bool:
        d = np.diff(v)
        strict = bool(np.all(d > 0)) or bool(np.all(d < 0))
        changes = d[d != 0]
        counting = (bool(np.all(v == np.round(v))) and np.unique(v).size > 2
                    and changes.size > 0 and np.mean(changes > 0) >= COUNTER_RISES)
        return v.size > 2 and (strict or counting)

    return all(one(x[idx]) for idx in groups) if groups else one(x)
