"""The hexapod's 18 actuators as thermal models: their datasheets (HEBI X8-9 and X8-16, one per joint, JOINTS
order) and Jorgensen et al.'s Eq. 5 from them, for the thermal-aware distribution before the robot has a log.

The humanoid's :mod:`humanoid_pb.thermal` has the same shape: ``actuator_specs(params)`` and
``datasheet_bank(params, ambient_C)``; each robot's ``calibrate`` returns a
:class:`~thermolimb.identification.calibration.Calibration`.
"""

from __future__ import annotations

from thermolimb.model import ModelArrays
from thermolimb.plant import (
    ActuatorSpec,
    PlantEffects,
    Quantisation,
    SensorNoise,
    ThermalProtection,
    WindingTempco,
)

from .params import DAISY, DaisyParams

# the plant of the hexapod's thermal studies (calibration, endurance): copper's temperature coefficient is
# physics with a known value; the plant's speed losses are sized by choice, and on PyBullet's joint speeds
# (touch-down spikes) they make within-stride bursts no X8 datasheet supports
EFFECTS = PlantEffects(winding_tempco=WindingTempco(), sensor_noise=SensorNoise(),
                       quantisation=Quantisation())
# the measured thermistor cannot lead the winding, so protection on it never starts before the propagated
# crossing
PROTECTION = ThermalProtection(estimator="measured")


def actuator_specs(params: DaisyParams = DAISY) -> list[ActuatorSpec]:
    """One spec per joint (JOINTS order): the X8 of each leg's base, shoulder and elbow."""
    return list(params.joint_actuators)


def datasheet_bank(params: DaisyParams = DAISY, ambient_C: float = 25.0) -> ModelArrays:
    """Eq. 5 parameters of every joint's actuator, winding and housing lumped (two nodes) on the slow body."""
    return ModelArrays.from_specs(actuator_specs(params), ambient_C, lumped_nodes=2)
