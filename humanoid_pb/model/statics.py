"""Whole-body statics of the humanoid with Pinocchio: Jorgensen et al.'s Eqs. 18-24.

For a contact mode (double support, left or right single support) with 6-D
contact Jacobian ``J_c`` of the soles:

    Jbar_c = A^-1 J_c^T (J_c A^-1 J_c^T)^+          (dynamically consistent inverse)
    N_c    = I - Jbar_c J_c                          (contact null space)
    Gamma(q) = ( (S_a N_c)bar )^T N_c^T g(q)         (Eq. 23, the torques that hold q still)
    F_r    = Jbar_c^T ( g - S_a^T Gamma )            (Eq. 21 at rest: contact wrenches)
    F_act  = J_gamma(q) Gamma                        (Eq. 24: rods at the ankles and the waist)

Pinocchio (package ``pin``) gives ``A = M(q)`` (CRBA), ``g(q)``, frame
Jacobians and the derivatives of ``g``; PyBullet runs the same URDF.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..constants import FOOT_SIDE, JOINTS, SIDES, mode_feet, sole_frame
from ..params import VALKYRIE, ValkyrieParams
from .actuation import efforts as actuator_efforts
from .actuation import rod_pairs
from .valkyrie_urdf import urdf_path


@dataclass(frozen=True)
class Statics:
    """Everything Eq. 23 gives for one configuration and contact mode."""

    mode: str
    torques_Nm: np.ndarray  # Gamma (23,) in JOINTS order
    efforts: np.ndarray  # (23,) in ACTUATORS order: N m for motors, N for rods
    contact_wrenches: np.ndarray  # (k, 6) per sole, sole frame: force (N), moment (N m)


class WholeBody:
    """The humanoid's rigid-body model (Pinocchio), with Jorgensen et al.'s statics."""

    def __init__(self, params: ValkyrieParams = VALKYRIE):
        self.params = params
        self.model = pin.buildModelFromUrdf(str(urdf_path()), pin.JointModelFreeFlyer())
        self.data = self.model.createData()
        self.nv = self.model.nv
        self.v_index = np.array([self.model.joints[self.model.getJointId(j)].idx_v for j in JOINTS])
        self.q_index = np.array([self.model.joints[self.model.getJointId(j)].idx_q for j in JOINTS])
        self.sole_frame = {side: self.model.getFrameId(sole_frame(side)) for side in SIDES}
        self.S_a = np.zeros((len(JOINTS), self.nv))
        self.S_a[np.arange(len(JOINTS)), self.v_index] = 1.0
        self.rods = rod_pairs(params)
        # results of pure functions of this body, kept (see humanoid_pb.ik.poses.support_pose)
        self.solved: dict = {}

    # ------------------------------------------------------------ configuration
    def configuration(self, base_position_m, base_quaternion_xyzw, joint_angles_rad) -> np.ndarray:
        """Pinocchio ``q`` from a base pose and joint angles (23, JOINTS order)."""
        q = pin.neutral(self.model)
        q[:3] = base_position_m
        q[3:7] = base_quaternion_xyzw
        q[self.q_index] = joint_angles_rad
        return q

    def joint_angles(self, q: np.ndarray) -> np.ndarray:
        return q[self.q_index]

    def sole_poses(self, q: np.ndarray) -> dict[str, pin.SE3]:
        pin.framesForwardKinematics(self.model, self.data, q)
        return {side: self.data.oMf[fid].copy() for side, fid in self.sole_frame.items()}

    def com(self, q: np.ndarray) -> np.ndarray:
        return pin.centerOfMass(self.model, self.data, q).copy()

    def gravity(self, q: np.ndarray) -> np.ndarray:
        return pin.computeGeneralizedGravity(self.model, self.data, q).copy()

    def contact_jacobian(self, q: np.ndarray, mode: str) -> np.ndarray:
        """``J_c`` (6k x nv): sole twists in their own (LOCAL) frames."""
        pin.computeJointJacobians(self.model, self.data, q)
        pin.framesForwardKinematics(self.model, self.data, q)
        blocks = [pin.getFrameJacobian(self.model, self.data, self.sole_frame[FOOT_SIDE[f]], pin.LOCAL)
                  for f in mode_feet(mode)]
        return np.vstack(blocks)

    # ---------------------------------------------------------------- statics
    def contact_null_space(self, q: np.ndarray, Jc: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(A^-1, Jc_bar, Nc)`` at ``q`` for the contact Jacobian ``Jc``: the inverse mass matrix (CRBA),
        the dynamically consistent inverse ``A^-1 Jc' (Jc A^-1 Jc')^+`` and the null space ``I - Jc_bar Jc``
        (Eq. 21), what the statics and Jorgensen et al.'s descent step (Eq. 32) both project through."""
        A = pin.crba(self.model, self.data, q)
        A_inv = np.linalg.inv(np.triu(A) + np.triu(A, 1).T)
        Jc_bar = A_inv @ Jc.T @ np.linalg.pinv(Jc @ A_inv @ Jc.T)
        return A_inv, Jc_bar, np.eye(self.nv) - Jc_bar @ Jc

    def balancing_torques(self, q: np.ndarray, mode: str) -> tuple[np.ndarray, np.ndarray]:
        """Eqs. 21 and 23 at configuration ``q`` in contact ``mode``: the joint torques that hold the robot
        still there and the sole wrenches (feet x 6) they leave, without the actuators' efforts (what the
        balance controller needs every control period)."""
        g = self.gravity(q)
        A_inv, Jc_bar, Nc = self.contact_null_space(q, self.contact_jacobian(q, mode))
        X = self.S_a @ Nc
        X_bar = A_inv @ X.T @ np.linalg.pinv(X @ A_inv @ X.T)
        gamma = X_bar.T @ Nc.T @ g
        return gamma, (Jc_bar.T @ (g - self.S_a.T @ gamma)).reshape(-1, 6)

    def statics(self, q: np.ndarray, mode: str) -> Statics:
        """Eqs. 21, 23 and 24 at configuration ``q`` in contact ``mode``."""
        gamma, wrenches = self.balancing_torques(q, mode)
        return Statics(mode, gamma, self.efforts(q, gamma), wrenches)

    def efforts(self, q: np.ndarray, torques_Nm: np.ndarray) -> np.ndarray:
        """Eq. 24: actuator efforts (ACTUATORS order) from joint torques; rods through their Jacobians."""
        return actuator_efforts(self.rods, self.joint_angles(q), torques_Nm)
