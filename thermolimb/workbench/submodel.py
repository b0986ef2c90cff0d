"""The largest part of a model a log identifies: a parameter the log cannot place is held at its datasheet
value (or an offset at the logged ambient), else its term is set aside, and the report says which and why."""

from __future__ import annotations

from dataclasses import replace
from typing import Callable, Mapping, Sequence

import numpy as np

from ..identification import IdentifiabilityError
from ..logs import ActuatorSeries, LogError
from ..model.model import model_parameters
from ..model.terms import TERMS
from .carry import only_heats
from .excitation import effort_levels, own_shares

# A coefficient of heat from the effort alone whose input varies apart from the constant's and the others' by
# less than this share (excitation.own_shares) is set aside where the offset's is not (the log pins the
# offset: its effort rests or runs low; where neither is pinned, the fit's identifiability decides, and an
# offset goes to the logged ambient). On two levels the share is 0 but for the effort's noise (0.010-0.020 on
# the plant's step tests and PMSM profile 24), and a hold derated in steps is alike (0.073); the real joints
# that vary their effort hold 0.165 (the BLDC bench) and more (python benchmarks/transfer.py --sources
# ur3,wx200,bldc,pmsm,plant,step --shares)
OWN_SHARE = 0.1


def identifiable_submodel(
    fit: Callable,
    model: tuple[str, ...],
    series: Sequence[ActuatorSeries],
    hold: bool = True,
    datasheet: Mapping[str, float] | None = None,
    levels: bool = True,
):
    """``fit(model, held)`` (a :class:`~thermolimb.workbench.validation.FitReport`), narrowing the model while
    the log cannot identify a parameter; the report says how in ``set_aside``.

    * A parameter with a ``datasheet`` value (``{"RC_s": 600.0}``) that the log cannot identify, or that the
      fit leaves uncertain (standard error over half of it, or a time constant over three log durations), is
      held at that value.
    * An offset the log cannot tell from its heating (effort never low) is held at the logged ambient's mean,
      when the log has one and ``hold``.
    * Otherwise a term goes: the one owning the parameter the fit could not determine or one it cannot be
      told from, preferring a term other than the model's first heat source (on a two-level step test the
      effort bias goes, Joule heating stays).
    * Before any fit, a log holding its effort at fewer distinct levels than the offset and the coefficients
      of heat from the effort alone (:func:`within_levels`) loses such a term other than the first heat
      source: the fit cannot pin them, however small the noise that lets it return values; and one whose input
      the effort moves almost only as it moves the others' (``levels=False``: neither counted, as in a
      stability replicate, whose model the whole log's count has narrowed already).

    Raises the fit's error when none applies (the time constant without a datasheet value, an offset without
    a logged ambient, the last heat source): then nothing the model means can be identified.
    """
    datasheet = dict(datasheet or {})
    check_datasheet(datasheet, model)
    units = series[0].units if series else {}
    aside, held = [], {}
    model = within_levels(model, series, aside) if levels else model

    def hold_value(name: str, value: float, reason: str) -> None:
        held[name] = value
        parameter = next(p for p in model_parameters(model) if p.name == name)
        aside.append(
            {"parameter": name, "held_at": value, "unit": parameter.unit_in(units), "reason": reason}
        )

    while True:
        try:
            report = fit(model, dict(held))
        except IdentifiabilityError as exc:
            if exc.parameter in datasheet and exc.parameter not in held and hold:
                hold_value(exc.parameter, datasheet[exc.parameter], f"its datasheet value: {exc}")
                continue
            ambient = [s.signals.ambient_C for s in series if s.signals.ambient_C is not None]
            if exc.parameter == "T_offset_C" and hold and "T_offset_C" not in held and ambient:
                value = float(np.mean(np.concatenate(ambient)))
                hold_value("T_offset_C", value, f"held at the logged ambient's mean, {value:.2f} degC: {exc}")
                continue
            term = _term_to_set_aside(model, exc)
            if term is None:
                raise
            own = exc.parameter in {p.name for p in TERMS[term].parameters}
            what = (f"cannot identify {exc.parameter}" if own else
                    f"cannot tell {', '.join(p.name for p in TERMS[term].parameters)} from {exc.parameter}")
            aside.append(
                {"term": term, "reason": f"this log {what}; identifying {term} needs {_needs(term)}"}
            )
            model = tuple(t for t in model if t != term)
            continue
        loose = [
            (name, flag)
            for name in datasheet
            if name in report.model.params and name not in held and hold
            # uncertain, or a time constant unseen
            for flag in report.flags
            if flag.startswith(f"{name} = ")
        ]
        rest = resting_offset(series, report) if hold and "T_offset_C" not in held else None
        if rest is not None and not loose:
            hold_value("T_offset_C", *rest)
            continue
        if not loose:
            return replace(report, set_aside=tuple(aside))
        for name, flag in loose:
            hold_value(name, datasheet[name], f"its datasheet value, since the log leaves it loose: {flag}")


def resting_offset(series: Sequence[ActuatorSeries], report) -> tuple[float, str] | None:
    """Where every run of ``series`` only heats and ``report``'s fit put the offset where its flags call it
    implausible (at a bound, or far from the readings), the value to hold the offset at and why: the logged
    ambient's mean, or else the coolest run's first reading (the winding taken to start at the ambient).

    A log that never cools cannot fix the temperature the winding cools to: the offset trades with the time
    constant along the rise (on the BLDC bench's full-throttle ramp, T_offset_C 400 degC at its bound and RC_s
    342 +- 1500 s, correlation +0.99).  A run only heats where no reading falls below the run's highest so far
    by more than a twentieth of its rise (:func:`.carry.only_heats`; measured: 0.1 % and 0.7 % on the bench's
    two runs).
    """
    placed = any(f.startswith("T_offset_C = ") for f in report.flags)
    if "T_offset_C" not in report.model.params or not placed:
        return None
    if not all(map(only_heats, series)):
        return None
    falls = [(float(np.max(np.maximum.accumulate(t) - t)), float(t.max() - t[0]))
             for t in (s.temperature_C for s in series)]
    fall, rise = max(falls, key=lambda x: x[0] / x[1])
    why = (f"this log only heats (no run falls by more than {fall:.2g} K below its highest reading, of a "
           f"{rise:.0f} K rise), so it cannot fix the temperature the winding cools to, and the fit put it "
           f"where its flags say it cannot be")
    ambient = [s.signals.ambient_C for s in series if s.signals.ambient_C is not None]
    if ambient:
        value = float(np.mean(np.concatenate(ambient)))
        return value, f"held at the logged ambient's mean, {value:.2f} degC: {why}"
    value = float(min(s.temperature_C[0] for s in series))
    start = f"held at the coolest run's first reading, {value:.2f} degC, the winding taken to start at the"
    return value, f"{start} ambient: {why}"


def within_levels(model: tuple[str, ...], series: Sequence[ActuatorSeries], aside: list) -> tuple[str, ...]:
    """``model`` without the terms of heat from the effort alone (Joule heating, the effort bias) that the
    log's effort levels cannot pin, each said in ``aside``.  Held at N distinct levels
    (:func:`.excitation.effort_levels`), the effort gives N steady states, which pin the offset and N - 1 such
    coefficients at most: on a step test (rest and one hold) Joule heating and the bias are one number between
    them, and a fit that returns both owes its values to the noise in the effort (``benchmarks/transfer.py
    --sources step``, fitted on the hold at 2.0: the bias at 40 +- 76 K/(N m), the other runs missed by 63.6 K
    with it and by 8.4 K without).  More levels pin no more where the effort moves one term's input almost
    only as it moves the constant's and the others' (:func:`.excitation.own_shares` under :data:`OWN_SHARE`)
    while the offset is pinned: a hold derated in steps, all of one sign. The hold at 2.5 there, derated to
    five levels, keeps 7.3 % of the bias's input its own, and misses the other runs by 21.3 K with the bias
    and 10.4 K without.  The first heat source stays."""
    alone = [t for t in model if from_effort_alone(t)]
    primary = next((t for t in model if TERMS[t].is_heat_source), None)
    if not series or len(alone) <= 1:
        return model
    levels = effort_levels(series)
    for term in [t for t in reversed(alone) if t != primary][:max(len(alone) - max(levels - 1, 1), 0)]:
        aside.append({"term": term, "reason": f"this log holds its effort at {levels} distinct level"
                      f"{'s' if levels != 1 else ''}, which pin the "
                      f"offset and {max(levels - 1, 0)} coefficient"
                      f"{'s' if levels != 2 else ''} of heat from the "
                      f"effort alone at most; identifying {term} needs "
                      f"{_needs(term)}"})
        model = tuple(t for t in model if t != term)
    for term in [t for t in reversed(alone) if t != primary and t in model]:
        rest = [t for t in alone if t in model]
        shares = own_shares(series, rest)
        if shares is not None and shares[term] < OWN_SHARE <= shares["T_offset_C"]:
            others = ", ".join(f"{t}'s" for t in rest if t != term)
            aside.append({"term": term, "reason": "this log's effort moves the "
                                                  f"input of {term} almost only as it "
                          f"moves {others} and the offset's: "
                          f"{100 * shares[term]:.1f} % of its variation is its own, "
                          f"under the {100 * OWN_SHARE:g} % asked of a coefficient fitted beside theirs (the "
                          f"offset's: {100 * shares['T_offset_C']:.0f} "
                          f"%); identifying {term} needs {_needs(term)}"})
            model = tuple(t for t in model if t != term)
    return model


def from_effort_alone(term: str) -> bool:
    """Whether ``term`` is heat from the effort alone: it reads only the effort and moves only the rise."""
    return TERMS[term].columns == ("effort",) and TERMS[term].rise_only


def _needs(term: str) -> str:
    """What identifying ``term`` needs of a log, from its parameters' excitation."""
    return "; ".join(dict.fromkeys(p.excitation for p in TERMS[term].parameters))


def check_datasheet(datasheet: Mapping[str, float], *models: Sequence[str]) -> None:
    """Refuse a datasheet value for a parameter none of ``models`` has, or outside the parameter's bounds."""
    params = {p.name: p for model in models for p in model_parameters(tuple(model))}
    for name, value in datasheet.items():
        if name not in params:
            named = " or ".join(",".join(m) for m in models)
            raise LogError(f"--datasheet names {name}, not a parameter of model {named}; expected one of "
                           f"{', '.join(params)}")
        p = params[name]
        if not (np.isfinite(value) and p.lower <= value <= p.upper):
            raise LogError(f"--datasheet {name}={value:g} is outside what "
                           f"{name} can be ({p.lower:g} to {p.upper:g} "
                           f"{p.unit})")


def _term_to_set_aside(model: tuple[str, ...], exc: IdentifiabilityError) -> str | None:
    owners = [next((t for t in model if any(p.name == name for p in TERMS[t].parameters)), None)
              for name in (exc.parameter, *exc.partners)]
    primary = next((t for t in model if TERMS[t].is_heat_source), None)
    candidates = sorted(dict.fromkeys(o for o in owners if o is not None), key=lambda t: t == primary)
    for term in candidates:
        if any(TERMS[t].is_heat_source for t in model if t != term):
            return term
    return None
