"""Leg statics: where each segment's mass sits, the leg's mass matrix, and the torques that hold its own
weight.

:func:`leg_statics` computes, once per leg and control step, everything the
controller and the stance-force problem need: the foot's position and
Jacobian, the mass matrix and the gravity torque.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..params import GRAVITY_M_S2, LINK_AXIAL_INERTIA_KG_M2, DaisyParams
from .kinematics import foot_position, point_jacobian


@dataclass(frozen=True)
class LegStatics:
    """One leg in one configuration (body frame)."""

    foot_m: np.ndarray  # (3,) foot centre
    jacobian: np.ndarray  # (3, 3) of the foot, d foot = J dq
    mass_matrix: np.ndarray  # (3, 3) joint space
    gravity_Nm: np.ndarray  # (3,) joint torques holding the leg's own weight


def _mass_points(params: DaisyParams) -> tuple[tuple[float, float, float, float], ...]:
    """``(mass, radial, along upper, along lower)`` of each segment's centre and the foot; the foot last."""
    (m0, c0, _), (m1, c1, _), (m2, c2, _) = params.segments()
    b, L1, L2 = params.bracket_m, params.upper_link_m, params.lower_link_m
    return (m0, c0, 0.0, 0.0), (m1, b, c1, 0.0), (m2, b, L1, c2), (params.foot_mass_kg, b, L1, L2)


def leg_statics(
    params: DaisyParams, leg: int, q: np.ndarray, world_R_body: np.ndarray | None = None
) -> LegStatics:
    """Foot position and Jacobian, mass matrix and gravity torque of leg ``leg`` at ``q`` (3,), each once."""
    R = np.eye(3) if world_R_body is None else world_R_body
    up = R.T @ np.array([0.0, 0.0, GRAVITY_M_S2])  # minus gravity, body frame
    M, g = np.zeros((3, 3)), np.zeros(3)
    for mass, radial, upper, lower in _mass_points(params):
        J = point_jacobian(params, leg, q, radial, upper, lower)
        M += mass * J.T @ J
        g += J.T @ (mass * up)
    # rotational inertia about each segment's centre: a link's inertia is i across it and LINK_AXIAL along it,
    # so about the vertical (yaw) axis a link pitched by a counts i cos^2 a + LINK_AXIAL sin^2 a; the foot is
    # a sphere
    (_, _, i0), (_, _, i1), (_, _, i2) = params.segments()
    foot, axial = params.foot_inertia_kg_m2, LINK_AXIAL_INERTIA_KG_M2
    upper, lower = q[1], q[1] + q[2]
    M[0, 0] += (i0 + i1 * np.cos(upper) ** 2 + axial * np.sin(upper) ** 2 + i2 * np.cos(lower) ** 2
                + axial * np.sin(lower) ** 2 + foot)
    M[1:, 1:] += np.array([[i1 + i2 + foot, i2 + foot], [i2 + foot, i2 + foot]])
    return LegStatics(foot_position(params, leg, q), J, M, g)  # J: the last point is the foot


def leg_mass_matrix(params: DaisyParams, leg: int, q: np.ndarray) -> np.ndarray:
    """Approximate joint-space mass matrix (3 x 3) of one leg: segment masses as points plus link inertias."""
    return leg_statics(params, leg, q).mass_matrix


def leg_gravity_torque(
    params: DaisyParams, leg: int, q: np.ndarray, world_R_body: np.ndarray | None = None
) -> np.ndarray:
    """Joint torques (N m) that hold the leg's own weight in configuration ``q`` (Nair et al.'s ``g_i``)."""
    return leg_statics(params, leg, q, world_R_body).gravity_Nm
