"""How joint torques become actuator efforts: one motor per joint, or a push-rod pair driving an ankle's or
the waist's pitch and roll together (Jorgensen et al.'s Eq. 24); actuator speeds and effort limits
likewise."""

from __future__ import annotations

import numpy as np

from ..constants import ACTUATORS, JOINTS, ROD_PAIRS, rod_actuators
from ..params import ValkyrieParams
from .pushrods import RodPair


def effort_limits(params: ValkyrieParams) -> np.ndarray:
    """Each actuator's effort limit (ACTUATORS order; N m for motors, N for rods)."""
    return np.array([params.rod_force_limit_N if "_rod_" in a else params.effort_limit(a) for a in ACTUATORS])


def rod_pairs(params: ValkyrieParams) -> dict[str, RodPair]:
    return {"left_ankle": RodPair(params.ankle_rod_m, *params.ankle_rod_arm_m),
            "right_ankle": RodPair(params.ankle_rod_m, *params.ankle_rod_arm_m),
            "waist": RodPair(params.waist_rod_m, *params.waist_rod_arm_m)}


_J = {name: i for i, name in enumerate(JOINTS)}
_A = {name: i for i, name in enumerate(ACTUATORS)}
_MOTORS = [(a, _J[a]) for a in ACTUATORS if "_rod_" not in a]


def rod_jacobians(rods: dict[str, RodPair], angles: np.ndarray) -> dict[str, np.ndarray]:
    """Each rod pair's length Jacobian (2 x 2: rod lengths by pitch and roll) at joint ``angles``: what the
    efforts and speeds at one configuration share."""
    return {pair: rods[pair].length_jacobian(angles[_J[pitch]], angles[_J[roll]])
            for pair, (pitch, roll) in ROD_PAIRS.items()}


def efforts(rods: dict[str, RodPair], angles: np.ndarray, torques_Nm: np.ndarray,
            jacobians: dict[str, np.ndarray] | None = None) -> np.ndarray:
    """Eq. 24: actuator efforts (ACTUATORS order; N m for motors, N for rods) from joint torques (JOINTS
    order); ``jacobians``: :func:`rod_jacobians` at ``angles``, when already computed."""
    jacobians = jacobians or rod_jacobians(rods, angles)
    out = np.empty(len(ACTUATORS))
    for a, j in _MOTORS:
        out[_A[a]] = torques_Nm[j]
    for pair, (pitch, roll) in ROD_PAIRS.items():
        tau = np.array([torques_Nm[_J[pitch]], torques_Nm[_J[roll]]])
        out[[_A[rod] for rod in rod_actuators(pair)]] = np.linalg.solve(jacobians[pair].T, tau)
    return out


def velocities(rods: dict[str, RodPair], angles: np.ndarray, qd: np.ndarray,
               jacobians: dict[str, np.ndarray] | None = None) -> np.ndarray:
    """Actuator speeds: joint rates for motors, rod length rates (m/s) for rods."""
    jacobians = jacobians or rod_jacobians(rods, angles)
    out = np.empty(len(ACTUATORS))
    for a, j in _MOTORS:
        out[_A[a]] = qd[j]
    for pair, (pitch, roll) in ROD_PAIRS.items():
        out[[_A[rod] for rod in rod_actuators(pair)]] = jacobians[pair] @ np.array(
            [qd[_J[pitch]], qd[_J[roll]]]
        )
    return out


def joint_fractions(actuator_fraction: np.ndarray) -> np.ndarray:
    """Allowed torque fraction per joint from per-actuator derating: a rod-driven joint takes its weaker
    rod's."""
    out = np.ones(len(JOINTS))
    for a, j in _MOTORS:
        out[j] = actuator_fraction[_A[a]]
    for pair, joints in ROD_PAIRS.items():
        weakest = min(actuator_fraction[_A[rod]] for rod in rod_actuators(pair))
        for joint in joints:
            out[_J[joint]] = weakest
    return out


_MOTOR_ROWS = np.array([_A[a] for a, _ in _MOTORS])
_MOTOR_COLS = np.array([j for _, j in _MOTORS])
ROD_BLOCKS = {  # each rod pair's rows (ACTUATORS) and columns (JOINTS: pitch, roll) in E
    pair: (np.array([_A[rod] for rod in rod_actuators(pair)]), np.array([_J[pitch], _J[roll]]))
    for pair, (pitch, roll) in ROD_PAIRS.items()}


def effort_matrix(rods: dict[str, RodPair], angles: np.ndarray) -> np.ndarray:
    """``E`` (ACTUATORS x JOINTS) with ``efforts = E tau`` at joint angles ``angles`` (Eq. 24 as a matrix)."""
    E = np.zeros((len(ACTUATORS), len(JOINTS)))
    E[_MOTOR_ROWS, _MOTOR_COLS] = 1.0
    for pair, (rows, cols) in ROD_BLOCKS.items():
        (a, b), (c, d) = rods[pair].length_jacobian(angles[cols[0]], angles[cols[1]]).T
        E[rows[:, None], cols] = np.array([[d, -b], [-c, a]]) / (a * d - b * c)  # the 2 x 2 inverse
    return E
