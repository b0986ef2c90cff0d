"""The hexapod's thermal limits, stated once and derived from its actuators' datasheets; everything else reads them.

Each joint's winding limit is its actuator's (HEBI's X8 vendor model: 155 degC).  The plant's protection starts
derating its margin below that; the environment's reward starts charging for heat further below, so that an
agent feels the heat before the protection takes torque away.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from thermolimb.plant import ThermalProtection

from .params import DAISY, DaisyParams

OVERHEAT_MARGIN_K = 35.0  # the reward's overheat term starts this far below the lowest winding limit (chosen)


@dataclass(frozen=True)
class ThermalLimits:
    """Per-joint winding limits (degC, JOINTS order) and the temperatures derived from them."""

    winding_C: tuple[float, ...]
    overheat_margin_K: float = OVERHEAT_MARGIN_K

    @classmethod
    def of(cls, params: DaisyParams = DAISY) -> "ThermalLimits":
        return cls(tuple(spec.winding_limit_C for spec in params.joint_actuators))

    @property
    def winding_limits_C(self) -> np.ndarray:
        return np.asarray(self.winding_C)

    @property
    def derating_from_C(self) -> np.ndarray:
        """Where the plant's protection starts derating each joint (its margin below the winding limit)."""
        return self.winding_limits_C - ThermalProtection().margin_K

    @property
    def overheat_from_C(self) -> float:
        """Where the environment's overheat penalty starts: ``overheat_margin_K`` below the lowest winding limit."""
        return float(min(self.winding_C)) - self.overheat_margin_K


LIMITS = ThermalLimits.of(DAISY)
