"""The plant and the robots refuse impossible parameters in one sentence naming the argument, its value and the
range expected; at run time they behave like a real drive: an effort beyond the peak is saturated and counted,
a command that is not a finite number faults its actuator instead of poisoning the state."""

from dataclasses import replace

import numpy as np
import pytest

from thermolimb.plant import X8_9, ThermalPlant
from thermolimb.rig import RigConfig


@pytest.mark.parametrize("make, message", [
    (lambda: ThermalPlant(["a"], [X8_9], ambient_C=float("nan")), "ambient_C = nan is outside"),
    (lambda: ThermalPlant(["a"], [X8_9], ambient_C=-500.0), "ambient_C = -500.0 is outside"),
    (lambda: ThermalPlant(["a"], [X8_9], ambient_C=1e6), "ambient_C = 1000000.0 is outside"),
    (lambda: ThermalPlant(["a"], [X8_9], initial_C=float("inf")), "initial_C = inf is outside"),
    (lambda: replace(X8_9, winding_limit_C=-5.0), "winding_limit_C = -5.0 is outside"),
    (lambda: replace(X8_9, continuous_effort=50.0), "continuous_effort = 50 is above effort_limit = 20"),
    (lambda: RigConfig(physics_hz=float("inf")), "physics_hz = inf is outside"),
    (lambda: RigConfig(foot_friction=-0.5), "foot_friction = -0.5 is outside"),
    (lambda: RigConfig(torque_noise_Nm=-0.1), "torque_noise_Nm = -0.1 is outside"),
])
def test_impossible_parameters_are_one_sentence(make, message):
    with pytest.raises(ValueError) as caught:
        make()
    assert message in str(caught.value) and len(str(caught.value).splitlines()) == 1


def test_hexapod_payload_nan_is_refused():
    from hexapod_pb.sim import SimConfig

    with pytest.raises(ValueError, match="payload_kg = nan is outside"):
        SimConfig(payload_kg=float("nan"))


def test_set_temperatures_takes_one_or_one_per_actuator_within_range():
    plant = ThermalPlant(["a", "b"], [X8_9, X8_9])
    with pytest.raises(ValueError, match="needs one temperature or 2"):
        plant.set_temperatures([30.0])
    with pytest.raises(ValueError, match="of a = -300.0 is outside"):
        plant.set_temperatures([-300.0, 20.0])
    plant.set_temperatures(40.0)
    assert np.allclose(plant.winding_C, 40.0)


def test_a_drive_saturates_at_its_peak_and_faults_on_poison():
    plant = ThermalPlant(["a", "b", "c"], [X8_9] * 3)
    with pytest.raises(ValueError, match="positive, finite number of seconds"):
        plant.step(np.ones(3), None, float("inf"))
    for _ in range(60):
        plant.step(np.array([np.nan, 1e6, 5.0]), np.array([0.0, 0.0, np.inf]), 1.0)
    assert list(plant.faulted) == [True, False, True]
    assert list(plant.saturations) == [0, 60, 0]
    assert np.all(np.isfinite(plant.winding_C)) and plant.winding_C[1] < X8_9.winding_limit_C + 200
    reference = ThermalPlant(["b"], [X8_9])
    for _ in range(60):
        reference.step(np.array([X8_9.effort_limit]), None, 1.0)
    assert plant.winding_C[1] == pytest.approx(reference.winding_C[0])  # held at the peak, not at 1e6 N m
    assert plant.winding_C[0] == pytest.approx(25.0)  # faulted: no torque, no heat
    plant.clear_faults()
    plant.step(np.array([5.0, 5.0, 5.0]), None, 1.0)
    assert not plant.faulted.any() and plant.winding_C[0] > 25.0


def test_an_environment_reports_faults_in_info():
    import gymnasium as gym

    from hexapod_pb import ENV_ID

    env = gym.make(ENV_ID, max_time_s=2.0)
    try:
        env.reset(seed=0)
        _, _, _, _, info = env.step(env.action_space.sample())
        assert info["actuator_faults"] == [] and isinstance(info["saturated_steps"], dict)
        env.unwrapped.sim.plant.step(np.full(18, np.nan), None, 0.02)
        _, _, _, _, info = env.step(env.action_space.sample())
        assert len(info["actuator_faults"]) == 18
    finally:
        env.close()


def test_protection_fails_safe_on_a_nan_reading():
    from thermolimb.plant import ThermalProtection

    protection = ThermalProtection(min_fraction=0.1)
    share = protection.fraction(np.array([np.nan, 60.0, 200.0]), np.array([155.0, 155.0, 155.0]))
    assert list(share) == [0.1, 1.0, 0.1]


def test_a_faulted_drive_is_in_the_rig_log():
    import gymnasium as gym

    from hexapod_pb import ENV_ID

    env = gym.make(ENV_ID, max_time_s=2.0)
    try:
        env.reset(seed=0)
        env.step(env.action_space.sample())
        sim = env.unwrapped.sim
        sim.plant.step(np.r_[np.nan, np.zeros(17)], None, 0.02)
        env.step(env.action_space.sample())
        log = sim.thermal_log()
        assert "fault" in log.extras
        assert log.series(sim.actuators[0]).signals.extra["fault"][-1] == 1.0
    finally:
        env.close()
