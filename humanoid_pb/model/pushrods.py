"""Push-rod pairs (ankles, waist): joint torques to rod forces, Jorgensen et al.'s Eq. 24 for these joints.

Each pair drives a (pitch, roll) joint pair through two linear actuators.
Rod ``k`` runs from an anchor on the upper body (fixed in the pitch joint's
parent frame) to an attachment on the lower body that turns with pitch, then
roll.  With ``l_k(q)`` the rod lengths, virtual work gives

    tau = J_l(q)^T F,   J_l = dl/dq   (2 x 2),   F = J_l^{-T} tau

At the zero pose the attachments sit at ``(arm_pitch, -+arm_roll, 0)`` from
the joint centre and the anchors one rod length along z from them;
``direction`` sets the sign convention of ``F``: with ``direction = -1`` the
ankle reproduces the published zero-pose map
``[[-0.0367, -0.0367], [-0.0341, +0.0341]]`` m (``tau = M F``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


def _rot_y(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def _rot_x(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


@dataclass(frozen=True)
class RodPair:
    """Geometry of one pair (see the module docstring for ``direction``)."""

    rod_m: float
    arm_pitch_m: float
    arm_roll_m: float
    direction: float = -1.0

    def _attachments(self) -> np.ndarray:
        return np.array([[self.arm_pitch_m, -self.arm_roll_m, 0.0], [self.arm_pitch_m, self.arm_roll_m, 0.0]])

    def _anchors(self) -> np.ndarray:
        return self._attachments() + np.array([0.0, 0.0, self.direction * self.rod_m])

    def lengths_m(self, pitch: float, roll: float) -> np.ndarray:
        R = _rot_y(pitch) @ _rot_x(roll)
        moved = self._attachments() @ R.T
        return np.linalg.norm(self._anchors() - moved, axis=1)

    def length_jacobian(self, pitch: float, roll: float) -> np.ndarray:
        """``J_l`` (2 rods x 2 joints), analytic: d|a - R b|/dq = -(a - R b) . (dR/dq b) / |a - R b|.

        With ``R = R_y(pitch) R_x(roll)`` and an attachment ``b = (x, y, 0)``:
        ``R b = (cp x + sp sr y, cr y, -sp x + cp sr y)``; written out in
        scalars, as the solvers call it thousands of times per plan.
        """
        cp, sp, cr, sr = math.cos(pitch), math.sin(pitch), math.cos(roll), math.sin(roll)
        x, h = self.arm_pitch_m, self.direction * self.rod_m
        rows = []
        for y in (-self.arm_roll_m, self.arm_roll_m):
            rod = (x - (cp * x + sp * sr * y), y - cr * y, h - (-sp * x + cp * sr * y))  # anchor - R b
            d_pitch = (-sp * x + cp * sr * y, 0.0, -cp * x - sp * sr * y)  # dR/dpitch b
            d_roll = (sp * cr * y, -sr * y, cp * cr * y)  # dR/droll b
            length = math.sqrt(rod[0] ** 2 + rod[1] ** 2 + rod[2] ** 2)
            rows.append((-(rod[0] * d_pitch[0] + rod[2] * d_pitch[2]) / length,
                         -(rod[0] * d_roll[0] + rod[1] * d_roll[1] + rod[2] * d_roll[2]) / length))
        return np.array(rows)

    def rod_forces_N(self, pitch: float, roll: float, tau_Nm: np.ndarray) -> np.ndarray:
        """Rod forces (N, positive pushing) that make the joint torques ``(tau_pitch, tau_roll)``."""
        return np.linalg.solve(self.length_jacobian(pitch, roll).T, np.asarray(tau_Nm, float))

    def torque_map(self, pitch: float, roll: float) -> np.ndarray:
        """``M`` with ``tau = M F`` (rows pitch, roll; columns rods)."""
        return self.length_jacobian(pitch, roll).T
