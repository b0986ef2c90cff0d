"""Nair et al.'s three load-carrying scenarios, run with any distribution strategy and the X8 thermal plant.

Per run: normalised torque of every actuator at every control step
(commanded and sensed, over Nair et al.'s continuous torques 8/16/8 N m), its
peak and mean per stride, measured and true winding temperatures, and the
time until an actuator first reaches its winding limit (``None`` if never).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from thermolimb.logs import ThermalLog
from thermolimb.plant import PlantEffects
from thermolimb.util.progress import progress

from ..control import cpg
from ..control.controller import Gains, ThermalContext
from ..control.loop import ControlLoop
from ..limits import LIMITS
from ..params import DAISY
from ..sim import HexapodSim, SimConfig
from ..thermal import datasheet_bank

SCENARIOS = {"walk_0kg": (True, 0.0), "walk_2kg": (True, 2.0), "stand_5kg": (False, 5.0)}


@dataclass(frozen=True)
class ScenarioResult:
    scenario: str
    strategy: str
    time_s: np.ndarray
    norm_commanded: np.ndarray  # (n, 18)
    norm_sensed: np.ndarray  # (n, 18)
    measured_C: np.ndarray  # (n, 18)
    winding_C: np.ndarray  # (n, 18) true
    distance_m: float
    fell: bool
    time_to_limit_s: float | None
    stride_steps: int
    log: ThermalLog  # the rig's thermal log; its notes say what solved the stance forces
    solvers: dict[str, int] = field(default_factory=dict)  # control periods per stance solution's label

    def per_stride(self, which: str = "commanded") -> tuple[float, float]:
        """Mean over strides of the stride's peak normalised torque, and the overall mean normalised
        torque."""
        norm = self.norm_commanded if which == "commanded" else self.norm_sensed
        k = self.stride_steps
        peaks = [norm[i : i + k].max() for i in range(0, len(norm) - k + 1, k)] or [norm.max()]
        return float(np.mean(peaks)), float(norm.mean())

    def summary(self) -> dict:
        peak, mean = self.per_stride()
        peak_s, mean_s = self.per_stride("sensed")
        return {"peak_norm_torque": peak, "mean_norm_torque": mean, "peak_norm_torque_sensed": peak_s,
                "mean_norm_torque_sensed": mean_s, "max_temperature_C": float(self.measured_C.max()),
                "time_to_limit_s": self.time_to_limit_s, "distance_m": self.distance_m, "fell": self.fell,
                "solvers": dict(self.solvers)}


def run_scenario(scenario: str, strategy: str, duration_s: float, seed: int = 0, ambient_C: float = 25.0,
                 effects: PlantEffects = PlantEffects.realistic_sensor(), gains: Gains = Gains(),
                 thermal: ThermalContext | None = None, quiet: bool = True) -> ScenarioResult:
    """Run one scenario for ``duration_s`` seconds (after a short settle) with one strategy."""
    if scenario not in SCENARIOS:
        raise ValueError(f"unknown scenario {scenario!r}; expected one of {', '.join(SCENARIOS)}")
    walking, payload = SCENARIOS[scenario]
    if strategy == "thermal_aware" and thermal is None:
        thermal = ThermalContext(datasheet_bank(ambient_C=ambient_C))
    config = SimConfig(payload_kg=payload, ambient_C=ambient_C)
    gait = cpg.CPGParams()
    scale = DAISY.continuous_effort_Nm
    with HexapodSim(config=config, plant_effects=effects, seed=seed) as sim:
        loop = ControlLoop(sim, DAISY, gait, payload, gains, thermal)
        reading = loop.settle(strategy)
        start = reading.body_position_m.copy()
        n = int(round(duration_s * config.control_hz))
        t, cmd, sensed, measured, winding = (
            np.empty(n),
            np.empty((n, 18)),
            np.empty((n, 18)),
            np.empty((n, 18)),
            np.empty((n, 18)),
        )
        fell, time_to_limit = False, None
        for k in progress(range(n), desc=f"{scenario} {strategy}", disable=quiet, unit="step"):
            reading = loop.step(strategy, walking)
            tau = loop.torques_Nm
            t[k] = reading.time_s
            cmd[k] = np.abs(np.clip(tau, -DAISY.effort_limit_Nm, DAISY.effort_limit_Nm)) / scale
            sensed[k] = np.abs(reading.torque_Nm) / scale
            measured[k] = reading.temperature_C
            winding[k] = sim.plant.winding_C
            if time_to_limit is None and np.any(measured[k] >= LIMITS.winding_limits_C):
                time_to_limit = float(reading.time_s)
            if loop.fallen:
                fell = True
                t, cmd, sensed, measured, winding = (
                    t[: k + 1],
                    cmd[: k + 1],
                    sensed[: k + 1],
                    measured[: k + 1],
                    winding[: k + 1],
                )
                break
        distance = float(reading.body_position_m[0] - start[0])
        log = sim.thermal_log()
    log = replace(log, notes=log.notes + (loop.solver_note(),))
    return ScenarioResult(scenario, strategy, t, cmd, sensed, measured, winding, distance, fell,
                          time_to_limit, int(round(gait.period_s * config.control_hz)), log,
                          dict(loop.solvers))
