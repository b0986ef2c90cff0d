"""Channels that vary and do nothing thermal, for checking that a diagnosis does not take a channel that only
varies."""

from __future__ import annotations

from dataclasses import dataclass

from .base import Effect, PlantEffect, Schedule, register


@dataclass(frozen=True)
class DecoyChannels(PlantEffect):
    """Channels that vary and do nothing thermal: a supply voltage (``supply [V]``) and an indicator (``led [1]``).
    For checking that a diagnosis does not take a channel that only varies."""

    name = "decoy_channels"
    draws_random = True
    supply: Schedule = Schedule((23.0, 23.5, 24.0, 24.5, 25.0), hold_s=(200.0, 800.0))
    led: Schedule = Schedule((0.0, 1.0), hold_s=(120.0, 600.0))

    def schedules(self):
        return {"supply": self.supply, "led": self.led}

    def logged(self, plant):
        return {"supply [V]": plant.schedule("supply"), "led [1]": plant.schedule("led")}


register(Effect("decoy_channels", plant=DecoyChannels))
