"""The periodic shortcut is the plant stepped: cycle maps, crossings, steady states, refusals."""

import numpy as np
import pytest

from thermolimb.plant import (
    X8_9,
    X8_16,
    MotionCooling,
    NeighborCoupling,
    PlantEffects,
    SensorLag,
    SpeedLosses,
    ThermalPlant,
    WindingTempco,
)
from thermolimb.plant.periodic import CycleMap

# every effect that keeps the network linear in its state, the driver boards included
LINEAR_EFFECTS = PlantEffects(winding_tempco=WindingTempco(), speed_losses=SpeedLosses(),
                              neighbor_coupling=NeighborCoupling(), motion_cooling=MotionCooling(),
                              sensor_lag=SensorLag())


def _cycle(steps=40, n=3, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(steps) / steps
    efforts = 12.0 * np.sin(2 * np.pi * t)[:, None] * rng.uniform(0.5, 1.5, n) + rng.normal(0, 1.0, (steps, n))
    velocities = 1.5 * np.cos(2 * np.pi * t)[:, None] * np.ones(n)
    return efforts, velocities


def _plant(ambient_C=30.0):
    return ThermalPlant(["a", "b", "c"], [X8_9, X8_16, X8_9], effects=LINEAR_EFFECTS, ambient_C=ambient_C)


def test_cycle_map_is_the_plant_stepped():
    efforts, velocities = _cycle()
    plant = _plant()
    cycle = CycleMap(plant, efforts, velocities, 0.02)
    prop = cycle.propagate(plant.state, 300 * cycle.period_s)
    windings = []
    for _ in range(300):
        windings.append(plant.winding_C)
        for e, v in zip(efforts, velocities):
            plant.step(e, v, 0.02)
    np.testing.assert_allclose(prop.winding_C, np.array(windings), atol=1e-9)
    np.testing.assert_allclose(prop.final_state, plant.state, atol=1e-9)


def test_a_cycle_followed_by_a_pause_is_the_joined_cycle():
    walking, walking_v = _cycle(steps=40, seed=1)
    pause, pause_v = np.tile([[3.0, 8.0, 1.0]], (15, 1)), np.zeros((15, 3))
    plant = _plant()
    joined = CycleMap(plant, walking, walking_v, 0.02).followed_by(CycleMap(plant, pause, pause_v, 0.02))
    whole = CycleMap(plant, np.vstack([walking, pause]), np.vstack([walking_v, pause_v]), 0.02)
    assert joined.steps == 55 and joined.period_s == pytest.approx(1.1)
    x0 = plant.state + np.linspace(0.0, 20.0, len(plant.state))
    np.testing.assert_allclose(joined.within(x0), whole.within(x0), atol=1e-9)
    np.testing.assert_allclose(joined.steady_state(), whole.steady_state(), atol=1e-9)
    with pytest.raises(ValueError, match="same network"):
        joined.followed_by(CycleMap(plant, pause, pause_v, 0.05))


def test_crossing_is_the_first_interval_over_the_threshold():
    efforts, velocities = _cycle()
    efforts = efforts * 2.5
    plant = _plant()
    cycle = CycleMap(plant, efforts, velocities, 0.02)
    threshold = 80.0
    prop = cycle.propagate(plant.state, 3600.0, threshold)
    assert prop.crossing is not None
    step = 0
    while plant.winding_C.max() < threshold:
        plant.step(efforts[step % len(efforts)], velocities[step % len(efforts)], 0.02)
        step += 1
    assert prop.crossing.time_s == pytest.approx(step * 0.02)
    assert prop.crossing.actuator == int(np.argmax(plant.winding_C))


def test_steady_state_is_a_fixed_point_and_decides_never():
    efforts, velocities = _cycle()
    plant = _plant()
    cycle = CycleMap(plant, efforts, velocities, 0.02)
    x = cycle.steady_state()
    np.testing.assert_allclose(cycle.M @ x + cycle.c, x, atol=1e-9)
    peak = cycle.steady_peak_C().max()
    assert cycle.propagate(plant.state, 20 * 3600.0, peak + 0.5).crossing is None
    assert cycle.propagate(plant.state, 20 * 3600.0, peak - 0.5).crossing is not None


def test_cycle_map_refuses_what_is_not_periodic():
    efforts, velocities = _cycle()
    drifting = ThermalPlant(["a"], [X8_9], effects=PlantEffects.from_names("ambient_variation"))
    with pytest.raises(ValueError, match="not periodic"):
        CycleMap(drifting, efforts[:, :1], velocities[:, :1], 0.02)
    with pytest.raises(ValueError, match="shape"):
        CycleMap(_plant(), efforts[:, :2], velocities[:, :2], 0.02)
    efforts[3, 1] = np.nan
    with pytest.raises(ValueError, match="finite"):
        CycleMap(_plant(), efforts, velocities, 0.02)


def test_one_threshold_per_actuator():
    efforts, velocities = _cycle()
    plant = _plant()
    cycle = CycleMap(plant, efforts * 2.5, velocities, 0.02)
    peak = cycle.steady_peak_C()
    hottest = int(np.argmax(peak))
    threshold = np.full(3, np.inf)
    threshold[(hottest + 1) % 3] = peak[(hottest + 1) % 3] - 1.0  # only a cooler actuator can cross
    prop = cycle.propagate(plant.state, 20 * 3600.0, threshold)
    assert prop.crossing.actuator == (hottest + 1) % 3
    assert prop.mean_winding_C.shape == prop.winding_C.shape == prop.peak_winding_C.shape
    assert np.all(prop.peak_winding_C >= prop.mean_winding_C)
