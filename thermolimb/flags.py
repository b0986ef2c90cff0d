"""Warnings about fitted values a user should not trust as physics.

A parameter pinned at a bound or vanishing (``betaR -> 0``: the log shows no
such heating), an offset far from any temperature the log supports, a time
constant the log is too short or too coarse to show.  Each flag is one
sentence; ``fit``, ``compare`` and ``diagnose`` print them, put them in their
JSON and on their plots.
"""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from .logs import ActuatorSeries
from .model.model import ThermalModel

OFFSET_MARGIN_K = 10.0  # an offset further than this (or half the logged range) from the reference is flagged
LONG_TIME_CONSTANT = 3.0  # a time constant longer than this many log durations is extrapolated
SHORT_TIME_CONSTANT = 0.5  # ... or shorter than this many sampling intervals is not seen
# terms after which T_offset is no longer an ambient temperature
OFFSET_REDEFINED_BY = ("housing_boundary", "ambient_variation")


def parameter_flags(model: ThermalModel, stderr: Mapping[str, float], series: Sequence[ActuatorSeries]) -> list[str]:
    """One sentence per fitted value that looks like an artefact of the log rather than physics."""
    flags = []
    duration = max(s.duration_s for s in series)
    dt = min(s.median_dt_s for s in series)
    for p in model.parameters:
        v = model.params[p.name]
        scale = abs(p.typical) if p.typical else 1.0
        if p.unit == "s":
            if v > LONG_TIME_CONSTANT * duration:
                flags.append(f"{p.name} = {v:.3g} s is longer than {LONG_TIME_CONSTANT:g}x the log ({duration:.0f} s): "
                             f"the log shows the start of a change, not its time constant")
            elif v < SHORT_TIME_CONSTANT * dt:
                flags.append(f"{p.name} = {v:.3g} s is shorter than {SHORT_TIME_CONSTANT:g} sampling intervals "
                             f"({dt:.3g} s): the log cannot show it")
            continue
        if p.lower == 0.0 and v <= 1e-6 * scale and not p.nuisance:
            flags.append(f"{p.name} vanishes ({v:.2g} {p.unit}): the log shows no effect of this term "
                         f"(identifying it needs {p.excitation})")
            continue
        for bound in (p.lower, p.upper):
            if np.isfinite(bound) and bound != 0.0 and abs(v - bound) <= 1e-4 * max(abs(bound), scale):
                flags.append(f"{p.name} = {v:.3g} {p.unit} is at its bound {bound:g}: the fit wants more than "
                             f"this term can give; another effect is missing")
    if not any(t in model.terms for t in OFFSET_REDEFINED_BY):
        flag = _offset_flag(model.params["T_offset_C"], series)
        if flag:
            flags.append(flag)
    return flags


def _offset_flag(offset_C: float, series: Sequence[ActuatorSeries]) -> str | None:
    measured = np.concatenate([s.temperature_C for s in series])
    ambient = [s.signals.ambient_C for s in series if s.signals.ambient_C is not None]
    if ambient:
        reference, what = float(np.mean(np.concatenate(ambient))), "the logged ambient"
    else:
        reference, what = float(measured.min()), "the coolest reading"
    margin = max(OFFSET_MARGIN_K, 0.5 * float(np.ptp(measured)))
    if abs(offset_C - reference) > margin:
        return (f"T_offset_C = {offset_C:.1f} degC is {abs(offset_C - reference):.0f} K from {what} "
                f"({reference:.1f} degC): other terms stand in for the heat balance, or heat flows the model lacks")
    return None
