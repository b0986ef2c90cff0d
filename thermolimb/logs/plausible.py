"""Units a log states in its headers, or gives away in its numbers: time in ms, min or h, or counted in
milliseconds since 1970; temperatures in kelvin, or switching between degC and K.  Each converted and said
in the log's notes, or refused in one sentence."""

from __future__ import annotations

import re
from typing import Mapping

import numpy as np

from ..util.errors import LogError
from ..util.lazy import pandas as pd
from .mapping import OPTIONAL, REQUIRED, TIME_OF, UNITS
from .units import CELSIUS, FAHRENHEIT, SCALED, canonical_headers, header_unit

TIME_SCALES = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9, "min": 60.0, "h": 3600.0}
# Numbers that are the seconds since 1970 of a day in 2000-2099: a time column counting milliseconds,
# microseconds or nanoseconds since 1970 reads 1e3, 1e6 or 1e9 times as much.
EPOCH_S = (9.46e8, 4.1e9)
EPOCH_UNITS = (("milliseconds", 1e-3), ("microseconds", 1e-6), ("nanoseconds", 1e-9))
# A temperature column whose every reading lies here is in kelvin: no actuator stays at 200 degC or more
# for a whole log (the hottest insulation class is rated 180-220 degC), while 200-500 K is -73 to 227 degC.
KELVIN_READINGS = (200.0, 500.0)
SHORT_S = 60.0  # a log shorter than this is looked at for a time unit larger than seconds
FASTEST_K_PER_S = 10.0  # no winding heats faster than this on average over a whole log
KELVIN_JUMP = (263.15, 283.15)  # a step this large between two readings is a switch between degC and K


def canonical_with_units(frame: pd.DataFrame, source: str, given: Mapping[str, str], channel: dict,
                          notes: list, stated: dict) -> pd.DataFrame:
    """A canonical log whose headers carry units (``time [s]``, ``effort [N m]``, ``temperature [degC]``):
    columns renamed to their canonical names, inputs' units taken from the header (an option still wins);
    the time's and temperatures' units go to ``stated`` (:func:`convert_stated`)."""
    renames, units = canonical_headers(frame.columns, REQUIRED + OPTIONAL)
    if not renames:
        return frame
    frame = frame.rename(columns=renames)
    for name, unit in units.items():
        if name in SCALED:
            if name not in given:
                channel[name] = unit
        elif name == "time" or UNITS.get(name) == "degC":
            stated[name] = unit
    return frame


def convert_stated(frame: pd.DataFrame, stated: Mapping[str, str], source: str, notes: list) -> pd.DataFrame:
    """Time in ms/min/h and temperatures in K, as their headers state, converted (said in the notes); any
    other unit of these refused."""
    for name, unit in stated.items():
        if name not in frame.columns:
            continue
        if name == "time":
            if unit not in TIME_SCALES:
                raise LogError(f"{source}: the time column's header gives "
                               f"the unit {unit!r}, which this suite does "
                               f"not read; expected one of {', '.join(TIME_SCALES)}")
            if unit != "s" and pd.api.types.is_numeric_dtype(frame[name]):
                frame[name] = frame[name] * TIME_SCALES[unit]
                notes.append(f"{source}: time read in {unit} (as stated), converted to s")
        elif unit == "K":
            frame[name] = pd.to_numeric(frame[name], errors="coerce") - 273.15
            notes.append(f"{source}: {name} read in K (as stated), converted to degC")
        elif unit in FAHRENHEIT:
            frame[name] = (pd.to_numeric(frame[name], errors="coerce") - 32.0) * (5.0 / 9.0)
            notes.append(f"{source}: {name} read in degrees Fahrenheit "
                         f"(as stated, {unit!r}), converted to degC")
        elif unit not in CELSIUS:
            raise LogError(f"{source}: the {name} column's header gives "
                           f"the unit {unit!r}, which this suite does not "
                           f"read; expected degC, K or degF")
    return frame


# a temperature column's name that may say degrees Fahrenheit without a header unit: "temp_F", "Motor Temp
# degF"
_FAHRENHEIT_NAME = re.compile(r"(?:^|[_\s.-])(?:f|degf|deg_f|fahrenheit)$|[°º]f$", re.IGNORECASE)


def fahrenheit_named(column: str) -> bool:
    """Whether a column's name ends as degrees Fahrenheit do (``temp_F``, ``Motor Temp degF``)."""
    return bool(_FAHRENHEIT_NAME.search(str(column).partition(TIME_OF)[0].strip()))


def refuse_unstated_fahrenheit(mapping: Mapping[str, str], stated: Mapping[str, str], source: str) -> None:
    """A mapped temperature column whose name ends as degrees Fahrenheit do (``temp_F``) and that states no
    unit is refused: its readings (68-250 degF for 20-120 degC) would pass for degrees Celsius, and the log
    does not say."""
    for name, column in mapping.items():
        if UNITS.get(name) == "degC" and name not in stated and fahrenheit_named(column):
            bare = str(column).partition(TIME_OF)[0]
            raise LogError(f"{source}: --map {name}={column}: the "
                           "column's name may say degrees Fahrenheit, and "
                           "neither its header nor the mapping gives "
                           f"a unit; say which, {name}={bare}:degF or "
                           f"{name}={bare}:degC")


def mapped_stated(mapping: Mapping[str, str]) -> dict[str, str]:
    """The time's and temperatures' units the mapped columns' headers give (``stamp [ms]``, ``T_winding
    [K]``)."""
    out = {}
    for name, column in mapping.items():
        if name == "time" or UNITS.get(name) == "degC":
            unit = header_unit(column.partition(TIME_OF)[0])
            if unit:
                out[name] = unit
    return out


def slowest_rate(out: dict[str, np.ndarray]) -> tuple[float, float] | None:
    """Of the actuators of a log, the smallest average rate of its temperature's span over its time span
    (K/s), with that span (K); ``None`` when an actuator's time does not move."""
    rates, names = [], np.asarray(out["actuator"], dtype=str)
    for name in np.unique(names):
        mine = names == name
        t, T = out["time"][mine], out["temperature"][mine]
        if np.ptp(t) <= 0:
            return None
        rates.append((float(np.ptp(T) / np.ptp(t)), float(np.ptp(T))))
    return min(rates) if rates else None


def plausible_units(out: dict[str, np.ndarray], stated: Mapping[str, str], numeric_time: bool, source: str,
                     notes: list) -> dict:
    """Unit mistakes a log's numbers show, where no header states the unit: time counted in milliseconds (or
    micro-, nanoseconds) since 1970, converted; time steps too long for seconds, said; temperatures in
    kelvin, converted.  Each said in the notes with the numbers that show it.  What it decided:
    ``{"time_scale": s per unit, "stated": {column: "K"}}``, for the later pieces of a log read in pieces."""
    decided: dict = {"stated": {}}
    t = out["time"]
    if "time" not in stated and numeric_time and t.size:
        lo, hi = float(np.min(t)), float(np.max(t))
        for unit, scale in EPOCH_UNITS:
            if EPOCH_S[0] <= lo * scale and hi * scale <= EPOCH_S[1] and not EPOCH_S[0] <= lo <= EPOCH_S[1]:
                day = pd.Timestamp(lo * scale, unit="s").strftime("%Y-%m-%d")
                out["time"] = t * scale
                decided["time_scale"] = scale
                notes.append(f"{source}: time reads {lo:.13g} at its first "
                             f"sample, which is {day} counted in {unit} "
                             "since 1970: converted to s (to keep seconds, "
                             "state them: a header 'time [s]' or --map "
                             f"time=COLUMN:s)")
                break
        else:
            if hi - lo >= 2 * 86400.0:  # only a log of days is looked at step by step
                step = float(np.median(_distinct_steps(t)))
                if step >= 100.0:
                    notes.append(f"{source}: time steps of {step:g} s (median) "
                                 f"over {(hi - lo) / 86400:.1f} days: if "
                                 "the time column counts milliseconds, "
                                 "state it: a header 'time [ms]' or --map "
                                 f"time=COLUMN:ms")
            elif 0 < hi - lo < SHORT_S:
                rate = slowest_rate(out)
                if rate is not None and rate[0] > FASTEST_K_PER_S:
                    notes.append(f"{source}: the temperature moves {rate[1]:.1f} K over the log's "
                                 f"{hi - lo:.3g} s ({rate[0]:.0f} K/s on average), faster "
                                 "than any winding heats for long: if the " f"time column counts minutes or "
                                 f"hours, state it: --map time=COLUMN:min or :h")
    for name in out:
        if UNITS.get(name) != "degC" or name in stated:
            continue
        values = out[name]
        lo, hi = float(np.min(values)), float(np.max(values))
        if KELVIN_READINGS[0] <= lo and hi <= KELVIN_READINGS[1]:
            out[name] = values - 273.15
            decided["stated"][name] = "K"
            notes.append(f"{source}: {name} reads {lo:.1f} to {hi:.1f} "
                         "throughout, which no actuator stays at in "
                         f"degC: taken as kelvin and converted to degC (to keep degC, state it: a header "
                         f"'{name} [degC]' or --map {name}=COLUMN:degC)")
        else:
            decided["stated"].setdefault(name, "degC")
    return decided


def _distinct_steps(t: np.ndarray) -> np.ndarray:
    """The steps between the distinct time stamps, ``np.diff(np.unique(t))``: without the sort where they are
    in order already (a 2 M-sample run's sort, 0.14 s)."""
    steps = np.diff(t)
    return steps[steps > 0] if np.all(steps >= 0) else np.diff(np.unique(t))


def refuse_unit_switch(g: pd.DataFrame, name: str, source: str) -> None:
    """A temperature jumping by about 273 K between two readings: part of the log is in kelvin."""
    for column in g.columns:
        if UNITS.get(column) != "degC":
            continue
        values = g[column].to_numpy()
        jump = np.abs(np.diff(values))
        switch = (jump >= KELVIN_JUMP[0]) & (jump <= KELVIN_JUMP[1])
        if switch.any():
            k = int(np.flatnonzero(switch)[0])
            t = g["time"].to_numpy()
            raise LogError(f"{source}: {column} of actuator {name!r} jumps "
                           f"by {values[k + 1] - values[k]:+.1f} K at "
                           f"row {g.index[k + 1]} (t = {t[k]:g} s to "
                           f"{t[k + 1]:g} s): part of the log reads kelvin, "
                           f"part degC; expected one unit throughout (convert one part)")
