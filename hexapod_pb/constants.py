"""Every name of the Daisy-like hexapod, written once.

Legs are numbered as on HEBI's Daisy: 1 left front, 2 right front, 3 left
middle, 4 right middle, 5 left rear, 6 right rear (x forward, y left, z up).
"""

from __future__ import annotations

LEGS = ("left_front", "right_front", "left_middle", "right_middle", "left_rear", "right_rear")
JOINT_KINDS = ("base", "shoulder", "elbow")

# the alternating tripods of HEBI's stock controller: {front-left, middle-right, rear-left} and the rest
TRIPODS = (("left_front", "right_middle", "left_rear"), ("right_front", "left_middle", "right_rear"))

BODY_LINK = "body"
PAYLOAD_LINK = "payload"


def joint_name(leg: str, kind: str) -> str:
    return f"{leg}_{kind}"


def foot_link(leg: str) -> str:
    return f"{leg}_foot"


JOINTS = tuple(joint_name(leg, kind) for leg in LEGS for kind in JOINT_KINDS)  # 18, leg-major
FEET = tuple(foot_link(leg) for leg in LEGS)
