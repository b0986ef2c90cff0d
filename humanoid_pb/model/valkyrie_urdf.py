"""Generate the Valkyrie-like humanoid's URDF (primitive shapes) from :class:`ValkyrieParams`.

``python -m humanoid_pb.model.valkyrie_urdf`` rewrites ``urdf/valkyrie_like.urdf``; a
test checks that the committed file equals this generator's output.  Each
foot carries a massless-looking ``<side>_sole`` frame at the centre of its
sole: the contact frame of the statics.
"""

from __future__ import annotations

from pathlib import Path

from thermolimb.urdf_builder import Shape, UrdfBuilder, box, box_inertia, number, xyz
from thermolimb.util.paths import urdf_dir, write_urdf

from ..constants import (
    ARM_JOINTS,
    LEG_JOINTS,
    PELVIS,
    SIDES,
    TORSO,
    arm_joint,
    foot_link,
    leg_joint,
    sole_frame,
)
from ..params import VALKYRIE, ValkyrieParams

URDF_NAME = "valkyrie_like.urdf"
AXES = {"yaw": "0 0 1", "roll": "1 0 0", "pitch": "0 1 0", "knee": "0 1 0", "elbow": "0 1 0"}


def _axis(joint: str) -> str:
    return next(v for k, v in AXES.items() if joint.endswith(k))


def _box_link(
    urdf: UrdfBuilder,
    name: str,
    mass: float,
    size,
    com=(0.0, 0.0, 0.0),
    visual=True,
    collision=False,
    color="grey",
) -> None:
    shape = Shape(box(size), com, material=color)
    urdf.link(name, mass, box_inertia(mass, size), com, [shape] if visual else [],
              [shape] if collision else [])


def _revolute(urdf: UrdfBuilder, name, parent, child, origin, params: ValkyrieParams) -> None:
    lo, hi = params.limits(name)
    urdf.revolute(name, parent, child, origin, _axis(name), lo, hi, params.effort_limit(name), 6.0, 0.5)


def generate(params: ValkyrieParams = VALKYRIE) -> str:
    p = params
    urdf = UrdfBuilder("valkyrie_like", "humanoid_pb.model.valkyrie_urdf from ValkyrieParams",
                       {"grey": "0.75 0.75 0.78 1", "dark": "0.2 0.2 0.25 1"})
    _box_link(urdf, PELVIS, p.pelvis_kg, (0.2, 0.3, 0.15))
    _revolute(urdf, "torso_yaw", PELVIS, "torso_yaw_link", "0 0 0.08", p)
    _box_link(urdf, "torso_yaw_link", p.waist_links_kg[0], (0.08, 0.08, 0.04), visual=False)
    _revolute(urdf, "torso_pitch", "torso_yaw_link", "torso_pitch_link", "0 0 0", p)
    _box_link(urdf, "torso_pitch_link", p.waist_links_kg[1], (0.08, 0.08, 0.04), visual=False)
    _revolute(urdf, "torso_roll", "torso_pitch_link", TORSO, "0 0 0", p)
    _box_link(urdf, TORSO, p.torso_kg, (0.30, 0.40, 0.55), com=(0.0, 0.0, p.torso_com_m), color="dark")
    sx, sy, sz = p.shoulder_m
    for side, sign in zip(SIDES, (1.0, -1.0)):
        names = [arm_joint(side, j) for j in ARM_JOINTS]
        m = p.arm_links_kg
        _revolute(urdf, names[0], TORSO, f"{side}_shoulder_pitch_link", xyz((sx, sign * sy, sz)), p)
        _box_link(urdf, f"{side}_shoulder_pitch_link", m[0], (0.1, 0.1, 0.1), visual=False)
        _revolute(urdf, names[1], f"{side}_shoulder_pitch_link", f"{side}_shoulder_roll_link", "0 0 0", p)
        _box_link(urdf, f"{side}_shoulder_roll_link", m[1], (0.1, 0.1, 0.1), visual=False)
        _revolute(urdf, names[2], f"{side}_shoulder_roll_link", f"{side}_upper_arm", "0 0 0", p)
        _box_link(urdf, f"{side}_upper_arm", m[2], (0.09, 0.09, p.upper_arm_m),
                  com=(0, 0, -p.upper_arm_m / 2))
        _revolute(urdf, names[3], f"{side}_upper_arm", f"{side}_forearm", f"0 0 {number(-p.upper_arm_m)}", p)
        _box_link(urdf, f"{side}_forearm", m[3], (0.08, 0.08, p.forearm_m), com=(0, 0, -p.forearm_m / 2))
    sole_x, sole_y = p.sole_m
    for side, sign in zip(SIDES, (1.0, -1.0)):
        j = [leg_joint(side, n) for n in LEG_JOINTS]
        m = p.leg_links_kg
        hip = xyz((0, sign * p.hip_lateral_m, -p.hip_below_pelvis_m))
        _revolute(urdf, j[0], PELVIS, f"{side}_hip_yaw_link", hip, p)
        _box_link(urdf, f"{side}_hip_yaw_link", m[0], (0.1, 0.1, 0.1), visual=False)
        _revolute(urdf, j[1], f"{side}_hip_yaw_link", f"{side}_hip_roll_link", "0 0 0", p)
        _box_link(urdf, f"{side}_hip_roll_link", m[1], (0.1, 0.1, 0.1), visual=False)
        _revolute(urdf, j[2], f"{side}_hip_roll_link", f"{side}_thigh", "0 0 0", p)
        _box_link(urdf, f"{side}_thigh", m[2], (0.14, 0.14, p.thigh_m), com=(0, 0, -p.thigh_m / 2))
        _revolute(urdf, j[3], f"{side}_thigh", f"{side}_shank", f"0 0 {number(-p.thigh_m)}", p)
        _box_link(urdf, f"{side}_shank", m[3], (0.11, 0.11, p.shank_m), com=(0, 0, -p.shank_m / 2))
        _revolute(urdf, j[4], f"{side}_shank", f"{side}_ankle_link", f"0 0 {number(-p.shank_m)}", p)
        _box_link(urdf, f"{side}_ankle_link", m[4], (0.05, 0.05, 0.05), visual=False)
        _revolute(urdf, j[5], f"{side}_ankle_link", foot_link(side), "0 0 0", p)
        _box_link(urdf, foot_link(side), m[5], (sole_x, sole_y, 0.05),
                  com=(p.sole_forward_m, 0.0, -p.ankle_height_m + 0.025), collision=True, color="dark")
        urdf.fixed(f"{side}_sole_joint", foot_link(side), sole_frame(side),
                   f"{number(p.sole_forward_m)} 0 {number(-p.ankle_height_m)}")
        _box_link(urdf, sole_frame(side), 1e-3, (0.01, 0.01, 0.01), visual=False)
    return urdf.text()


def urdf_path() -> Path:
    return urdf_dir() / URDF_NAME


if __name__ == "__main__":
    write_urdf(URDF_NAME, generate())
