"""The hexapod's thermal limits, stated once and derived from its actuators' datasheets; everything else reads
them.

Each joint's winding limit is its actuator's (HEBI's X8 vendor model: 155 degC).  The plant's protection
starts derating its margin below that; the environment's reward starts charging for heat further below (the
warning), so that an agent feels the heat before the protection takes torque away.
"""

from __future__ import annotations

from thermolimb.plant import ThermalLimits

from .params import DAISY

# the warning (the reward's overheat term) starts this far below the lowest winding limit
OVERHEAT_MARGIN_K = 35.0

_WINDING_C = tuple(spec.winding_limit_C for spec in DAISY.joint_actuators)
LIMITS = ThermalLimits(_WINDING_C, warning_C=min(_WINDING_C) - OVERHEAT_MARGIN_K)
