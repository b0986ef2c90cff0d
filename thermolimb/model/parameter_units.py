"""Units of parameters that depend on the units of the channels they multiply (see
:mod:`thermolimb.logs.units`).

A parameter's unit is a template naming its channels, ``K/({effort})^2``;
:func:`render` puts in the units a log gives, or says a unit was not given.
"""

from __future__ import annotations

import re
from typing import Mapping

SCALED = ("effort", "velocity", "current", "power")  # the inputs parameters' units are built on
CANONICAL = {"effort": "N m", "velocity": "rad/s", "current": "A", "power": "W"}  # the canonical log's units
NOT_GIVEN = "unit not given"


def render(template: str, units: Mapping[str, str] | None) -> str:
    """A parameter's unit with its channels' units put in: ``K/({effort})^2`` -> ``K/(N m)^2``, ``K/mA^2``, or
    ``K/(effort: unit not given)^2``."""
    units = units or {}

    def one(m: re.Match) -> str:
        channel = m.group(1)
        unit = units.get(channel, NOT_GIVEN)
        return f"{channel.removeprefix('extra.')}: {NOT_GIVEN}" if unit == NOT_GIVEN else unit

    text = re.sub(r"\{([^{}]+)\}", one, template)
    text = re.sub(r"\(([A-Za-z%\d]+)\)", r"\1", text)  # K/(mA)^2 -> K/mA^2; K/(N m)^2 keeps its brackets
    return re.sub(r"/1(\^[\d.]+)?$", "", text) or "1"  # per dimensionless unit: K/1 -> K


def spaced(unit: str) -> str:
    """A unit to write after a number: `` K``, or nothing for a dimensionless parameter (unit ``1``)."""
    return "" if unit in ("1", "") else f" {unit}"
