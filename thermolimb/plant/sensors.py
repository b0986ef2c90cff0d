"""The plant's thermistors: what a sensor on a temperature reports (noise and quantisation, as switched on),
from one stream of noise that stepping an interval at a time and advancing in blocks both read, and the
winding observer that fits these sensors."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..effects import PlantEffects
from .network import ActuatorSpec
from .observer import WindingObserver


class Thermistors:
    """The sensors of one plant: their noise and quantisation (``effects``), drawing from ``rng``."""

    def __init__(self, effects: PlantEffects, rng: np.random.Generator | None):
        self.effects = effects
        self._rng = rng
        self._unused = np.empty(0)  # drawn by a block that was cut short, read first

    def read(self, true_C: np.ndarray, noise: np.ndarray | None = None) -> np.ndarray:
        """What a thermistor on these temperatures reports (``noise``: the standard normals to use, drawn
        already)."""
        fx = self.effects
        readings = np.asarray(true_C, float)
        if fx.sensor_noise is not None:
            if noise is None:
                noise = self.standard_normal(readings.size).reshape(readings.shape)
            readings = readings + fx.sensor_noise.std_K * noise
        if fx.quantisation is not None:
            step = fx.quantisation.step_K
            # a whole number of steps, written as the step's decimals read (24.9, not 24.900000000000002)
            readings = np.round(np.round(readings / step) * step, max(0, int(np.ceil(-np.log10(step)))) + 6)
        return readings

    def standard_normal(self, count: int) -> np.ndarray:
        """The generator's next ``count`` standard normals; those a block drew but did not use come first, so
        a run reads the same noise whether it is stepped one interval at a time or in blocks."""
        taken, self._unused = self._unused[:count], self._unused[count:]
        if taken.size == count:
            return taken
        return np.concatenate([taken, self._rng.standard_normal(count - taken.size)])

    def put_back(self, noise: np.ndarray) -> None:
        """Normals a block drew but did not use: the next reads take them first."""
        self._unused = np.concatenate([np.ravel(noise), self._unused])

    def observer(self, specs: Sequence[ActuatorSpec], start_C: float) -> WindingObserver:
        """A winding observer for these sensors: their lag, and their noise and quantisation as its
        measurement noise."""
        fx = self.effects
        lag = fx.sensor_lag.time_constant_s if fx.sensor_lag is not None else None
        noise = fx.sensor_noise.std_K if fx.sensor_noise is not None else 0.0
        step = fx.quantisation.step_K if fx.quantisation is not None else 0.0
        alpha = fx.winding_tempco.alpha_per_K if fx.winding_tempco is not None else 0.0
        return WindingObserver(specs, lag, start_C, np.sqrt(noise**2 + step**2 / 12 + 0.01**2),
                               copper_alpha_per_K=alpha)
