"""Validating a frame into a :class:`~.series.ThermalLog`: canonical or wide columns, units stated or given
away, missing values, time that must increase, readings no actuator gives, each refused in one sentence
naming the file, the column and what is expected."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from ..util.errors import LogError
from ..util.frozen import FrozenMapping
from ..util.lazy import pandas as pd
from . import extras
from .dialect import shown_names
from .held import read_on_updates
from .mapping import EXTRA, OPTIONAL, REQUIRED, TIME_OF, UNITS, is_pattern, on_time
from .plausible import (
    canonical_with_units,
    convert_stated,
    mapped_stated,
    plausible_units,
    refuse_unit_switch,
    refuse_unstated_fahrenheit,
)
from .series import MIN_SAMPLES, ThermalLog
from .suspect import fahrenheit_note, leave_out
from .table import first_stamp, is_stamped, refuse_duplicates, time_seconds
from .units import NOT_GIVEN, channel_units
from .wide import apply_mapping, split_units

# no working actuator's winding, housing or air reads outside this: readings beyond are not degC
TEMPERATURE_RANGE_C = (-100.0, 500.0)
# revolutions a second: ODrive's and moteus's native velocity (turns/s, rev/s)
VELOCITY_UNITS = {"rad/s": 1.0, "m/s": 1.0, "rpm": 2.0 * np.pi / 60.0, "deg/s": np.pi / 180.0,
                  "rev/s": 2.0 * np.pi, "turn/s": 2.0 * np.pi}


@dataclass
class Reading:
    """How a log's first piece was read, so that every later piece of it (a log followed as it is written) is
    read alike: the units of time and temperatures it stated or gave away, the time's scale and origin.
    Filled by :func:`from_frame` on the first piece, given back for the later ones."""

    stated: dict = field(default_factory=dict)  # time and temperature units: stated, or found in the numbers
    time_scale: float = 1.0  # seconds per unit of a numeric time (an epoch counted in ms, us, ns)
    origin: object = None  # the first time stamp, for logs stamped with dates
    decided: bool = False


def from_frame(
    frame: pd.DataFrame,
    source: str = "<memory>",
    mapping: Mapping[str, str] | None = None,
    velocity_unit: str | None = None,
    actuator_name: str = "actuator",
    drop_incomplete: bool = False,
    units: Mapping[str, str | None] | None = None,
    copy: bool = True,
    reading: Reading | None = None,
) -> ThermalLog:
    """Validate a data frame (canonical, or wide with ``mapping``) into a :class:`ThermalLog`.

    Samples with only a time stamp are left out (they hold nothing); a sample
    missing some values is an error unless ``drop_incomplete``.  ``units``
    gives channels' units the frame does not (see :mod:`thermolimb.logs.units`).
    ``copy=False`` lets the log share the frame's float columns instead of copying them: for a frame the
    caller hands over (a large log read once), not one it goes on changing.

    ``reading``: a log read piece by piece (:mod:`.follow`).  On the first piece (``reading.decided`` false)
    it receives what the piece's headers and numbers decided; a later piece is read by those decisions, and
    the rules that need a whole run (enough samples, a sensor stuck or at its ceiling, degF readings) are left
    to the reader of the whole log.
    """
    mapping, from_map = split_units(mapping)
    if velocity_unit is not None and velocity_unit not in VELOCITY_UNITS:
        raise LogError(
            f"unknown velocity unit {velocity_unit!r}; expected one of {', '.join(VELOCITY_UNITS)}"
        )
    given = {**{k: v for k, v in (units or {}).items() if v}, **from_map}
    if velocity_unit is not None:
        given["velocity"] = velocity_unit
    channel = channel_units(mapping, given)
    notes = []
    stated = {**(mapped_stated(mapping) if mapping else {}),
              **{k: v for k, v in given.items() if k == "time" or UNITS.get(k) == "degC"}}
    if mapping:
        refuse_unstated_fahrenheit(mapping, stated, source)
    later = reading is not None and reading.decided
    refuse_duplicates(frame, set(mapping.values()) if mapping else set(REQUIRED + OPTIONAL), source, notes)
    if frame.attrs.get("read_as") and not later:
        notes.append(frame.attrs["read_as"])
    first_line = frame.attrs.get("headerless")
    if first_line is not None and not later:
        notes.append(f"{source}: the file has no header row (its "
                     f"first line, {first_line.strip()[:60]!r}, holds "
                     + ("numbers): its columns are named by --columns" if frame.attrs.get("named") else
                        "numbers): its columns are read as column1 to "
                        f"column{len(frame.columns)}; name them with "
                        f"--columns NAME,NAME,... (in the file's order) to map them by name"))
    if channel["velocity"] not in VELOCITY_UNITS and channel["velocity"] != NOT_GIVEN:
        notes.append(f"{source}: velocity unit {channel['velocity']!r} "
                     "(from the column's header) is not one this "
                     f"suite converts ({', '.join(VELOCITY_UNITS)}); "
                     "taken as not given -- name it with --velocity-unit")
        channel["velocity"] = NOT_GIVEN
    if mapping:
        frame = apply_mapping(frame, mapping, source, actuator_name, drop_incomplete)
        notes += frame.attrs.get("notes", [])
    else:
        frame = canonical_with_units(frame, source, given, channel, notes, stated)
        if "actuator" not in frame.columns and set(REQUIRED) - {"actuator"} <= set(frame.columns):
            frame = frame.assign(actuator=actuator_name)  # one actuator's file, named as a wide file's is
    if later:
        stated.update(reading.stated)
    frame = convert_stated(frame, stated, source, notes)
    missing = [c for c in REQUIRED if c not in frame.columns]
    if missing:
        hint = "" if mapping else "; name them with --map canonical=column"
        if not mapping and all(str(c).startswith("column") for c in frame.columns):  # no header row
            hint = "; the file has no header row: name its columns in order with --columns time,actuator,..."
        raise LogError(
            f"{source}: missing column(s) {', '.join(missing)} (expected {', '.join(REQUIRED)}); "
            f"the file has {shown_names(frame.columns)}{hint}"
        )
    keep = [c for c in REQUIRED + OPTIONAL if c in frame.columns]
    frame = frame.reset_index(drop=True)
    measured = [c for c in keep if c not in ("time", "actuator")]
    empty = frame[measured].isna().all(axis=1).to_numpy()
    if empty.any():
        notes.append(f"{source}: {int(empty.sum())} sample(s) (rows times "
                     "actuators) with no measured value, only a time stamp, left out")
        frame = frame.loc[~empty].reset_index(drop=True)
    # a later piece of a followed log may be a row whose optional cell is blank
    if not frame.empty and not later:
        refuse_empty_columns(frame, measured, mapping, source)
    apart = on_other_rows(frame, measured, mapping, from_map) if mapping and not later else None
    frame = _as_numbers(frame, measured, source, notes, drop_incomplete)
    if drop_incomplete:
        incomplete = frame[measured].isna().any(axis=1).to_numpy()
        if incomplete.any() and apart is not None and incomplete.all():
            raise LogError(f"{source}: no row holds every channel: {apart}")
        if incomplete.any():
            notes.append(f"{source}: {int(incomplete.sum())} incomplete "
                         "sample(s) left out (--drop-incomplete), first "
                         f"at row {int(np.flatnonzero(incomplete)[0])}; the inputs before them are held"
                         + ("" if apart is None else f" ({apart})"))
            frame = frame.loc[~incomplete].reset_index(drop=True)
    if frame.empty:
        raise LogError(f"{source}: the log has no rows with measurements")
    names = _as_text(frame["actuator"])
    blank = frame["actuator"].isna().to_numpy() | _blank(names)
    if blank.any() and drop_incomplete and not blank.all():
        notes.append(f"{source}: {int(blank.sum())} row(s) with a blank "
                     "actuator name left out (--drop-incomplete), "
                     f"first at row {int(np.flatnonzero(blank)[0])}")
        frame, names = frame.loc[~blank].reset_index(drop=True), names[~blank].reset_index(drop=True)
    elif blank.any():
        row = int(np.flatnonzero(blank)[0])
        raise LogError(f"{source}: column 'actuator' is blank at row "
                       f"{row}; expected an actuator name in every row "
                       f"(or leave such rows out with --drop-incomplete)")
    # the validated columns, as arrays (a float column of the frame is taken as it is, not copied)
    origin = reading.origin if later else (first_stamp(frame["time"]) if reading is not None else None)
    out = {
        "time": np.array(time_seconds(frame["time"], source, "time", origin, notes), copy=copy),
        "actuator": names,
    }
    numeric_time = pd.api.types.is_numeric_dtype(frame["time"])
    if not numeric_time and not later and is_stamped(frame["time"]):  # numbers written as text are not stamps
        notes.append(f"{source}: time stamps turned into seconds from the first sample")
    for c in keep:
        if c in ("time", "actuator"):
            continue
        if pd.api.types.is_float_dtype(frame[c]):
            out[c] = frame[c].to_numpy(float, copy=copy)
            continue
        values = pd.to_numeric(frame[c], errors="coerce")
        bad = values.isna() & frame[c].notna()
        if bad.any():
            row = int(np.flatnonzero(bad.to_numpy())[0])
            value = str(frame[c].iloc[row]).strip()
            if _THOUSANDS.match(value):
                raise LogError(f"{source}: column {c!r} writes numbers with "
                               f"thousands separators ({value!r} at row "
                               f"{row}); expected plain numbers in {UNITS[c]}: export without the separators")
            raise LogError(f"{source}: column {c!r} is not numeric at row {row} ({frame[c].iloc[row]!r}); "
                           f"expected {UNITS[c]} (or leave such samples out with --drop-incomplete)")
        out[c] = values.to_numpy(float, copy=copy)
    explicit = {k: v for k, v in mapping.items() if k.startswith(EXTRA)}
    extra_values, extra_units, extra_notes = extras.collect(frame, given, explicit, source)
    notes += extra_notes
    for c, values in out.items():
        if c == "actuator":
            continue
        nan = ~np.isfinite(values)
        if nan.any():
            row = int(np.flatnonzero(nan)[0])
            fix = (f"; expected finite numbers in {UNITS[c]} (fill them, or leave those samples out with "
                   f"--drop-incomplete)" if apart is None else f": {apart}")
            raise LogError(f"{source}: column {c!r} has {int(nan.sum())} "
                           "missing or non-finite value(s), first at "
                           f"row {row}{fix}")
    if later:
        out["time"] = out["time"] * reading.time_scale if reading.time_scale != 1.0 else out["time"]
    else:
        decided = plausible_units(out, stated, numeric_time, source, notes)
        if reading is not None:
            reading.stated = {**stated, **decided.get("stated", {})}
            reading.time_scale, reading.origin, reading.decided = decided.get("time_scale", 1.0), origin, True
    for c in (c for c in out if UNITS.get(c) == "degC"):
        values = out[c]
        outside = (values < TEMPERATURE_RANGE_C[0]) | (values > TEMPERATURE_RANGE_C[1])
        if outside.any():
            row = int(np.flatnonzero(outside)[0])
            raise LogError(
                f"{source}: column {c!r} reads {values[row]:g} at row {row}; expected degC between "
                f"{TEMPERATURE_RANGE_C[0]:g} and {TEMPERATURE_RANGE_C[1]:g} "
                "(a log in kelvin, in tenths of a degree "
                f"or in raw counts needs converting first)"
            )
    if (
        "velocity" in out
        and channel["velocity"] in VELOCITY_UNITS
        and VELOCITY_UNITS[channel["velocity"]] != 1.0
    ):
        out["velocity"] = out["velocity"] * VELOCITY_UNITS[channel["velocity"]]
        channel["velocity"] = "m/s" if channel["velocity"] == "m/s" else "rad/s"
    for name, values in extra_values.items():
        out[EXTRA + name] = values
        channel[EXTRA + name] = extra_units[name] or NOT_GIVEN
    out = pd.DataFrame(out, copy=False)
    parts, set_aside = [], []
    for name, g in _by_actuator(out):
        t = g["time"].to_numpy()
        steps = np.diff(t)
        if np.any(steps <= 0):
            k = int(np.flatnonzero(steps <= 0)[0])
            hints = []
            if mapping and "actuator" not in mapping and not is_pattern(mapping):
                hints.append("if the file holds rows of several actuators, map the column naming them "
                             "(--map actuator=COLUMN)")
            if t[k + 1] < t[k] - 10 * float(np.median(steps)):  # far back: a clock that restarts
                hints.append("if it joins recordings whose clocks restart, "
                             "give each as a file of its own (a run each)")
            raise LogError(f"{source}: time does not increase for actuator {name!r} at row {g.index[k + 1]} "
                           f"(t = {t[k]:g} s then {t[k + 1]:g} s); "
                           "expected strictly increasing time in seconds"
                           + "".join(f"; {h}" for h in hints))
        try:  # one actuator's trouble stays its own: of several, it is set aside and said, the others read
            if len(g) < MIN_SAMPLES and not later:
                raise LogError(f"{source}: actuator {name!r} has {len(g)} "
                               f"samples; at least {MIN_SAMPLES} are "
                               f"needed")
            refuse_unit_switch(g, name, source)
            if reading is None:  # a log followed piece by piece is read as its pieces come
                g = read_on_updates(g, name, source, notes)
            if not later:
                g = leave_out(g, name, source, notes, MIN_SAMPLES)
        except LogError as exc:
            if later or out["actuator"].nunique() == 1:
                raise
            set_aside.append(exc)
            notes.append(f"{exc}; {SET_ASIDE}")
            continue
        if not later:
            note = fahrenheit_note(g["temperature"].to_numpy(), g["effort"].to_numpy(),
                                   g["ambient"].to_numpy() if "ambient" in g else None, source, name)
            if note:
                notes.append(note)
        parts.append(g)
    if not parts:
        raise set_aside[0]
    whole = parts[0] if len(parts) == 1 else pd.concat(parts, ignore_index=True)
    return ThermalLog(whole, source, tuple(notes), FrozenMapping(channel))


SET_ASIDE = "that actuator is set aside, the others are read"
_UTF7_MINUS = "+AC0-"  # a minus sign written by an encoder in UTF-7 ('+AC0-2.5' for -2.5)


def _as_numbers(frame: pd.DataFrame, measured: list[str], source: str, notes: list[str],
                drop_incomplete: bool) -> pd.DataFrame:
    """The measured columns with minus signs an encoder wrote in UTF-7 read as minus signs, and, with
    ``drop_incomplete``, cells that are not numbers made missing (so that their samples are left out), each
    said once with its count, first row and value.  Without ``drop_incomplete`` such a cell is refused later,
    by the column's check; numbers with thousands separators are left to it too (dropping them would drop the
    log)."""
    changed = {}
    for c in measured:
        column = frame[c]
        if pd.api.types.is_numeric_dtype(column) or c == "actuator":
            continue
        text = column.astype("string")
        mangled = text.str.contains(_UTF7_MINUS, regex=False).fillna(False).to_numpy(bool)
        if mangled.any():
            row = int(np.flatnonzero(mangled)[0])
            notes.append(f"{source}: column {c!r} writes minus signs as {_UTF7_MINUS!r} (UTF-7) in "
                         f"{int(mangled.sum())} cell(s), first at row "
                         f"{row} ({column.iloc[row]!r}): read as '-'")
            column = text.str.replace(_UTF7_MINUS, "-", regex=False)
        values = pd.to_numeric(column, errors="coerce")
        bad = (values.isna() & column.notna() & (column.astype("string").str.strip() != "")).to_numpy(bool)
        if drop_incomplete and bad.any():
            row = int(np.flatnonzero(bad)[0])
            if _THOUSANDS.match(str(column.iloc[row]).strip()):
                changed[c] = column
                continue
            notes.append(f"{source}: column {c!r} holds {int(bad.sum())} "
                         "cell(s) that are not numbers, first at row "
                         f"{row} ({column.iloc[row]!r}); their samples are left out (--drop-incomplete)")
            changed[c] = values
        elif mangled.any():
            changed[c] = column
    return frame.assign(**changed) if changed else frame


# 1.000,0 / 12.345.678,9 (a point groups, a comma is the decimal) or 1,000.0 (the other way round)
_THOUSANDS = re.compile(r"^[-+]?\d{1,3}(\.\d{3})+(,\d+)?$|^[-+]?\d{1,3}(,\d{3})+(\.\d+)?$")


def _by_actuator(frame: pd.DataFrame):
    """``(name, rows)`` of each actuator in order of appearance; a frame of one actuator is its own rows (no
    copy: a large log read for one actuator is not held twice)."""
    first = frame["actuator"].iloc[0]
    if (frame["actuator"] == first).all():
        return [(first, frame)]
    return frame.groupby("actuator", sort=False, observed=True)


def log_from_arrays(
    time_s: np.ndarray,
    names: tuple[str, ...],
    effort: np.ndarray,
    temperature_C: np.ndarray,
    velocity: np.ndarray | None = None,
    current_A: np.ndarray | None = None,
    ambient_C: np.ndarray | None = None,
    source: str = "<memory>",
    housing_C: np.ndarray | None = None,
    extra: Mapping[str, np.ndarray] | None = None,
) -> ThermalLog:
    """Build a canonical log from ``(n_samples, n_actuators)`` arrays (``ambient_C``: ``(n_samples,)``);
    ``extra``: more channels by column header (unit in brackets, ``fan [%]``), each ``(n_samples,
    n_actuators)``."""
    n, m = effort.shape
    data = {
        "time": np.tile(time_s, m),
        "actuator": np.repeat(np.asarray(names, dtype=object), n),
        "effort": effort.T.ravel(),
        "temperature": temperature_C.T.ravel(),
    }
    if velocity is not None:
        data["velocity"] = velocity.T.ravel()
    if current_A is not None:
        data["current"] = current_A.T.ravel()
    if ambient_C is not None:
        data["ambient"] = np.tile(ambient_C, m)
    if housing_C is not None:
        data["housing"] = housing_C.T.ravel()
    for column, values in (extra or {}).items():
        data[column] = np.asarray(values).T.ravel()
    return from_frame(pd.DataFrame(data), source=source)


def _as_text(column: pd.Series) -> pd.Series:
    """A column as text.  A categorical one (a large log read in pieces) stays categorical, with its few
    categories turned into text: converting row by row would make a string per row (144 MB for 2 M rows)."""
    if not isinstance(column.dtype, pd.CategoricalDtype):
        return column.astype(str)
    return column.cat.rename_categories([str(c) for c in column.cat.categories])


def _blank(names: pd.Series) -> np.ndarray:
    """Where a column of actuator names (:func:`_as_text`) is missing or blank."""
    if isinstance(names.dtype, pd.CategoricalDtype):
        codes = names.cat.codes.to_numpy()
        empty = np.array([c.strip() == "" for c in names.cat.categories] + [True])
        return empty[codes]
    return (names.isna() | (names.str.strip() == "")).to_numpy()


def refuse_empty_columns(frame, measured: list[str], mapping: Mapping[str, str] | None, source: str) -> None:
    """A channel whose column holds no value at all is refused by name (leaving out incomplete rows would
    leave none): the column is not logged, or another one was meant."""
    for c in measured:
        if frame[c].isna().all():
            named = f" (the file's {mapping[c]!r})" if mapping and c in mapping else ""
            fix = (
                "" if c in REQUIRED else f", or leave {c} out" + (" of --map" if mapping else " of the file")
            )
            raise LogError(f"{source}: column {c!r}{named} holds no value "
                           f"in any of its {len(frame)} rows; expected "
                           f"numbers in {UNITS[c]}{fix}")


def held_beside_temperature(frame, channels: list[str]) -> dict[str, int]:
    """Of ``frame``'s rows that hold a temperature, how many hold each of ``channels`` too (the temperature
    itself: how many hold one)."""
    has_temperature = frame["temperature"].notna().to_numpy()
    return {c: int(frame.loc[has_temperature, c].notna().sum()) for c in channels}


def apart(held: Mapping[str, int]) -> str | None:
    """The first input that fewer than half of the temperature's rows hold (:func:`held_beside_temperature`):
    a channel logged on rows of its own, as topics merged into one table are; else ``None``."""
    return next((c for c, n in held.items() if c != "temperature" and n < 0.5 * held["temperature"]), None)


def on_other_rows(
    frame, measured: list[str], mapping: Mapping[str, str], units: Mapping[str, str]
) -> str | None:
    """Where the temperature and an input share one time column but are logged on different rows
    (:func:`apart`), how to read each on its own samples (:mod:`.align`); else ``None``."""
    if "time" not in mapping or any(TIME_OF in str(v) for v in mapping.values()):
        return None
    held = held_beside_temperature(frame, measured)
    thin = apart(held)
    if thin is None:
        return None
    stated = {c: f"{mapping[c]}:{units[c]}" if c in units else mapping[c] for c in ["time", *measured]}
    spec = ",".join(
        [f"time={stated['time']}"] + [f"{c}={on_time(stated[c], mapping['time'])}" for c in measured]
    )
    return (f"the temperature and the {thin} are logged on different rows ({held[thin]} of the temperature's "
            f"{held['temperature']} rows hold the {thin}): read each on its own samples with "
            f"--map \"{spec}\"")
