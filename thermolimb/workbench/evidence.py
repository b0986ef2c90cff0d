"""How much a held-out verdict rests on: validation samples, their span in time constants, distinct readings.

Every fit, comparison and recommendation states it.  Below ``MIN_SAMPLES_TO_RANK``
held-out samples nothing is ranked or recommended (a handful of readings
cannot tell two models apart); below ``THIN_SAMPLES`` samples, or when the
held-out data span less than ``THIN_TIME_CONSTANTS`` of the model's time
constant (they show the start of a response, not the response), the verdict is
given with a warning.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..util.numbers import significant

MIN_SAMPLES_TO_RANK = 10
THIN_SAMPLES = 30
THIN_TIME_CONSTANTS = 1.0


@dataclass(frozen=True)
class Evidence:
    """What the validation of one fit holds."""

    samples: int
    span_s: float
    time_constant_s: float
    readings_C: np.ndarray = field(repr=False, compare=False)  # the held-out readings

    @classmethod
    def of(cls, segments, time_constant_s: float) -> "Evidence":
        measured = np.concatenate([s.measured_C for s in segments]) if segments else np.array([])
        return cls(samples=int(measured.size),
                   span_s=float(sum(s.time_s[-1] - s.time_s[0] for s in segments if s.time_s.size)),
                   time_constant_s=float(time_constant_s), readings_C=measured)

    @cached_property
    def distinct_readings(self) -> int:
        """How many different values the held-out readings take: counted when said (a sort of every held-out
        reading, 0.4 s of a 6 M-row log's diagnosis when each replicate's evidence counted them unsaid)."""
        return int(np.unique(self.readings_C).size)

    @property
    def time_constants(self) -> float:
        return self.span_s / self.time_constant_s if self.time_constant_s > 0 else float("inf")

    @property
    def rankable(self) -> bool:
        """Enough held-out samples to rank models or recommend a change at all."""
        return self.samples >= MIN_SAMPLES_TO_RANK

    @property
    def thin(self) -> bool:
        return self.samples < THIN_SAMPLES or self.time_constants < THIN_TIME_CONSTANTS

    @property
    def verdict(self) -> str:
        return "too thin" if not self.rankable else "thin" if self.thin else "enough"

    def sentence(self) -> str:
        """``evidence: 6 validation samples over 31 s (1.2 time constants of RC_s = 25.7 s), 3 distinct
        readings: too thin to rank ...``"""
        head = (f"evidence: {self.samples} validation samples over {significant(self.span_s, 3)} s "
                f"({self.time_constants:.1f} time constants of "
                f"RC_s = {significant(self.time_constant_s, 3)} s), "
                f"{self.distinct_readings} distinct readings")
        if not self.rankable:
            return (f"{head}: too thin to rank models or recommend a change (at least {MIN_SAMPLES_TO_RANK} "
                    f"held-out samples needed; a longer log, or a larger --split share held out)")
        reasons = []
        if self.samples < THIN_SAMPLES:
            reasons.append(f"fewer than {THIN_SAMPLES} samples")
        if self.time_constants < THIN_TIME_CONSTANTS:
            reasons.append(f"less than {THIN_TIME_CONSTANTS:g} time constant")
        if reasons:
            return f"{head}: thin ({' and '.join(reasons)}), so treat the ranking as a hint"
        return head

    def to_json(self) -> dict:
        return {"validation_samples": self.samples, "validation_span_s": self.span_s,
                "time_constant_s": self.time_constant_s, "time_constants": self.time_constants,
                "distinct_readings": self.distinct_readings, "verdict": self.verdict,
                "min_samples_to_rank": MIN_SAMPLES_TO_RANK, "thin_below_samples": THIN_SAMPLES,
                "thin_below_time_constants": THIN_TIME_CONSTANTS, "sentence": self.sentence()}
