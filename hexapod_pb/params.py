"""Physical parameters of the Daisy-like hexapod (frozen; SI units in the names).

Provenance of every number is in ``urdf/README.md``; in short: mounting angles,
radial offsets, link lengths, actuator masses and limits are HEBI's published
Daisy/X-series numbers (``shared/reference/facts.md``); the base-to-shoulder
bracket, link-tube and bracket masses are chosen here so that the legs weigh
135 N and the body 75 N, as in Nair et al..
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from thermolimb.constants import GRAVITY_M_S2
from thermolimb.plant import X8_9, X8_16, ActuatorSpec

from .constants import JOINT_KINDS, LEGS

LINK_AXIAL_INERTIA_KG_M2 = 1e-4  # each leg link about its own long axis (thin tubes)
FALLEN_BODY_HEIGHT_M = 0.08  # the body below this height: the robot has fallen
SETTLE_S = 0.5  # standing still after a reset, before a run is measured


@dataclass(frozen=True)
class DaisyParams:
    mount_yaw_deg: tuple[float, ...] = (30.0, -30.0, 90.0, -90.0, 150.0, -150.0)  # per leg, in LEGS order
    mount_radius_m: tuple[float, ...] = (0.2375, 0.2375, 0.1875, 0.1875, 0.2375, 0.2375)
    bracket_m: float = 0.05  # base-yaw axis to shoulder axis (chosen)
    upper_link_m: float = 0.325
    lower_link_m: float = 0.325
    foot_radius_m: float = 0.025  # rounded "mushroom" foot
    body_mass_kg: float = 75.0 / GRAVITY_M_S2
    body_size_m: tuple[float, float, float] = (0.50, 0.32, 0.10)
    x8_9_mass_kg: float = 0.480
    x8_16_mass_kg: float = 0.500
    foot_mass_kg: float = 0.060
    bracket_mass_kg: float = 0.20  # chosen: bracket between base and shoulder actuators
    upper_tube_mass_kg: float = 0.30  # chosen: link tube, shoulder to elbow
    lower_tube_mass_kg: float = 0.2736  # chosen so that one leg weighs 135 N / 6
    # the actuator of each joint kind (JOINT_KINDS order: base, shoulder, elbow): HEBI's X8 datasheets,
    # written once in thermolimb.plant; effort and velocity limits and continuous efforts (Nair et al.'s
    # 8/16/8 N m) come from them
    actuators: tuple[ActuatorSpec, ActuatorSpec, ActuatorSpec] = (X8_9, X8_16, X8_9)
    nominal_body_height_m: float = 0.16  # body centre above the ground when standing
    # horizontal distance shoulder axis -> foot (feet 0.46-0.51 m from the centre)
    nominal_foot_reach_m: float = 0.22

    def __post_init__(self):
        if len(self.mount_yaw_deg) != len(LEGS) or len(self.mount_radius_m) != len(LEGS):
            raise ValueError(f"DaisyParams needs one mount angle and radius per leg ({len(LEGS)})")
        if len(self.actuators) != len(JOINT_KINDS):
            raise ValueError(f"DaisyParams needs one actuator per joint kind ({', '.join(JOINT_KINDS)})")
        positive = (
            "bracket_m",
            "upper_link_m",
            "lower_link_m",
            "foot_radius_m",
            "body_mass_kg",
            "x8_9_mass_kg",
            "x8_16_mass_kg",
            "foot_mass_kg",
            "nominal_body_height_m",
            "nominal_foot_reach_m",
        )
        bad = [n for n in positive if not getattr(self, n) > 0]
        if bad:
            raise ValueError(f"DaisyParams: {', '.join(bad)} must be positive")
        reach = np.hypot(self.nominal_foot_reach_m, self.nominal_body_height_m)
        if reach >= self.upper_link_m + self.lower_link_m:
            raise ValueError("DaisyParams: the nominal stance needs a "
                             f"reach of {reach:.3f} m, more than the leg's "
                             f"{self.upper_link_m + self.lower_link_m:.3f} m")

    @property
    def leg_mass_kg(self) -> float:
        return (self.x8_9_mass_kg * 2 + self.x8_16_mass_kg + self.foot_mass_kg + self.bracket_mass_kg
                + self.upper_tube_mass_kg + self.lower_tube_mass_kg)

    def segments(self) -> tuple[tuple[float, float, float], ...]:
        """``(mass_kg, com_m, inertia_kg_m2)`` of the base bracket, upper and lower links.

        Each is an actuator (a point mass at the joint, about a 10 cm body) plus
        a uniform tube; ``com_m`` is measured from the segment's joint along it.
        """
        return (_segment(self.x8_9_mass_kg, self.bracket_mass_kg, self.bracket_m),
                _segment(self.x8_16_mass_kg, self.upper_tube_mass_kg, self.upper_link_m),
                _segment(self.x8_9_mass_kg, self.lower_tube_mass_kg, self.lower_link_m))

    @property
    def foot_inertia_kg_m2(self) -> float:
        """The foot, a solid sphere, about any axis through its centre."""
        return 2.0 / 5.0 * self.foot_mass_kg * self.foot_radius_m**2

    @property
    def robot_mass_kg(self) -> float:
        return self.body_mass_kg + len(LEGS) * self.leg_mass_kg

    @property
    def robot_weight_N(self) -> float:
        return self.robot_mass_kg * GRAVITY_M_S2

    def mount_position_m(self, leg: int) -> np.ndarray:
        a = np.radians(self.mount_yaw_deg[leg])
        r = self.mount_radius_m[leg]
        return np.array([r * np.cos(a), r * np.sin(a), 0.0])

    def mount_yaw_rad(self, leg: int) -> float:
        return float(np.radians(self.mount_yaw_deg[leg]))

    @property
    def joint_actuators(self) -> tuple[ActuatorSpec, ...]:
        """The actuator of every joint, in JOINTS order (18: base X8-9, shoulder X8-16, elbow X8-9 for every
        leg)."""
        return tuple(self.actuators) * len(LEGS)

    @property
    def effort_limit_Nm(self) -> np.ndarray:
        """Peak effort per joint, in JOINTS order."""
        return np.array([spec.effort_limit for spec in self.joint_actuators])

    @property
    def continuous_effort_Nm(self) -> np.ndarray:
        """What each joint's actuator holds indefinitely, in JOINTS order (Nair et al.'s normalising
        torques)."""
        return np.array([spec.continuous_effort for spec in self.joint_actuators])


def _segment(actuator_kg: float, tube_kg: float, length_m: float) -> tuple[float, float, float]:
    m = actuator_kg + tube_kg
    com = tube_kg * length_m / 2.0 / m
    inertia = tube_kg * length_m**2 / 12.0 + tube_kg * (length_m / 2.0 - com) ** 2
    inertia += actuator_kg * com**2 + actuator_kg * 0.0025
    return m, com, inertia


DAISY = DaisyParams()
