"""What the humanoid's controller sees each control step: the sensor data hardware gives it.

Kept apart from the simulator so that the pure controller does not import it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Reading:
    """One control step's sensor data: encoders, torque sensing, measured temperatures, IMU, foot forces."""

    time_s: float
    q_rad: np.ndarray  # (23,) JOINTS order
    qd_rad_s: np.ndarray
    torque_Nm: np.ndarray  # sensed joint torques
    temperature_C: np.ndarray  # (23,) ACTUATORS order, measured
    base_position_m: np.ndarray  # pelvis, world (state estimate)
    base_quaternion_xyzw: np.ndarray
    base_velocity_m_s: np.ndarray  # world
    base_omega_rad_s: np.ndarray  # world
    foot_force_N: np.ndarray  # (2, 3) ground force on each foot, world


def roll_pitch_rad(quaternion_xyzw: np.ndarray) -> tuple[float, float]:
    """Roll and pitch (rad) of a base orientation, Z-Y-X (yaw, pitch, roll) convention."""
    x, y, z, w = np.asarray(quaternion_xyzw, float)
    roll = np.arctan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2.0 * (w * y - z * x), -1.0, 1.0))
    return float(roll), float(pitch)
