"""Heat in proportion to measured electrical input power, for benches that log power, not torque.  The plant
has no counterpart: its heat is the current's."""

from __future__ import annotations

import numpy as np

from ..model.terms import LinearTerm, Parameter, register_term
from .base import Effect, register


@register_term
class PowerHeating(LinearTerm):
    """Heat in proportion to measured electrical input power (benches that log power, not torque)."""

    name = "power_heating"
    label = "heating from electrical power"
    description = "heating in proportion to electrical input power (its losses are a share of it)"
    parameters = (
        Parameter("powerR_K_per_W", "K/({power})", 0.0, np.inf, 0.1,
                  "steady-state rise per watt of input power (loss share times thermal resistance)",
                  "power at three or more distinct levels"),
    )
    columns = ("power",)
    is_heat_source = True

    def regressor(self, s):
        return s.channel("power")


register(Effect("power_heating", PowerHeating, residual="power", rides="power"))
