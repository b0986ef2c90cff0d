"""The periodic shortcut checked against the plant stepped every control period in PyBullet."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from thermolimb.util.numbers import to_microsecond

from ...constants import JOINTS
from ...params import DAISY
from ...sim import HexapodSim, SimConfig
from ...thermal import EFFECTS, PROTECTION
from .cells import THERMAL_STRATEGIES
from .cycle import _run_duty, measure_cycle
from .gait import NOMINAL_GAIT


@dataclass(frozen=True)
class PeriodicCheck:
    """The propagated cell against the whole run in PyBullet: the hottest actuator's true winding, averaged
    over each cycle (a cycle's start falls at a slightly different phase of the stride as the run goes on, and
    the winding swings by kelvins within a stride)."""

    duration_s: float
    cycle_start_s: np.ndarray
    pybullet_hottest_C: np.ndarray  # hottest cycle-mean true winding, full PyBullet run
    propagated_hottest_C: np.ndarray  # the same from one measured cycle, propagated

    @property
    def max_abs_difference_K(self) -> float:
        return float(np.max(np.abs(self.pybullet_hottest_C - self.propagated_hottest_C)))

    @property
    def final_difference_K(self) -> float:
        return float(self.propagated_hottest_C[-1] - self.pybullet_hottest_C[-1])

    def summary(self) -> dict:
        return {
            "duration_s": to_microsecond(self.duration_s),
            "max_abs_difference_K": self.max_abs_difference_K,
            "final_difference_K": self.final_difference_K,
            "final_pybullet_C": float(self.pybullet_hottest_C[-1]),
            "final_propagated_C": float(self.propagated_hottest_C[-1]),
        }


def check_periodic(payload_kg: float, ambient_C: float, mode: str, strategy: str, duration_s: float,
                   seed: int = 0) -> PeriodicCheck:
    """Run a temperature-independent strategy in PyBullet for ``duration_s`` and propagate its first cycle as
    long.

    Both start from cold and settle and warm up alike; the full run keeps
    going with the thermal plant stepped every control period.
    """
    if strategy in THERMAL_STRATEGIES:
        raise ValueError("check a strategy whose torques do not depend "
                         "on the temperatures (one cycle propagated)")
    cycle = measure_cycle(payload_kg, mode, strategy, ambient_C, seed=seed)
    if cycle.fell:
        raise ValueError(f"the robot cannot {mode} with {payload_kg} kg under {strategy}: nothing to check")
    steps = cycle.map.steps
    config = SimConfig(payload_kg=payload_kg, ambient_C=ambient_C)
    cycles = int(np.ceil(duration_s / cycle.map.period_s))
    hottest = np.empty(cycles)
    start = None
    with HexapodSim(config=config, plant_effects=EFFECTS, seed=seed, protection=PROTECTION) as sim:
        total = np.zeros(len(JOINTS))
        for k, _ in _run_duty(sim, DAISY, NOMINAL_GAIT, payload_kg, config, mode == "walk", strategy, None,
                              cycles * steps):
            if k == -1:
                start = sim.plant.state
            elif k >= 0:
                total += sim.plant.winding_C
                if (k + 1) % steps == 0:
                    hottest[k // steps] = total.max() / steps
                    total[:] = 0.0
    prop = cycle.map.propagate(start, cycles * cycle.map.period_s)
    return PeriodicCheck(cycles * cycle.map.period_s, prop.cycle_start_s, hottest,
                         prop.mean_winding_C.max(axis=1))
