"""The humanoid's thermal actuators: rotary motors at most joints, push-rod pairs at the ankles and waist.

Valkyrie's actuator thermal data is not public; the specs are calibrated to
what Jorgensen et al. report on hardware, in three steps:

1. Time constant.  Jorgensen et al. predict 20 s ahead and set that horizon to
   half the learned RC, so a winding's RC is 40 s: 20 J/K on 2 K/W, on a
   slow housing (2000 J/K, 1 K/W) that a two-minute experiment barely warms.
2. Heat scale.  Balancing on one leg heats the stance leg from 25 degC into
   the 75 degC warning zone "in less than two minutes".  Statics (Eq. 23 at
   the nominal single support, :mod:`humanoid_pb.statics`) says which
   actuator is: the stance ankle's push rods, at 24.7 % of the rod limit
   (the centre of mass sits over the sole's centre, 4 cm ahead of the ankle
   axis: the 125 kg above it * 9.81 m/s^2 * 0.04 m = 49 N m of pitch, 24 % of
   205 N m, shared by two rods on 3.7 cm arms), then the knee at 24.3 %
   (85 N m: bent 0.6 rad, it carries the body on a lever of about 7 cm),
   then the hip roll at 20.9 % (73 N m: the pelvis and the free leg held
   sideways over the stance hip); everything else is below 10 %.  Reaching
   75 degC from 25 degC after ``TIME_TO_WARNING_S`` = 100 s on the winding's
   RC needs a steady rise of 50 / (1 - e^(-100/40)) = 54.5 K, so the
   hottest actuator's copper loss is 54.5 K / 2 K/W = 27.2 W at 24.7 % of
   its limit, that is ``COPPER_LOSS_AT_30_PCT_W`` = 40 W at 30 % of the limit.
   The same rule sizes every actuator (effort per amp from its limit), so
   which actuator is hottest follows from the geometry, not from a choice.
3. Limit.  Valkyrie's actuators "can operate up to 90 degC": protection
   starts derating there, its margin below a winding limit of 105 degC.

Jorgensen et al.'s Fig. 5 (the knee over squats every 4.5 minutes) would fix the
knee's own scale, but its temperatures are not in Jorgensen et al.'s text; the knee
is sized by the same rule as the rest (tests check the derivation).
"""

from __future__ import annotations

import numpy as np

from thermolimb.model import FirstOrderBank
from thermolimb.plant import ActuatorSpec, ThermalNetwork, ThermalProtection

from .constants import ACTUATORS, JOINTS, ROD_PAIRS, rod_actuators
from .params import ValkyrieParams
from .pushrods import RodPair
from .scenarios import DEFAULT, Scenario
from .scenarios import scenario as get_scenario

# winding (tau = 20 J/K * 2 K/W = 40 s, Jorgensen et al.'s RC) on a slow housing (2000 J/K, 1 K/W)
VALKYRIE_NETWORK = ThermalNetwork(("winding", "housing"), (20.0, 2000.0), (2.0, 1.0))
TIME_TO_WARNING_S = 100.0  # single-leg balancing: 25 -> 75 degC at the hottest actuator's static effort
OPERATING_LIMIT_C = 90.0  # Jorgensen et al.: Valkyrie's actuators operate up to 90 degC; derating starts there
WINDING_LIMIT_C = OPERATING_LIMIT_C + ThermalProtection().margin_K


def actuator_specs(params: ValkyrieParams, scenario: str | Scenario = DEFAULT) -> list[ActuatorSpec]:
    """One spec per actuator (ACTUATORS order): 0.5 ohm windings sized by the ``scenario``
    (:mod:`humanoid_pb.scenarios`; the default is the rule above, ``COPPER_LOSS_AT_30_PCT_W`` at 30 % of the limit)."""
    sizing = get_scenario(scenario)
    specs = []
    for name in ACTUATORS:
        if "_rod_" in name:
            limit = params.rod_force_limit_N
        else:
            limit = params.effort_limit(name)
        per_amp = sizing.effort_per_amp(name, limit, 0.5)
        specs.append(ActuatorSpec(name.split("_")[-1], per_amp, 0.5, limit, 0.4 * limit, 6.0, VALKYRIE_NETWORK,
                                  winding_limit_C=WINDING_LIMIT_C, driver=None))
    return specs


def datasheet_bank(params: ValkyrieParams, ambient_C: float = 25.0, scenario: str | Scenario = DEFAULT) -> FirstOrderBank:
    """Eq. 5 of every actuator from its data, without identification: the winding node on a housing at ambient.

    RC = C_w R_w (40 s) and betaR = R_e R_w / k^2: what a controller can plan
    with before it has a log of its own.
    """
    return FirstOrderBank.from_specs(actuator_specs(params, scenario), ambient_C, lumped_nodes=1)


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
