"""Cooling that improves with speed: airflow while moving raises the conductance to ambient."""

from __future__ import annotations

from dataclasses import dataclass

from ..model.terms import Term, register_term
from .base import Effect, Hidden, PlantEffect, airflow_parameter, register, speed


@register_term
class MotionCoolingTerm(Term):
    """Cooling improves with speed: the loss to ambient times ``1 + h |v|``."""

    name = "motion_cooling"
    label = "cooling by motion"
    description = "cooling that improves with speed (airflow)"
    parameters = (airflow_parameter("cooling_per_rad_s", "the conductance to ambient", "warm"),)
    columns = ("velocity",)

    def forms(self, s):
        return (speed(s),)

    def combine(self, p, forms):
        h = p["cooling_per_rad_s"] * forms[0]
        return h * p["T_offset_C"], -h


@dataclass(frozen=True)
class MotionCooling(PlantEffect):
    """Airflow while moving: the outer node's conductance to ambient times (1 + gain |v|)."""

    name = "motion_cooling"
    state_dependent = True
    gain_per_rad_s: float = 0.6

    def heat(self, net, at, constant, per_kelvin):
        extra_g = net.outer_conductance * self.gain_per_rad_s * at.speed
        constant[..., net.outer] += extra_g * at.ambient_C
        per_kelvin[..., net.outer] -= extra_g


# the plant's airflow cools its outer node; on the X8 the model may place it on the housing mass
register(
    Effect(
        "motion_cooling",
        MotionCoolingTerm,
        MotionCooling,
        residual="|velocity|",
        hidden=Hidden("motion_cooling", "motion_cooling", also=("housing_motion_cooling",)),
        rides="velocity",
    )
)
