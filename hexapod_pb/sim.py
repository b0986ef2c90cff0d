"""The hexapod in PyBullet, run like a rig: the only module that talks to PyBullet.

One ``BulletClient`` per world (DIRECT by default).  Joint and link names are
mapped to indices once.  The default velocity motors are disabled and the
commanded torques -- held between control steps, like a fixed-rate
controller's output -- are sent before every physics step.  Each control step
also advances the thermal plant of all 18 actuators with the torques actually
applied (after thermal derating) and records a canonical thermal log.

What the controller sees (:class:`Reading`) is what hardware gives it: joint
encoders, series-elastic torque sensing (applied torque plus noise), the
plant's measured temperatures, an IMU (body orientation and angular rate) and
a body-velocity estimate.
"""

from __future__ import annotations

import contextlib
import os
import sys
from dataclasses import dataclass, field

import numpy as np
import pybullet
from pybullet_utils.bullet_client import BulletClient

from thermolimb.logs import ThermalLog, log_from_arrays
from thermolimb.plant import ACTUATORS, PlantEffects, ThermalPlant, ThermalProtection

from .constants import ACTUATOR_MODEL, FEET, JOINT_KINDS, JOINTS, LEGS, PAYLOAD_LINK
from .kinematics import inverse_kinematics, nominal_foot
from .params import DAISY, GRAVITY_M_S2, DaisyParams
from .urdf_model import urdf_path


@contextlib.contextmanager
def silenced_stdout():
    """PyBullet prints to the C-level standard output on connect; keep it off ours (``--json`` output)."""
    sys.stdout.flush()
    saved = os.dup(1)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        yield
    finally:
        os.dup2(saved, 1)
        os.close(devnull)
        os.close(saved)


@dataclass(frozen=True)
class SimConfig:
    physics_hz: float = 500.0
    control_hz: float = 50.0  # as on the real Daisy
    gui: bool = False
    fixed_base: bool = False  # hang the body in the air (kinematic checks)
    payload_kg: float = 0.0
    foot_friction: float = 0.9
    torque_noise_Nm: float = 0.05  # series-elastic torque sensing noise (1 sigma)
    ambient_C: float = 25.0

    def __post_init__(self):
        if not (self.physics_hz > 0 and self.control_hz > 0):
            raise ValueError("physics_hz and control_hz must be positive")
        ratio = self.physics_hz / self.control_hz
        if abs(ratio - round(ratio)) > 1e-9 or ratio < 1:
            raise ValueError(f"physics_hz ({self.physics_hz}) must be a whole multiple of control_hz ({self.control_hz})")
        if self.payload_kg < 0:
            raise ValueError(f"payload_kg must be >= 0, got {self.payload_kg}")

    @property
    def substeps(self) -> int:
        return int(round(self.physics_hz / self.control_hz))

    @property
    def control_dt_s(self) -> float:
        return 1.0 / self.control_hz


@dataclass(frozen=True)
class Reading:
    """One control step's sensor data (arrays in JOINTS / LEGS order)."""

    time_s: float
    q_rad: np.ndarray  # (18,)
    qd_rad_s: np.ndarray  # (18,)
    torque_Nm: np.ndarray  # (18,) sensed
    temperature_C: np.ndarray  # (18,) measured winding temperatures
    world_R_body: np.ndarray  # (3, 3) IMU orientation
    body_omega_rad_s: np.ndarray  # (3,) IMU angular rate, body frame
    body_velocity_m_s: np.ndarray  # (3,) velocity estimate, body frame
    body_position_m: np.ndarray  # (3,) position estimate, world frame (for logging and scenarios)
    contact_force_N: np.ndarray = field(default=None)  # (6, 3) per foot, world frame, force on the foot


class HexapodSim:
    """A world with the hexapod, its thermal plant and its log."""

    def __init__(self, params: DaisyParams = DAISY, config: SimConfig = SimConfig(),
                 plant_effects: PlantEffects = PlantEffects.realistic_sensor(), seed: int = 0,
                 protection: ThermalProtection = ThermalProtection()):
        self.params = params
        self.config = config
        self.rng = np.random.default_rng(seed)
        mode = pybullet.GUI if config.gui else pybullet.DIRECT
        with silenced_stdout():
            self.client = BulletClient(connection_mode=mode)
        c = self.client
        c.setGravity(0, 0, -GRAVITY_M_S2)
        c.setTimeStep(1.0 / config.physics_hz)
        plane = c.createCollisionShape(pybullet.GEOM_PLANE)
        self.ground = c.createMultiBody(0, plane)
        c.changeDynamics(self.ground, -1, lateralFriction=config.foot_friction)
        start_height = params.nominal_body_height_m + (0.3 if config.fixed_base else 0.0)
        self.robot = c.loadURDF(str(urdf_path()), [0, 0, start_height], useFixedBase=config.fixed_base,
                                flags=pybullet.URDF_USE_INERTIA_FROM_FILE)
        self._index_names()
        for j in self.joint_index:
            c.setJointMotorControl2(self.robot, j, pybullet.VELOCITY_CONTROL, force=0.0)
        for j in self.foot_index:
            c.changeDynamics(self.robot, j, lateralFriction=config.foot_friction)
        c.changeDynamics(self.robot, self.link_index[PAYLOAD_LINK], mass=max(config.payload_kg, 1e-3))
        self.reset_stance()
        specs = [ACTUATORS[ACTUATOR_MODEL[k]] for _ in LEGS for k in JOINT_KINDS]
        self.plant = ThermalPlant(JOINTS, specs, effects=plant_effects, ambient_C=config.ambient_C,
                                  rng=self.rng, protection=protection)
        self.time_s = 0.0
        self._command = np.zeros(len(JOINTS))
        self._applied = np.zeros(len(JOINTS))
        self._log: dict[str, list] = {"time": [], "effort": [], "velocity": [], "temperature": [], "ambient": []}

    # ------------------------------------------------------------------ setup
    def _index_names(self):
        c = self.client
        by_joint, by_link = {}, {}
        for j in range(c.getNumJoints(self.robot)):
            info = c.getJointInfo(self.robot, j)
            by_joint[info[1].decode()] = j
            by_link[info[12].decode()] = j
        missing = [n for n in JOINTS if n not in by_joint] + [n for n in FEET if n not in by_link]
        if missing:
            raise RuntimeError(f"the URDF lacks {missing}; regenerate it with python -m hexapod_pb.urdf_model")
        self.joint_index = [by_joint[n] for n in JOINTS]
        self.foot_index = [by_link[n] for n in FEET]
        self.link_index = by_link

    def stance_angles(self, body_p_feet: np.ndarray | None = None) -> np.ndarray:
        """Joint angles (18,) putting each foot at ``body_p_feet`` (6 x 3), default the nominal stance."""
        feet = [nominal_foot(self.params, i) for i in range(len(LEGS))] if body_p_feet is None else body_p_feet
        return np.concatenate([inverse_kinematics(self.params, i, feet[i]) for i in range(len(LEGS))])

    def reset_stance(self, q: np.ndarray | None = None) -> None:
        q = self.stance_angles() if q is None else q
        for j, angle in zip(self.joint_index, q):
            self.client.resetJointState(self.robot, j, float(angle), 0.0)

    # ---------------------------------------------------------------- sensing
    def read(self) -> Reading:
        c = self.client
        states = c.getJointStates(self.robot, self.joint_index)
        q = np.array([s[0] for s in states])
        qd = np.array([s[1] for s in states])
        pos, orn = c.getBasePositionAndOrientation(self.robot)
        lin, ang = c.getBaseVelocity(self.robot)
        world_R_body = np.array(c.getMatrixFromQuaternion(orn)).reshape(3, 3)
        sensed = self._applied + self.rng.normal(0.0, self.config.torque_noise_Nm, self._applied.shape)
        return Reading(
            time_s=self.time_s, q_rad=q, qd_rad_s=qd, torque_Nm=sensed,
            temperature_C=self.plant.measured_C, world_R_body=world_R_body,
            body_omega_rad_s=world_R_body.T @ np.array(ang), body_velocity_m_s=world_R_body.T @ np.array(lin),
            body_position_m=np.array(pos), contact_force_N=self.contact_forces(),
        )

    def contact_forces(self) -> np.ndarray:
        """Ground force on each foot (6 x 3, world frame, N), rebuilt from the contact points."""
        out = np.zeros((len(LEGS), 3))
        for point in self.client.getContactPoints(bodyA=self.ground, bodyB=self.robot):
            link = point[4]
            if link not in self.foot_index:
                continue
            leg = self.foot_index.index(link)
            # PyBullet's normal on B points towards A: the ground pushes the foot along -n; the friction
            # force on A is fn n - (f1 d1 + f2 d2), so on B it is the opposite
            normal_on_b = np.array(point[7])
            out[leg] += -point[9] * normal_on_b + point[10] * np.array(point[11]) + point[12] * np.array(point[13])
        return out

    def foot_positions_world(self) -> np.ndarray:
        states = self.client.getLinkStates(self.robot, self.foot_index)
        return np.array([s[4] for s in states])

    def body_pose(self) -> tuple[np.ndarray, np.ndarray]:
        pos, orn = self.client.getBasePositionAndOrientation(self.robot)
        return np.array(pos), np.array(self.client.getMatrixFromQuaternion(orn)).reshape(3, 3)

    def foot_jacobian_world(self, leg: int) -> np.ndarray:
        """PyBullet's linear Jacobian (3 x 3) of a foot with respect to its leg's joints (fixed base only)."""
        q = [s[0] for s in self.client.getJointStates(self.robot, self.joint_index)]
        zeros = [0.0] * len(q)
        lin, _ = self.client.calculateJacobian(self.robot, self.foot_index[leg], [0, 0, 0], q, zeros, zeros)
        lin = np.array(lin)
        offset = lin.shape[1] - len(q)  # 6 floating-base columns when not fixed
        return lin[:, offset + 3 * leg : offset + 3 * leg + 3]

    # --------------------------------------------------------------- stepping
    def step(self, torque_Nm: np.ndarray) -> Reading:
        """Hold ``torque_Nm`` (18,) for one control period, derated by thermal protection; return the next reading."""
        limit = self.params.effort_limit_Nm
        command = np.clip(np.asarray(torque_Nm, float), -limit, limit)
        self._command = command
        self._applied = self.plant.derate(command)
        c = self.client
        for _ in range(self.config.substeps):
            c.setJointMotorControlArray(self.robot, self.joint_index, pybullet.TORQUE_CONTROL,
                                        forces=self._applied.tolist())
            c.stepSimulation()
        qd = np.array([s[1] for s in c.getJointStates(self.robot, self.joint_index)])
        self._record(qd)
        self.plant.step(self._applied, qd, self.config.control_dt_s)
        self.time_s += self.config.control_dt_s
        return self.read()

    def _record(self, qd: np.ndarray) -> None:
        self._log["time"].append(self.time_s)
        self._log["effort"].append(self._applied.copy())
        self._log["velocity"].append(qd)
        self._log["temperature"].append(self.plant.measured_C)
        self._log["ambient"].append(self.plant.ambient_C)

    def thermal_log(self) -> ThermalLog:
        """What the robot logged so far, in the canonical format (one row per actuator and control step)."""
        if len(self._log["time"]) < 2:
            raise ValueError("the simulation has not run long enough to make a log")
        return log_from_arrays(np.array(self._log["time"]), JOINTS, np.array(self._log["effort"]),
                               np.array(self._log["temperature"]), velocity=np.array(self._log["velocity"]),
                               ambient_C=np.array(self._log["ambient"]), source="hexapod simulation")

    def close(self) -> None:
        if self.client is not None:
            self.client.disconnect()
            self.client = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
