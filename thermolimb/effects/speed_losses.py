"""Friction and iron losses that grow with speed: ``k1 |v| + k2 v^2``."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.terms import Parameter, Term, register_term
from .base import Effect, Hidden, PlantEffect, register, speed


@register_term
class SpeedLossesTerm(Term):
    """Friction and iron losses that grow with speed: ``k1 |v| + k2 v^2``."""

    name = "speed_losses"
    label = "speed losses"
    description = "friction and iron losses growing with speed"
    parameters = (
        Parameter("speed_K_per_rad_s", "K/({velocity})", 0.0, np.inf, 1.0,
                  "rise per unit speed (friction)", "motion at several speeds"),
        Parameter("speed2_K_per_rad2_s2", "K/({velocity})^2", 0.0, np.inf, 0.5,
                  "rise per squared speed (iron losses)", "motion at several speeds"),
    )
    columns = ("velocity",)
    rise_only = True

    def forms(self, s):
        v = speed(s)
        return v, v**2

    def combine(self, p, forms):
        return p["speed_K_per_rad_s"] * forms[0] + p["speed2_K_per_rad2_s2"] * forms[1], 0.0

    def features(self, s, temperature_C):
        return np.column_stack(self.forms(s))


@dataclass(frozen=True)
class SpeedLosses(PlantEffect):
    """Losses growing with output speed: bearing/gear friction (into the housing) and iron losses
    (winding)."""

    name = "speed_losses"
    friction_W_per_rad_s: float = 1.5  # W per rad/s of |velocity|
    iron_W_per_rad2_s2: float = 2.0  # W per (rad/s)^2

    def heat(self, net, at, constant, per_kelvin):
        constant[..., net.winding] += self.iron_W_per_rad2_s2 * at.speed**2
        constant[..., net.housing] += self.friction_W_per_rad_s * at.speed


register(Effect("speed_losses", SpeedLossesTerm, SpeedLosses, residual="|velocity|",
                hidden=Hidden("speed_losses", "speed_losses", also=("housing_friction",)), rides="velocity"))
