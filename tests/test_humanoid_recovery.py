"""Jorgensen et al.'s recovery experiment end to end (slow): calibrate, heat on one leg, recover without falling."""

import numpy as np
import pytest

from humanoid_pb.calibration import calibrate
from humanoid_pb.constants import ACTUATORS, leg_actuators
from humanoid_pb.experiments.recovery import run_recovery
from humanoid_pb.limits import LIMITS
from humanoid_pb.params import VALKYRIE
from humanoid_pb.thermal import datasheet_bank


@pytest.fixture(scope="module")
def bank():
    """Models identified from the robot's own 90 s calibration log (only the slow tests use it)."""
    return calibrate(90.0).bank


@pytest.mark.slow
def test_calibration_identifies_the_winding_time_constant(bank):
    leg = [ACTUATORS.index(a) for a in leg_actuators("right")]
    assert np.median(bank.RC_s[leg]) == pytest.approx(40.0, rel=0.15)  # 40 s in the plant


@pytest.mark.slow
@pytest.mark.parametrize("strategy", ["thermal_aware", "minimum_effort"])
def test_recovers_from_the_warning_zone_without_falling(bank, strategy):
    run = run_recovery(strategy, bank, max_heat_s=120.0, max_recovery_s=90.0)
    assert run.warning_at_s is not None and run.warning_at_s < 120.0  # the stance leg heats within two minutes
    assert not run.fell
    assert run.recovery_s is not None
    T = np.array(run.temperature_C)
    assert T[-1].max() < LIMITS.recovered_C <= LIMITS.warning_C


def test_same_seed_same_run():
    bank = datasheet_bank(VALKYRIE)
    one = run_recovery("minimum_effort", bank, max_heat_s=5.0, max_recovery_s=0.0)
    two = run_recovery("minimum_effort", bank, max_heat_s=5.0, max_recovery_s=0.0)
    np.testing.assert_array_equal(np.array(one.temperature_C), np.array(two.temperature_C))


@pytest.mark.slow
def test_env_policy_plans_with_models_of_the_robot_it_drives():
    """A robot whose windings run 25 % hotter than its datasheet: the thermal-aware policy identifies that from the
    robot's own calibration run, and recovers it without falling."""
    from contextlib import closing
    from dataclasses import replace

    import gymnasium as gym

    from humanoid_pb import ENV_ID
    from humanoid_pb.policies import POLICIES
    from humanoid_pb.thermal import actuator_specs

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
    assert not env.unwrapped.fallen and info["recovered"] and end_C < LIMITS.recovered_C < start_C


def test_first_order_cooling_times_and_the_steady_state_a_ratio_needs():
    from humanoid_pb.experiments.recovery import first_order_cooling_s, steady_needed_for_ratio

    fast = first_order_cooling_s(LIMITS.warning_C, LIMITS.recovered_C, 25.0, 40.0)
    assert fast == pytest.approx(40.0 * np.log(50.0 / 45.0))
    needed = steady_needed_for_ratio(2.0, 25.0)
    assert 45.0 < needed < LIMITS.recovered_C
    assert first_order_cooling_s(LIMITS.warning_C, LIMITS.recovered_C, needed, 40.0) == pytest.approx(2 * fast)
    assert first_order_cooling_s(LIMITS.warning_C, LIMITS.recovered_C, 71.0, 40.0) == np.inf  # held above 70 it never recovers


def test_double_support_unloads_the_hot_ankle_rods_as_fully_as_lifting_the_leg():
    """Why contact switching does not pay on this robot (the recovery demo reports the same numbers)."""
    from humanoid_pb.experiments.recovery import cooling_bound
    from humanoid_pb.ik.poses import crouch_angles, single_support, standing
    from humanoid_pb.model.statics import WholeBody

    body = WholeBody()
    q = standing(body, crouch_angles())
    bound = cooling_bound(body, datasheet_bank(VALKYRIE), "right_ankle_rod_b",
                          {"double": ("double", q), "left": ("left", single_support(body, q, "left")),
                           "right": ("right", single_support(body, q, "right"))})
    assert bound["double"]["effort_fraction"] < 0.02 and bound["left"]["effort_fraction"] < 0.02
    assert bound["double"]["warning_to_recovered_s"] == pytest.approx(bound["left"]["warning_to_recovered_s"], rel=0.05)
    assert bound["right"]["effort_fraction"] > 0.2 and bound["right"]["steady_C"] > LIMITS.warning_C
    assert bound["right"]["warning_to_recovered_s"] == np.inf  # on the hot foot it never cools


def test_the_environments_planner_steps_off_a_hot_leg_held_in_a_crouch():
    """With the right leg hot, holding the nominal crouch keeps its knee loaded: the thermal objective stands on
    the cool (left) foot, minimum effort stays in double support; with every actuator cool both stay in double."""
    from humanoid_pb.control.planner import ContactModePlanner
    from humanoid_pb.ik.poses import crouch_angles, standing
    from humanoid_pb.model.statics import WholeBody

    body = WholeBody()
    q = standing(body, crouch_angles())
    bank = datasheet_bank(VALKYRIE)
    hot = np.full(len(ACTUATORS), 40.0)
    hot[[ACTUATORS.index(a) for a in leg_actuators("right")]] = 78.0
    assert ContactModePlanner(body, "thermal").plan_nominal(q, bank, hot) == "left"
    assert ContactModePlanner(body, "effort").plan_nominal(q, None, hot) == "double"
    assert ContactModePlanner(body, "thermal").plan_nominal(q, bank, np.full(len(ACTUATORS), 40.0)) == "double"


@pytest.mark.parametrize("scenario", ["ankle", "walking"])
def test_the_weight_goes_from_one_foot_to_the_other_and_into_the_planned_posture_without_a_fall(scenario):
    """The move the thermal-aware strategy makes when it leaves the hot leg: from balancing on the right foot,
    through the crouch, onto the left foot in the posture the planner found there (at 1.5 s per weight shift
    and lift this fell in both scenarios)."""
    from humanoid_pb.control.executor import Executor
    from humanoid_pb.control.planner import ContactModePlanner
    from humanoid_pb.experiments.recovery import FALLEN_PELVIS_HEIGHT_M
    from humanoid_pb.sim import HumanoidSim

    with HumanoidSim(seed=0, scenario=scenario) as sim:
        executor = Executor(sim)
        reading = sim.read()
        executor.go("right")
        lowest = np.inf
        for _ in range(int(15.0 / sim.config.control_dt_s)):
            reading = executor.tick(reading)
        temperatures = np.full(len(ACTUATORS), 40.0)
        temperatures[[ACTUATORS.index(a) for a in leg_actuators("right")]] = LIMITS.warning_C
        plan = ContactModePlanner(sim.body, "thermal").plan(executor.q_nominal, datasheet_bank(VALKYRIE),
                                                            temperatures)
        left = plan.results["left"]
        executor.go("left", sim.body.joint_angles(left.q), left.torques_Nm)
        for _ in range(int(15.0 / sim.config.control_dt_s)):
            reading = executor.tick(reading)
            lowest = min(lowest, reading.base_position_m[2])
        assert executor.mode == "left" and not executor.moving
    assert lowest > FALLEN_PELVIS_HEIGHT_M
