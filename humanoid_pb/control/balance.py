"""Whole-body balance controller: feed-forward statics plus joint feedback, as pure functions.

    tau = Gamma(q, mode) + Kp (q_des - q) - Kd qd

``Gamma`` is Jorgensen et al.'s Eq. 23 at the measured configuration in the current contact mode (the torques
that hold the robot still there), sent at the control rate; the joint impedance towards the planned
configuration runs in the actuators at the physics rate (:meth:`thermolimb.rig.BulletRig.step_impedance`).
Motions between configurations are smooth interpolations (:class:`Motion`), so that weight shifts and foot
lifts are slow compared with the robot's balance dynamics.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..constants import ARM_JOINTS, JOINTS, WAIST_JOINTS
from ..model.statics import WholeBody


@dataclass(frozen=True)
class BalanceGains:
    leg_kp_Nm_rad: float = 2500.0
    leg_kd_Nm_s_rad: float = 60.0
    waist_kp_Nm_rad: float = 1500.0
    waist_kd_Nm_s_rad: float = 50.0
    arm_kp_Nm_rad: float = 300.0
    arm_kd_Nm_s_rad: float = 10.0

    def vectors(self) -> tuple[np.ndarray, np.ndarray]:
        kp, kd = np.empty(len(JOINTS)), np.empty(len(JOINTS))
        for i, j in enumerate(JOINTS):
            if j in WAIST_JOINTS:
                kp[i], kd[i] = self.waist_kp_Nm_rad, self.waist_kd_Nm_s_rad
            elif any(j.endswith(a) for a in ARM_JOINTS):
                kp[i], kd[i] = self.arm_kp_Nm_rad, self.arm_kd_Nm_s_rad
            else:
                kp[i], kd[i] = self.leg_kp_Nm_rad, self.leg_kd_Nm_s_rad
        return kp, kd


@dataclass(frozen=True)
class Motion:
    """A smooth (minimum-jerk) move of the joint targets from ``start`` to ``goal`` over ``duration_s``."""

    start: np.ndarray
    goal: np.ndarray
    t0_s: float
    duration_s: float

    def at(self, t_s: float) -> np.ndarray:
        s = np.clip((t_s - self.t0_s) / self.duration_s, 0.0, 1.0) if self.duration_s > 0 else 1.0
        blend = s**3 * (10 - 15 * s + 6 * s**2)
        return self.start + blend * (self.goal - self.start)

    def done(self, t_s: float) -> bool:
        return t_s >= self.t0_s + self.duration_s


@dataclass(frozen=True)
class ImpedanceCommand:
    """What the controller sends the actuators each control step: feed-forward, targets and gains."""

    feedforward_Nm: np.ndarray
    q_des: np.ndarray
    kp_Nm_rad: np.ndarray
    kd_Nm_s_rad: np.ndarray


def balance_command(body: WholeBody, q_pin: np.ndarray, q_des: np.ndarray, mode: str,
                    gains: BalanceGains = BalanceGains()) -> ImpedanceCommand:
    """Hold the measured configuration in ``mode`` (Eq. 23) and pull towards ``q_des`` (joint impedance)."""
    kp, kd = gains.vectors()
    return ImpedanceCommand(body.balancing_torques(q_pin, mode)[0], np.asarray(q_des, float), kp, kd)
