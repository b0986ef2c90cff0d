"""A holding brake whose coil heats the winding while engaged; its state is logged.  The catalog has no brake:
the diagnosis finds it from the log's channel (``diagnose --discover``)."""

from __future__ import annotations

from dataclasses import dataclass

from .base import Effect, PlantEffect, Schedule, register


@dataclass(frozen=True)
class HoldingBrake(PlantEffect):
    """A holding brake whose coil heats the winding while engaged (logged as ``brake [1]``, 1 engaged)."""

    name = "holding_brake"
    draws_random = True
    coil_W: float = 3.0
    schedule: Schedule = Schedule((0.0, 1.0), hold_s=(120.0, 600.0))
    column: str = "brake [1]"
    scale: float = 1.0

    def heat(self, net, at, constant, per_kelvin):
        constant[..., net.winding] += self.coil_W * at.schedules["brake"].at(at.time_s)

    def schedules(self):
        return {"brake": self.schedule}

    def logged(self, plant):
        return {self.column: self.scale * plant.schedule("brake")}


register(Effect("holding_brake", plant=HoldingBrake))
