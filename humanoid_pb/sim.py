"""The humanoid on the shared PyBullet rig (:mod:`thermolimb.rig`): the humanoid's only module that talks to
PyBullet.

Floating base on the ground.  Joint torques become actuator efforts through
the push rods at the ankles and waist (Eq. 24), so the thermal plant heats
rods there and motors elsewhere; thermal derating of a rod limits both joints
it drives.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from thermolimb.plant import ActuatorSpec, PlantEffects, ThermalProtection
from thermolimb.rig import BulletRig, RigConfig

from . import thermal
from .constants import ACTUATORS, FEET, JOINTS
from .ik.poses import crouch_angles
from .model import actuation
from .model.statics import WholeBody
from .model.valkyrie_urdf import urdf_path
from .params import VALKYRIE, ValkyrieParams
from .readings import Reading
from .scenarios import DEFAULT, Scenario
from .scenarios import scenario as get_scenario


class HumanoidSim(BulletRig):
    """A world with the humanoid standing on the ground in ``joint_angles``, feet flat.

    ``scenario`` (:mod:`humanoid_pb.scenarios`) sizes the actuators (unless ``specs`` are given) and sets the
    stance (``stance_angles``): where the robot starts without ``joint_angles``, and what the
    :class:`~humanoid_pb.control.executor.Executor` holds."""

    def __init__(self, joint_angles: np.ndarray | None = None, params: ValkyrieParams = VALKYRIE,
                 config: RigConfig = RigConfig(physics_hz=1000.0, control_hz=50.0),
                 plant_effects: PlantEffects = PlantEffects.realistic_sensor(), seed: int = 0,
                 protection: ThermalProtection = ThermalProtection(),
                 body: WholeBody | None = None, specs: Sequence[ActuatorSpec] | None = None,
                 scenario: str | Scenario = DEFAULT):
        self.params = params
        self.scenario = get_scenario(scenario)
        self.stance_angles = crouch_angles(self.scenario.crouch_depth_rad)
        self.body = body or WholeBody(params)
        self.rods = self.body.rods
        self._jacobians: tuple[bytes | None, dict] = (None, {})
        self._fractions: tuple[bytes | None, np.ndarray] = (None, np.ones(0))
        angles = self.stance_angles if joint_angles is None else np.asarray(joint_angles, float)
        base = self.standing_base(angles)
        limits = np.array([params.effort_limit(j) for j in JOINTS])
        specs = thermal.actuator_specs(params, self.scenario) if specs is None else list(specs)
        super().__init__(urdf_path(), JOINTS, FEET, ACTUATORS, specs, limits, config,
                         base, plant_effects=plant_effects, seed=seed, protection=protection)
        self.set_joint_positions(angles)

    def standing_base(self, angles: np.ndarray) -> np.ndarray:
        """Pelvis position (level, at the origin) that puts the lower sole on the ground."""
        q = self.body.configuration([0.0, 0.0, 0.0], [0, 0, 0, 1], angles)
        soles = self.body.sole_poses(q)
        return np.array([0.0, 0.0, -min(p.translation[2] for p in soles.values())])

    # ------------------------------------------------------------- rig hooks
    def _rod_jacobians(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """The rod pairs' Jacobians at ``q``, computed once per configuration (a period's end is the next
        one's start: its efforts, speeds and protection share them)."""
        key = np.asarray(q, float).tobytes()
        if self._jacobians[0] != key:
            self._jacobians = (key, actuation.rod_jacobians(self.rods, q))
        return self._jacobians[1]

    def actuator_efforts(self, q, torques_Nm):
        return actuation.efforts(self.rods, q, torques_Nm, self._rod_jacobians(q))

    def actuator_velocities(self, q, qd):
        return actuation.velocities(self.rods, q, qd, self._rod_jacobians(q))

    def torques_at_fraction(self, torques_Nm, actuator_fraction):
        # one share a period, asked at every physics step
        key = np.asarray(actuator_fraction, float).tobytes()
        if self._fractions[0] != key:
            self._fractions = (key, actuation.joint_fractions(actuator_fraction))
        return torques_Nm * self._fractions[1]

    # --------------------------------------------------------------- sensing
    def read(self) -> Reading:
        q, qd = self.joint_states()
        pos, _, lin, ang = self.base_state()
        return Reading(self.time_s, q, qd, self.sensed_torques(), self.plant.measured_C, pos,
                       self.base_quaternion(), lin, ang, self.contact_forces())

    def pinocchio_q(self, reading: Reading) -> np.ndarray:
        """The Pinocchio configuration of a reading."""
        return self.body.configuration(reading.base_position_m, reading.base_quaternion_xyzw, reading.q_rad)

    def step(self, torque_Nm: np.ndarray) -> Reading:
        self.step_torques(torque_Nm)
        return self.read()

    def render(self, width: int = 480, height: int = 480, yaw_deg: float = 30.0) -> np.ndarray:
        """An offscreen RGB image (height x width x 3, uint8) of the robot, with PyBullet's software
        renderer."""
        pos, _, _, _ = self.base_state()
        # head to feet
        return super().render([pos[0], pos[1], 0.9], 4.0, yaw_deg, -10.0, width, height, fov_deg=40.0)

    def command(self, cmd) -> Reading:
        """One control step with an :class:`~humanoid_pb.control.balance.ImpedanceCommand`."""
        self.step_impedance(cmd.feedforward_Nm, cmd.q_des, cmd.kp_Nm_rad, cmd.kd_Nm_s_rad)
        return self.read()
