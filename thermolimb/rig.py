"""A robot in PyBullet run like a hardware-in-the-loop rig: what every robot of the suite shares.

One ``BulletClient`` per world (DIRECT by default, GUI on request); joint and
link names mapped to indices once; default velocity motors disabled; the
commanded torques, held between control steps like a fixed-rate controller's
output, sent before every physics step.  Each control step also advances the
thermal plant with the actuators' efforts (after thermal derating) and records
a canonical thermal log.  Robots subclass :class:`BulletRig` to say how joint
torques become actuator efforts (one-to-one by default; push rods otherwise).
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import sys
from collections import deque
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import numpy as np

from .constants import GRAVITY_M_S2
from .logs import ThermalLog, log_from_arrays
from .plant import ActuatorSpec, PlantEffects, ThermalPlant, ThermalProtection
from .util.errors import check_range

_LIBC = ctypes.CDLL(None)  # the process's C library: its fflush empties what C code buffered


@contextlib.contextmanager
def silenced(fd: int = 1):
    """Keep what C code prints on file descriptor ``fd`` off ours: PyBullet prints its build time on the
    standard error when imported (a second line under a one-line error) and more on the standard output when
    it connects (``--json`` output)."""
    stream = sys.stdout if fd == 1 else sys.stderr
    stream.flush()
    saved = os.dup(fd)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, fd)
        yield
    finally:
        # C's own buffer too: where the standard output is a file or a pipe, what PyBullet printed
        # ("argv[0]=") would otherwise be written later, on our stream
        _LIBC.fflush(None)
        os.dup2(saved, fd)
        os.close(devnull)
        os.close(saved)


with silenced(2):
    import pybullet
    from pybullet_utils.bullet_client import BulletClient


@dataclass(frozen=True)
class RigConfig:
    physics_hz: float = 500.0
    control_hz: float = 50.0
    gui: bool = False
    fixed_base: bool = False
    foot_friction: float = 0.9
    torque_noise_Nm: float = 0.05  # torque sensing noise (1 sigma)
    ambient_C: float = 25.0
    log_capacity: int | None = None  # control steps the in-memory log keeps (the latest); None: all of them

    def __post_init__(self):
        owner = type(self).__name__
        check_range(owner, "physics_hz", self.physics_hz, 1.0, 100_000.0, "Hz")
        check_range(owner, "control_hz", self.control_hz, 0.01, 100_000.0, "Hz")
        check_range(owner, "foot_friction", self.foot_friction, 0.0, 10.0)
        check_range(owner, "torque_noise_Nm", self.torque_noise_Nm, 0.0, 100.0, "N m")
        check_range(owner, "ambient_C", self.ambient_C, -60.0, 150.0, "degC")
        if self.log_capacity is not None and self.log_capacity < 2:
            raise ValueError(
                f"log_capacity must be None or at least 2 control steps, got {self.log_capacity}"
            )
        ratio = self.physics_hz / self.control_hz
        if abs(ratio - round(ratio)) > 1e-9 or ratio < 1:
            raise ValueError(f"physics_hz ({self.physics_hz}) must be a whole "
                             f"multiple of control_hz ({self.control_hz})")

    @property
    def substeps(self) -> int:
        return int(round(self.physics_hz / self.control_hz))

    @property
    def control_dt_s(self) -> float:
        return 1.0 / self.control_hz


class BulletRig:
    """A world with one robot, its thermal plant and its log."""

    def __init__(self, urdf: Path, joints: Sequence[str], feet: Sequence[str], actuators: Sequence[str],
                 specs: Sequence[ActuatorSpec], effort_limit: np.ndarray, config: RigConfig,
                 base_position_m: Sequence[float], base_quaternion_xyzw: Sequence[float] = (0, 0, 0, 1),
                 plant_effects: PlantEffects = PlantEffects.realistic_sensor(), seed: int = 0,
                 protection: ThermalProtection = ThermalProtection()):
        self.config = config
        self.joints = tuple(joints)
        self.actuators = tuple(actuators)
        self.effort_limit = np.asarray(effort_limit, float)
        self.rng = np.random.default_rng(seed)
        with silenced():
            self.client = BulletClient(connection_mode=pybullet.GUI if config.gui else pybullet.DIRECT)
        c = self.client
        c.setGravity(0, 0, -GRAVITY_M_S2)
        c.setTimeStep(1.0 / config.physics_hz)
        self.ground = c.createMultiBody(0, c.createCollisionShape(pybullet.GEOM_PLANE))
        c.changeDynamics(self.ground, -1, lateralFriction=config.foot_friction)
        self.robot = c.loadURDF(str(urdf), list(base_position_m), list(base_quaternion_xyzw),
                                useFixedBase=config.fixed_base, flags=pybullet.URDF_USE_INERTIA_FROM_FILE)
        by_joint, by_link = {}, {}
        for j in range(c.getNumJoints(self.robot)):
            info = c.getJointInfo(self.robot, j)
            by_joint[info[1].decode()] = j
            by_link[info[12].decode()] = j
        missing = [n for n in self.joints if n not in by_joint] + [n for n in feet if n not in by_link]
        if missing:
            raise RuntimeError(f"{urdf.name} lacks {missing}; regenerate it from its parameters")
        self.joint_index = [by_joint[n] for n in self.joints]
        self.foot_index = [by_link[n] for n in feet]
        self.link_index = by_link
        for j in self.joint_index:
            c.setJointMotorControl2(self.robot, j, pybullet.VELOCITY_CONTROL, force=0.0)
        for j in self.foot_index:
            c.changeDynamics(self.robot, j, lateralFriction=config.foot_friction)
        self.plant = ThermalPlant(self.actuators, specs, effects=plant_effects, ambient_C=config.ambient_C,
                                  rng=self.rng, protection=protection)
        self.time_s = 0.0
        self.control_steps = 0  # time_s is this many control periods (a product, not a sum that drifts)
        self._joint_states = None  # (q, qd) read since the last physics step: read once, whoever asks
        self.applied_Nm = np.zeros(len(self.joints))
        # the actuators' efforts over the last control period
        self.last_efforts = np.zeros(len(self.actuators))
        self._log = {key: deque(maxlen=config.log_capacity)
                     for key in ("time", "effort", "velocity", "temperature", "ambient", "fault")}
        from .monitor.live import from_environment

        self.stream = from_environment()  # a live view of the plant (thermolimb.monitor.live), when asked for

    # ------------------------------------------------------------- robot hooks
    def actuator_efforts(self, q: np.ndarray, torques_Nm: np.ndarray) -> np.ndarray:
        """Actuator efforts for joint torques (one actuator per joint unless a robot says otherwise)."""
        return torques_Nm

    def actuator_velocities(self, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        return qd

    def torques_at_fraction(self, torques_Nm: np.ndarray, actuator_fraction: np.ndarray) -> np.ndarray:
        """Joint torques when each actuator may give ``actuator_fraction`` of its effort (one-to-one by
        default)."""
        return self.plant.scale_efforts(torques_Nm, actuator_fraction)

    def protected_torques(self, q: np.ndarray, qd: np.ndarray, torques_Nm: np.ndarray) -> np.ndarray:
        """Joint torques after thermal protection, for torques to be held over one control period.

        Every robot goes through this one call: the actuators' efforts and
        speeds for these torques, the plant's :meth:`~ThermalPlant.protection_fraction`
        with the control period (so the observer's predictive current cap acts
        at slow control rates too), mapped back to the joints.
        """
        return self.torques_at_fraction(torques_Nm, self._protection_fraction(q, qd, torques_Nm))

    def _protection_fraction(self, q: np.ndarray, qd: np.ndarray, torques_Nm: np.ndarray) -> np.ndarray:
        efforts = self.actuator_efforts(q, torques_Nm)
        return self.plant.protection_fraction(efforts, self.actuator_velocities(q, qd),
                                              self.config.control_dt_s)

    # ----------------------------------------------------------------- sensing
    def joint_states(self) -> tuple[np.ndarray, np.ndarray]:
        """Joint angles (rad) and rates (rad/s), read from PyBullet once per physics state: the period's end,
        the robot's reading and the next period's start share one read."""
        q, qd = self._states()
        return q.copy(), qd.copy()

    def _states(self) -> tuple[np.ndarray, np.ndarray]:  # the read itself, not to be written to
        if self._joint_states is None:
            states = self.client.getJointStates(self.robot, self.joint_index)
            self._joint_states = np.array([s[0] for s in states]), np.array([s[1] for s in states])
        return self._joint_states

    def set_joint_positions(self, q: np.ndarray) -> None:
        for j, angle in zip(self.joint_index, q):
            self.client.resetJointState(self.robot, j, float(angle), 0.0)
        self._joint_states = None

    def base_state(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(position, world_R_base, linear velocity, angular velocity)``, world frame."""
        pos, orn = self.client.getBasePositionAndOrientation(self.robot)
        lin, ang = self.client.getBaseVelocity(self.robot)
        R = np.array(self.client.getMatrixFromQuaternion(orn)).reshape(3, 3)
        return np.array(pos), R, np.array(lin), np.array(ang)

    def render(self, target_m, distance_m: float, yaw_deg: float, pitch_deg: float, width: int = 240,
               height: int = 240, fov_deg: float = 50.0) -> np.ndarray:
        """An offscreen RGB image (height x width x 3, uint8) from PyBullet's software renderer."""
        c = self.client
        view = c.computeViewMatrixFromYawPitchRoll([float(v) for v in target_m], distance_m, yaw_deg,
                                                   pitch_deg, 0.0, 2)
        proj = c.computeProjectionMatrixFOV(fov_deg, width / height, 0.05, 10.0)
        _, _, rgba, _, _ = c.getCameraImage(width, height, view, proj, renderer=c.ER_TINY_RENDERER)
        return np.asarray(rgba, dtype=np.uint8).reshape(height, width, 4)[:, :, :3]

    def joint_space_dynamics(self) -> tuple[np.ndarray, np.ndarray]:
        """PyBullet's mass matrix and gravity torques ``(M, g)`` over the joints at the current configuration.

        The floating base's rows and columns, if any, are left out (g then
        holds the joints with the base held still).
        """
        q = [float(v) for v in self.joint_states()[0]]
        zeros = [0.0] * len(q)
        M = np.array(self.client.calculateMassMatrix(self.robot, q))
        g = np.array(self.client.calculateInverseDynamics(self.robot, q, zeros, zeros))
        offset = M.shape[0] - len(q)
        return M[offset:, offset:], g[offset:]

    def base_quaternion(self) -> np.ndarray:
        return np.array(self.client.getBasePositionAndOrientation(self.robot)[1])

    def contact_forces(self) -> np.ndarray:
        """Ground force on each foot link (k x 3, world frame, N), rebuilt from the contact points."""
        out = np.zeros((len(self.foot_index), 3))
        for point in self.client.getContactPoints(bodyA=self.ground, bodyB=self.robot):
            if point[4] not in self.foot_index:
                continue
            # PyBullet's normal on B points towards A: the ground pushes the foot along -n; the friction
            # force on A is fn n - (f1 d1 + f2 d2), so on B it is the opposite
            out[self.foot_index.index(point[4])] += (
                -point[9] * np.array(point[7])
                + point[10] * np.array(point[11])
                + point[12] * np.array(point[13])
            )
        return out

    def link_positions(self, links: Sequence[int]) -> np.ndarray:
        return np.array([s[4] for s in self.client.getLinkStates(self.robot, list(links))])

    def sensed_torques(self) -> np.ndarray:
        return self.applied_Nm + self.rng.normal(0.0, self.config.torque_noise_Nm, self.applied_Nm.shape)

    # ---------------------------------------------------------------- stepping
    def step_torques(self, torque_Nm: np.ndarray) -> None:
        """Hold ``torque_Nm`` for one control period (clipped, thermally derated), then step the plant."""
        q, qd = self.joint_states()
        command = np.clip(np.asarray(torque_Nm, float), -self.effort_limit, self.effort_limit)
        self.applied_Nm = self.protected_torques(q, qd, command)
        forces = self.applied_Nm.tolist()
        apply, step = self.client.setJointMotorControlArray, self.client.stepSimulation  # bound once
        for _ in range(self.config.substeps):
            apply(self.robot, self.joint_index, pybullet.TORQUE_CONTROL, forces=forces)
            step()
        self._joint_states = None
        self._after_control_period()

    def step_impedance(self, feedforward_Nm: np.ndarray, q_des: np.ndarray, kp_Nm_rad: np.ndarray,
                       kd_Nm_s_rad: np.ndarray) -> None:
        """One control period with the actuators' own joint impedance loop run at the physics rate.

        Every physics step applies ``tau = tau_ff + kp (q_des - q) - kd qd``
        (clipped to the effort limits), scaled by the share thermal protection
        allows for the torques the loop asks for at the period's start; the
        plant and the log see the period's mean.
        """
        def loop(q, qd):  # the actuators' joint impedance, within the effort limits
            return np.clip(feedforward_Nm + kp_Nm_rad * (q_des - q) - kd_Nm_s_rad * qd, -self.effort_limit,
                           self.effort_limit)

        q, qd = self.joint_states()
        fraction = self._protection_fraction(q, qd, loop(q, qd))
        # bound once: the loop runs at the physics rate, where each lookup through the client costs
        apply, step = self.client.setJointMotorControlArray, self.client.stepSimulation
        total = np.zeros(len(self.joints))
        for _ in range(self.config.substeps):
            tau = self.torques_at_fraction(loop(*self._states()), fraction)
            apply(self.robot, self.joint_index, pybullet.TORQUE_CONTROL, forces=tau.tolist())
            step()
            self._joint_states = None
            total += tau
        self.applied_Nm = total / self.config.substeps
        self._after_control_period()

    def _after_control_period(self) -> None:
        q, qd = self.joint_states()
        efforts = self.actuator_efforts(q, self.applied_Nm)
        self.last_efforts = efforts
        velocities = self.actuator_velocities(q, qd)
        self._log["time"].append(self.time_s)
        self._log["effort"].append(efforts)
        self._log["velocity"].append(velocities)
        self._log["temperature"].append(self.plant.measured_C)
        self._log["ambient"].append(self.plant.ambient_C)
        self.plant.step(efforts, velocities, self.config.control_dt_s)
        self._log["fault"].append(self.plant.faulted.astype(float))  # a drive faulted by a non-finite command
        self.control_steps += 1
        self.time_s = round(self.control_steps * self.config.control_dt_s, 9)
        if self.stream is not None:
            self.stream.publish(self)

    def plant_faults(self) -> dict:
        """The drives' faults and saturations so far, for an environment's ``info``: ``actuator_faults`` (the
        actuators a non-finite command faulted) and ``saturated_steps`` (control periods each held at its
        peak)."""
        plant = self.plant
        return {"actuator_faults": [n for n, f in zip(plant.names, plant.faulted) if f],
                "saturated_steps": {n: int(c) for n, c in zip(plant.names, plant.saturations) if c}}

    def thermal_log(self) -> ThermalLog:
        """What the robot logged so far (the latest ``log_capacity`` control steps, if bounded), in the
        canonical format (one row per actuator and control step)."""
        if len(self._log["time"]) < 2:
            raise ValueError("the simulation has not run long enough to make a log")
        faults = np.array(self._log["fault"])
        return log_from_arrays(np.array(self._log["time"]), self.actuators, np.array(self._log["effort"]),
                               np.array(self._log["temperature"]), velocity=np.array(self._log["velocity"]),
                               ambient_C=np.array(self._log["ambient"]), source=f"{type(self).__name__} "
                               f"simulation", extra={"fault [1]": faults} if faults.any() else None)

    def close(self) -> None:
        if self.client is not None:
            self.client.disconnect()
            self.client = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
