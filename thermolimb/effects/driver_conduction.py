"""The driver board conducts into the winding and carries an electronics load of its own; its thermistor is
logged.  The catalog has no board: the diagnosis finds it from the log's channel (``diagnose --discover``)."""

from __future__ import annotations

from dataclasses import dataclass

from .base import Effect, PlantEffect, Schedule, register


@dataclass(frozen=True)
class DriverConduction(PlantEffect):
    """The driver board conducts into the winding (``conductance_W_per_K``) and carries an electronics load of
    its own that switches between ``schedule.levels`` (W); its thermistor is logged as ``driver [degC]``.
    Needs actuators with a driver board (:class:`~thermolimb.plant.network.DriverSpec`)."""

    name = "driver_conduction"
    draws_random = True
    conductance_W_per_K: float = 0.15
    schedule: Schedule = Schedule((0.0, 2.0, 4.0, 6.0))
    column: str = "driver [degC]"

    def check(self, specs):
        if any(spec.driver is None for spec in specs):
            raise ValueError("driver_conduction needs every actuator to have a driver board (ActuatorSpec.driver)")

    def wire(self, net):
        g = self.conductance_W_per_K
        for w, d in zip(net.winding, net.driver):
            for p, q in ((w, d), (d, w)):
                net.A[p, p] -= g * net.inv_capacity[p]
                net.A[p, q] += g * net.inv_capacity[p]

    def heat(self, net, at, constant, per_kelvin):
        constant[..., net.driver] += at.schedules["driver_load"].at(at.time_s)

    def schedules(self):
        return {"driver_load": self.schedule}

    def logged(self, plant):
        return {self.column: plant.measured_driver_C}


register(Effect("driver_conduction", plant=DriverConduction))
