"""What the gait planner may change (duty factor, foot reach, body height, pauses) and what it chooses
from."""

from __future__ import annotations

from dataclasses import dataclass, replace

from ...control import cpg
from ...params import DAISY, DaisyParams

MODES = ("walk", "stand")


@dataclass(frozen=True)
class Gait:
    """What the planner may change: duty factor, foot reach from the shoulder (m), body height (m), and the
    share of the time spent standing still (a pause after every eight strides)."""

    duty_factor: float = cpg.CPGParams().duty_factor
    foot_reach_m: float = DAISY.nominal_foot_reach_m
    body_height_m: float = DAISY.nominal_body_height_m
    pause_share: float = 0.0

    def __post_init__(self):
        if not 0.0 <= self.pause_share < 1.0:
            raise ValueError(f"pause_share is a share of the time in [0, 1), got {self.pause_share}")

    def params(self, base: DaisyParams = DAISY) -> DaisyParams:
        return replace(base, nominal_foot_reach_m=self.foot_reach_m, nominal_body_height_m=self.body_height_m)

    def cpg(self) -> cpg.CPGParams:
        """The CPG at this duty factor, its step lengthened to keep the nominal gait's planned speed."""
        nominal = cpg.CPGParams()
        step = nominal.speed_m_s * self.duty_factor * nominal.period_s
        return replace(nominal, duty_factor=self.duty_factor, step_length_m=step)


NOMINAL_GAIT = Gait()
GAIT_CHOICES = {
    "duty_factor": (0.55, 0.75),
    "foot_reach_m": (0.16, 0.19, 0.22),
    "body_height_m": (0.13, 0.16),
    "pause_share": (0.0, 0.1, 0.2),
}
