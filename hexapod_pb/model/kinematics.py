"""Per-leg kinematics in the body frame: forward kinematics, analytic Jacobian, inverse kinematics.

Leg ``i`` is mounted at ``body_p_mount`` with yaw ``a``.  Its base joint
yaws about +z; shoulder and elbow pitch about the leg's ``-y`` axis (positive
lifts the link).  With heading ``psi = a + q_base`` and, in the leg's
vertical plane, ``r`` the horizontal distance from the base axis and ``z`` the
height from the shoulder axis:

    r = bracket + L1 cos(qs) + L2 cos(qs + qe)
    z = L1 sin(qs) + L2 sin(qs + qe)
    body_p_foot = body_p_mount + (r cos psi, r sin psi, z)
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..constants import LEGS
from ..params import DaisyParams


def leg_plane(params: DaisyParams, q: np.ndarray) -> tuple[float, float]:
    """``(r, z)`` of the foot in the leg's vertical plane (m)."""
    L1, L2 = params.upper_link_m, params.lower_link_m
    qs, qe = q[1], q[2]
    r = params.bracket_m + L1 * np.cos(qs) + L2 * np.cos(qs + qe)
    z = L1 * np.sin(qs) + L2 * np.sin(qs + qe)
    return r, z


def foot_position(params: DaisyParams, leg: int, q: np.ndarray) -> np.ndarray:
    """Foot centre in the body frame (m) for joint angles ``q = (base, shoulder, elbow)`` (rad)."""
    r, z = leg_plane(params, q)
    psi = params.mount_yaw_rad(leg) + q[0]
    return params.mount_position_m(leg) + np.array([r * np.cos(psi), r * np.sin(psi), z])


def joint_axes(params: DaisyParams, leg: int, q: np.ndarray) -> np.ndarray:
    """Body-frame unit axes of the base (+z), shoulder and elbow (the leg's -y): rows."""
    psi = params.mount_yaw_rad(leg) + q[0]
    pitch = np.array([np.sin(psi), -np.cos(psi), 0.0])
    return np.vstack([[0.0, 0.0, 1.0], pitch, pitch])


def point_jacobian(params: DaisyParams, leg: int, q: np.ndarray, radial_m: float, along_upper_m: float,
                   along_lower_m: float) -> np.ndarray:
    """Body-frame linear Jacobian (3 x 3) of a point on the leg.

    The point lies ``radial_m`` out from the base axis, then ``along_upper_m``
    along the upper link and ``along_lower_m`` along the lower link (the foot:
    bracket, L1, L2).
    """
    qs, qe = q[1], q[2]
    psi = params.mount_yaw_rad(leg) + q[0]
    c, s = np.cos(psi), np.sin(psi)
    r = radial_m + along_upper_m * np.cos(qs) + along_lower_m * np.cos(qs + qe)
    dr_ds = -along_upper_m * np.sin(qs) - along_lower_m * np.sin(qs + qe)
    dz_ds = along_upper_m * np.cos(qs) + along_lower_m * np.cos(qs + qe)
    dr_de = -along_lower_m * np.sin(qs + qe)
    dz_de = along_lower_m * np.cos(qs + qe)
    return np.array([[-r * s, dr_ds * c, dr_de * c], [r * c, dr_ds * s, dr_de * s], [0.0, dz_ds, dz_de]])


def foot_jacobian(params: DaisyParams, leg: int, q: np.ndarray) -> np.ndarray:
    """``J`` (3 x 3) with ``d body_p_foot = J dq`` (linear part)."""
    return point_jacobian(params, leg, q, params.bracket_m, params.upper_link_m, params.lower_link_m)


class UnreachableError(ValueError):
    """A foot target outside the leg's workspace."""


def inverse_kinematics(params: DaisyParams, leg: int, body_p_foot: np.ndarray) -> np.ndarray:
    """Joint angles (knee up: the elbow above the foot) that put the foot at ``body_p_foot``."""
    d = np.asarray(body_p_foot, float) - params.mount_position_m(leg)
    psi = np.arctan2(d[1], d[0])
    q_base = np.arctan2(np.sin(psi - params.mount_yaw_rad(leg)), np.cos(psi - params.mount_yaw_rad(leg)))
    r = np.hypot(d[0], d[1]) - params.bracket_m
    z = d[2]
    L1, L2 = params.upper_link_m, params.lower_link_m
    cos_e = (r * r + z * z - L1 * L1 - L2 * L2) / (2.0 * L1 * L2)
    if not -1.0 <= cos_e <= 1.0:
        raise UnreachableError(f"leg {leg}: foot target {np.round(body_p_foot, 3)} m is out of reach")
    q_elbow = -np.arccos(cos_e)
    q_shoulder = np.arctan2(z, r) - np.arctan2(L2 * np.sin(q_elbow), L1 + L2 * np.cos(q_elbow))
    return np.array([q_base, q_shoulder, q_elbow])


def nominal_feet(params: DaisyParams) -> np.ndarray:
    """Every leg's standing foot position (legs x 3, body frame), computed once per set of parameters."""
    return _nominal_feet(params).copy()


@lru_cache(maxsize=8)
def _nominal_feet(params: DaisyParams) -> np.ndarray:
    return np.array([nominal_foot(params, i) for i in range(len(LEGS))])


def nominal_foot(params: DaisyParams, leg: int) -> np.ndarray:
    """Standing foot position in the body frame: along the mount direction, on the ground."""
    a = params.mount_yaw_rad(leg)
    heading = np.array([np.cos(a), np.sin(a), 0.0])
    reach = params.bracket_m + params.nominal_foot_reach_m
    p = params.mount_position_m(leg) + reach * heading
    p[2] = -params.nominal_body_height_m + params.foot_radius_m
    return p
