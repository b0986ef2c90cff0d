"""The sensor's floor: the smallest validation error a log can resolve, and when a model has reached it.

Two things bound how well any model can follow a thermistor's readings:

* **quantisation**: readings on a grid of step ``q`` (0.1 degC, 0.125 degC,
  whole degrees) carry a rounding error of standard deviation ``q / sqrt(12)``;
* **noise**: readings that jitter from sample to sample; estimated from the
  second differences of the model's residual (measured less simulated:
  what the readings do that the model does not follow), which cancel a
  slowly varying misfit's trend and slope and leave ``6 sigma^2`` of white
  noise (a median absolute deviation, so that the few samples where a
  fast winding jumps do not count).  Without a residual, the readings' own
  second differences (which also count fast heating as noise).

The floor is the larger of the two.  When a model's validation error is
within :data:`FLOOR_FACTOR` of it, what is left is mostly the sensor: effects
that would change the error by hundredths of a kelvin cannot be told apart,
and the diagnosis recommends nothing and says so.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..util.numbers import places3

# a validation error within this of the floor (an excess error below 0.75 floors) is at it
FLOOR_FACTOR = 1.25
GRID_SHARE = 0.95  # readings on the same grid for it to be a quantisation step
MAD_TO_SIGMA = 1.4826  # a normal distribution's standard deviation over its median absolute deviation


@dataclass(frozen=True)
class SensorFloor:
    """What the readings can resolve (K): their quantisation step (0 when none), its rounding error, the
    high-frequency noise, and the floor (the larger)."""

    step_K: float
    quantisation_K: float
    noise_K: float

    @property
    def floor_K(self) -> float:
        return max(self.quantisation_K, self.noise_K)

    @property
    def kind(self) -> str:
        return "quantisation" if self.quantisation_K >= self.noise_K else "noise"

    def reached(self, rmse_K: float) -> bool:
        """Whether a validation error is within :data:`FLOOR_FACTOR` of the floor (a floor of 0 is never
        reached)."""
        return self.floor_K > 0 and rmse_K <= FLOOR_FACTOR * self.floor_K

    def sentence(self, rmse_K: float) -> str:
        floor = places3(self.floor_K)
        what = (
            f"a {floor} K quantisation floor ({self.step_K:.3g} degC steps)"
            if self.kind == "quantisation"
            else f"a {floor} K noise floor (the readings' sample-to-sample noise)"
        )
        if self.reached(rmse_K):
            return f"validation RMSE {rmse_K:.3f} K against {what}: nothing more can be told apart here"
        return f"validation RMSE {rmse_K:.3f} K against {what}"

    def to_json(self, rmse_K: float) -> dict:
        return {"step_K": self.step_K, "quantisation_K": self.quantisation_K, "noise_K": self.noise_K,
                "floor_K": self.floor_K, "kind": self.kind, "factor": FLOOR_FACTOR,
                "reached": self.reached(rmse_K), "sentence": self.sentence(rmse_K)}


def quantisation_step(readings: np.ndarray) -> float:
    """The grid step of the readings (the smallest change between two readings, when at least
    :data:`GRID_SHARE` of them lie on a grid of it), or 0."""
    x = np.asarray(readings, float)
    changes = np.abs(np.diff(x))
    changes = changes[changes > 1e-9]
    if changes.size == 0:
        return 0.0
    step = float(np.min(changes))
    if step < 1e-4:
        return 0.0
    units = (x - x[0]) / step
    on_grid = np.abs(units - np.round(units)) < 1e-3
    return step if float(np.mean(on_grid)) >= GRID_SHARE else 0.0


def high_frequency_noise_K(readings: np.ndarray) -> float:
    """White noise of the readings from their second differences (module docstring)."""
    x = np.asarray(readings, float)
    if x.size < 5:
        return 0.0
    second = np.diff(x, 2)
    return float(MAD_TO_SIGMA * np.median(np.abs(second - np.median(second))) / np.sqrt(6.0))


def sensor_floor(series, residuals=None) -> SensorFloor:
    """The floor of the readings of every run in ``series`` (the coarsest step and the largest noise);
    ``residuals``: a model's residual per run (measured less simulated, K), whose noise is the readings'."""
    steps = [quantisation_step(s.temperature_C) for s in series]
    step = max(steps) if all(steps) else 0.0
    noisy = residuals if residuals is not None else [s.temperature_C for s in series]
    noise = max(high_frequency_noise_K(r) for r in noisy)
    return SensorFloor(step, step / np.sqrt(12.0), noise)
