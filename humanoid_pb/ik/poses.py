"""Nominal configurations: the crouch, and single-support poses with the centre of mass over the stance sole.

Kinematic IK by damped least squares on Pinocchio Jacobians: the stance
sole stays where it is, the centre of mass moves over the stance sole's
centre, and the free sole lifts straight up, level.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..constants import JOINTS, SIDES, leg_joint
from ..model.statics import WholeBody

LIFT_M = 0.05


def crouch_angles(depth_rad: float = 0.3) -> np.ndarray:
    """Both knees bent by ``2 depth``, hips and ankles by ``-depth``: feet flat, trunk upright."""
    angles = np.zeros(len(JOINTS))
    for side in SIDES:
        angles[JOINTS.index(leg_joint(side, "hip_pitch"))] = -depth_rad
        angles[JOINTS.index(leg_joint(side, "knee"))] = 2 * depth_rad
        angles[JOINTS.index(leg_joint(side, "ankle_pitch"))] = -depth_rad
    return angles


def standing(body: WholeBody, angles: np.ndarray) -> np.ndarray:
    """Pinocchio ``q`` with the pelvis level above the origin and the lower sole on the ground."""
    q = body.configuration([0.0, 0.0, 0.0], [0, 0, 0, 1], angles)
    soles = body.sole_poses(q)
    q[2] = -min(p.translation[2] for p in soles.values())
    return q


def support_pose(body: WholeBody, q_double: np.ndarray, stance: str, lift_m: float = LIFT_M) -> np.ndarray:
    """:func:`single_support`, solved once per body, start, side and lift: the planner asks for both sides'
    poses at every decision and the executor for the same ones again, and a pure function of these need not
    rerun."""
    key = ("single_support", np.asarray(q_double, float).tobytes(), stance, float(lift_m))
    if key not in body.solved:
        body.solved[key] = single_support(body, q_double, stance, lift_m)
    return body.solved[key].copy()


def single_support(body: WholeBody, q_double: np.ndarray, stance: str, lift_m: float = LIFT_M,
                   iterations: int = 50, damping: float = 1e-3) -> np.ndarray:
    """From a double-support ``q``: the CoM over the ``stance`` sole and the other sole lifted by
    ``lift_m``."""
    model, data = body.model, body.data
    free = next(s for s in SIDES if s != stance)
    start = body.sole_poses(q_double)
    stance_target = start[stance]
    free_target = pin.SE3(start[free].rotation, start[free].translation + np.array([0.0, 0.0, lift_m]))
    com_target = stance_target.translation[:2]
    q = q_double.copy()
    for _ in range(iterations):
        pin.computeJointJacobians(model, data, q)
        pin.framesForwardKinematics(model, data, q)
        e_stance = pin.log6(stance_target.inverse() * data.oMf[body.sole_frame[stance]]).vector
        e_free = pin.log6(free_target.inverse() * data.oMf[body.sole_frame[free]]).vector
        com = pin.centerOfMass(model, data, q)
        e_com = com[:2] - com_target
        J = np.vstack([pin.getFrameJacobian(model, data, body.sole_frame[stance], pin.LOCAL),
                       pin.getFrameJacobian(model, data, body.sole_frame[free], pin.LOCAL),
                       pin.jacobianCenterOfMass(model, data, q)[:2]])
        e = np.concatenate([e_stance, e_free, e_com])
        if np.max(np.abs(e)) < 1e-9:
            break
        dq = -J.T @ np.linalg.solve(J @ J.T + damping * np.eye(len(e)), e)
        q = pin.integrate(model, q, dq)
    return q
