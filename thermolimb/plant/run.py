"""Drive a plant through a profile and record a canonical log."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np

from ..logs import ThermalLog, log_from_arrays
from ..util.errors import UsageError
from ..util.progress import progress
from .effects import PlantEffects
from .network import ActuatorSpec, ThermalNetwork
from .plant import ThermalPlant
from .profiles import PROFILES, Profile

BLOCK_STEPS = 512  # intervals a plant advances at once while protection leaves them alone (see free_block)
MIN_BLOCK_STEPS = 16


@dataclass(frozen=True)
class PlantRun:
    """Everything a profile run produced; ``log`` is what a robot would have logged."""

    log: ThermalLog
    time_s: np.ndarray
    effort: np.ndarray  # (n, m) applied efforts
    true_winding_C: np.ndarray  # (n, m)
    measured_C: np.ndarray  # (n, m)
    estimated_C: np.ndarray | None = None  # (n, m) the protection observer's winding estimate, if it runs one


def run_profile(plant: ThermalPlant, profile: Profile, include_drivers: bool = False,
                quiet: bool = True, housing_sensor: bool = False, in_blocks: bool = True) -> PlantRun:
    """Apply a profile (scaled to each actuator's continuous effort) and log every sample.

    Efforts are clipped to each actuator's limit and derated by the plant's
    thermal protection; the log records what was applied.  ``housing_sensor``
    logs a second thermistor on each actuator's housing node (column ``housing``).
    While protection leaves the actuators alone the plant advances in blocks of
    up to ``BLOCK_STEPS`` intervals (:meth:`~ThermalPlant.free_block`, where the
    plant allows it); ``in_blocks=False`` steps every interval alone, which gives
    the same run to rounding, more slowly.
    """
    m = plant.n
    if include_drivers and housing_sensor and plant.driver_names:
        raise UsageError("a log with driver channels cannot also carry housing sensors; choose one")
    if profile.load.shape[1] != m:
        raise ValueError(f"profile has {profile.load.shape[1]} actuators, plant has {m}")
    continuous = np.array([s.continuous_effort for s in plant.specs])
    limit = np.array([s.effort_limit for s in plant.specs])
    vlimit = np.array([s.velocity_limit for s in plant.specs])
    t = profile.time_s
    n = t.size
    effort = np.empty((n, m))
    velocity = np.clip(profile.velocity_rad_s, -vlimit, vlimit)
    winding = np.empty((n, m))
    measured = np.empty((n, m))
    estimated = np.empty((n, m)) if plant.observer is not None else None
    current = np.empty((n, m))
    n_drivers = len(plant.driver_names) if include_drivers else 0
    driver = np.empty((n, n_drivers))
    ambient = np.empty(n)
    housing = np.empty((n, m)) if housing_sensor else None
    channels: dict[str, np.ndarray] = {}
    commanded = np.clip(profile.load * continuous, -limit, limit)
    blocks = in_blocks and plant.steps_in_blocks and not housing_sensor and not n_drivers
    size = BLOCK_STEPS
    k = 0
    bar = progress(total=n, desc="plant", disable=quiet, unit="step")
    while k < n:
        if blocks and k + 1 < n:
            # the intervals protection leaves alone, advanced in one block while the time step holds
            steps = np.diff(t[k : min(k + size, n - 1) + 1])
            uneven = np.flatnonzero(np.abs(steps - steps[0]) > 1e-9 * steps[0])
            stop = k + (int(uneven[0]) if uneven.size else steps.size)
            done = _record_block(plant, commanded[k:stop], velocity[k:stop], steps[0], k, effort, winding,
                                 measured, estimated, ambient, current)
            bar.update(done)
            size = BLOCK_STEPS if k + done == stop else max(MIN_BLOCK_STEPS, size // 4)
            k += done
            if done:
                continue
        dt = t[k + 1] - t[k] if k + 1 < n else None
        effort[k] = plant.derate(commanded[k], velocity[k], dt)
        winding[k] = plant.winding_C
        measured[k] = plant.measured_C
        if estimated is not None:
            estimated[k] = plant.observer.winding_C
        if housing_sensor:
            housing[k] = plant.read(plant.node_C("housing"))
        if n_drivers:
            driver[k] = plant.measured_driver_C
        ambient[k] = plant.ambient_C
        for column, values in plant.logged_channels().items():
            channels.setdefault(column, np.empty((n, m)))[k] = values
        if k + 1 < n:
            plant.step(effort[k], velocity[k], t[k + 1] - t[k])
        current[k] = plant.current_A
        bar.update(1)
        k += 1
    bar.close()
    names = plant.names
    if n_drivers:
        has = [i for i, s in enumerate(plant.specs) if s.driver is not None]
        names = names + plant.driver_names
        effort_log = np.hstack([effort, effort[:, has]])
        log = log_from_arrays(t, names, effort_log, np.hstack([measured, driver]),
                              velocity=np.hstack([velocity, velocity[:, has]]),
                              current_A=np.hstack([current, current[:, has]]), ambient_C=ambient,
                              extra={c: np.hstack([v, v[:, has]]) for c, v in channels.items()})
    else:
        log = log_from_arrays(t, names, effort, measured, velocity=velocity, current_A=current, ambient_C=ambient,
                              housing_C=housing, extra=channels)
    return PlantRun(log, t, effort, winding, measured, estimated)


def _record_block(plant, commanded, velocity, dt, k, effort, winding, measured, estimated, ambient, current) -> int:
    """One :meth:`~ThermalPlant.free_block` from sample ``k``, written into the run's arrays; its length."""
    block = plant.free_block(commanded, velocity, dt)
    rows = slice(k, k + block.steps)
    effort[rows], winding[rows], measured[rows] = block.effort, block.true_winding_C, block.measured_C
    ambient[rows], current[rows] = block.ambient_C, block.current_A
    if estimated is not None:
        estimated[rows] = block.estimated_C
    return block.steps


def simulate_profile(
    profile: str,
    duration_s: float,
    dt_s: float,
    names: Sequence[str],
    specs: Sequence[ActuatorSpec],
    effects: PlantEffects,
    seed: int,
    ambient_C: float = 25.0,
    network: ThermalNetwork | None = None,
    include_drivers: bool = False,
    quiet: bool = True,
    load_scale: float = 1.0,
    housing_sensor: bool = False,
) -> PlantRun:
    """One call from a profile name to a log: what ``thermolimb simulate`` does.

    ``seed`` drives both the profile's randomness and the sensor noise;
    ``load_scale`` multiplies every effort (a heavier payload), before the
    actuators' effort limits clip it.
    """
    if not load_scale > 0:
        raise UsageError(f"load_scale must be positive, got {load_scale}")
    if profile not in PROFILES:
        raise UsageError(f"unknown profile {profile!r}; built-in profiles: {', '.join(PROFILES)}")
    rng = np.random.default_rng(seed)
    if network is not None:
        specs = [replace(s, network=network) for s in specs]
    prof = PROFILES[profile](duration_s, dt_s, len(names), rng)
    prof = replace(prof, load=prof.load * load_scale)
    plant = ThermalPlant(names, specs, effects=effects, ambient_C=ambient_C, rng=rng)
    return run_profile(plant, prof, include_drivers=include_drivers, quiet=quiet, housing_sensor=housing_sensor)
