"""The seed's experiment: heat the stance leg on one foot, then recover, thermal-aware against minimum effort.

Everything the controller knows is what the rig gives it: encoders, torque
sensing, measured temperatures.  The thermal model it plans with is
identified (output error, ``joule,effort_bias``) from the robot's own log of a
calibration run, not copied from the plant.

Modes change only through the nominal double-support crouch (as the seed
assumes), with a minimum dwell time; single support means shifting the
weight over the stance foot, then lifting the other foot.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Sequence

import numpy as np

from thermolimb.identification.bank import identify_bank
from thermolimb.logs import ThermalLog
from thermolimb.model import FirstOrderBank
from thermolimb.plant import ActuatorSpec
from thermolimb.progress import progress

from .actuators import effort_limits
from .balance import Motion, balance_command
from .constants import ACTUATORS, leg_actuators
from .params import FALLEN_PELVIS_HEIGHT_M, RECOVERED_C, WARNING_C
from .planner import ContactModePlanner
from .poses import crouch_angles, single_support, standing
from .sim import HumanoidSim

SHIFT_S = 1.5  # weight shift, and foot lift or placement, each
DWELL_S = 8.0  # minimum time in a mode before the next decision
DECIDE_EVERY_S = 2.0


class Executor:
    """Drives the humanoid through contact modes and configurations, through the nominal crouch."""

    def __init__(self, sim: HumanoidSim):
        self.sim = sim
        self.body = sim.body
        self.nominal_angles = crouch_angles()
        self.q_nominal = standing(self.body, self.nominal_angles)
        self.mode = "double"
        self.target = self.nominal_angles.copy()
        self.queue: list[tuple[Motion, str]] = []
        self.settled_since = 0.0
        self.hold_torques: np.ndarray | None = None  # the IK's balancing torques at the goal, fed forward there

    def support_angles(self, side: str, lift_m: float) -> np.ndarray:
        return self.body.joint_angles(single_support(self.body, self.q_nominal, side, lift_m=lift_m))

    def go(self, mode: str, goal_angles: np.ndarray | None = None, goal_torques: np.ndarray | None = None) -> None:
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
            plan.append((Motion(self.support_angles(side, 0.0), self.nominal_angles, t + SHIFT_S, SHIFT_S), "double"))
            here, t = self.nominal_angles, t + 2 * SHIFT_S
        if mode == "double":
            goal = self.nominal_angles if goal_angles is None else goal_angles
            plan.append((Motion(here, goal, t, SHIFT_S), "double"))
        else:
            shifted = self.support_angles(mode, 0.0)
            lifted = self.support_angles(mode, 0.05) if goal_angles is None else goal_angles
            plan.append((Motion(here, shifted, t, SHIFT_S), "double"))
            plan.append((Motion(shifted, lifted, t + SHIFT_S, SHIFT_S), mode))
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


def calibrate(duration_s: float, seed: int = 0, quiet: bool = True,
              specs: Sequence[ActuatorSpec] | None = None) -> tuple[FirstOrderBank, ThermalLog]:
    """A calibration run (double support, then each foot, in turn) and the models identified from its log.

    ``specs``: the robot's actuators if they are not the datasheet's (the
    calibration runs on the robot; nothing reads the specs but its plant).
    """
    with HumanoidSim(crouch_angles(), seed=seed, specs=specs) as sim:
        ex = Executor(sim)
        reading = sim.read()
        schedule = ["right", "double", "left", "double"]
        phase_s = duration_s / len(schedule)
        k = 0
        for step in progress(range(int(duration_s / sim.config.control_dt_s)), desc="calibration", disable=quiet):
            if sim.time_s >= k * phase_s and k < len(schedule) and not ex.moving:
                ex.go(schedule[k])
                k += 1
            reading = ex.tick(reading)
        log = sim.thermal_log()
    return identify_bank(log, ACTUATORS, effort_limits(sim.params)), log


@dataclass
class RecoveryRun:
    strategy: str
    time_s: list = field(default_factory=list)
    temperature_C: list = field(default_factory=list)
    modes: list = field(default_factory=list)
    decisions: list = field(default_factory=list)  # (time, mode) chosen
    warning_at_s: float | None = None
    recovery_s: float | None = None
    hot_leg_below_70_s: float | None = None
    fell: bool = False
    configurations: dict = field(default_factory=dict)  # mode -> joint angles chosen

    def summary(self) -> dict:
        return {"recovery_s": self.recovery_s, "hot_leg_below_70_s": self.hot_leg_below_70_s, "fell": self.fell,
                "warning_at_s": self.warning_at_s, "modes_chosen": [m for _, m in self.decisions]}


def run_recovery(strategy: str, bank: FirstOrderBank, seed: int = 0, heat_side: str = "right",
                 max_heat_s: float = 240.0, max_recovery_s: float = 240.0, quiet: bool = True) -> RecoveryRun:
    """Balance on ``heat_side`` until an actuator reaches 75 degC, then recover with ``strategy``:
    ``"thermal_aware"`` (Eq. 33 over the three modes, re-decided every 2 s after an 8 s dwell) or
    ``"minimum_effort"`` (the least-effort mode and configuration, held)."""
    if strategy not in ("thermal_aware", "minimum_effort"):
        raise ValueError(f"strategy must be 'thermal_aware' or 'minimum_effort', got {strategy!r}")
    run = RecoveryRun(strategy)
    hot_leg = [ACTUATORS.index(a) for a in leg_actuators(heat_side)]
    with HumanoidSim(crouch_angles(), seed=seed) as sim:
        ex = Executor(sim)
        planner = ContactModePlanner(sim.body, "thermal" if strategy == "thermal_aware" else "effort")
        reading = sim.read()
        ex.go(heat_side)
        recovering = False
        next_decision = 0.0
        total_s = max_heat_s + max_recovery_s
        for _ in progress(range(int(total_s / sim.config.control_dt_s)), desc=strategy, disable=quiet):
            reading = ex.tick(reading)
            t = sim.time_s
            T = reading.temperature_C
            run.time_s.append(t)
            run.temperature_C.append(T.copy())
            run.modes.append(ex.mode)
            if reading.base_position_m[2] < FALLEN_PELVIS_HEIGHT_M:
                run.fell = True
                break
            if not recovering:
                if T.max() >= WARNING_C:
                    recovering, run.warning_at_s, next_decision = True, t, t
                elif t > max_heat_s:
                    break
                continue
            if run.hot_leg_below_70_s is None and T[hot_leg].max() < RECOVERED_C:
                run.hot_leg_below_70_s = t - run.warning_at_s
            if T.max() < RECOVERED_C:
                run.recovery_s = t - run.warning_at_s
                break
            if t >= next_decision and not ex.moving and t - ex.settled_since >= (DWELL_S if run.decisions else 0.0):
                plan = planner.plan(ex.q_nominal, bank, T)
                mode, results = plan.mode, plan.results
                if not run.decisions or mode != run.decisions[-1][1]:
                    angles = sim.body.joint_angles(results[mode].q)
                    run.configurations[mode] = angles
                    ex.go(mode, angles, results[mode].torques_Nm)
                    run.decisions.append((t, mode))
                next_decision = t + DECIDE_EVERY_S
    return run  # recovery_s stays None when the time ran out


def first_order_to_C(start_C: float, end_C: float, steady_C: np.ndarray, rc_s: float) -> np.ndarray:
    """Time (s) for a first-order winding to cool from ``start_C`` to ``end_C`` towards ``steady_C``; inf if it cannot."""
    steady_C = np.asarray(steady_C, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = rc_s * np.log((start_C - steady_C) / (end_C - steady_C))
    return np.where(steady_C < end_C, t, np.inf)


def steady_needed_for_ratio(ratio: float, fastest_steady_C: float, start_C: float = WARNING_C,
                            end_C: float = RECOVERED_C) -> float:
    """The steady temperature (degC) a slower mode must hold for its cooling from ``start_C`` to ``end_C`` to take
    ``ratio`` times as long as towards ``fastest_steady_C`` (same RC): solves ln(a'/b') = ratio ln(a/b)."""
    x = ((start_C - fastest_steady_C) / (end_C - fastest_steady_C)) ** ratio
    return (start_C - end_C * x) / (1.0 - x)


def cooling_bound(body, bank: FirstOrderBank, hot_actuator: str, configurations: dict) -> dict:
    """Why one recovery can or cannot cool ``hot_actuator`` faster than another: for each held configuration
    (name -> (mode, q)), its efforts by Eq. 23, the hot actuator's steady temperature under ``bank`` and its
    first-order time from the warning (75 degC) to 70 degC.  Transitions come on top (the leg is loaded while
    the robot moves through the nominal crouch)."""
    i = ACTUATORS.index(hot_actuator)
    out = {}
    for name, (mode, q) in configurations.items():
        efforts = body.statics(q, mode).efforts
        steady = bank.equilibrium_C(efforts)
        out[name] = {"mode": mode, "effort_fraction": float(abs(efforts[i]) / effort_limits(body.params)[i]),
                     "steady_C": float(steady[i]),
                     "warning_to_70_s": float(first_order_to_C(WARNING_C, RECOVERED_C, steady[i], bank.RC_s[i]))}
    return out
