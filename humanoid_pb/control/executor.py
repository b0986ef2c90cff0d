"""Drive the humanoid through contact modes and postures, every change through the nominal crouch (as
Jorgensen et al. assumes): what the recovery experiment, the calibration run and the environment share."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..ik.poses import standing, support_pose
from ..sim import HumanoidSim
from .balance import Motion, balance_command

SHIFT_S = 1.5  # foot placement, a shift back to the middle, a move inside double support, each
# weight shift onto one foot, and the lift, each: at 1.5 s a switch from one foot to the other fell
ENTRY_S = 2.5


class Executor:
    """Drives the humanoid through contact modes and configurations, through the nominal crouch."""

    def __init__(self, sim: HumanoidSim):
        self.sim = sim
        self.body = sim.body
        self.nominal_angles = sim.stance_angles
        self.q_nominal = standing(self.body, self.nominal_angles)
        self.mode = "double"
        self.target = self.nominal_angles.copy()
        self.queue: list[tuple[Motion, str]] = []
        self.settled_since = 0.0
        # the IK's balancing torques at the goal, fed forward there
        self.hold_torques: np.ndarray | None = None

    def support_angles(self, side: str, lift_m: float) -> np.ndarray:
        return self.body.joint_angles(support_pose(self.body, self.q_nominal, side, lift_m))

    def go(
        self, mode: str, goal_angles: np.ndarray | None = None, goal_torques: np.ndarray | None = None
    ) -> None:
        """Plan the motion to ``mode`` (through the nominal crouch) ending in ``goal_angles``.

        ``goal_torques``: the balancing torques chosen with the goal (the IK's
        ``Gamma``, which sets how the weight is shared between the feet); fed
        forward once there, instead of Eq. 23's.
        """
        self.hold_torques = goal_torques
        t = self.sim.time_s
        here = self.target
        plan = []
        if self.mode != "double":  # place the lifted foot, then shift back to the middle
            side = self.mode
            plan.append((Motion(here, self.support_angles(side, 0.0), t, SHIFT_S), side))
            plan.append(
                (Motion(self.support_angles(side, 0.0), self.nominal_angles, t + SHIFT_S, SHIFT_S), "double")
            )
            here, t = self.nominal_angles, t + 2 * SHIFT_S
        if mode == "double":
            goal = self.nominal_angles if goal_angles is None else goal_angles
            plan.append((Motion(here, goal, t, SHIFT_S), "double"))
        else:
            shifted = self.support_angles(mode, 0.0)
            lifted = self.support_angles(mode, 0.05) if goal_angles is None else goal_angles
            plan.append((Motion(here, shifted, t, ENTRY_S), "double"))
            plan.append((Motion(shifted, lifted, t + ENTRY_S, ENTRY_S), mode))
        self.queue = plan

    @property
    def moving(self) -> bool:
        return bool(self.queue) and not self.queue[-1][0].done(self.sim.time_s)

    def tick(self, reading):
        t = self.sim.time_s
        for motion, mode in self.queue:
            if t >= motion.t0_s:
                self.target, self.mode = motion.at(t), mode
        if self.queue and self.queue[-1][0].done(t):
            self.queue = []
            self.settled_since = t
        command = balance_command(self.body, self.sim.pinocchio_q(reading), self.target, self.mode)
        if not self.queue and self.hold_torques is not None:
            command = replace(command, feedforward_Nm=self.hold_torques)
        return self.sim.command(command)
