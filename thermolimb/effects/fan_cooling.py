"""A fan whose logged duty raises the conductance to ambient.  The catalog has no fan: the diagnosis finds it
from the log's channel (``diagnose --discover``)."""

from __future__ import annotations

from dataclasses import dataclass

from .base import Effect, PlantEffect, Schedule, register


@dataclass(frozen=True)
class FanCooling(PlantEffect):
    """A fan whose duty (logged as ``fan [%]``) multiplies the outer node's conductance to ambient by
    ``1 + gain * duty``.  The model's catalog has no fan: its one channel is the logged duty."""

    name = "fan_cooling"
    draws_random = True
    gain: float = 1.0
    schedule: Schedule = Schedule((0.0, 0.25, 0.5, 0.75, 1.0))
    column: str = "fan [%]"
    scale: float = 100.0  # logged value per unit of duty

    def heat(self, net, at, constant, per_kelvin):
        extra_g = net.outer_conductance * self.gain * at.schedules["fan"].at(at.time_s)
        constant[..., net.outer] += extra_g * at.ambient_C
        per_kelvin[..., net.outer] -= extra_g

    def schedules(self):
        return {"fan": self.schedule}

    def logged(self, plant):
        return {self.column: self.scale * plant.schedule("fan")}


register(Effect("fan_cooling", plant=FanCooling))
