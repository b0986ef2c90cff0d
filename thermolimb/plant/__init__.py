"""The thermal plant: the rig's "hardware" that heats every simulated actuator."""

from .effects import (EFFECT_TYPES, AmbientVariation, EffortBias, FieldWeakening, MotionCooling,
                      NeighborCoupling, PlantEffects, Quantisation, SensorLag, SensorNoise, SpeedLosses,
                      WindingTempco)
from .network import (ACTUATORS, FIRST_ORDER_NETWORK, NETWORKS, SECOND_ORDER_NETWORK, X5_NETWORK, X8_9,
                      X8_16, X8_NETWORK, ActuatorSpec, DriverSpec, ThermalNetwork)
from .plant import ThermalPlant, ThermalProtection
from .profiles import PROFILES, Profile
from .run import PlantRun, run_profile, simulate_profile

__all__ = [
    "ACTUATORS", "EFFECT_TYPES", "FIRST_ORDER_NETWORK", "NETWORKS", "PROFILES", "SECOND_ORDER_NETWORK",
    "X5_NETWORK", "X8_9", "X8_16", "X8_NETWORK", "ActuatorSpec", "AmbientVariation", "DriverSpec",
    "EffortBias", "FieldWeakening", "MotionCooling", "NeighborCoupling", "PlantEffects", "PlantRun",
    "Profile", "Quantisation", "SensorLag", "SensorNoise", "SpeedLosses", "ThermalNetwork", "ThermalPlant",
    "ThermalProtection", "WindingTempco", "run_profile", "simulate_profile",
]
