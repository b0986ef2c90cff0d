"""Jorgensen et al.'s experiment: heat the stance leg on one foot, then recover, thermal-aware against minimum
effort.

Everything the controller knows is what the rig gives it: encoders, torque
sensing, measured temperatures.  The thermal model it plans with is
identified (output error, ``joule,effort_bias``) from the robot's own log of a
calibration run, not copied from the plant.

Modes change only through the nominal double-support crouch (as Jorgensen et al.
assumes), with a minimum dwell time; single support means shifting the
weight over the stance foot, then lifting the other foot.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from thermolimb.model import ModelArrays
from thermolimb.util.numbers import to_microsecond
from thermolimb.util.progress import progress

from ..constants import ACTUATORS, leg_actuators
from ..control.executor import Executor
from ..control.planner import ContactModePlanner
from ..limits import LIMITS
from ..model.actuation import effort_limits
from ..params import FALLEN_PELVIS_HEIGHT_M
from ..scenarios import DEFAULT, Scenario
from ..sim import HumanoidSim

DWELL_S = 8.0  # minimum time in a mode before the next decision
DECIDE_EVERY_S = 2.0


@dataclass
class RecoveryRun:
    strategy: str
    time_s: list = field(default_factory=list)
    temperature_C: list = field(default_factory=list)
    modes: list = field(default_factory=list)
    decisions: list = field(default_factory=list)  # (time, mode) chosen
    warning_at_s: float | None = None
    recovery_s: float | None = None
    hot_leg_recovery_s: float | None = None
    fell: bool = False
    configurations: dict = field(default_factory=dict)  # mode -> joint angles chosen

    def safe_after_warning(self, indices) -> float | None:
        """Seconds from the warning until the actuators at ``indices`` are all below 70 degC (None: not
        reached)."""
        if self.warning_at_s is None:
            return None
        t = np.array(self.time_s)
        below = np.array(self.temperature_C)[:, indices].max(axis=1) < LIMITS.recovered_C
        after = np.flatnonzero(below & (t >= self.warning_at_s))
        return to_microsecond(t[after[0]] - self.warning_at_s) if after.size else None

    def summary(self) -> dict:
        return {
            "recovery_s": self.recovery_s,
            "hot_leg_recovery_s": self.hot_leg_recovery_s,
            "fell": self.fell,
            "warning_at_s": self.warning_at_s,
            "modes_chosen": [m for _, m in self.decisions],
        }


def run_recovery(strategy: str, bank: ModelArrays, seed: int = 0, heat_side: str = "right",
                 max_heat_s: float = 240.0, max_recovery_s: float = 240.0, quiet: bool = True,
                 scenario: str | Scenario = DEFAULT) -> RecoveryRun:
    """Balance on ``heat_side`` until an actuator reaches 75 degC, then recover with ``strategy``:
    ``"thermal_aware"`` (Eq. 33 over the three modes, re-decided every 2 s after an 8 s dwell) or
    ``"minimum_effort"`` (the least-effort mode and configuration, held).  ``scenario``: the stance and the
    actuators (:mod:`humanoid_pb.scenarios`)."""
    if strategy not in ("thermal_aware", "minimum_effort"):
        raise ValueError(f"strategy must be 'thermal_aware' or 'minimum_effort', got {strategy!r}")
    run = RecoveryRun(strategy)
    hot_leg = [ACTUATORS.index(a) for a in leg_actuators(heat_side)]
    with HumanoidSim(seed=seed, scenario=scenario) as sim:
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
                if T.max() >= LIMITS.warning_C:
                    recovering, run.warning_at_s, next_decision = True, t, t
                elif t > max_heat_s:
                    break
                continue
            if run.hot_leg_recovery_s is None and T[hot_leg].max() < LIMITS.recovered_C:
                run.hot_leg_recovery_s = to_microsecond(t - run.warning_at_s)
            if T.max() < LIMITS.recovered_C:
                run.recovery_s = to_microsecond(t - run.warning_at_s)
                break
            if (
                t >= next_decision
                and not ex.moving
                and t - ex.settled_since >= (DWELL_S if run.decisions else 0.0)
            ):
                plan = planner.plan(ex.q_nominal, bank, T)
                mode, results = plan.mode, plan.results
                if not run.decisions or mode != run.decisions[-1][1]:
                    angles = sim.body.joint_angles(results[mode].q)
                    run.configurations[mode] = angles
                    ex.go(mode, angles, results[mode].torques_Nm)
                    run.decisions.append((t, mode))
                next_decision = t + DECIDE_EVERY_S
    return run  # recovery_s stays None when the time ran out


def first_order_cooling_s(start_C: float, end_C: float, steady_C: np.ndarray, rc_s: float) -> np.ndarray:
    """Time (s) for a first-order winding to cool from ``start_C`` to ``end_C`` towards ``steady_C``; inf if
    it cannot."""
    steady_C = np.asarray(steady_C, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = rc_s * np.log((start_C - steady_C) / (end_C - steady_C))
    return np.where(steady_C < end_C, t, np.inf)


def steady_needed_for_ratio(ratio: float, fastest_steady_C: float, start_C: float = LIMITS.warning_C,
                            end_C: float = LIMITS.recovered_C) -> float:
    """The steady temperature (degC) a slower mode must hold for its cooling from ``start_C`` to ``end_C`` to
    take ``ratio`` times as long as towards ``fastest_steady_C`` (same RC): solves ln(a'/b') = ratio
    ln(a/b)."""
    x = ((start_C - fastest_steady_C) / (end_C - fastest_steady_C)) ** ratio
    return (start_C - end_C * x) / (1.0 - x)


def cooling_bound(body, bank: ModelArrays, hot_actuator: str, configurations: dict) -> dict:
    """Why one recovery can or cannot cool ``hot_actuator`` faster than another: for each held configuration
    (name -> (mode, q)), its efforts by Eq. 23, the hot actuator's steady temperature under ``bank`` and its
    first-order time from the warning (75 degC) to 70 degC.  Transitions come on top (the leg is loaded while
    the robot moves through the nominal crouch)."""
    i = ACTUATORS.index(hot_actuator)
    out = {}
    for name, (mode, q) in configurations.items():
        efforts = body.statics(q, mode).efforts
        steady = bank.equilibrium_C(efforts)
        out[name] = {
            "mode": mode,
            "effort_fraction": float(abs(efforts[i]) / effort_limits(body.params)[i]),
            "steady_C": float(steady[i]),
            "warning_to_recovered_s": float(
                first_order_cooling_s(LIMITS.warning_C, LIMITS.recovered_C, steady[i], bank.RC_s[i])
            ),
        }
    return out
