"""What every real reading has: noise and a quantisation step.  The plant's thermistors apply them
(:class:`~thermolimb.plant.sensors.Thermistors`); the model has no term for them, and the diagnosis
measures them as the sensor's floor (:mod:`thermolimb.workbench.floor`)."""

from __future__ import annotations

from dataclasses import dataclass

from .base import Effect, PlantEffect, register


@dataclass(frozen=True)
class SensorNoise(PlantEffect):
    """White Gaussian noise on every temperature reading."""

    name = "sensor_noise"
    draws_random = True
    std_K: float = 0.05


@dataclass(frozen=True)
class Quantisation(PlantEffect):
    """Readings are rounded to a step."""

    name = "quantisation"
    step_K: float = 0.1


register(Effect("sensor_noise", plant=SensorNoise), Effect("quantisation", plant=Quantisation))
