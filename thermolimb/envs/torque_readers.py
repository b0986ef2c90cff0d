"""What :class:`~.thermal_wrapper.ThermalWrapper` reads from an environment after each step: how long a step
is (:func:`step_seconds`) and the joints' torques and velocities (:func:`torque_reader`: a MuJoCo model's
actuators, this suite's PyBullet robots, or the user's ``torque=f(env)``)."""

from __future__ import annotations

from typing import Callable, Sequence

import gymnasium as gym
import numpy as np

from ..util.errors import UsageError


def step_seconds(env: gym.Env) -> float:
    """The simulated time one ``step`` covers: ``env.unwrapped.dt`` (MuJoCo's and most environments'), or the
    suite's robots' ``decision_s``."""
    u = env.unwrapped
    for name in ("dt", "decision_s"):
        value = getattr(u, name, None)
        if isinstance(value, (int, float)) and value > 0:
            return float(value)
    raise UsageError(f"{type(u).__name__} does not say how long a "
                     "step is (no dt); wrap an environment with one")


class TorqueReader:
    """The joints' torques (and velocities, when known) after a step, from ``f(env) -> array`` (N m).

    ``per_effort``: the factor turning a torque into the effort a model heats from (a current: 1 / the torque
    constant), or ``None`` for torque.  Subclasses read a MuJoCo model's actuators or the suite's robots; each
    is a plain object, so that a wrapped environment pickles (a subprocess vector environment)."""

    per_effort: float | None = None

    def __init__(self, joints: Sequence[str], torque: Callable | None = None):
        self.joints = tuple(joints)
        self.torque = torque

    def raw(self, env) -> tuple[np.ndarray, np.ndarray | None]:
        return self.torque(env), None

    def read(self, env) -> tuple[np.ndarray, np.ndarray | None]:
        torque, velocity = self.raw(env)
        torque = np.asarray(torque, float)
        if torque.shape != (len(self.joints),) or not np.isfinite(torque).all():
            raise UsageError(f"the torque read for {len(self.joints)} joints "
                             f"is {torque!r}; expected that many finite "
                             f"numbers (N m)")
        return torque, velocity

    def derated(self, env, action, fraction: np.ndarray):
        raise UsageError("protect=True scales each actuator's command: this environment's actuators are not "
                         "known to the wrapper (give a MuJoCo environment, or scale the action yourself)")


class MujocoReader(TorqueReader):
    """A MuJoCo environment's actuator forces times their gears, and its actuator velocities over them."""

    def __init__(self, joints: Sequence[str], idx, gear: np.ndarray):
        super().__init__(joints)
        self.idx, self.gear = idx, gear

    def raw(self, env):
        data = env.unwrapped.data
        return data.actuator_force[self.idx] * self.gear, data.actuator_velocity[self.idx] / self.gear

    def derated(self, env, action, fraction):
        scaled = np.array(action, dtype=float, copy=True)
        scaled[self.idx] = scaled[self.idx] * fraction
        return scaled.astype(np.asarray(action).dtype)


class RigReader(TorqueReader):
    """The suite's PyBullet robots: the rig's applied torques and joint velocities (the world is rebuilt at
    every reset, so it is looked up each step)."""

    def __init__(self, joints: Sequence[str], idx: np.ndarray):
        super().__init__(joints)
        self.idx = idx

    def raw(self, env):
        rig = env.unwrapped.sim
        return rig.applied_Nm[self.idx], rig.joint_states()[1][self.idx]


def torque_reader(env: gym.Env, joints: Sequence[str] | None, torque: Callable | None) -> TorqueReader:
    u = env.unwrapped
    if torque is not None:
        if not joints:
            raise UsageError("torque=f(env) needs joints=[...]: the names of the torques it returns, in "
                             "order")
        return TorqueReader(joints, torque)
    model = getattr(u, "model", None)
    if model is not None and hasattr(model, "actuator_gear") and hasattr(u, "data"):
        names = mujoco_actuator_names(model)
        chosen = list(joints) if joints else names
        missing = [j for j in chosen if j not in names]
        if missing:
            raise UsageError(f"joints {missing} are not actuators of this "
                             f"MuJoCo model; it has {', '.join(names)}")
        idx = np.array([names.index(j) for j in chosen])
        gear = model.actuator_gear[idx, 0].copy()
        if np.array_equal(idx, np.arange(idx[0], idx[0] + idx.size)):  # in order: a view, not a gather
            idx = slice(int(idx[0]), int(idx[0]) + idx.size)
        return MujocoReader(chosen, idx, gear)
    if getattr(u, "JOINTS", ()) and hasattr(u, "sim"):  # this suite's robots (their world is built at reset)
        names = list(u.JOINTS)
        chosen = list(joints) if joints else names
        missing = [j for j in chosen if j not in names]
        if missing:
            raise UsageError(f"joints {missing} are not joints of this robot; it has {', '.join(names)}")
        return RigReader(chosen, np.array([names.index(j) for j in chosen]))
    raise UsageError(f"{type(u).__name__}: the wrapper reads torques "
                     "from MuJoCo environments and this suite's "
                     f"PyBullet robots; for another environment pass torque=f(env) and joints=[...]")


def mujoco_actuator_names(model) -> list[str]:
    """Each actuator's name, or for an unnamed one (Gymnasium's Ant) the name of the joint it drives."""
    import mujoco

    names = []
    for i in range(model.nu):
        name = model.actuator(i).name
        if not name and model.actuator_trntype[i] == mujoco.mjtTrn.mjTRN_JOINT:
            name = model.joint(int(model.actuator_trnid[i, 0])).name
        names.append(name or f"actuator{i}")
    return names
