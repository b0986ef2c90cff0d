"""A held duty on the plant: the truth a forecast is judged against (``benchmarks/forecast.py``, the forecast
demo and its tests); and a bench step test, logged as a bench logs one (``benchmarks/transfer.py --sources
step``).

An actuator starts at rest (or warmed by a held effort first), then holds an effort and a speed; the plant
records its noise-free thermistor reading and its winding every step.  The warm-up is returned as the history
a monitor would have seen (its inputs and readings), so that a forecast can place the model's slow states.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..effects import PlantEffects
from ..logs import ActuatorSeries, ThermalLog, from_frame
from ..model.signals import Signals
from .network import ActuatorSpec
from .plant import ThermalPlant
from .profiles import Profile
from .run import run_profile


@dataclass(frozen=True)
class HeldDuty:
    signals: Signals  # the hold's inputs, from its start
    sensor_C: np.ndarray  # the thermistor's noise-free reading over the hold
    winding_C: np.ndarray  # the winding over the hold
    history: ActuatorSeries | None  # the warm-up (None: from rest)
    effort: float
    speed_rad_s: float

    @property
    def start_C(self) -> float:
        return float(self.sensor_C[0])


def held_duty(
    spec,
    effects: PlantEffects,
    effort: float,
    speed_rad_s: float,
    hold_s: float,
    dt_s: float = 1.0,
    warm_effort: float | None = None,
    warm_s: float = 0.0,
    name: str = "knee",
) -> HeldDuty:
    """Hold ``effort`` at ``speed_rad_s`` for ``hold_s`` on a plant of one ``spec`` actuator, from rest or
    after ``warm_s`` at ``warm_effort`` (no sensor noise: the truth)."""
    plant = ThermalPlant([name], [spec], effects)
    readings = [plant.measured_C[0]]
    for _ in range(int(round(warm_s / dt_s))):
        plant.step(np.array([warm_effort]), np.zeros(1), dt_s)
        readings.append(plant.measured_C[0])
    history = None
    if len(readings) > 1:
        n = len(readings)
        history = ActuatorSeries(name,
                                 Signals(np.arange(n) * dt_s, np.full(n, float(warm_effort)), np.zeros(n)),
                                 np.array(readings))
    n = int(round(hold_s / dt_s)) + 1
    sensor, winding = np.empty(n), np.empty(n)
    sensor[0], winding[0] = plant.measured_C[0], plant.winding_C[0]
    for k in range(1, n):
        plant.step(np.array([effort]), np.array([speed_rad_s]), dt_s)
        sensor[k], winding[k] = plant.measured_C[0], plant.winding_C[0]
    signals = Signals(np.arange(n) * dt_s, np.full(n, float(effort)), np.full(n, float(speed_rad_s)))
    return HeldDuty(signals, sensor, winding, history, float(effort), float(speed_rad_s))


def step_test(
    spec: ActuatorSpec,
    effects: PlantEffects,
    load: float,
    seed: int,
    warm_s: float = 0.0,
    hold_s: float = 1080.0,
    total_s: float = 2200.0,
    dt_s: float = 0.5,
    name: str = "knee",
) -> ThermalLog:
    """``load`` times the continuous effort held for ``hold_s``, then released (to 2 % of it; the effort's
    noise 1 % of it), ``total_s`` logged in all with the plant's sensor; ``warm_s`` at the continuous effort
    before it, not logged: a run that starts warm.  At rest throughout: two effort levels, unless the plant's
    protection derates the hold."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(round((warm_s + total_s) / dt_s)) + 1) * dt_s
    level = np.where(t < warm_s, 1.0, np.where(t < warm_s + hold_s, load, 0.02)) + rng.normal(
        0.0, 0.01, t.size
    )
    plant = ThermalPlant([name], [spec], effects=effects, rng=rng)
    frame = run_profile(plant, Profile(t, level[:, None], np.zeros((t.size, 1)))).log.frame
    frame = frame[frame["time"] >= warm_s].reset_index(drop=True)
    frame["time"] -= warm_s
    return from_frame(frame,
                      source=f"step test at {load:g} x the continuous effort" + (", warm" if warm_s else ""))
