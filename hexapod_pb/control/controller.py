"""Hybrid motion-force control of the hexapod (Nair et al.'s Eq. 6), as pure functions.

Swing legs: joint-space PID through the leg's mass matrix, tracking the CPG's
foot targets by inverse kinematics, plus gravity compensation.

Stance legs (point contact with friction, ``P = diag(0, 0, 0, 1, 1, 1)``):

    tau = J^T ( P Lambda (Kp e + Kd de + Ki int e) + (I - P) F_d ) + g,   Lambda = (J^T)^+ M

with ``F_d = -f`` the wrench the foot must exert, ``f`` the stance force
chosen by the distribution strategy for the net ground wrench the body needs:
its weight, plus feedback on body height, attitude and horizontal velocity
(the CPG gives the walking speed).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from thermolimb.model import ModelArrays

from ..constants import LEGS
from ..model.kinematics import inverse_kinematics, joint_axes, nominal_feet
from ..model.legs import leg_statics
from ..params import GRAVITY_M_S2, DaisyParams
from ..readings import Reading
from . import cpg
from .stance import StanceProblem, StanceSolution
from .wrench import STRATEGIES, distribute

P_POINT_CONTACT = np.diag([0.0, 0.0, 0.0, 1.0, 1.0, 1.0])


@dataclass(frozen=True)
class Gains:
    # joint-space PID of swing legs, as accelerations (scaled by the leg mass matrix)
    swing_kp_1_s2: float = 200.0
    swing_kd_1_s: float = 20.0
    swing_ki_1_s3: float = 0.0
    # Nair et al.'s motion term on stance legs acts through the whole body; softer than the swing legs'
    # (chosen: with the swing gains on stance legs a 10 s walk was as stable here, body yaw under 0.002 rad)
    stance_kp_1_s2: float = 60.0
    stance_kd_1_s: float = 10.0
    height_kp_1_s2: float = 60.0  # body height, as an acceleration per metre of error
    height_kd_1_s: float = 12.0
    velocity_kv_1_s: float = 3.0  # horizontal velocity tracking
    attitude_kp_Nm_rad: float = 200.0
    # 50 makes the body's yaw run away at 50 Hz (tests/test_hexapod_control.py)
    attitude_kd_Nm_s_rad: float = 5.0
    stance_motion_scale: float = 1.0  # Nair et al.'s motion term on stance legs (Eq. 6); 0 turns it off
    smoothing_1_N2: float = 1e-3  # proximal weight of the control-rate minimax (see wrench.minimax)
    # friction pyramid the distribution respects (None: Nair et al.'s unconstrained friction)
    friction: float = 0.6
    min_normal_N: float = 2.0  # keep every stance foot loaded
    # the stance programs' solver, named, and the one that takes over should it fail (said in each solution)
    solver: str = "daqp"
    fallback: str | None = "highs"


@dataclass(frozen=True)
class ThermalContext:
    """What the thermal-aware distribution needs: identified models of all 18 joints and a horizon."""

    bank: ModelArrays
    horizon_s: float = 20.0


@dataclass
class ControllerState:
    cpg_state: np.ndarray
    integral: np.ndarray = field(default_factory=lambda: np.zeros(18))
    last: StanceSolution | None = None


def body_wrench(
    params: DaisyParams,
    payload_kg: float,
    reading: Reading,
    gains: Gains,
    velocity_m_s: np.ndarray,
    height_m: float,
) -> np.ndarray:
    """Ground wrench ``(F, M)`` on the robot, body frame: weight plus posture and velocity feedback."""
    R = reading.world_R_body
    mass = params.robot_mass_kg + payload_kg
    v_world = R @ reading.body_velocity_m_s
    desired_v_world = R @ velocity_m_s
    accel = np.zeros(3)
    accel[:2] = gains.velocity_kv_1_s * (desired_v_world[:2] - v_world[:2])
    accel[2] = (
        gains.height_kp_1_s2 * (height_m - reading.body_position_m[2]) - gains.height_kd_1_s * v_world[2]
    )
    force_world = mass * (np.array([0.0, 0.0, GRAVITY_M_S2]) + accel)
    roll = np.arctan2(R[2, 1], R[2, 2])
    pitch = -np.arcsin(np.clip(R[2, 0], -1, 1))
    yaw = np.arctan2(R[1, 0], R[0, 0])
    attitude_error = np.array([-roll, -pitch, -yaw])  # level, heading along the world x axis
    moment = gains.attitude_kp_Nm_rad * attitude_error - gains.attitude_kd_Nm_s_rad * reading.body_omega_rad_s
    return np.concatenate([R.T @ force_world, moment])


def control_step(
    reading: Reading,
    state: ControllerState,
    params: DaisyParams,
    gait: cpg.CPGParams,
    strategy: str | dict[str, float],
    dt_s: float,
    payload_kg: float = 0.0,
    gains: Gains = Gains(),
    thermal: ThermalContext | None = None,
    walking: bool = True,
) -> tuple[np.ndarray, ControllerState, dict]:
    """Torques (18,) for one control step, the next controller state, and what was decided.

    ``strategy`` is a name, or ``{name: weight}`` to blend the strategies' stance forces (a convex
    combination of balanced distributions is balanced).
    """
    weights = (
        {strategy: 1.0} if isinstance(strategy, str) else {k: float(v) for k, v in strategy.items() if v > 0}
    )
    unknown = [k for k in weights if k not in STRATEGIES]
    if unknown or not weights:
        raise ValueError(f"unknown strategy {unknown or strategy!r}; expected one of {', '.join(STRATEGIES)}")
    if "thermal_aware" in weights and thermal is None:
        raise ValueError("the thermal_aware strategy needs a ThermalContext (identified models)")
    nominal = nominal_feet(params)
    cpg_state = cpg.step(state.cpg_state, gait, dt_s) if walking else state.cpg_state
    planned_stance = cpg.stance(cpg_state, gait) if walking else np.ones(len(LEGS), bool)
    targets = cpg.foot_targets(cpg_state, gait, nominal) if walking else nominal
    q_des = np.concatenate([inverse_kinematics(params, i, targets[i]) for i in range(len(LEGS))])
    q, qd = reading.q_rad, reading.qd_rad_s
    error = q_des - q
    integral = state.integral + error * dt_s
    swing_pid = gains.swing_kp_1_s2 * error - gains.swing_kd_1_s * qd + gains.swing_ki_1_s3 * integral
    stance_pd = gains.stance_kp_1_s2 * error - gains.stance_kd_1_s * qd

    speed = gait.speed_m_s if walking else 0.0
    velocity = speed * np.array([np.cos(gait.heading_rad), np.sin(gait.heading_rad), 0.0])
    wrench = body_wrench(params, payload_kg, reading, gains, velocity, params.nominal_body_height_m)
    legs = tuple(int(i) for i in np.flatnonzero(planned_stance))
    statics = [leg_statics(params, i, q[3 * i : 3 * i + 3], reading.world_R_body) for i in range(len(LEGS))]
    problem = StanceProblem.from_statics(params, {i: statics[i] for i in legs}, payload_kg=payload_kg,
                                         wrench=wrench, friction=gains.friction,
                                         min_normal_N=gains.min_normal_N, world_R_body=reading.world_R_body)
    bank, horizon_s = (thermal.bank, thermal.horizon_s) if thermal is not None else (None, 0.0)
    solution = distribute(problem, weights, state.last, bank, reading.temperature_C, horizon_s,
                          gains.smoothing_1_N2, gains.solver, gains.fallback)

    torques = np.zeros(18)
    # a stance leg's torques: its share of the wrench with its gravity (the problem's T f + g, computed once),
    # plus the motion PD in the directions a point contact leaves free (rotations about the foot)
    stance_torques = dict(zip(legs, solution.torques_Nm.reshape(-1, 3)))
    for i in range(len(LEGS)):
        sl = slice(3 * i, 3 * i + 3)
        M, g = statics[i].mass_matrix, statics[i].gravity_Nm
        if i in stance_torques:
            J = np.vstack([statics[i].jacobian, joint_axes(params, i, q[sl]).T])
            Lam = np.linalg.pinv(J.T) @ M
            torques[sl] = (
                J.T @ (gains.stance_motion_scale * P_POINT_CONTACT @ (Lam @ stance_pd[sl]))
                + stance_torques[i]
            )
        else:
            torques[sl] = M @ swing_pid[sl] + g
    info = {"stance": planned_stance, "solution": solution, "wrench": wrench, "targets": targets}
    return torques, replace(state, cpg_state=cpg_state, integral=integral, last=solution), info
