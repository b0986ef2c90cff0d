"""Drive a plant through a profile and record a canonical log."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Iterator, Sequence

import numpy as np

from ..effects import PlantEffects
from ..logs import ThermalLog, log_from_arrays
from ..util.errors import UsageError
from ..util.progress import progress
from .blocks import free_block
from .network import ActuatorSpec, ThermalNetwork
from .plant import ThermalPlant
from .profiles import PROFILES, Profile, from_table

BLOCK_STEPS = 512  # intervals a plant advances at once while protection leaves them alone (see free_block)
MIN_BLOCK_STEPS = 16
PIECE_SAMPLES = 100_000  # samples a run held in memory at once when it is written as it goes


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
    up to ``BLOCK_STEPS`` intervals (:func:`~.blocks.free_block`, where the
    plant allows it); ``in_blocks=False`` steps every interval alone, which gives
    the same run to rounding, more slowly.
    """
    return next(run_profile_in_pieces(plant, profile, include_drivers, quiet, housing_sensor, in_blocks,
                                      piece_samples=max(profile.time_s.size, 1)))


def run_profile_in_pieces(plant: ThermalPlant, profile: Profile, include_drivers: bool = False,
                          quiet: bool = True, housing_sensor: bool = False, in_blocks: bool = True,
                          piece_samples: int = PIECE_SAMPLES) -> Iterator[PlantRun]:
    """:func:`run_profile` over consecutive windows of about ``piece_samples`` samples (none shorter than half
    of it), one :class:`PlantRun` each, the plant carried from one window to the next: the same run, held in
    memory one window at a time (``thermolimb simulate`` writes each as it comes)."""
    m = plant.n
    if include_drivers and housing_sensor and plant.driver_names:
        raise UsageError("a log with driver channels cannot also carry housing sensors; choose one")
    lacking = [(name, spec) for name, spec in zip(plant.names, plant.specs) if housing_sensor
               and "housing" not in spec.network.node_names]
    if lacking:  # found before a row is written, not as a traceback once the first window is simulated
        name, spec = lacking[0]
        raise UsageError(f"a housing sensor needs a housing node, and actuator {name}'s network has "
                         f"{', '.join(spec.network.node_names)}; use "
                         "a network with a housing (x8, x5) or drop it")
    if profile.load.shape[1] != m:
        raise ValueError(f"profile has {profile.load.shape[1]} actuators, plant has {m}")
    continuous = np.array([s.continuous_effort for s in plant.specs])
    limit = np.array([s.effort_limit for s in plant.specs])
    vlimit = np.array([s.velocity_limit for s in plant.specs])
    n = profile.time_s.size
    n_drivers = len(plant.driver_names) if include_drivers else 0
    blocks = in_blocks and plant.steps_in_blocks and not housing_sensor and not n_drivers
    bar = progress(total=n, desc="plant", disable=quiet, unit="step")
    edges = np.linspace(0, n, max(1, n // piece_samples) + 1).astype(int)
    for first, stop in zip(edges[:-1], edges[1:]):
        window = slice(first, stop)
        commanded = np.clip(profile.load[window] * continuous, -limit, limit)
        velocity = np.clip(profile.velocity_rad_s[window], -vlimit, vlimit)
        yield _run_window(plant, profile.time_s, first, stop, commanded, velocity, n_drivers, housing_sensor,
                          blocks, bar)
    bar.close()


def _run_window(
    plant, t, first, stop, commanded, velocity, n_drivers, housing_sensor, blocks, bar
) -> PlantRun:
    """Samples ``first`` to ``stop`` of the run; the last steps the plant on to the next window's first."""
    n, m, rows = t.size, plant.n, stop - first
    effort = np.empty((rows, m))
    winding = np.empty((rows, m))
    measured = np.empty((rows, m))
    estimated = np.empty((rows, m)) if plant.observer is not None else None
    current = np.empty((rows, m))
    driver = np.empty((rows, n_drivers))
    ambient = np.empty(rows)
    housing = np.empty((rows, m)) if housing_sensor else None
    channels: dict[str, np.ndarray] = {}
    size = BLOCK_STEPS
    k = first
    while k < stop:
        i = k - first
        steppable = min(stop, n - 1)  # samples before it step the plant on to the next
        if blocks and k < steppable:
            # the intervals protection leaves alone, advanced in one block while the time step holds
            steps = np.diff(t[k : min(k + size, steppable) + 1])
            uneven = np.flatnonzero(np.abs(steps - steps[0]) > 1e-9 * steps[0])
            end = k + (int(uneven[0]) if uneven.size else steps.size)
            done = _record_block(plant, commanded[i : i + end - k], velocity[i : i + end - k], steps[0], i,
                                 effort, winding, measured, estimated, ambient, current)
            bar.update(done)
            size = BLOCK_STEPS if k + done == end else max(MIN_BLOCK_STEPS, size // 4)
            k += done
            if done:
                continue
            i = k - first
        dt = t[k + 1] - t[k] if k + 1 < n else None
        effort[i] = plant.derate(commanded[i], velocity[i], dt)
        winding[i] = plant.winding_C
        measured[i] = plant.measured_C
        if estimated is not None:
            estimated[i] = plant.observer.winding_C
        if housing_sensor:
            housing[i] = plant.read(plant.node_C("housing"))
        if n_drivers:
            driver[i] = plant.measured_driver_C
        ambient[i] = plant.ambient_C
        for column, values in plant.logged_channels().items():
            channels.setdefault(column, np.empty((rows, m)))[i] = values
        if k + 1 < n:
            plant.step(effort[i], velocity[i], t[k + 1] - t[k])
        current[i] = plant.current_A
        bar.update(1)
        k += 1
    t = t[first:stop]
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
        log = log_from_arrays(t, names, effort, measured, velocity=velocity, current_A=current,
                              ambient_C=ambient, housing_C=housing, extra=channels)
    return PlantRun(log, t, effort, winding, measured, estimated)


def _record_block(
    plant, commanded, velocity, dt, k, effort, winding, measured, estimated, ambient, current
) -> int:
    """One :func:`~.blocks.free_block` from sample ``k``, written into the run's arrays; its length."""
    block = free_block(plant, commanded, velocity, dt)
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
    plant, prof = _plant_and_profile(profile, duration_s, dt_s, names, specs, effects, seed, ambient_C,
                                     network, load_scale)
    return run_profile(plant, prof, include_drivers=include_drivers, quiet=quiet,
                       housing_sensor=housing_sensor)


def simulate_profile_in_pieces(profile: str, duration_s: float, dt_s: float, names: Sequence[str],
                               specs: Sequence[ActuatorSpec], effects: PlantEffects, seed: int,
                               ambient_C: float = 25.0, network: ThermalNetwork | None = None,
                               include_drivers: bool = False, quiet: bool = True, load_scale: float = 1.0,
                               housing_sensor: bool = False,
                               piece_samples: int = PIECE_SAMPLES) -> Iterator[PlantRun]:
    """:func:`simulate_profile` one window of about ``piece_samples`` samples at a time
    (:func:`run_profile_in_pieces`): the same run, for writing a long one as it goes."""
    plant, prof = _plant_and_profile(profile, duration_s, dt_s, names, specs, effects, seed, ambient_C,
                                     network, load_scale)
    return run_profile_in_pieces(plant, prof, include_drivers, quiet, housing_sensor,
                                 piece_samples=piece_samples)


def _plant_and_profile(
    profile, duration_s, dt_s, names, specs, effects, seed, ambient_C, network, load_scale
):
    if not load_scale > 0:
        raise UsageError(f"load_scale must be positive, got {load_scale}")
    planned = profile not in PROFILES and str(profile).lower().endswith((".csv", ".parquet"))
    if profile not in PROFILES and not planned:
        raise UsageError(f"unknown profile {profile!r}; built-in profiles: {', '.join(PROFILES)}, or a plan "
                         f"(.csv)")
    rng = np.random.default_rng(seed)
    if network is not None:
        specs = [replace(s, network=network) for s in specs]
    prof = (from_table(profile, dt_s, names, specs) if planned else
            PROFILES[profile](duration_s, dt_s, len(names), rng))
    prof = replace(prof, load=prof.load * load_scale)
    return ThermalPlant(names, specs, effects=effects, ambient_C=ambient_C, rng=rng), prof
