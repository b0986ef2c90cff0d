"""The thermal plant: the rig's "hardware" that heats every simulated actuator.

Its effects (speed losses, copper's tempco, a lagging sensor, a fan, ...) are the plant side of
:mod:`thermolimb.effects`, re-exported here for the plant's users.
"""

from ..effects import (
                       PLANT_EFFECTS,
                       AmbientVariation,
                       EffortBias,
                       FieldWeakening,
                       MotionCooling,
                       NeighborCoupling,
                       PlantEffects,
                       Quantisation,
                       SensorLag,
                       SensorNoise,
                       SpeedLosses,
                       WindingTempco,
)
from .network import (
                       ACTUATOR_SPECS,
                       FIRST_ORDER_NETWORK,
                       NETWORKS,
                       SECOND_ORDER_NETWORK,
                       X5_NETWORK,
                       X8_9,
                       X8_16,
                       X8_NETWORK,
                       ActuatorSpec,
                       DriverSpec,
                       ThermalNetwork,
)
from .plant import ThermalPlant
from .profiles import PROFILES, Profile
from .protection import ThermalLimits, ThermalProtection
from .run import PlantRun, run_profile, run_profile_in_pieces, simulate_profile, simulate_profile_in_pieces

__all__ = [
    "ACTUATOR_SPECS",
    "ActuatorSpec",
    "AmbientVariation",
    "MotionCooling",
    "WindingTempco",
    "DriverSpec",
    "PLANT_EFFECTS",
    "FIRST_ORDER_NETWORK",
    "FieldWeakening",
    "SpeedLosses",
    "NETWORKS",
    "NeighborCoupling",
    "PROFILES",
    "PlantEffects",
    "PlantRun",
    "Profile",
    "Quantisation",
    "SECOND_ORDER_NETWORK",
    "SensorNoise",
    "EffortBias",
    "ThermalNetwork",
    "ThermalPlant",
    "ThermalLimits",
    "ThermalProtection",
    "SensorLag",
    "X5_NETWORK",
    "X8_16",
    "X8_9",
    "X8_NETWORK",
    "run_profile",
    "run_profile_in_pieces",
    "simulate_profile",
    "simulate_profile_in_pieces",
]
