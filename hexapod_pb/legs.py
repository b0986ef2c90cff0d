"""Leg statics: where each segment's mass sits, and the torques that hold a leg's own weight."""

from __future__ import annotations

import numpy as np

from .params import GRAVITY_M_S2, DaisyParams


def point_jacobian(params: DaisyParams, leg: int, q: np.ndarray, radial_m: float, along_upper_m: float,
                   along_lower_m: float) -> np.ndarray:
    """Body-frame linear Jacobian (3 x 3) of a point on the leg.

    The point lies ``radial_m`` out from the base axis, then ``along_upper_m``
    along the upper link and ``along_lower_m`` along the lower link.
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


def leg_gravity_torque(params: DaisyParams, leg: int, q: np.ndarray, world_R_body: np.ndarray | None = None) -> np.ndarray:
    """Joint torques (N m) that hold the leg's own weight in configuration ``q`` (the seed's ``g_i``)."""
    R = np.eye(3) if world_R_body is None else world_R_body
    up = R.T @ np.array([0.0, 0.0, GRAVITY_M_S2])  # minus gravity, body frame
    (m0, c0, _), (m1, c1, _), (m2, c2, _) = params.segments()
    b, L1, L2 = params.bracket_m, params.upper_link_m, params.lower_link_m
    points = ((m0, c0, 0.0, 0.0), (m1, b, c1, 0.0), (m2, b, L1, c2), (params.foot_mass_kg, b, L1, L2))
    tau = np.zeros(3)
    for mass, radial, upper, lower in points:
        tau += point_jacobian(params, leg, q, radial, upper, lower).T @ (mass * up)
    return tau
