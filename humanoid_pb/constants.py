"""Every name of the Valkyrie-like humanoid, written once.

Actuated joints: 6 per leg, 3 in the waist, 4 per arm (23).  Valkyrie's
forearm, wrist and neck joints carry almost no load and are left out.
"""

from __future__ import annotations

SIDES = ("left", "right")
LEG_JOINTS = ("hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle_pitch", "ankle_roll")
ARM_JOINTS = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow")
WAIST_JOINTS = ("torso_yaw", "torso_pitch", "torso_roll")

PELVIS = "pelvis"
TORSO = "torso"


def leg_joint(side: str, name: str) -> str:
    return f"{side}_{name}"


arm_joint = leg_joint  # both are "<side>_<joint>"


def joint_kind(joint: str) -> str:
    """The joint without its side: ``left_knee`` -> ``knee`` (waist joints have no side)."""
    side = next((s for s in SIDES if joint.startswith(f"{s}_")), None)
    return joint if side is None else joint[len(side) + 1 :]


def foot_link(side: str) -> str:
    return f"{side}_foot"


def sole_frame(side: str) -> str:
    """The frame at the centre of a foot's sole, on the ground."""
    return f"{side}_sole"


def rod_actuators(pair: str) -> tuple[str, str]:
    """The two push rods of a rod pair."""
    return f"{pair}_rod_a", f"{pair}_rod_b"


JOINTS = (
    tuple(leg_joint(s, j) for s in SIDES for j in LEG_JOINTS)
    + WAIST_JOINTS
    + tuple(arm_joint(s, j) for s in SIDES for j in ARM_JOINTS)
)
FEET = tuple(foot_link(s) for s in SIDES)
FOOT_SIDE = {foot_link(s): s for s in SIDES}

# joint pairs driven by two linear push-rod actuators (Jorgensen et al.'s Sec. III)
ROD_PAIRS = {
    "left_ankle": ("left_ankle_pitch", "left_ankle_roll"),
    "right_ankle": ("right_ankle_pitch", "right_ankle_roll"),
    "waist": ("torso_pitch", "torso_roll"),
}
# the thermal "actuators": rotary joints, and two rods for each rod pair
ACTUATORS = tuple(
    [j for j in JOINTS if not any(j in pair for pair in ROD_PAIRS.values())]
    + [rod for pair in ROD_PAIRS for rod in rod_actuators(pair)]
)

CONTACT_MODES = ("double", "left", "right")  # double support, left single support, right single support


def mode_feet(mode: str) -> tuple[str, ...]:
    return {"double": FEET, "left": (FEET[0],), "right": (FEET[1],)}[mode]


def leg_actuators(side: str) -> tuple[str, ...]:
    """The thermal actuators of one leg: hip and knee motors and the two ankle rods."""
    return tuple(a for a in ACTUATORS if a.startswith(f"{side}_") and not any(arm in a for arm in ARM_JOINTS))


TORSO_ACTUATORS = tuple(a for a in ACTUATORS if a.startswith("torso") or a.startswith("waist"))
