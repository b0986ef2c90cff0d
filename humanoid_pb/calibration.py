"""The humanoid's calibration run and the thermal models identified from its log (what a planner may know)."""

from __future__ import annotations

from typing import Sequence

from thermolimb.identification.calibration import Calibration, identify_bank, measured_ambient_C
from thermolimb.plant import ActuatorSpec
from thermolimb.util.progress import progress

from .constants import ACTUATORS
from .control.executor import Executor
from .model.actuation import effort_limits
from .scenarios import DEFAULT, Scenario
from .sim import HumanoidSim


def calibrate(
    duration_s: float,
    seed: int = 0,
    *,
    quiet: bool = True,
    specs: Sequence[ActuatorSpec] | None = None,
    scenario: str | Scenario = DEFAULT,
) -> Calibration:
    """A calibration run (double support, then each foot, in turn) and the models identified from its log.

    ``specs``: the robot's actuators if they are not the datasheet's (the calibration runs on the robot;
    nothing reads the specs but its plant); ``scenario``: its stance and, without ``specs``, its actuators
    (:mod:`humanoid_pb.scenarios`).
    """
    with HumanoidSim(seed=seed, specs=specs, scenario=scenario) as sim:
        ex = Executor(sim)
        reading = sim.read()
        schedule = ["right", "double", "left", "double"]
        phase_s = duration_s / len(schedule)
        k = 0
        for step in progress(
            range(int(duration_s / sim.config.control_dt_s)), desc="calibration", disable=quiet
        ):
            if sim.time_s >= k * phase_s and k < len(schedule) and not ex.moving:
                ex.go(schedule[k])
                k += 1
            reading = ex.tick(reading)
        log = sim.thermal_log()
    return Calibration(identify_bank(log, ACTUATORS, effort_limits(sim.params)), log, measured_ambient_C(log))
