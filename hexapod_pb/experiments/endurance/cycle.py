"""One periodic duty of the hexapod measured in PyBullet: a cycle of strides (or of standing) recorded once
its gait is periodic, and the plant's exact affine map over it."""

from __future__ import annotations

import hashlib
import pickle
from dataclasses import dataclass, replace

import numpy as np

from thermolimb.plant.periodic import CycleMap

from ...constants import JOINTS
from ...control.controller import Gains, ThermalContext
from ...control.loop import ControlLoop
from ...params import FALLEN_BODY_HEIGHT_M, DaisyParams
from ...sim import HexapodSim, SimConfig
from ...thermal import EFFECTS, PROTECTION
from .gait import MODES, NOMINAL_GAIT, Gait

WARMUP_STRIDES = 3
CYCLE_STRIDES = 8
# a gait turning faster than this by itself is not periodic (measured: <= 0.3 to 25 kg)
MAX_YAW_DRIFT_DEG_PER_MIN = 5.0


@dataclass(frozen=True)
class Cycle:
    """One measured cycle of a periodic duty, and its map on the plant's network."""

    map: CycleMap
    distance_per_s_m: float
    fell: bool
    mean_sq_effort: np.ndarray  # (18,) N^2 m^2 over the cycle
    mean_effort: np.ndarray  # (18,) N m
    yaw_drift_deg: float  # heading change over the cycle: a gait that turns by itself is not periodic


def cycle_steps(gait: Gait, control_hz: float) -> int:
    """Control steps of a cycle's eight strides (its pause not counted)."""
    return int(round(CYCLE_STRIDES * gait.cpg().period_s * control_hz))


def pause_steps(gait: Gait, control_hz: float) -> int:
    """Control steps of the pause that makes ``pause_share`` of a cycle."""
    return int(round(cycle_steps(gait, control_hz) * gait.pause_share / (1.0 - gait.pause_share)))


def _run_duty(
    sim: HexapodSim,
    params: DaisyParams,
    gait: Gait,
    payload_kg: float,
    config: SimConfig,
    walking: bool,
    forces: str,
    thermal: ThermalContext | None,
    steps: int,
):
    """Settle, warm up for a few strides, then run ``steps`` control steps; yield ``(k, reading)`` after each
    step.

    ``k`` counts from the end of the warm-up: -1 is the last warm-up step,
    0 the first recorded one.  A stance no solver can meet raises
    ``RuntimeError`` (the legs cannot hold the load).
    """
    loop = ControlLoop(sim, params, gait.cpg(), payload_kg, Gains(), thermal)
    loop.settle(forces)
    warmup = cycle_steps(gait, config.control_hz) // CYCLE_STRIDES * WARMUP_STRIDES
    for k in range(warmup + steps):
        yield k - warmup, loop.step(forces, walking)


def measure_cycle(
    payload_kg: float,
    mode: str,
    forces: str,
    ambient_C: float,
    gait: Gait = NOMINAL_GAIT,
    state: np.ndarray | None = None,
    thermal: ThermalContext | None = None,
    seed: int = 0,
) -> Cycle:
    """Run the robot until its duty is periodic and record one cycle; the plant starts in ``state`` (or at
    ambient).

    Walking with a pause, the pause is measured standing from the state the
    strides leave, and joined to their cycle.
    """
    if mode not in MODES:
        raise ValueError(f"unknown mode {mode!r}; expected one of {', '.join(MODES)}")
    moving = replace(gait, pause_share=0.0)
    hz = SimConfig().control_hz
    strides = _record(payload_kg, mode == "walk", forces, ambient_C, moving, state, thermal, seed,
                      cycle_steps(moving, hz))
    if mode == "stand" or pause_steps(gait, hz) == 0 or strides.fell:
        return strides
    start = np.full(strides.map.M.shape[0], float(ambient_C)) if state is None else state
    pause = _record(payload_kg, False, forces, ambient_C, moving, strides.map.M @ start + strides.map.c,
                    thermal, seed, pause_steps(gait, hz))
    if pause.fell:
        return pause
    joined = strides.map.followed_by(pause.map)
    mean_sq, mean = _with_pause(strides, pause, pause.map.steps / joined.steps)
    return Cycle(joined, strides.distance_per_s_m * strides.map.period_s / joined.period_s, False, mean_sq,
                 mean, strides.yaw_drift_deg)


def _with_pause(cycle: Cycle, pause: Cycle | None, share: float) -> tuple[np.ndarray, np.ndarray]:
    """A cycle's mean squared and mean effort with ``share`` of the time spent in ``pause`` (if any)."""
    if pause is None:
        return cycle.mean_sq_effort, cycle.mean_effort
    return ((1 - share) * cycle.mean_sq_effort + share * pause.mean_sq_effort,
            (1 - share) * cycle.mean_effort + share * pause.mean_effort)


def _record(*args) -> Cycle:
    """:func:`_measured`, run once per process for each set of arguments: a gait plan, the strategies and the
    periodic check ask for some of the same cycles (the same duty from the same state), and a run is
    deterministic, so the second asks get the first's record."""
    key = hashlib.sha256(pickle.dumps(args, protocol=5)).digest()
    if key not in _MEASURED:
        if len(_MEASURED) >= MEASURED_AT_MOST:
            _MEASURED.clear()
        _MEASURED[key] = _measured(*args)
    return _MEASURED[key]


MEASURED_AT_MOST = 256  # cycles kept (a few kB each)
_MEASURED: dict[bytes, Cycle] = {}


def _measured(
    payload_kg: float,
    walking: bool,
    forces: str,
    ambient_C: float,
    gait: Gait,
    state: np.ndarray | None,
    thermal: ThermalContext | None,
    seed: int,
    steps: int,
) -> Cycle:
    """Settle and warm up, then record ``steps`` control steps of walking (or standing) as a cycle."""
    config = SimConfig(payload_kg=payload_kg, ambient_C=ambient_C)
    params = gait.params()
    efforts, velocities = np.zeros((steps, len(JOINTS))), np.zeros((steps, len(JOINTS)))
    with HexapodSim(
        params=params, config=config, plant_effects=EFFECTS, seed=seed, protection=PROTECTION
    ) as sim:
        if state is not None:
            sim.plant.set_state(state)
        start, start_yaw, fell = sim.read().body_position_m.copy(), 0.0, False
        reading = None
        try:
            for k, reading in _run_duty(
                sim, params, gait, payload_kg, config, walking, forces, thermal, steps
            ):
                if reading.body_position_m[2] < FALLEN_BODY_HEIGHT_M:
                    fell = True
                    break
                if k == -1:
                    start, start_yaw = reading.body_position_m.copy(), _yaw_deg(reading.world_R_body)
                elif k >= 0:
                    efforts[k], velocities[k] = sim.applied_Nm, reading.qd_rad_s
        except RuntimeError:  # a stance problem no solver can meet: the legs cannot hold this load
            fell = True
        if fell:
            efforts[:], velocities[:] = 0.0, 0.0
        if fell or not walking:
            distance = 0.0  # standing goes nowhere by definition (the body's drift is not distance)
        else:
            distance = float(reading.body_position_m[0] - start[0])
        drift = 0.0 if fell else abs(_wrapped_deg(_yaw_deg(reading.world_R_body) - start_yaw))
        cycle_map = CycleMap(sim.plant, efforts, velocities, config.control_dt_s)
    return Cycle(cycle_map, distance / cycle_map.period_s, fell, (efforts**2).mean(axis=0),
                 efforts.mean(axis=0), drift)


def _yaw_deg(world_R_body: np.ndarray) -> float:
    return float(np.degrees(np.arctan2(world_R_body[1, 0], world_R_body[0, 0])))


def _wrapped_deg(angle_deg: float) -> float:
    """An angle difference in [-180, 180) degrees: a heading crossing +-180 has not turned a full circle."""
    return (angle_deg + 180.0) % 360.0 - 180.0
