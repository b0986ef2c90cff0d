"""The humanoid's thermal limits, stated once; everything else reads them.

Jorgensen et al.'s recovery experiment on Valkyrie: an actuator above
75 degC is in the warning zone, and the robot has recovered when every
actuator is below 70 degC; Valkyrie's actuators "can operate up to 90 degC".
The plant's protection starts derating at that operating limit, so the
winding limit it derates towards is the operating limit plus its margin.
"""

from __future__ import annotations

from thermolimb.plant import ThermalLimits, ThermalProtection

from .constants import ACTUATORS

OPERATING_C = 90.0  # Jorgensen et al.: Valkyrie's actuators can operate up to 90 degC

LIMITS = ThermalLimits((OPERATING_C + ThermalProtection().margin_K,) * len(ACTUATORS),
                       warning_C=75.0,  # Jorgensen et al.: the warning zone starts here
                       recovered_C=70.0)  # Jorgensen et al.: recovered when every actuator is below this
