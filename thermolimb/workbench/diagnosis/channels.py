"""Every channel the log carries is a candidate: the forms a heat balance allows for an extra channel ``x``.

* a heat input: ``c x``, ``c |x|`` (a channel of both signs), ``c x^2``, and
  ``c x |effort|`` (a supply voltage times a current-like effort);
* a change of the conductance to ambient: ``-h x (T - T_offset)``, the
  conductance times ``1 + h x`` (a fan's duty, a coolant's flow), which must
  stay positive over the log; and the same change on a slow mass's conductance
  in place of the winding's (a fan on the housing), where the model has that mass;
* for a temperature (a unit of degC or K, or a name saying so): a boundary
  the winding relaxes towards, ``g (x - 25 degC)`` with ``0 <= g <= 1``
  (a driver board, a coolant, a housing sensor the mapping did not name);
  a channel with no unit whose values lie in the range of the log's own
  temperatures may be one, and is tried both as a boundary and as the other forms.

Each form is a generated :class:`~thermolimb.model.terms.Term`
(:mod:`thermolimb.model.generated`) and goes through the same machinery as
a catalog effect: score test, refit of the strongest form of each channel,
held-out validation, plausibility, identifiability and confounding.
"""

from __future__ import annotations

import numpy as np

from ...logs import ActuatorSeries
from ...logs.units import CELSIUS
from ...model.generated import Feature, Spec, define, identifier, slow_masses
from ...model.parameter_units import NOT_GIVEN
from ...model.signals import EXTRA
from ...model.terms import TERMS
from .candidates import Candidate

TEMPERATURE_UNITS = CELSIUS + ("K",)
TEMPERATURE_WORDS = ("temp", "°c", "degc", "ambient", "coolant", "housing")
# a channel with no unit is temperature-like if it stays this close to the log's temperatures
TEMPERATURE_SPAN_K = 30.0
BOUNDARY_REFERENCE_C = 25.0  # a boundary's offset is the model's offset at this channel temperature
CONDUCTANCE_MARGIN = 0.98  # the conductance's multiplier may fall to 2 % of its value, never below


def is_temperature(name: str, unit: str | None) -> bool:
    """Whether a channel is a temperature, from its unit or, without one, its name."""
    if unit and unit.strip() in TEMPERATURE_UNITS:
        return True
    given = unit and unit.strip() not in ("", "1", NOT_GIVEN)
    return any(word in name.lower() for word in TEMPERATURE_WORDS) and not given


def in_temperature_range(x: np.ndarray, unit: str | None, series: list[ActuatorSeries]) -> bool:
    """A channel with no unit that takes many values, all within :data:`TEMPERATURE_SPAN_K` of the log's
    temperatures, and reaches within a third of that of them (an on/off or a small signal near 0 does not)."""
    if unit and unit not in ("", NOT_GIVEN):
        return False
    measured = np.concatenate([s.temperature_C for s in series])
    low, high = measured.min() - TEMPERATURE_SPAN_K, measured.max() + TEMPERATURE_SPAN_K
    return bool(np.unique(x[:1000]).size > 2 and x.min() >= low and x.max() <= high
                and x.max() >= measured.min() - TEMPERATURE_SPAN_K / 3)


def unused_channels(model: tuple[str, ...], series: list[ActuatorSeries]) -> list[str]:
    """Extra channels of the log that vary on every run and that no term of ``model`` reads."""
    read = {c for name in model for c in TERMS[name].columns}
    names = series[0].signals.extra.keys()
    return [n for n in names if f"extra.{n}" not in read
            and all(n in s.signals.extra and np.ptp(s.signals.extra[n]) > 0 for s in series)]


def channel_terms(channel: str, series: list[ActuatorSeries]) -> list[str]:
    """Register the forms of one extra channel as generated terms; their names, in the order above."""
    unit = series[0].units.get(f"extra.{channel}")
    x = np.concatenate([s.signals.extra[channel] for s in series])
    ident, column, template = identifier(channel), f"extra.{channel}", f"{{extra.{channel}}}"
    shown = f"`{channel}`"
    forms: list[tuple] = []
    named, ranged = is_temperature(channel, unit), in_temperature_range(x, unit, series)
    if named or ranged:
        forms.append(
            (
                "boundary",
                f"the winding relaxes towards the logged temperature {shown}",
                [
                    Feature(
                        f"{ident}_boundary_gain",
                        "1",
                        column,
                        "minus",
                        f"({channel} - 25 degC)",
                        f"the logged temperature {shown}",
                        threshold=BOUNDARY_REFERENCE_C,
                        lower=-1.0,
                        upper=2.0,
                        typical=0.3,
                        plausible=(0.0, 1.0),
                    )
                ],
                (),
                None,
            )
        )
    if not named:
        scale = float(np.max(np.abs(x))) or 1.0
        if not ranged:  # the boundary is this form, with a temperature's bounds
            forms.append(
                (
                    "heat",
                    f"heat in proportion to the logged channel {shown}",
                    [
                        Feature(
                            f"{ident}_heat_K",
                            f"K/({template})",
                            column,
                            "value",
                            channel,
                            shown,
                            typical=1.0 / scale,
                        )
                    ],
                    (),
                    None,
                )
            )
        if x.min() < 0.0 < x.max():
            forms.append(("heat_abs", f"heat in proportion to the magnitude of {shown}", [Feature(
                f"{ident}_heat_abs_K", f"K/({template})", column, "abs_power", f"|{channel}|", f"|{shown}|",
                typical=1.0 / scale)], (), None))
        if not np.allclose(x**2, x):  # an on/off channel is its own square
            forms.append(
                (
                    "heat_sq",
                    f"heat in proportion to the square of {shown}",
                    [
                        Feature(
                            f"{ident}_heat_sq_K",
                            f"K/({template})^2",
                            column,
                            "square",
                            f"{channel}^2",
                            f"{shown} squared",
                            typical=1.0 / scale**2,
                        )
                    ],
                    (),
                    None,
                )
            )
        forms.append(("heat_effort", f"heat in proportion to {shown} times the effort's magnitude", [Feature(
            f"{ident}_heat_effort_K", f"K/({template} · {{effort}})", column, "times_abs_effort",
            f"{channel} |effort|", f"{shown} times |effort|", typical=1.0 / scale)], ("effort",), None))
        lower = -CONDUCTANCE_MARGIN / x.max() if x.max() > 0 else -np.inf
        upper = CONDUCTANCE_MARGIN / -x.min() if x.min() < 0 else np.inf
        param = f"{ident}_conductance_per_unit"
        forms.append(
            (
                "conductance",
                f"the conductance to ambient changes with {shown} (a fan, a coolant)",
                [
                    Feature(
                        param,
                        f"1/({template})",
                        column,
                        "value",
                        f"{channel} (T - T_offset)",
                        f"{shown} times the rise above the offset",
                        gain=True,
                        sign=-1.0,
                        lower=lower,
                        upper=upper,
                        typical=0.1 / scale,
                    )
                ],
                (),
                (param, float(x.min()), float(x.max())),
            )
        )
        # offered where the model has that mass (the term requires it)
        for mass, words in slow_masses().items():
            param = f"{ident}_{mass}_conductance_per_unit"
            forms.append((f"{mass}_conductance", f"the conductance of {words} to "
                                                 f"ambient changes with {shown} (a fan "
                          f"on the housing)", [Feature(
                              param, f"1/({template})", column, "value", f"{channel} on {mass}",
                              f"{shown} on the conductance of {words}", lower=lower, upper=upper,
                              typical=0.1 / scale)], (), (param, float(x.min()), float(x.max())), mass))
    names = []
    for form, description, features, needs, conductance, *mass in forms:  # *mass: a slow mass's conductance
        name = f"{ident}_{form}"
        define(Spec(name, description, needs + (column,), tuple(features), conductance, *mass))
        names.append(name)
    return names


def channel_candidates(model: tuple[str, ...], train: list[ActuatorSeries],
                       every: list[ActuatorSeries]) -> list[Candidate]:
    """The changes a log's extra channels offer ``model``: the forms of every extra channel it does not read
    (present on ``every`` run, varying on the ``train`` ones), and for each form the model has taken, the same
    channel's other forms in its place (the score test that chose it among them is local: on the held-out data
    another may carry over better)."""
    out = []
    for channel in unused_channels(model, train):
        if not all(channel in s.signals.extra for s in every):
            continue
        unit = train[0].units.get(f"extra.{channel}") or NOT_GIVEN
        for name in channel_terms(channel, train):
            # a slow mass's conductance without the mass: the mass comes with it, when all it needs is in the
            # model
            brings = tuple(r for r in TERMS[name].requires if r not in model)
            if not all(q in model for b in brings for q in TERMS[b].requires):
                continue
            out.append(Candidate(name, model + brings + (name,), kind="channel", channel=channel,
                                 channel_unit=unit, source=TERMS[name].source, brings=brings))
    for taken in model:
        channel = next((c.removeprefix(EXTRA) for c in TERMS[taken].columns if c.startswith(EXTRA)), None)
        if (not TERMS[taken].generated or channel is None
                or not all(channel in s.signals.extra for s in every)):
            continue
        forms = channel_terms(channel, train)
        for name in forms if taken in forms else ():  # a channel's form, not a discovered form that reads it
            if name not in model and all(r in model for r in TERMS[name].requires):
                out.append(Candidate(name, tuple(name if t == taken else t for t in model), kind="swap",
                                     replaces=taken, channel=channel, source=TERMS[name].source))
    return out
