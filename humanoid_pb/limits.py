"""The humanoid's thermal limits, stated once; everything else reads them.

Jorgensen et al.'s recovery experiment on Valkyrie: an actuator above
75 degC is in the warning zone, and the robot has recovered when every
actuator is below 70 degC; Valkyrie's actuators "can operate up to 90 degC".
The plant's protection starts derating at that operating limit, so the
winding limit it derates towards is the operating limit plus its margin.
"""

from __future__ import annotations

from dataclasses import dataclass

from thermolimb.plant import ThermalProtection


@dataclass(frozen=True)
class ThermalLimits:
    """Temperatures (degC) the experiment, the environment, the planner and the plant's sizing read."""

    warning_C: float = 75.0  # Jorgensen et al.: the warning zone starts here
    recovered_C: float = 70.0  # Jorgensen et al.: recovered when every actuator is below this
    operating_C: float = 90.0  # Jorgensen et al.: Valkyrie's actuators can operate up to 90 degC

    @property
    def winding_C(self) -> float:
        """The winding limit: the operating limit plus the protection's margin, so derating starts at 90 degC."""
        return self.operating_C + ThermalProtection().margin_K

    @property
    def still_hot_C(self) -> float:
        """Above this an actuator has still to recover (the thermal potential weighs it more): the recovered level."""
        return self.recovered_C


LIMITS = ThermalLimits()
