"""Generate the Daisy-like hexapod's URDF from :class:`~hexapod_pb.params.DaisyParams`.

``python -m hexapod_pb.model.daisy_urdf`` rewrites ``urdf/daisy_like.urdf``; a test
checks that the committed file equals this generator's output.
"""

from __future__ import annotations

from pathlib import Path

from thermolimb.urdf_builder import Shape, UrdfBuilder, box, box_inertia, cylinder, number, sphere
from thermolimb.util.paths import urdf_dir, write_urdf

from ..constants import BODY_LINK, LEGS, PAYLOAD_LINK, foot_link, joint_name
from ..params import DAISY, LINK_AXIAL_INERTIA_KG_M2, DaisyParams

URDF_NAME = "daisy_like.urdf"
PAYLOAD_SIZE_M = 0.12
PAYLOAD_PLACEHOLDER_KG = 0.001  # the simulator sets the scenario's payload mass
DAMPING = 0.05  # joint damping, N m s/rad


def generate(params: DaisyParams = DAISY) -> str:
    """The URDF text (deterministic: same parameters, same bytes)."""
    p = params
    body = p.body_size_m
    urdf = UrdfBuilder("daisy_like", "hexapod_pb.model.daisy_urdf from DaisyParams",
                       {"grey": "0.5 0.5 0.55 1", "red": "0.8 0.15 0.1 1", "black": "0.1 0.1 0.1 1"})
    urdf.link(BODY_LINK, p.body_mass_kg, box_inertia(p.body_mass_kg, body),
              visuals=[Shape(box(body), material="grey")], collisions=[Shape(box(body))])
    s = (PAYLOAD_SIZE_M,) * 3
    urdf.link(PAYLOAD_LINK, PAYLOAD_PLACEHOLDER_KG, box_inertia(PAYLOAD_PLACEHOLDER_KG, s),
              visuals=[Shape(box(s), material="red")])
    urdf.fixed("payload_mount", BODY_LINK, PAYLOAD_LINK, f"0 0 {number(body[2] / 2 + s[2] / 2)}")
    small = LINK_AXIAL_INERTIA_KG_M2
    base, shoulder, elbow = p.actuators
    (m0, c0, i0), (m1, c1, i1), (m2, c2, i2) = p.segments()

    def tube(length: float, radius: float, color: str) -> Shape:  # along the link's x axis
        return Shape(cylinder(length, radius), (length / 2, 0.0, 0.0), "0 1.5708 0", color)

    for i, leg in enumerate(LEGS):
        mount = p.mount_position_m(i)
        urdf.revolute(joint_name(leg, "base"), BODY_LINK, f"{leg}_base_link",
                      f"{number(mount[0])} {number(mount[1])} 0", "0 0 1", -1.2, 1.2, base.effort_limit,
                      base.velocity_limit, DAMPING, f"0 0 {number(p.mount_yaw_rad(i))}")
        urdf.link(f"{leg}_base_link", m0, (small, i0, i0), (c0, 0.0, 0.0), [tube(p.bracket_m, 0.03, "black")])
        urdf.revolute(joint_name(leg, "shoulder"), f"{leg}_base_link", f"{leg}_upper",
                      f"{number(p.bracket_m)} 0 0", "0 -1 0", -1.6, 1.6, shoulder.effort_limit,
                      shoulder.velocity_limit, DAMPING, "0 0 0")
        urdf.link(f"{leg}_upper", m1, (small, i1, i1), (c1, 0.0, 0.0), [tube(p.upper_link_m, 0.02, "grey")])
        urdf.revolute(joint_name(leg, "elbow"), f"{leg}_upper", f"{leg}_lower", f"{number(p.upper_link_m)} "
                      f"0 0", "0 -1 0", -2.8, 0.5, elbow.effort_limit, elbow.velocity_limit, DAMPING, "0 0 0")
        urdf.link(f"{leg}_lower", m2, (small, i2, i2), (c2, 0.0, 0.0), [tube(p.lower_link_m, 0.015, "grey")])
        urdf.fixed(f"{leg}_foot_mount", f"{leg}_lower", foot_link(leg), f"{number(p.lower_link_m)} 0 0")
        foot = sphere(p.foot_radius_m)
        urdf.link(foot_link(leg), p.foot_mass_kg, [p.foot_inertia_kg_m2] * 3,
                  visuals=[Shape(foot, material="black")], collisions=[Shape(foot)])
    return urdf.text()


def urdf_path() -> Path:
    return urdf_dir() / URDF_NAME


if __name__ == "__main__":
    write_urdf(URDF_NAME, generate())
