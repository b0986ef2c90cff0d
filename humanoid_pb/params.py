"""Physical parameters of the Valkyrie-like humanoid (frozen; SI units in the names).

Published Valkyrie numbers (``shared/reference/facts.md``): masses of pelvis,
torso, legs and arms, hip offsets, thigh and shank lengths, foot sole, joint
effort limits, ankle and waist push rods.  Where the split of a published
mass among links, or a length, is chosen here, ``urdf/README.md`` says so.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from thermolimb.util.frozen import FrozenMapping

from .constants import joint_kind

FALLEN_PELVIS_HEIGHT_M = 0.6  # the pelvis below this height: the robot has fallen


@dataclass(frozen=True)
class ValkyrieParams:
    pelvis_kg: float = 8.2
    torso_kg: float = 39.5  # chest, head and electronics
    waist_links_kg: tuple[float, float] = (0.5, 0.5)  # torso yaw and pitch links (chosen)
    # hip yaw, hip roll, thigh, shank, ankle, foot = 24.8
    leg_links_kg: tuple[float, ...] = (2.4, 3.0, 9.5, 5.5, 0.9, 3.5)
    arm_links_kg: tuple[float, ...] = (2.6, 2.9, 5.5, 4.0)  # shoulder pitch, roll, upper arm, forearm = 15.0
    hip_lateral_m: float = 0.1016
    hip_below_pelvis_m: float = 0.1853
    thigh_m: float = 0.431
    shank_m: float = 0.406
    ankle_height_m: float = 0.09  # ankle axis above the sole (chosen)
    sole_m: tuple[float, float] = (0.27, 0.16)
    sole_forward_m: float = 0.04  # sole centre ahead of the ankle axis (chosen)
    torso_com_m: float = 0.30  # torso centre of mass above the waist (chosen)
    shoulder_m: tuple[float, float, float] = (-0.03, 0.25, 0.45)  # left shoulder in the torso frame (chosen)
    upper_arm_m: float = 0.30
    forearm_m: float = 0.28
    effort_limit_Nm: FrozenMapping = field(default_factory=lambda: {
        "hip_yaw": 190.0, "hip_roll": 350.0, "hip_pitch": 350.0, "knee": 350.0, "ankle_pitch": 205.0,
        "ankle_roll": 205.0, "torso_yaw": 190.0, "torso_pitch": 150.0, "torso_roll": 150.0,
        "shoulder_pitch": 190.0, "shoulder_roll": 190.0, "shoulder_yaw": 65.0, "elbow": 65.0})
    joint_limits_rad: FrozenMapping = field(default_factory=lambda: {
        "hip_yaw": (-0.8, 0.8), "hip_roll": (-0.5, 0.5), "hip_pitch": (-2.4, 1.6), "knee": (0.0, 2.06),
        "ankle_pitch": (-0.93, 0.65), "ankle_roll": (-0.4, 0.4), "torso_yaw": (-1.3, 1.3),
        "torso_pitch": (-0.13, 0.67), "torso_roll": (-0.23, 0.23), "shoulder_pitch": (-2.8, 2.0),
        "shoulder_roll": (-1.5, 1.5), "shoulder_yaw": (-3.0, 3.0), "elbow": (-2.2, 0.1)})
    # push rods (facts.md): ankle rods 0.105 m, anchored +-0.04 m either side of the shin axis; at the zero
    # pose the rod force -> (pitch, roll) torque map is [[-0.0367, -0.0367], [-0.0341, +0.0341]] m
    ankle_rod_m: float = 0.105
    ankle_rod_anchor_m: float = 0.04
    ankle_rod_arm_m: tuple[float, float] = (0.0367, 0.0341)  # pitch, roll moment arms at the zero pose
    waist_rod_m: float = 0.131
    waist_rod_anchor_m: float = 0.07
    waist_rod_arm_m: tuple[float, float] = (0.06, 0.065)  # chosen: about the 0.07 m anchors
    # working range of the IK: balance controllers keep away from the straight-knee singularity
    knee_min_rad: float = 0.3
    rod_force_limit_N: float = 2800.0  # ~205 N m / 0.0367 m * 0.5 (derived in facts.md)

    def __post_init__(self):
        # read-only: a default must not change under anyone
        for name in ("effort_limit_Nm", "joint_limits_rad"):
            object.__setattr__(self, name, FrozenMapping(getattr(self, name)))
        masses = (self.pelvis_kg, self.torso_kg, *self.waist_links_kg, *self.leg_links_kg, *self.arm_links_kg)
        if any(not m > 0 for m in masses):
            raise ValueError("ValkyrieParams: every link mass must be positive")
        if len(self.leg_links_kg) != 6 or len(self.arm_links_kg) != 4:
            raise ValueError("ValkyrieParams: 6 leg link masses and 4 arm link masses are expected")
        lengths = (self.thigh_m, self.shank_m, self.ankle_height_m, self.upper_arm_m, self.forearm_m)
        if any(not x > 0 for x in lengths):
            raise ValueError("ValkyrieParams: every segment length must be positive")

    @property
    def mass_kg(self) -> float:
        return (self.pelvis_kg + self.torso_kg + sum(self.waist_links_kg) + 2 * sum(self.leg_links_kg)
                + 2 * sum(self.arm_links_kg))

    def effort_limit(self, joint: str) -> float:
        return self.effort_limit_Nm[joint_kind(joint)]

    def limits(self, joint: str) -> tuple[float, float]:
        return self.joint_limits_rad[joint_kind(joint)]


VALKYRIE = ValkyrieParams()
