"""The physical effects the suite knows: one module each, holding the model's term, the residual's sign of it,
the plant's realisation and the plant log that hides it (:mod:`.base`).

``EFFECTS[name]`` is everything about one effect, by its catalog name; ``PLANT_EFFECTS`` the plant's switches.
The modules are imported in the order below, which is the catalog's order (the order changes are tried
in) and the order the plant applies its effects in.  A new effect is one module here, its name in
the import list below, and its tests (``docs/architecture.md``).
"""

# in this order: the catalog's, then the plant's effects that have no term
from . import (  # noqa: F401
               ambient_variation,
               current_heating,
               decoy_channels,
               driver_conduction,
               effort_bias,
               fan_cooling,
               holding_brake,
               housing_boundary,
               joule,
               motion_cooling,
               neighbor_coupling,
               power_heating,
               readings,
               sensor_lag,
               slow_masses,
               speed_losses,
               winding_tempco,
)
from .ambient_variation import AmbientVariation
from .base import (
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
from .current_heating import FieldWeakening
from .decoy_channels import DecoyChannels
from .driver_conduction import DriverConduction
from .effort_bias import EffortBias
from .fan_cooling import FanCooling
from .holding_brake import HoldingBrake
from .motion_cooling import MotionCooling
from .neighbor_coupling import NeighborCoupling
from .readings import Quantisation, SensorNoise
from .sensor_lag import SensorLag
from .speed_losses import SpeedLosses
from .winding_tempco import WindingTempco

__all__ = ["EFFECTS", "AmbientVariation", "DecoyChannels", "DriverConduction", "Effect", "EffortBias", "FanCooling",
           "FieldWeakening", "HOT_AND_COOL", "Hidden", "HoldingBrake", "MotionCooling", "NeighborCoupling", "ONSETS", "PHASES", "PLANT_EFFECTS", "SLOW_DRIFT",
           "PlantEffect", "PlantEffects", "Quantisation", "Schedule", "SensorLag", "SensorNoise", "SpeedLosses",
           "WindingTempco"]
