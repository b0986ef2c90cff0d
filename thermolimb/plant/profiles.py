"""Built-in effort and velocity profiles for ``thermolimb simulate``.

Each profile is a pure function ``(duration_s, dt_s, n_actuators, rng) ->
Profile`` giving *normalised* effort (fraction of each actuator's continuous
effort) and velocity in rad/s; :func:`thermolimb.plant.run.run_profile`
scales them to each actuator.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..util.errors import UsageError


@dataclass(frozen=True)
class Profile:
    time_s: np.ndarray  # (n,)
    load: np.ndarray  # (n, m): effort / continuous effort
    velocity_rad_s: np.ndarray  # (n, m)


def _grid(duration_s: float, dt_s: float) -> np.ndarray:
    if not (duration_s > 0 and dt_s > 0 and duration_s >= 10 * dt_s):
        raise UsageError(f"need duration_s >= 10 * dt_s > 0, got duration {duration_s} s and dt {dt_s} s")
    return np.arange(int(round(duration_s / dt_s)) + 1) * dt_s


def _limb_weights(m: int) -> np.ndarray:
    """How strongly each actuator of a limb is loaded (knee, hip, ankle, ... repeating)."""
    return np.resize(np.array([1.0, 0.8, 0.6]), m)


def _smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def squat(duration_s: float, dt_s: float, n_actuators: int, rng: np.random.Generator,
          period_s: float = 270.0, hold_s: float = 90.0, move_s: float = 3.0,
          squat_load: float = 1.3, stand_load: float = 0.35, travel_rad: float = 1.2) -> Profile:
    """Jorgensen et al.'s Fig. 5 experiment: a double-support squat and stand-up every 4.5 minutes."""
    t = _grid(duration_s, dt_s)
    phase = np.mod(t, period_s)
    down = _smoothstep(phase / move_s) - _smoothstep((phase - move_s - hold_s) / move_s)
    depth = down  # 0 standing, 1 squatting
    ddepth = np.gradient(depth, t)
    w = _limb_weights(n_actuators)
    load = (stand_load + (squat_load - stand_load) * depth)[:, None] * w
    load = load + rng.normal(0.0, 0.02, load.shape)
    velocity = (travel_rad * ddepth)[:, None] * w
    return Profile(t, load, velocity)


def single_leg(duration_s: float, dt_s: float, n_actuators: int, rng: np.random.Generator,
               stance_load: float = 1.2, sway_load: float = 0.08, sway_hz: float = 0.3) -> Profile:
    """Balancing on one leg: a ramp onto the leg, then a high load with postural sway."""
    t = _grid(duration_s, dt_s)
    ramp = _smoothstep(t / 5.0)
    sway = np.sin(2 * np.pi * sway_hz * t)
    w = _limb_weights(n_actuators)
    load = (0.3 + (stance_load - 0.3) * ramp + sway_load * sway)[:, None] * w
    load = load + rng.normal(0.0, 0.02, load.shape)
    velocity = (0.05 * np.cos(2 * np.pi * sway_hz * t))[:, None] * w
    return Profile(t, load, velocity)


def walking(duration_s: float, dt_s: float, n_actuators: int, rng: np.random.Generator,
            gait_period_s: float = 1.0, walk_s: tuple[float, float] = (60.0, 300.0),
            rest_s: tuple[float, float] = (30.0, 120.0)) -> Profile:
    """Bouts of walking (periodic load and motion) separated by rests standing."""
    t = _grid(duration_s, dt_s)
    walking_now = np.zeros(t.shape, bool)
    edge, walk = 0.0, True
    while edge < t[-1]:
        length = rng.uniform(*(walk_s if walk else rest_s))
        walking_now |= walk & (t >= edge) & (t < edge + length)
        edge, walk = edge + length, not walk
    m = n_actuators
    phase = 2 * np.pi * t[:, None] / gait_period_s + np.linspace(0.0, np.pi, m)[None, :]
    w = _limb_weights(m)
    gait_load = (0.7 + 0.5 * np.sin(phase)) * w
    load = np.where(walking_now[:, None], gait_load, 0.4 * w)
    velocity = np.where(walking_now[:, None], 1.5 * np.cos(phase) * w, 0.0)
    load = load + rng.normal(0.0, 0.02, load.shape)
    return Profile(t, load, velocity)


def random_holds(duration_s: float, dt_s: float, n_actuators: int, rng: np.random.Generator,
                 segment_s: tuple[float, float] = (20.0, 240.0), motion_probability: float = 0.4) -> Profile:
    """Random holds at random loads (both signs) and random oscillating motions: rich excitation."""
    t = _grid(duration_s, dt_s)
    m = n_actuators
    load = np.empty((t.size, m))
    velocity = np.zeros((t.size, m))
    edge = 0.0
    while edge <= t[-1]:
        length = rng.uniform(*segment_s)
        sel = (t >= edge) & (t < edge + length)
        tau = t[sel] - edge
        for j in range(m):
            level = rng.uniform(-1.2, 1.3)
            if rng.random() < motion_probability:
                hz = rng.uniform(0.1, 1.0)
                amplitude = rng.uniform(0.3, 2.5)
                load[sel, j] = level + 0.4 * np.sin(2 * np.pi * hz * tau)
                velocity[sel, j] = amplitude * np.cos(2 * np.pi * hz * tau)
            else:
                load[sel, j] = level
        edge += length
    load = load + rng.normal(0.0, 0.02, load.shape)
    return Profile(t, load, velocity)


def stairs(
    duration_s: float,
    dt_s: float,
    n_actuators: int,
    rng: np.random.Generator,
    levels: tuple[float, ...] = (0.4, 0.9, 1.4, 0.0, 2.2, 0.6),
    stall_fraction: float = 0.5,
) -> Profile:
    """A dynamometer run: stair-step loads (a rest step among them), some held at stall (no motion), the rest
    turning at a load-dependent speed."""
    t = _grid(duration_s, dt_s)
    step = np.minimum((t / (t[-1] + dt_s) * len(levels)).astype(int), len(levels) - 1)
    w = _limb_weights(n_actuators)
    level = np.asarray(levels)[step]
    load = level[:, None] * w + rng.normal(0.0, 0.01, (t.size, n_actuators))
    stalled = rng.random(len(levels)) < stall_fraction
    speed = np.where(stalled[step], 0.0, 0.5 + 0.8 * level)
    return Profile(t, load, speed[:, None] * w)


def pulses(duration_s: float, dt_s: float, n_actuators: int, rng: np.random.Generator, count: int = 3,
           load: float = 2.5, on_fraction: float = 0.12) -> Profile:
    """A bench step test: ``count`` load pulses, each followed by cooling, at rest otherwise."""
    t = _grid(duration_s, dt_s)
    period = (t[-1] + dt_s) / count
    start = period * (0.15 + 0.1 * rng.random(count))
    k = np.minimum((t // period).astype(int), count - 1)
    on = (t - k * period >= start[k]) & (t - k * period < start[k] + on_fraction * period)
    w = _limb_weights(n_actuators)
    level = np.where(on, load, 0.02)[:, None] * w + rng.normal(0.0, 0.01, (t.size, n_actuators))
    return Profile(t, level, np.zeros((t.size, n_actuators)))


PROFILES: dict[str, Callable[..., Profile]] = {
    "squat": squat,
    "single_leg": single_leg,
    "walking": walking,
    "random": random_holds,
    "stairs": stairs,
    "pulses": pulses,
}


def from_table(path, dt_s: float, names, specs) -> Profile:
    """A profile from a file of set-points (``thermolimb plan --out``: ``time, actuator, effort[,
    velocity]``, in the actuators' units), sampled every ``dt_s`` from its first time to its last, each
    set-point held until the next; an actuator the file does not name rests.  The efforts are given as shares
    of each actuator's continuous effort, as a built-in profile's are."""
    from ..util.lazy import pandas as pd

    try:
        table = pd.read_csv(path) if str(path).lower().endswith(".csv") else pd.read_parquet(path)
    except (OSError, ValueError) as exc:
        raise UsageError(f"--profile {path}: cannot be read as a plan ({exc}); expected a CSV of time, "
                         f"actuator, effort and velocity, as thermolimb plan writes") from None
    missing = [c for c in ("time", "actuator", "effort") if c not in table.columns]
    if missing:
        raise UsageError(f"--profile {path}: no column {missing[0]!r}; expected time, actuator, effort (and "
                         f"velocity), as thermolimb plan writes")
    unknown = sorted(set(table["actuator"].astype(str)) - set(names))
    if unknown:
        raise UsageError(f"--profile {path}: it sets actuator {unknown[0]!r}, which --actuators does not "
                         f"name ({', '.join(names)}); expected --actuators {unknown[0]}:MODEL")
    values = table[["time", "effort"] + (["velocity"] if "velocity" in table else [])].to_numpy(float)
    if not np.isfinite(values).all() or not np.all(np.diff(table["time"].to_numpy(float)) >= 0):
        raise UsageError(f"--profile {path}: its times must increase and every set-point be a finite number")
    start, end = float(table["time"].min()), float(table["time"].max())
    t = _grid(end - start, dt_s)
    load, velocity = np.zeros((t.size, len(names))), np.zeros((t.size, len(names)))
    for k, (name, spec) in enumerate(zip(names, specs)):
        rows = table[table["actuator"].astype(str) == name]
        if rows.empty:
            continue
        at = np.searchsorted(rows["time"].to_numpy(float) - start, t, side="right") - 1
        at = np.clip(at, 0, len(rows) - 1)
        load[:, k] = rows["effort"].to_numpy(float)[at] / spec.continuous_effort
        if "velocity" in rows:
            velocity[:, k] = rows["velocity"].to_numpy(float)[at]
    return Profile(t, load, velocity)
