"""The humanoid's thermal actuators: rotary motors at most joints, push-rod pairs at the ankles and waist.

Valkyrie's actuator thermal data is not public; these specs are chosen so
that, like the seed's robot, the first-order time constant of a winding is
about 40 s (the seed's horizon is 20 s = RC/2) and balancing on one leg
heats the stance leg into the 75 degC warning zone within about two minutes.
"""

from __future__ import annotations

import numpy as np

from thermolimb.model import FirstOrderBank
from thermolimb.plant import ActuatorSpec, ThermalNetwork

from .constants import ACTUATORS, JOINTS, ROD_PAIRS, rod_actuators
from .params import ValkyrieParams
from .pushrods import RodPair

# winding (tau = 20 J/K * 2 K/W = 40 s) on a slow housing (2000 J/K, 1 K/W): chosen
VALKYRIE_NETWORK = ThermalNetwork(("winding", "housing"), (20.0, 2000.0), (2.0, 1.0))
WINDING_LIMIT_C = 150.0


def actuator_specs(params: ValkyrieParams) -> list[ActuatorSpec]:
    """One spec per actuator (ACTUATORS order): 0.5 ohm windings; 60 W of copper loss at 30 % of the effort limit."""
    specs = []
    for name in ACTUATORS:
        if "_rod_" in name:
            limit = params.rod_force_limit_N
        else:
            limit = params.effort_limit(name)
        per_amp = 0.3 * limit / np.sqrt(60.0 / 0.5)  # 60 W of copper loss at 30 % of the limit (chosen)
        specs.append(ActuatorSpec(name.split("_")[-1], per_amp, 0.5, limit, 0.4 * limit, 6.0, VALKYRIE_NETWORK,
                                  winding_limit_C=WINDING_LIMIT_C, driver=None))
    return specs


def datasheet_bank(params: ValkyrieParams, ambient_C: float = 25.0) -> FirstOrderBank:
    """Eq. 5 of every actuator from its data, without identification: the winding node on a housing at ambient.

    RC = C_w R_w (40 s) and betaR = R_e R_w / k^2: what a controller can plan
    with before it has a log of its own.
    """
    specs = actuator_specs(params)
    net = VALKYRIE_NETWORK
    rc = net.capacity_J_per_K[0] * net.resistance_K_per_W[0]
    beta = np.array([s.winding_resistance_ohm * net.resistance_K_per_W[0] / s.effort_per_amp**2 for s in specs])
    n = len(specs)
    return FirstOrderBank(np.full(n, rc), beta, np.zeros(n), np.full(n, ambient_C))


def effort_limits(params: ValkyrieParams) -> np.ndarray:
    """Each actuator's effort limit (ACTUATORS order; N m for motors, N for rods)."""
    return np.array([s.effort_limit for s in actuator_specs(params)])


def rod_pairs(params: ValkyrieParams) -> dict[str, RodPair]:
    return {"left_ankle": RodPair(params.ankle_rod_m, *params.ankle_rod_arm_m),
            "right_ankle": RodPair(params.ankle_rod_m, *params.ankle_rod_arm_m),
            "waist": RodPair(params.waist_rod_m, *params.waist_rod_arm_m)}


_J = {name: i for i, name in enumerate(JOINTS)}
_A = {name: i for i, name in enumerate(ACTUATORS)}
_MOTORS = [(a, _J[a]) for a in ACTUATORS if "_rod_" not in a]


def efforts(rods: dict[str, RodPair], angles: np.ndarray, torques_Nm: np.ndarray) -> np.ndarray:
    """Eq. 24: actuator efforts (ACTUATORS order; N m for motors, N for rods) from joint torques (JOINTS order)."""
    out = np.empty(len(ACTUATORS))
    for a, j in _MOTORS:
        out[_A[a]] = torques_Nm[j]
    for pair, (pitch, roll) in ROD_PAIRS.items():
        tau = np.array([torques_Nm[_J[pitch]], torques_Nm[_J[roll]]])
        out[[_A[rod] for rod in rod_actuators(pair)]] = rods[pair].rod_forces_N(angles[_J[pitch]], angles[_J[roll]], tau)
    return out


def velocities(rods: dict[str, RodPair], angles: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """Actuator speeds: joint rates for motors, rod length rates (m/s) for rods."""
    out = np.empty(len(ACTUATORS))
    for a, j in _MOTORS:
        out[_A[a]] = qd[j]
    for pair, (pitch, roll) in ROD_PAIRS.items():
        J = rods[pair].length_jacobian(angles[_J[pitch]], angles[_J[roll]])
        out[[_A[rod] for rod in rod_actuators(pair)]] = J @ np.array([qd[_J[pitch]], qd[_J[roll]]])
    return out


def joint_fractions(actuator_fraction: np.ndarray) -> np.ndarray:
    """Allowed torque fraction per joint from per-actuator derating: a rod-driven joint takes its weaker rod's."""
    out = np.ones(len(JOINTS))
    for a, j in _MOTORS:
        out[j] = actuator_fraction[_A[a]]
    for pair, joints in ROD_PAIRS.items():
        weakest = min(actuator_fraction[_A[rod]] for rod in rod_actuators(pair))
        for joint in joints:
            out[_J[joint]] = weakest
    return out


def effort_matrix(rods: dict[str, RodPair], angles: np.ndarray) -> np.ndarray:
    """``E`` (ACTUATORS x JOINTS) with ``efforts = E tau`` at joint angles ``angles`` (Eq. 24 as a matrix)."""
    E = np.zeros((len(ACTUATORS), len(JOINTS)))
    for a, j in _MOTORS:
        E[_A[a], j] = 1.0
    for pair, (pitch, roll) in ROD_PAIRS.items():
        inv_t = np.linalg.inv(rods[pair].length_jacobian(angles[_J[pitch]], angles[_J[roll]]).T)
        rows = [_A[rod] for rod in rod_actuators(pair)]
        E[np.ix_(rows, [_J[pitch], _J[roll]])] = inv_t
    return E
