"""The inputs a thermal model sees for one actuator, as plain arrays."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Signals:
    """Time series of one actuator, sampled at ``time_s``.

    Inputs are held constant over each sample interval (zero-order hold).
    Optional channels are ``None`` when the log does not have them.
    """

    time_s: np.ndarray
    effort: np.ndarray  # N m (rotary) or N (linear)
    velocity: np.ndarray | None = None  # rad/s or m/s
    current_A: np.ndarray | None = None
    ambient_C: np.ndarray | None = None
    neighbor_temperature_C: np.ndarray | None = None  # (n, m): the other actuators' measured temperatures
    neighbor_names: tuple[str, ...] = field(default=())

    def __post_init__(self):
        n = self.time_s.shape[0]
        for name in ("effort", "velocity", "current_A", "ambient_C", "neighbor_temperature_C"):
            value = getattr(self, name)
            if value is not None and value.shape[0] != n:
                raise ValueError(f"Signals.{name} has {value.shape[0]} samples, time_s has {n}")

    @property
    def n(self) -> int:
        return int(self.time_s.shape[0])

    @property
    def dt_s(self) -> np.ndarray:
        """Interval lengths, ``n - 1`` of them."""
        return np.diff(self.time_s)

    def channel(self, name: str) -> np.ndarray:
        """A channel by its log column name, with an error naming what is missing."""
        attr = {
            "effort": "effort",
            "velocity": "velocity",
            "current": "current_A",
            "ambient": "ambient_C",
            "neighbors": "neighbor_temperature_C",
        }[name]
        value = getattr(self, attr)
        if value is None:
            raise KeyError(f"this model needs the '{name}' column, which the log does not have")
        return value

    def slice(self, start: int, stop: int) -> "Signals":
        def cut(x):
            return None if x is None else x[start:stop]

        return Signals(
            time_s=self.time_s[start:stop],
            effort=self.effort[start:stop],
            velocity=cut(self.velocity),
            current_A=cut(self.current_A),
            ambient_C=cut(self.ambient_C),
            neighbor_temperature_C=cut(self.neighbor_temperature_C),
            neighbor_names=self.neighbor_names,
        )
