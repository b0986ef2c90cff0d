"""Joule heat from the measured current, which also sees current that makes no torque.

The plant makes such current by field weakening: above a base speed the drive adds d-axis current,
``i_d = k (|v| - v_base)``, which heats the winding and makes no torque, so heat from effort alone misses it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.terms import LinearTerm, Parameter, register_term
from .base import Effect, Hidden, PlantEffect, register


@register_term
class CurrentHeating(LinearTerm):
    """Joule heat from the measured current, which also sees current that makes no torque."""

    name = "current_heating"
    label = "Joule heating from current"
    description = "Joule heating from measured current squared"
    parameters = (
        Parameter("currentR_K_per_A2", "K/({current})^2", 0.0, np.inf, 0.01,
                  "steady-state rise per squared ampere (R_e * R_thermal)",
                  "current at three or more distinct levels"),
    )
    columns = ("current",)
    is_heat_source = True
    squared_channel = "current"

    def regressor(self, s):
        return s.channel("current") ** 2


@dataclass(frozen=True)
class FieldWeakening(PlantEffect):
    """Current that makes no torque: d-axis current above a base speed, i_d = k (|v| - v_base)."""

    name = "field_weakening"
    base_speed_rad_s: float = 0.8
    current_A_per_rad_s: float = 1.5

    def extra_current_A(self, speed, share):
        # thermal protection caps the whole current; the motor then falls short of that speed, which this
        # kinematic plant does not model
        return self.current_A_per_rad_s * np.maximum(speed - self.base_speed_rad_s, 0.0) * share


register(Effect("current_heating", CurrentHeating, FieldWeakening, residual="current^2",
                hidden=Hidden("field_weakening", "field_weakening"), rides="current"))
