"""The physical effects the suite knows: one module each, holding the model's term, the residual's sign of it,
the plant's realisation and the plant log that hides it (:mod:`.base`).

``EFFECTS[name]`` is everything about one effect, by its catalog name; ``PLANT_EFFECTS`` the plant's switches.
The modules are imported in :data:`MODULES`' order, which is the catalog's order (the order changes are tried
in) and the order the plant applies its effects in.  A new effect is one module here, its name in
:data:`MODULES`, and its tests (``docs/architecture.md``).
"""

from importlib import import_module

# the catalog's order (the order changes are tried in, and the plant applies its effects in), then the plant's
# effects that have no term; imported one by one in this order (an import sorter must not reorder them)
MODULES = (
    "joule",
    "effort_bias",
    "current_heating",
    "power_heating",
    "housing_boundary",
    "winding_tempco",
    "speed_losses",
    "neighbor_coupling",
    "ambient_variation",
    "motion_cooling",
    "slow_masses",
    "sensor_lag",
    "readings",
    "logged_channels",
)
for _module in MODULES:
    import_module(f"{__name__}.{_module}")

from .ambient_variation import AmbientVariation  # noqa: E402
from .base import (  # noqa: E402
    EFFECTS,
    HOT_AND_COOL,
    ONSETS,
    PHASES,
    PLANT_EFFECTS,
    SLOW_DRIFT,
    Effect,
    Hidden,
    PlantEffect,
    PlantEffects,
    Schedule,
)
from .current_heating import FieldWeakening  # noqa: E402
from .effort_bias import EffortBias  # noqa: E402
from .logged_channels import DecoyChannels, DriverConduction, FanCooling, HoldingBrake  # noqa: E402
from .motion_cooling import MotionCooling  # noqa: E402
from .neighbor_coupling import NeighborCoupling  # noqa: E402
from .readings import Quantisation, SensorNoise  # noqa: E402
from .sensor_lag import SensorLag  # noqa: E402
from .speed_losses import SpeedLosses  # noqa: E402
from .winding_tempco import WindingTempco  # noqa: E402

__all__ = [
    "EFFECTS",
    "HOT_AND_COOL",
    "MODULES",
    "ONSETS",
    "PHASES",
    "PLANT_EFFECTS",
    "SLOW_DRIFT",
    "AmbientVariation",
    "DecoyChannels",
    "DriverConduction",
    "Effect",
    "EffortBias",
    "FanCooling",
    "FieldWeakening",
    "Hidden",
    "HoldingBrake",
    "MotionCooling",
    "NeighborCoupling",
    "PlantEffect",
    "PlantEffects",
    "Quantisation",
    "Schedule",
    "SensorLag",
    "SensorNoise",
    "SpeedLosses",
    "WindingTempco",
]
