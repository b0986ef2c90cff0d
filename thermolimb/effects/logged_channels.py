"""Effects the catalog has no term for, each logging a channel of its own: a fan's duty, a holding brake's
state, a driver board's temperature, and channels that vary and do nothing thermal.  The diagnosis finds the
first three from the log's channels (``diagnose --discover``) and must leave the decoys alone."""

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
            raise ValueError("driver_conduction needs every actuator to "
                             "have a driver board (ActuatorSpec.driver)")

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



@dataclass(frozen=True)
class DecoyChannels(PlantEffect):
    """Channels that vary and do nothing thermal: a supply voltage (``supply [V]``) and an indicator (``led
    [1]``). For checking that a diagnosis does not take a channel that only varies."""

    name = "decoy_channels"
    draws_random = True
    supply: Schedule = Schedule((23.0, 23.5, 24.0, 24.5, 25.0), hold_s=(200.0, 800.0))
    led: Schedule = Schedule((0.0, 1.0), hold_s=(120.0, 600.0))

    def schedules(self):
        return {"supply": self.supply, "led": self.led}

    def logged(self, plant):
        return {"supply [V]": plant.schedule("supply"), "led [1]": plant.schedule("led")}



register(
    *(Effect(cls.name, plant=cls) for cls in (FanCooling, HoldingBrake, DriverConduction, DecoyChannels))
)
