"""The units of a log's input channels, taken from the log, never assumed.

A parameter's unit depends on the unit of the channel it multiplies: βR is
in K/(N m)^2 for a torque logged in N m, in K/mA^2 for a current logged as
effort in mA.  Each log carries the units of its ``effort``, ``velocity``,
``current`` and ``power`` channels:

* the canonical long format (``time, actuator, effort, temperature, ...``,
  what the suite's plant writes) is in its documented units: N m, rad/s, A, W;
* a mapped column takes the unit its header gives (``Effort [mA]``,
  ``Power (W)``), or the one given with the mapping (``--map effort=COL:mA``)
  or its option (``--effort-unit mA``, ``--velocity-unit rpm``);
* otherwise the channel's unit is "unit not given", and every unit built on
  it says so instead of guessing.

Velocity given in rpm, deg/s, rev/s or turn/s is converted to rad/s when the log is read.
"""

from __future__ import annotations

import re
from typing import Mapping

from ..model.parameter_units import CANONICAL, NOT_GIVEN, SCALED

# units a mapping may name after a colon (COLUMN:UNIT); anything else after a colon is part of the column's
# name
KNOWN = (
    "N m",
    "Nm",
    "N",
    "mN m",
    "kN",
    "A",
    "mA",
    "W",
    "mW",
    "kW",
    "V",
    "rad/s",
    "m/s",
    "rpm",
    "deg/s",
    "rev/s",
    "turn/s",
    "%",
    "s",
    "ms",
    "us",
    "ns",
    "min",
    "h",
    "degC",
    "K",
    "degF",
)
CELSIUS = ("degC", "°C", "C", "deg C", "celsius", "Celsius")  # what a header may call degrees Celsius
# ... and degrees Fahrenheit (a thrust stand's "Temp (ºF)": an ordinal sign, not a degree sign, is common)
FAHRENHEIT = ("degF", "°F", "ºF", "F", "deg F", "fahrenheit", "Fahrenheit")
_HEADER = re.compile(r"[\[(]\s*([^\[\]()]+?)\s*[\])]\s*$")
# units whose spelling in any case means one thing (``RPM``, ``DegC``); ``mA`` and ``MA``, ``ms`` and ``Ms``
# do not
SPELLINGS = {u.lower(): u for u in ("rpm", "rad/s", "deg/s", "rev/s", "turn/s", "degC", "degF")}


def spelled(unit: str) -> str:
    """A unit in the spelling the suite uses where its case says nothing (``RPM`` -> ``rpm``, ``DegC`` ->
    ``degC``)."""
    return SPELLINGS.get(unit.strip().lower(), unit)


def header_unit(column: str) -> str | None:
    """The unit a column's header gives at its end (``Effort [mA]`` -> ``mA``, ``Power (W)`` -> ``W``,
    ``Speed [RPM]`` -> ``rpm``), or ``None``."""
    m = _HEADER.search(str(column).partition("@")[0])
    return spelled(m.group(1)) if m else None


def base_name(column) -> str:
    """A column's name without the unit its header may carry, lower case (``Temperature [degC]`` ->
    ``temperature``)."""
    return _HEADER.sub("", str(column)).strip().lower()


def canonical_headers(columns, names) -> tuple[dict[str, str], dict[str, str]]:
    """Columns of a canonical log that carry their unit (``effort [N m]``, ``temperature (degC)``):
    ``({column: canonical name}, {canonical name: unit})``; names already present bare are left alone."""
    renames, units = {}, {}
    present = {str(c) for c in columns}
    for column in columns:
        unit = header_unit(column)
        base = _HEADER.sub("", str(column)).strip().lower() if unit else ""
        if base in names and base not in present and base not in units:
            renames[column], units[base] = base, unit
    return renames, units


def split_unit(value: str) -> tuple[str, str | None]:
    """``COLUMN:UNIT`` -> ``(COLUMN, UNIT)`` when UNIT is a known unit; otherwise the whole value is the
    column."""
    column, sep, unit = str(value).rpartition(":")
    if sep and spelled(unit) in KNOWN and column:
        return column, spelled(unit)
    return str(value), None


def channel_units(mapping: Mapping[str, str] | None, given: Mapping[str, str | None]) -> dict[str, str]:
    """The unit of each scaled channel: ``given`` (a mapping's ``:UNIT`` or an option), else the mapped
    column's header, else, for a canonical log (no mapping), the canonical unit; else :data:`NOT_GIVEN`."""
    units = {}
    for channel in SCALED:
        if given.get(channel):
            units[channel] = str(given[channel])
        elif not mapping:
            units[channel] = CANONICAL[channel]
        elif channel in mapping:
            units[channel] = header_unit(mapping[channel]) or NOT_GIVEN
        else:
            units[channel] = NOT_GIVEN
    return units
