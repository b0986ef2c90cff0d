"""What a log shows a thermal model, counted directly: the effort levels it holds, and its heating and cooling
transients.  Large standard errors have two causes a user acts on differently -- a log that does not excite
the model (hold more effort levels, let it heat and cool) and a model that misses something (run ``diagnose``);
these counts, with the sensor's floor (:mod:`.floor`), tell them apart."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

LEVEL_BINS = 20  # effort levels: the effort's 1-99 % range in this many bins ...
LEVEL_SHARE = 0.02  # ... each holding at least this share of the samples
TRANSIENT_SHARE = 0.1  # a transient rises or falls by this share of the temperature range ...
MIN_TRANSIENT_K = 0.5  # ... and at least this much
MIN_LEVELS, MIN_TRANSIENTS = 3, 2  # a log with fewer does not excite the model
MAX_SAMPLES = 20_000  # transients are counted on every k-th reading of a longer run (they last many samples)


@dataclass(frozen=True)
class Excitation:
    effort_levels: int
    heating: int
    cooling: int

    @property
    def ample(self) -> bool:
        """Enough of each for the first-order model's parameters (three levels pin RC, betaR and a bias)."""
        return (self.effort_levels >= MIN_LEVELS and self.heating >= MIN_TRANSIENTS
                and self.cooling >= MIN_TRANSIENTS)

    def words(self) -> str:
        levels = f"{self.effort_levels} effort level{'s' if self.effort_levels != 1 else ''}"
        transients = "transient" if self.cooling == 1 else "transients"
        return f"{levels}, {self.heating} heating and {self.cooling} cooling {transients}"


def excitation(series) -> Excitation:
    """The counts over every run of ``series``."""
    efforts = np.concatenate([s.signals.effort for s in series])
    lo, hi = np.percentile(efforts, [1, 99])
    if hi > lo:
        counts, _ = np.histogram(np.clip(efforts, lo, hi), bins=LEVEL_BINS, range=(lo, hi))
        levels = int(np.sum(counts >= LEVEL_SHARE * efforts.size))
    else:
        levels = 1
    heating = cooling = 0
    for s in series:
        h, c = _transients(s.temperature_C)
        heating, cooling = heating + h, cooling + c
    return Excitation(levels, heating, cooling)


def _transients(temperature_C: np.ndarray) -> tuple[int, int]:
    """Rises and falls between turning points, each at least :data:`TRANSIENT_SHARE` of the range (and
    :data:`MIN_TRANSIENT_K`): a zigzag over the readings, a turn confirmed once the reading has come back by
    that much."""
    x = np.asarray(temperature_C, float)
    x = x[:: max(1, x.size // MAX_SAMPLES)]
    threshold = max(MIN_TRANSIENT_K, TRANSIENT_SHARE * float(np.ptp(x)))
    rises = falls = 0
    trend, low, high, extreme = 0, x[0], x[0], x[0]
    for v in x[1:]:
        if trend == 0:
            low, high = min(low, v), max(high, v)
            if v - low >= threshold:
                trend, extreme = 1, v
            elif high - v >= threshold:
                trend, extreme = -1, v
        elif trend == 1:
            if v > extreme:
                extreme = v
            elif extreme - v >= threshold:
                rises, trend, extreme = rises + 1, -1, v
        elif v < extreme:
            extreme = v
        elif v - extreme >= threshold:
            falls, trend, extreme = falls + 1, 1, v
    return rises + (trend == 1), falls + (trend == -1)
