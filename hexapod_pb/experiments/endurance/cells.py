"""A cell of the endurance envelope: how long the hexapod works at a payload, ambient and duty before it
derates."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from thermolimb.model import ModelArrays
from thermolimb.util.numbers import to_microsecond

from ...constants import JOINTS
from ...control.controller import ThermalContext
from ...limits import LIMITS
from ...thermal import PROTECTION
from .cycle import MAX_YAW_DRIFT_DEG_PER_MIN, measure_cycle
from .gait import GAIT_CHOICES, NOMINAL_GAIT, Gait
from .planning import plan_gait

STRATEGIES = ("vertical_only", "minimax", "minimax_lex", "thermal_aware", "thermal_gait")
THERMAL_STRATEGIES = ("thermal_aware", "thermal_gait")


@dataclass(frozen=True)
class CellResult:
    payload_kg: float
    ambient_C: float
    mode: str
    strategy: str
    time_to_derate_s: float | None
    horizon_s: float
    distance_per_s_m: float
    fell: bool
    hottest: str  # the actuator that derates first, or the hottest at the horizon
    hottest_C: float  # its winding when derating starts, or at the horizon
    steady_hottest_C: float | None  # the hottest winding of the last measured cycle repeated forever
    # the largest heading drift measured: above a few degrees the gait is not periodic
    yaw_drift_deg_per_min: float
    windows: int
    gait: Gait

    @property
    def holds_heading(self) -> bool:
        return self.yaw_drift_deg_per_min <= MAX_YAW_DRIFT_DEG_PER_MIN

    def row(self) -> dict:
        return {
            "payload_kg": self.payload_kg,
            "ambient_C": self.ambient_C,
            "mode": self.mode,
            "strategy": self.strategy,
            "time_to_derate_s": to_microsecond(self.time_to_derate_s),
            "horizon_s": self.horizon_s,
            "distance_per_s_m": self.distance_per_s_m,
            "fell": self.fell,
            "hottest": self.hottest,
            "hottest_C": self.hottest_C,
            "steady_hottest_C": self.steady_hottest_C,
            "yaw_drift_deg_per_min": self.yaw_drift_deg_per_min,
            "holds_heading": self.holds_heading,
            "windows": self.windows,
            "duty_factor": self.gait.duty_factor,
            "foot_reach_m": self.gait.foot_reach_m,
            "body_height_m": self.gait.body_height_m,
            "pause_share": self.gait.pause_share,
        }


def derating_threshold_C() -> np.ndarray:
    """Winding temperature (degC) at which each actuator's protection starts to derate."""
    limits = LIMITS.winding_limits_C
    return limits - PROTECTION.margin_K


def endurance(payload_kg: float, ambient_C: float, mode: str, strategy: str, horizon_s: float,
              bank: ModelArrays | None = None, window_s: float = 1800.0, gait: Gait | None = None,
              seed: int = 0, choices: dict[str, tuple[float, ...]] = GAIT_CHOICES) -> CellResult:
    """Time until the first actuator derates (``None`` if not within ``horizon_s``), from cold at
    ``ambient_C``.

    ``bank`` (identified, :func:`at_ambient` this ambient) is needed by the
    thermal-aware strategies; ``gait`` skips ``thermal_gait``'s planning
    (``choices`` are the gaits it plans among).
    """
    if strategy not in STRATEGIES:
        raise ValueError(f"unknown strategy {strategy!r}; expected one of {', '.join(STRATEGIES)}")
    thermal = None
    if strategy in THERMAL_STRATEGIES:
        if bank is None:
            raise ValueError(f"the {strategy} strategy needs models identified from the robot's log (bank=)")
        thermal = ThermalContext(bank)
    if gait is None:
        gait = (
            plan_gait(payload_kg, mode, ambient_C, bank, seed, choices).gait
            if strategy == "thermal_gait"
            else NOMINAL_GAIT
        )
    forces = "thermal_aware" if strategy in THERMAL_STRATEGIES else strategy
    window = window_s if thermal is not None else horizon_s
    threshold = derating_threshold_C()
    state, elapsed, windows = None, 0.0, 0
    distances, fell, crossing, winding, steady, drift = [], False, None, None, None, 0.0
    while elapsed < horizon_s - 1e-9:
        cycle = measure_cycle(payload_kg, mode, forces, ambient_C, gait, state, thermal, seed)
        windows += 1
        if cycle.fell:  # the robot cannot do this duty at all: nothing to propagate
            fell = True
            winding = winding or ("", float(ambient_C))
            break
        distances.append(cycle.distance_per_s_m)
        steady = float(cycle.map.steady_peak_C().max())
        drift = max(drift, cycle.yaw_drift_deg / cycle.map.period_s * 60.0)
        if state is None:
            state = np.full(cycle.map.M.shape[0], ambient_C)
        span = min(window, horizon_s - elapsed)
        prop = cycle.map.propagate(state, span, threshold)
        if prop.crossing is not None:
            crossing = elapsed + prop.crossing.time_s
            j = prop.crossing.actuator
            winding = (JOINTS[j], float(prop.peak_winding_C[-1, j]))
            break
        state = prop.final_state
        elapsed += len(prop.cycle_start_s) * cycle.map.period_s
        w = state[cycle.map.winding_index]
        winding = (JOINTS[int(np.argmax(w))], float(np.max(w)))
    return CellResult(float(payload_kg), float(ambient_C), mode, strategy, crossing, float(horizon_s),
                      0.0 if fell else float(np.mean(distances)), fell, winding[0], winding[1], steady, drift,
                      windows, gait)
