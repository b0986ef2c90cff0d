"""Random piecewise-constant channels of the plant (a fan's duty, a brake, a board's load), drawn from a
seed."""

from __future__ import annotations

import numpy as np

from ..effects import Schedule


class ScheduledChannel:
    """One schedule per actuator: a level held for a random time, then another (see
    :class:`thermolimb.effects.Schedule`).

    Levels are drawn as time passes, so a schedule needs no duration; plant
    time only moves forward, and the same generator gives the same schedules.
    """

    def __init__(self, schedule: Schedule, n: int, rng: np.random.Generator):
        if not schedule.levels or not 0.0 < schedule.hold_s[0] <= schedule.hold_s[1]:
            raise ValueError(f"a schedule needs levels and 0 < hold_s[0] <= hold_s[1], got {schedule}")
        self._levels = np.asarray(schedule.levels, float)
        self._hold = schedule.hold_s
        self._rng = rng
        self._value = self._draw(n)
        self._until = rng.uniform(*self._hold, n)

    def _draw(self, k: int) -> np.ndarray:
        return self._levels[self._rng.integers(self._levels.size, size=k)]

    def at(self, time_s: float) -> np.ndarray:
        """Each actuator's level at ``time_s`` (not earlier than the last time asked)."""
        due = time_s >= self._until
        while due.any():
            self._value[due] = self._draw(int(due.sum()))
            self._until[due] += self._rng.uniform(*self._hold, int(due.sum()))
            due = time_s >= self._until
        return self._value.copy()
