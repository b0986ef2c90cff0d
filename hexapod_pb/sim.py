"""The hexapod on the shared PyBullet rig (:mod:`thermolimb.rig`): the hexapod's only module that talks to
PyBullet.

One ``BulletClient`` per world (DIRECT by default).  Joint and link names are
mapped to indices once.  The default velocity motors are disabled and the
commanded torques -- held between control steps, like a fixed-rate
controller's output -- are sent before every physics step.  Each control step
also advances the thermal plant of all 18 actuators with the torques actually
applied (after thermal derating) and records a canonical thermal log.

What the controller sees (:class:`~hexapod_pb.readings.Reading`) is what hardware gives it: joint
encoders, series-elastic torque sensing (applied torque plus noise), the
plant's measured temperatures, an IMU (body orientation and angular rate) and
a body-velocity estimate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from thermolimb.plant import PlantEffects, ThermalProtection
from thermolimb.rig import BulletRig, RigConfig
from thermolimb.util.errors import check_range

from .constants import FEET, JOINTS, LEGS, PAYLOAD_LINK
from .model.daisy_urdf import urdf_path
from .model.kinematics import inverse_kinematics, nominal_foot
from .params import DAISY, DaisyParams
from .readings import Reading


@dataclass(frozen=True)
class SimConfig(RigConfig):
    """The rig's rates and sensing, plus the payload fixed on top of the body (kg)."""

    payload_kg: float = 0.0

    def __post_init__(self):
        super().__post_init__()
        check_range("SimConfig", "payload_kg", self.payload_kg, 0.0, 1000.0, "kg")


class HexapodSim(BulletRig):
    """A world with the hexapod, its thermal plant and its log."""

    def __init__(self, params: DaisyParams = DAISY, config: SimConfig = SimConfig(),
                 plant_effects: PlantEffects = PlantEffects.realistic_sensor(), seed: int = 0,
                 protection: ThermalProtection = ThermalProtection()):
        self.params = params
        height = params.nominal_body_height_m + (0.3 if config.fixed_base else 0.0)
        super().__init__(urdf_path(), JOINTS, FEET, JOINTS, params.joint_actuators, params.effort_limit_Nm,
                         config, [0, 0, height], plant_effects=plant_effects, seed=seed,
                         protection=protection)
        self.client.changeDynamics(self.robot, self.link_index[PAYLOAD_LINK],
                                   mass=max(config.payload_kg, 1e-3))
        self.reset_stance()

    def stance_angles(self, body_p_feet: np.ndarray | None = None) -> np.ndarray:
        """Joint angles (18,) putting each foot at ``body_p_feet`` (6 x 3), default the nominal stance."""
        feet = (
            [nominal_foot(self.params, i) for i in range(len(LEGS))] if body_p_feet is None else body_p_feet
        )
        return np.concatenate([inverse_kinematics(self.params, i, feet[i]) for i in range(len(LEGS))])

    def reset_stance(self, q: np.ndarray | None = None) -> None:
        self.set_joint_positions(self.stance_angles() if q is None else q)

    # ---------------------------------------------------------------- sensing
    def read(self) -> Reading:
        q, qd = self.joint_states()
        pos, world_R_body, lin, ang = self.base_state()
        return Reading(time_s=self.time_s, q_rad=q, qd_rad_s=qd, torque_Nm=self.sensed_torques(),
                       temperature_C=self.plant.measured_C, world_R_body=world_R_body,
                       body_omega_rad_s=world_R_body.T @ ang, body_velocity_m_s=world_R_body.T @ lin,
                       body_position_m=pos, contact_force_N=self.contact_forces())

    def foot_positions_world(self) -> np.ndarray:
        return self.link_positions(self.foot_index)

    def body_pose(self) -> tuple[np.ndarray, np.ndarray]:
        pos, R, _, _ = self.base_state()
        return pos, R

    def foot_jacobian_world(self, leg: int) -> np.ndarray:
        """PyBullet's linear Jacobian (3 x 3) of a foot with respect to its leg's joints (fixed base only)."""
        q = [float(v) for v in self.joint_states()[0]]
        zeros = [0.0] * len(q)
        lin, _ = self.client.calculateJacobian(self.robot, self.foot_index[leg], [0, 0, 0], q, zeros, zeros)
        lin = np.array(lin)
        offset = lin.shape[1] - len(q)  # 6 floating-base columns when not fixed
        return lin[:, offset + 3 * leg : offset + 3 * leg + 3]

    # --------------------------------------------------------------- stepping
    def render(self, width: int = 240, height: int = 240) -> np.ndarray:
        """An offscreen RGB image of the robot, looking down at it from behind."""
        pos, _, _, _ = self.base_state()
        return super().render(pos, 1.5, 30.0, -25.0, width, height)

    def step(self, torque_Nm: np.ndarray) -> Reading:
        """Hold ``torque_Nm`` (18,) for one control period, derated by thermal protection; return the next
        reading."""
        self.step_torques(torque_Nm)
        return self.read()
