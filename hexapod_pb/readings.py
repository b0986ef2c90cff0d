"""What the hexapod's controller sees each control step: the sensor data hardware gives it.

Kept apart from the simulator so that the pure controller does not import it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Reading:
    """One control step's sensor data (arrays in JOINTS / LEGS order)."""

    time_s: float
    q_rad: np.ndarray  # (18,)
    qd_rad_s: np.ndarray  # (18,)
    torque_Nm: np.ndarray  # (18,) sensed
    temperature_C: np.ndarray  # (18,) measured winding temperatures
    world_R_body: np.ndarray  # (3, 3) IMU orientation
    body_omega_rad_s: np.ndarray  # (3,) IMU angular rate, body frame
    body_velocity_m_s: np.ndarray  # (3,) velocity estimate, body frame
    body_position_m: np.ndarray  # (3,) position estimate, world frame (for logging and scenarios)
    contact_force_N: np.ndarray = field(default=None)  # (6, 3) per foot, world frame, force on the foot
