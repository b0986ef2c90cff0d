"""The seed's recovery experiment end to end (slow): calibrate, heat on one leg, recover without falling."""

import numpy as np
import pytest

from humanoid_pb.actuators import datasheet_bank
from humanoid_pb.constants import ACTUATORS, leg_actuators
from humanoid_pb.params import RECOVERED_C, VALKYRIE, WARNING_C
from humanoid_pb.recovery import calibrate, run_recovery


@pytest.fixture(scope="module")
def bank():
    """Models identified from the robot's own 90 s calibration log (only the slow tests use it)."""
    return calibrate(90.0)[0]


@pytest.mark.slow
def test_calibration_identifies_the_winding_time_constant(bank):
    leg = [ACTUATORS.index(a) for a in leg_actuators("right")]
    assert np.median(bank.RC_s[leg]) == pytest.approx(40.0, rel=0.15)  # 40 s in the plant


@pytest.mark.slow
@pytest.mark.parametrize("strategy", ["thermal_aware", "minimum_effort"])
def test_recovers_from_the_warning_zone_without_falling(bank, strategy):
    run = run_recovery(strategy, bank, max_heat_s=60.0, max_recovery_s=90.0)
    assert run.warning_at_s is not None and run.warning_at_s < 120.0  # the stance leg heats within two minutes
    assert not run.fell
    assert run.recovery_s is not None
    T = np.array(run.temperature_C)
    assert T[-1].max() < RECOVERED_C <= WARNING_C


def test_same_seed_same_run():
    bank = datasheet_bank(VALKYRIE)
    one = run_recovery("minimum_effort", bank, max_heat_s=5.0, max_recovery_s=0.0)
    two = run_recovery("minimum_effort", bank, max_heat_s=5.0, max_recovery_s=0.0)
    np.testing.assert_array_equal(np.array(one.temperature_C), np.array(two.temperature_C))


@pytest.mark.slow
def test_env_policy_plans_with_models_of_the_robot_it_drives():
    """A robot whose windings run 25 % hotter than its datasheet: the thermal-aware policy identifies that from the
    robot's own calibration run, and drives it without falling.  (Whether it recovers is the environment's
    calibration question: at this seed the crouching knee heats past 100 degC whatever the plan.)"""
    from contextlib import closing
    from dataclasses import replace

    import gymnasium as gym

    from humanoid_pb import ENV_ID
    from humanoid_pb.actuators import actuator_specs
    from humanoid_pb.policies import POLICIES

    worn = tuple(replace(s, winding_resistance_ohm=1.25 * s.winding_resistance_ohm) for s in actuator_specs(VALKYRIE))
    policy = POLICIES["thermal_aware"](seed=0)
    with closing(gym.make(ENV_ID, actuator_specs=worn, max_time_s=90.0)) as env:
        obs, _ = env.reset(seed=1)
        start_C = env.unwrapped.sim.plant.measured_C.max()
        terminated = truncated = False
        while not (terminated or truncated):
            obs, _, terminated, truncated, info = env.step(policy(env, obs))
        identified = policy.models(env.unwrapped)
        end_C = env.unwrapped.sim.plant.measured_C.max()
    sheet = datasheet_bank(VALKYRIE)
    leg = [ACTUATORS.index(a) for a in leg_actuators("right") + leg_actuators("left")]
    ratio = np.median(identified.betaR_K_per_effort2[leg] / sheet.betaR_K_per_effort2[leg])
    assert ratio == pytest.approx(1.25, rel=0.15)
    assert not env.unwrapped.fallen and np.isfinite([start_C, end_C]).all()
