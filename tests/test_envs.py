"""The Gymnasium contract of both environments, strategies and their comparison."""

import json
import tempfile
from contextlib import closing
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from hexapod_pb import ENV_ID as HEXAPOD_ID  # importing the robot packages registers their environments
from humanoid_pb import ENV_ID as HUMANOID_ID
from humanoid_pb.constants import JOINTS
from thermolimb.cli.main import main
from thermolimb.envs.policies import make_policy, strategies

CASES = [(HEXAPOD_ID, {}), (HUMANOID_ID, {}), (HUMANOID_ID, {"action_type": "configuration"})]


@pytest.mark.parametrize("env_id, kwargs", CASES)
def test_passes_gymnasiums_checker(env_id, kwargs):
    with closing(gym.make(env_id, **kwargs)) as env:
        check_env(env.unwrapped, skip_render_check=True)


def rollout(env_id, kwargs, seed, steps=3, actions=None):
    with closing(gym.make(env_id, max_time_s=30.0, **kwargs)) as env:
        env.action_space.seed(seed)
        actions = [env.action_space.sample() for _ in range(steps)] if actions is None else actions
        obs, _ = env.reset(seed=seed)
        trace, rewards = [obs], []
        for action in actions:
            obs, reward, terminated, truncated, info = env.step(action)
            assert reward == pytest.approx(sum(info["reward_terms"].values()), abs=1e-12)  # the sum of its terms
            assert env.observation_space.contains(obs)
            trace.append(obs)
            rewards.append(reward)
            if terminated or truncated:
                break
    return np.array(trace), np.array(rewards)


@pytest.mark.parametrize("env_id, kwargs", CASES[:2])
def test_same_seed_and_actions_give_identical_trajectories(env_id, kwargs):
    one, two = rollout(env_id, kwargs, seed=5)[0], rollout(env_id, kwargs, seed=5)[0]
    np.testing.assert_array_equal(one, two)
    other = rollout(env_id, kwargs, seed=6)[0]
    assert not np.array_equal(one[0], other[0])  # reset draws a different start


@pytest.mark.parametrize("env_id", [HEXAPOD_ID, HUMANOID_ID])
def test_rgb_array_frames(env_id):
    with closing(gym.make(env_id, render_mode="rgb_array")) as env:
        env.reset(seed=0)
        frame = env.render()
    assert frame.shape == (240, 240, 3) and frame.dtype == np.uint8 and frame.std() > 0


@pytest.mark.parametrize("vector", [gym.vector.SyncVectorEnv, gym.vector.AsyncVectorEnv])
def test_vector_environments_step_as_the_single_ones(vector):
    """Each sub-environment of a vector environment gives what the same environment alone gives."""
    actions = np.array([[0.0, 1.0, 0.0, 1.0], [1.0, 0.0, 0.0, 0.5]], dtype=np.float32)
    with closing(vector([lambda: gym.make(HEXAPOD_ID, max_time_s=30.0)] * 2)) as envs:
        first, _ = envs.reset(seed=[1, 2])
        obs, rewards, _, _, _ = envs.step(actions)
    for k, seed in enumerate((1, 2)):
        trace, single_rewards = rollout(HEXAPOD_ID, {}, seed, actions=[actions[k]])
        np.testing.assert_array_equal(first[k], trace[0])
        np.testing.assert_array_equal(obs[k], trace[1])
        assert rewards[k] == single_rewards[0]


@pytest.mark.slow  # half a minute or more on two cores (the default run stays under ten minutes)
def test_every_strategy_is_a_policy():
    for env_id in (HEXAPOD_ID, HUMANOID_ID):
        with closing(gym.make(env_id, max_time_s=3.0)) as env:
            obs, _ = env.reset(seed=0)
            for name in strategies(env_id):
                action = make_policy(env_id, name, seed=0)(env, obs)
                assert env.action_space.contains(np.asarray(action, dtype=env.action_space.dtype)
                                                 if env_id == HEXAPOD_ID else action)
    with pytest.raises(ValueError, match="no strategy 'minimax'"):
        make_policy(HUMANOID_ID, "minimax")


def test_compare_strategies_json(tmp_path, capsys):
    code = main(["compare-strategies", "--env", HEXAPOD_ID, "--episodes", "1", "--max-time", "3",
                 "--strategies", "vertical_only,minimax", "--plot", str(tmp_path), "--json"])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert [r["strategy"] for r in out["table"]] == ["vertical_only", "minimax"]
    assert all(e["distance_m"] > 0 for e in out["episodes"])
    assert (tmp_path / "HexapodLoadCarry-v0.png").is_file()


def test_ray_backend_with_a_local_ray_instance():
    pytest.importorskip("ray")
    from thermolimb.envs.episodes import run_episodes

    ray_eps = run_episodes(HEXAPOD_ID, 1, seed=3, strategies=("vertical_only", "minimax"), backend="ray", max_time_s=2.0)
    local = run_episodes(HEXAPOD_ID, 1, seed=3, strategies=("vertical_only", "minimax"), backend="process", max_time_s=2.0)
    assert [e.episode_return for e in ray_eps] == [e.episode_return for e in local]  # same seeds, same episodes


@pytest.mark.slow
def test_ppo_agent_trains_for_a_few_thousand_steps():
    pytest.importorskip("stable_baselines3")
    from thermolimb_demos.ppo_agent import evaluate_agent, train

    before = set(Path(tempfile.gettempdir()).glob("SB3-*"))
    model = train(2048, seed=0)
    assert model.num_timesteps >= 2048
    assert set(Path(tempfile.gettempdir()).glob("SB3-*")) == before  # nothing left behind in the temporary folder
    returns = evaluate_agent(model, 1)
    assert np.isfinite(returns).all()


@pytest.mark.parametrize("env_id, kwargs, bad", [
    (HEXAPOD_ID, {}, [np.nan, 0.0, 0.0, 1.0]),
    (HEXAPOD_ID, {}, [np.inf, 0.0, 0.0, 1.0]),
    (HUMANOID_ID, {"action_type": "configuration"}, [np.nan, 0.0, 0.0, 0.0]),
    (HUMANOID_ID, {}, -1),
    (HUMANOID_ID, {}, 3),
    (HUMANOID_ID, {}, 1.5),
])
def test_actions_outside_the_space_are_refused_and_the_environment_stays_usable(env_id, kwargs, bad):
    with closing(gym.make(env_id, max_time_s=30.0, **kwargs).unwrapped) as env:
        env.reset(seed=0)
        with pytest.raises(ValueError, match="action must"):
            env.step(np.array(bad, dtype=np.float32) if isinstance(bad, list) else bad)
        obs, reward, *_ = env.step(env.action_space.sample())
        assert np.isfinite(obs).all() and np.isfinite(reward)


@pytest.mark.parametrize("max_time_s", [np.nan, np.inf, 0.0, -1.0])
def test_episode_length_must_be_positive_and_finite(max_time_s):
    with pytest.raises(ValueError, match="max_time_s must be a positive, finite"):
        gym.make(HEXAPOD_ID, max_time_s=max_time_s)


def test_an_episode_has_max_time_over_decision_steps_and_then_refuses_to_step():
    with closing(gym.make(HEXAPOD_ID, max_time_s=3.0).unwrapped) as env:
        env.reset(seed=0)
        action = np.array([1.0, 0.0, 0.0, 0.0], dtype=np.float32)  # standing still: nothing ends it early
        ends = [env.step(action)[3] for _ in range(3)]
        assert ends == [False, False, True]
        with pytest.raises(RuntimeError, match="call reset"):
            env.step(action)
        env.reset(seed=1)
        env.step(action)  # usable again after reset


def test_a_ray_address_where_nothing_answers_is_refused_quickly():
    pytest.importorskip("ray")
    import time

    from thermolimb.envs.episodes import run_episodes

    start = time.perf_counter()
    with pytest.raises(ValueError, match="no Ray cluster answers at 127.0.0.1:1"):
        run_episodes(HEXAPOD_ID, 1, seed=0, strategies=("minimax",), backend="ray", address="127.0.0.1:1")
    assert time.perf_counter() - start < 15.0


@pytest.mark.slow  # 20 s on two cores
def test_the_rig_log_of_a_long_episode_stays_bounded():
    with closing(gym.make(HEXAPOD_ID, max_time_s=1e6, decision_s=5.0).unwrapped) as env:
        env.reset(seed=0)
        action = np.array([1.0, 0.0, 0.0, 0.0], dtype=np.float32)
        for _ in range(16):  # 80 s of control at 50 Hz: 4000 steps against a capacity of 3000
            env.step(action)
        log = env.sim.thermal_log()
        steps = log.series(log.actuators[0]).n
        assert steps == env.LOG_CAPACITY
        assert log.series(log.actuators[0]).time_s[-1] == pytest.approx(env.sim.time_s - env.sim.config.control_dt_s)


def test_hexapod_reward_terms_mean_what_they_say():
    with closing(gym.make(HEXAPOD_ID, max_time_s=30.0).unwrapped) as env:
        env.reset(seed=0)
        walk = np.array([0.0, 1.0, 0.0, 1.0], dtype=np.float32)
        for _ in range(2):
            *_, info = env.step(walk)
        assert info["reward_terms"]["distance"] > 0.02  # walking forward earns metres
        assert info["reward_terms"]["overheat"] == 0.0 and info["max_temperature_C"] < 120.0
        env.sim.plant.set_temperatures(np.full(18, 130.0))
        *_, info = env.step(np.array([1.0, 0.0, 0.0, 0.0], dtype=np.float32))  # standing
        assert abs(info["reward_terms"]["distance"]) < 0.02
        assert info["reward_terms"]["overheat"] < 0.0  # hot windings cost


def test_humanoid_reward_terms_mean_what_they_say():
    with closing(gym.make(HUMANOID_ID, max_time_s=30.0).unwrapped) as env:
        _, info = env.reset(seed=0)  # one leg starts between 72 and 80 degC
        before = info["max_temperature_C"]
        *_, info = env.step(0)  # double support
        terms = info["reward_terms"]
        assert terms["cooling"] == pytest.approx(before - info["max_temperature_C"])  # positive when it cools
        assert terms["warning"] < 0.0  # actuators above 75 degC
        assert terms["effort"] < 0.0 and terms["fall"] == 0.0


def test_reset_ranges_and_reward_weights_are_constructor_arguments():
    with closing(gym.make(HEXAPOD_ID, payload_range_kg=(3.0, 3.0), ambient_range_C=(30.0, 30.0),
                          initial_temperature_range_C=(130.0, 130.0), overheat_from_C=100.0,
                          overheat_weight_per_K=1.0)) as env:
        _, info = env.reset(seed=0)
        assert info["payload_kg"] == 3.0
        assert env.unwrapped.sim.plant.ambient_C == 30.0
        _, _, _, _, info = env.step(np.array([1.0, 0.0, 0.0, 0.0], np.float32))
        # windings start at 130 degC: the overheat term is minus one per kelvin of the hottest reading above 100 degC
        assert info["reward_terms"]["overheat"] == pytest.approx(-(info["max_temperature_C"] - 100.0))
    with closing(gym.make(HUMANOID_ID, hot_range_C=(78.0, 78.0), cool_range_C=(40.0, 40.0))) as env:
        obs, info = env.reset(seed=0)
        assert info["max_temperature_C"] == pytest.approx(78.0, abs=0.3)  # the hot leg, read through 0.05 K noise

    from hexapod_pb.env import HexapodLoadCarryEnv
    from humanoid_pb.env import HumanoidThermalRecoveryEnv

    for env_class in (HexapodLoadCarryEnv, HumanoidThermalRecoveryEnv):  # what help(env.unwrapped) shows
        assert all(word in env_class.__doc__ for word in ("Action", "Observation", "Reward", "unit", "Parameters"))


@pytest.mark.parametrize("kwargs,message", [({"payload_range_kg": (5.0, 1.0)}, "payload_range_kg"),
                                            ({"ambient_range_C": "hot"}, "ambient_range_C")])
def test_bad_reset_ranges_are_refused_naming_them(kwargs, message):
    with pytest.raises(ValueError, match=message):
        gym.make(HEXAPOD_ID, **kwargs)


@pytest.mark.parametrize("options", [{"payload_kg": 3.0}, "fast"])
def test_reset_refuses_options_it_does_not_take(options):
    with closing(gym.make(HEXAPOD_ID)) as env:
        with pytest.raises(ValueError, match="option"):
            env.reset(seed=0, options=options)
        env.reset(seed=0)  # still usable


@pytest.mark.parametrize("env_id", [HEXAPOD_ID, HUMANOID_ID])
def test_a_live_world_is_not_copied_but_an_idle_environment_is(env_id):
    import copy
    import pickle

    with closing(gym.make(env_id)) as env:
        with closing(copy.deepcopy(env)) as idle:  # no world yet: nothing shared
            idle.reset(seed=0)
        env.reset(seed=0)
        for copier in (pickle.dumps, copy.deepcopy, lambda e: copy.copy(e.unwrapped)):
            with pytest.raises(TypeError, match="live PyBullet world cannot be copied or pickled"):
                copier(env)
        env.step(env.action_space.sample())  # the original still steps


def test_compare_strategies_scenario_is_checked_before_any_episode(capsys):
    assert main(["compare-strategies", "--env", HUMANOID_ID, "--scenario", "squat", "--episodes", "1"]) == 2
    assert "no humanoid scenario 'squat'; expected one of ankle, walking" in capsys.readouterr().err
    assert main(["compare-strategies", "--env", HEXAPOD_ID, "--scenario", "walking", "--episodes", "1"]) == 2
    assert "takes no scenario" in capsys.readouterr().err


def test_humanoid_walking_scenario_holds_its_stance_and_reports_the_hot_legs_recovery():
    with closing(gym.make(HUMANOID_ID, max_time_s=6.0, scenario="walking").unwrapped) as env:
        _, info = env.reset(seed=0)
        assert env.executor.nominal_angles[JOINTS.index("left_knee")] == pytest.approx(0.9)
        assert info["hot_recovery_s"] is None  # the hot leg starts between 72 and 80 degC
        *_, info = env.step(0)
        assert not info["fell"] and env.sim.read().base_position_m[2] > 0.95
