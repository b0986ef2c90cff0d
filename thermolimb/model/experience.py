"""What a model was identified on, and where a question goes beyond it.

A model file keeps the ranges of its calibration log (``provenance["ranges"]``: the effort, velocity, ambient
and temperature it read, and its median sample interval).  A forecast whose inputs leave them asks the model
to extrapolate: :func:`beyond` says so, one sentence per input, and gives the factor the answer's model-error
band is widened by -- the heat grows with the square of the effort, so an effort ``k`` times the largest seen
widens it ``k**2``; any other input outside its range (or a log sampled more coarsely than the calibration's)
at least doubles it.  A forecast that climbs above the hottest reading the model was identified on is said to,
and its band doubled from where it does (:func:`hotter_than_seen`).

Jorgensen et al.'s offset is the ambient plus the bias heat (Eq. 5: ``T_offset = T_amb + P_bias R``), so a
model that does not read the ambient carries the air it was identified in inside its offset.  On a run whose
logged ambient lies outside that air, the offset follows it (:func:`ambient_shift_K`): a motor on a bench
whose coolant ran at 91 degC (PMSM profile 46) and then at 19 degC (profile 24) does not keep a 108 degC
offset.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Mapping

import numpy as np

from .model import ThermalModel
from .signals import Signals
from .terms import TERMS

MARGIN = 0.1  # an effort or velocity up to 10 % beyond the largest seen is within experience
MARGIN_K = 5.0  # an ambient or start temperature within 5 K of the range seen
EQ5 = "T_offset = T_amb + P_bias R, Jorgensen et al. Eq. 5"  # why the offset follows the ambient, as said
RATE_RATIO = 2.0  # a sample interval up to twice the calibration's


def beyond(ranges: Mapping | None, signals: Signals, start_C: float, reads_ambient: bool,
           effort_unit: str = "", shift_K: float = 0.0) -> tuple[list[str], float]:
    """Notes on where ``signals`` from ``start_C`` leave the calibration's ``ranges``, and the band's
    widening; ``shift_K``: how far the offset follows the ambient (:func:`ambient_shift_K`)."""
    notes, factor = [], 1.0
    if not ranges:
        return notes, factor
    for name, values, unit in (("effort", signals.effort, effort_unit),
                               ("velocity", signals.velocity, "rad/s")):
        seen = ranges.get(name)
        if values is None or not seen:
            continue
        largest, asked = max(abs(seen[0]), abs(seen[1])), float(np.max(np.abs(values)))
        if asked > (1.0 + MARGIN) * largest:
            ratio = asked / max(largest, 1e-12)
            factor = max(factor, ratio**2 if name == "effort" else 2.0)
            notes.append(f"extrapolated: the {name} reaches {asked:.3g}{(' ' + unit) if unit else ''}, "
                         f"{ratio:.2g} times the largest the model was identified on ({largest:.3g})")
    seen = ranges.get("ambient_C")
    if signals.ambient_C is not None:
        lo, hi = float(np.min(signals.ambient_C)), float(np.max(signals.ambient_C))
        # a colder or hotter air, said either way
        if seen and (lo < seen[0] - MARGIN_K or hi > seen[1] + MARGIN_K):
            factor = max(factor, 2.0)
            notes.append(f"extrapolated: the ambient ({lo:.1f} to {hi:.1f} degC) leaves the {seen[0]:.1f} to "
                         f"{seen[1]:.1f} degC the model was identified in")
        if shift_K:
            notes.append("the model does not read the ambient "
                         "temperature: its offset follows this log's mean "
                         f"ambient beyond the calibration's, {shift_K:+.1f} K ({EQ5})")
        elif not reads_ambient:
            notes.append("the model does not read the ambient temperature: "
                         "the one here changes nothing (its offset "
                         "stands for the air it was identified in)")
    seen = ranges.get("temperature_C")
    if seen and not seen[0] - MARGIN_K <= start_C <= seen[1] + MARGIN_K:
        factor = max(factor, 2.0)
        notes.append(f"extrapolated: the start, {start_C:.1f} degC, "
                     f"is outside the {seen[0]:.1f} to {seen[1]:.1f} "
                     f"degC the model's log read")
    dt = ranges.get("dt_s")
    if dt and signals.time_s.size > 1:
        own = float(np.median(np.diff(signals.time_s)))
        if own > RATE_RATIO * dt:  # a finer log only tells the model more
            factor = max(factor, 2.0)
            notes.append(f"the log is sampled every {own:.3g} s, the "
                         f"model's calibration every {dt:.3g} s: the effort "
                         f"between its readings is taken as held, which the calibration never had to")
    return notes, factor


def ambient_shift_K(model: ThermalModel, seen, ambient_C: np.ndarray | None) -> float:
    """How far ``model``'s offset moves on a run whose logged ambient is ``ambient_C``, the calibration's
    ambient having spanned ``seen`` (``[low, high]`` degC): the excursion of the run's mean ambient beyond
    that span, kelvin for kelvin, and 0 within it (the offset already holds that air: a run inside it keeps
    its model unchanged, and the shift grows from 0 as a run leaves it).  0 too for a model that reads the
    ambient itself or whose offset is no ambient (:func:`offset_is_ambient`), and without a logged ambient."""
    if (
        ambient_C is None
        or not seen
        or "T_offset_C" not in model.params
        or not offset_is_ambient(model.terms)
    ):
        return 0.0
    values = np.asarray(ambient_C, float)
    values = values[np.isfinite(values)]
    low, high = float(seen[0]), float(seen[1])
    if values.size == 0 or not (np.isfinite(low) and np.isfinite(high)):
        return 0.0
    mean = float(values.mean())
    return mean - float(np.clip(mean, low, high))


def common_air(series: list) -> tuple[list, float | None]:
    """Runs of one actuator logged in different air, each brought to their common air: where every run logs
    its ambient and the runs' mean ambients lie more than ``MARGIN_K`` apart, each run's temperatures (the
    winding's, the ambient, the housing's, the neighbours') moved by its mean ambient's excursion from the
    mean of the runs' means, kelvin for kelvin (Eq. 5: a model whose offset does not read the ambient then has
    one offset per run, following its air; one that reads the ambient sees the swings within each run).
    ``(series, reference degC)``, or the runs unchanged and ``None``."""
    means = []
    for s in series:
        values = s.signals.ambient_C
        values = None if values is None else values[np.isfinite(values)]
        if values is None or values.size == 0:
            return list(series), None
        means.append(float(values.mean()))
    if len(means) < 2 or max(means) - min(means) <= MARGIN_K:
        return list(series), None
    reference = float(np.mean(means))
    return [_moved(s, mean - reference) for s, mean in zip(series, means)], reference


def _moved(series, shift_K: float):
    s = series.signals
    moved = {name: getattr(s, name) - shift_K for name in ("ambient_C", "housing_C", "neighbor_temperature_C")
             if getattr(s, name) is not None}
    signals = replace(s, **moved, air_shift_K=s.air_shift_K + shift_K)
    return replace(series, signals=signals, temperature_C=series.temperature_C - shift_K)


def air_words(series: list, reference_C: float | None) -> str:
    """The scheme's words on runs brought to their common air (:func:`common_air`)."""
    if reference_C is None:
        return ""
    each = ", ".join(f"{s.run or f'run {k + 1}'} {reference_C + s.signals.air_shift_K:.1f}"
                     for k, s in enumerate(series))
    return ("; the runs ran in different air (mean ambient "
            f"{each} degC): each run's offset follows its own, the "
            f"one fitted is at their mean, {reference_C:.1f} degC ({EQ5})")


def offset_air(ranges) -> list[float] | None:
    """The ambient span a saved model's offset stands for: its runs' common air where they ran in different
    air (``ranges["offset_air_C"]``), else the calibration's ambient span."""
    ranges = ranges or {}
    return ranges.get("offset_air_C") or ranges.get("ambient_C")


def offset_is_ambient(terms) -> bool:
    """Whether the offset of a model of ``terms`` is the ambient plus the bias heat: no term reads the ambient
    or moves the temperature heat flows to (the housing, ambient variation, a logged temperature as a
    boundary: a generated form of a channel minus a reference temperature)."""
    for name in terms:
        term = TERMS[name]
        spec = getattr(term, "spec", None)
        if (term.redefines_offset or term.boundary or "ambient" in term.columns
                or (spec is not None and any(f.form == "minus" for f in spec.features))):
            return False
    return True


def shifted(model: ThermalModel, shift_K: float) -> ThermalModel:
    """``model`` with its offset moved by ``shift_K`` (itself when the shift is 0)."""
    if not shift_K:
        return model
    return model.with_params({**model.params, "T_offset_C": model.params["T_offset_C"] + shift_K})


def ambient_span(series) -> list[float] | None:
    """``[low, high]`` of the logged ambient over ``series`` (degC), or None unless every one logs it."""
    values = [s.signals.ambient_C for s in series]
    if not values or any(v is None for v in values):
        return None
    return [
        float(np.nanmin([np.nanmin(v) for v in values])),
        float(np.nanmax([np.nanmax(v) for v in values])),
    ]


def moved_words(moved: list[tuple[str, float]]) -> str:
    """The scheme's words on offsets that followed held-out runs' ambient (:func:`ambient_shift_K`), given
    ``(label, K)`` for each."""
    if not moved:
        return ""
    each = ", ".join(f"{label} {shift:+.1f} K" for label, shift in moved)
    return (f"; the offset followed the ambient of {len(moved)} "
            f"held-out run{'s' if len(moved) > 1 else ''} beyond "
            f"the fitted runs' ({each}; {EQ5})")


def hotter_than_seen(ranges: Mapping | None, predicted_C: np.ndarray) -> tuple[list[str], np.ndarray]:
    """A note when ``predicted_C`` climbs more than ``MARGIN_K`` above the hottest reading of the
    calibration's ``ranges``, and the band's widening per sample: 2 from where it does, 1 before (the model's
    error was measured on temperatures it saw; a 60 s answer on the way to an unseen 90 degC is not one)."""
    seen = (ranges or {}).get("temperature_C")
    hotter = np.asarray(predicted_C, float) > (seen[1] + MARGIN_K if seen else np.inf)
    if not hotter.any():
        return [], np.ones(hotter.shape)
    return (
        [
            "extrapolated: the forecast climbs to "
            f"{float(np.max(predicted_C)):.1f} degC, above the hottest reading "
            f"the model was identified on ({seen[1]:.1f} degC)"
        ],
        np.where(np.maximum.accumulate(hotter), 2.0, 1.0),
    )
