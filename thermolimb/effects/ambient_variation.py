"""An ambient that drifts and swings: the model's offset follows the logged ambient."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.terms import LinearTerm, Parameter, register_term
from .base import Effect, Hidden, PlantEffect, register

AMBIENT_REFERENCE_C = 25.0  # T_offset is the offset at this logged ambient when ambient_variation is on


@register_term
class AmbientVariationTerm(LinearTerm):
    """The offset follows the logged ambient (the base model keeps it constant)."""

    name = "ambient_variation"
    label = "ambient variation"
    description = "offset follows the logged ambient temperature"
    parameters = (
        Parameter("ambient_gain", "1", -1.0, 3.0, 1.0,
                  "kelvin of offset per kelvin of logged ambient (1 for a perfect ambient sensor)",
                  "ambient that changes during the log", plausible=(0.5, 1.5)),
    )
    columns = ("ambient",)
    boundary = True
    redefines_offset = True

    def regressor(self, s):
        return s.channel("ambient") - AMBIENT_REFERENCE_C


@dataclass(frozen=True)
class AmbientVariation(PlantEffect):
    """Ambient temperature drifting and oscillating: T_amb(t) = T0 + drift t + A sin(2 pi t / period)."""

    name = "ambient_variation"
    amplitude_K: float = 3.0
    period_s: float = 2400.0
    drift_K_per_h: float = 2.0

    def ambient_C(self, start_C, time_s):
        return float(start_C + self.drift_K_per_h * time_s / 3600.0
                     + self.amplitude_K * np.sin(2.0 * np.pi * time_s / self.period_s))


register(Effect("ambient_variation", AmbientVariationTerm, AmbientVariation, residual="ambient",
                hidden=Hidden("ambient_variation", "ambient_variation"), rides="ambient"))
