"""Units of parameters that depend on the units of the channels they multiply (see
:mod:`thermolimb.logs.units`).

A parameter's unit is a template naming its channels, ``K/({effort})^2``;
:func:`render` puts in the units a log gives, or says a unit was not given.
"""

from __future__ import annotations

import re
from typing import Mapping

from ..util.errors import UsageError

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


# an effort's units by kind, each in its kind's first unit: a log in one is read in another of its kind
EFFORT_SCALES = ({"N m": 1.0, "Nm": 1.0, "N·m": 1.0, "mN m": 1e-3}, {"A": 1.0, "mA": 1e-3},
                 {"W": 1.0, "mW": 1e-3, "kW": 1e3}, {"N": 1.0, "kN": 1e3})


def effort_factor(model_unit: str, log_unit: str, what: str) -> float:
    """The factor that turns a log's effort in ``log_unit`` into the ``model_unit`` a model heats from: 1
    where they agree or either is not given, the ratio where both are units of one kind (mA and A), and a
    refusal in one sentence where they are not (a current and a torque).  ``what`` names the model for the
    sentence."""
    if model_unit == log_unit or NOT_GIVEN in (model_unit, log_unit) or not model_unit or not log_unit:
        return 1.0
    for kind in EFFORT_SCALES:
        if model_unit in kind and log_unit in kind:
            return kind[log_unit] / kind[model_unit]
    raise UsageError(f"{what} heats from an effort in {model_unit}; the log gives its effort in {log_unit}, "
                     f"which is no {model_unit} (a torque is no current): refit on this log's effort, or log "
                     f"the one the model was fitted on")
