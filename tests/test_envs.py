"""The Gymnasium contract of both environments, strategies and their comparison."""

import json

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import thermolimb  # noqa: F401  (registers the environments)
from thermolimb.cli.main import main
from thermolimb.envs import HEXAPOD_ID, HUMANOID_ID
from thermolimb.envs.strategies import STRATEGIES, make_policy

CASES = [(HEXAPOD_ID, {}), (HUMANOID_ID, {}), (HUMANOID_ID, {"action_type": "configuration"})]


@pytest.mark.parametrize("env_id, kwargs", CASES)
def test_passes_gymnasiums_checker(env_id, kwargs):
    env = gym.make(env_id, **kwargs)
    check_env(env.unwrapped, skip_render_check=True)
    env.close()


def rollout(env_id, kwargs, seed, steps=3):
    env = gym.make(env_id, max_time_s=30.0, **kwargs)
    env.action_space.seed(seed)
    actions = [env.action_space.sample() for _ in range(steps)]
    obs, _ = env.reset(seed=seed)
    trace = [obs]
    for action in actions:
        obs, reward, terminated, truncated, info = env.step(action)
        assert reward == pytest.approx(sum(info["reward_terms"].values()), abs=1e-12)  # reward is the sum of its terms
        assert env.observation_space.contains(obs)
        trace.append(obs)
        if terminated or truncated:
            break
    env.close()
    return np.array(trace)


@pytest.mark.parametrize("env_id, kwargs", CASES[:2])
def test_same_seed_and_actions_give_identical_trajectories(env_id, kwargs):
    one, two = rollout(env_id, kwargs, seed=5), rollout(env_id, kwargs, seed=5)
    np.testing.assert_array_equal(one, two)
    other = rollout(env_id, kwargs, seed=6)
    assert not np.array_equal(one[0], other[0])  # reset draws a different start


@pytest.mark.parametrize("env_id", [HEXAPOD_ID, HUMANOID_ID])
def test_rgb_array_frames(env_id):
    env = gym.make(env_id, render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    env.close()
    assert frame.shape == (240, 240, 3) and frame.dtype == np.uint8 and frame.std() > 0


@pytest.mark.parametrize("vector", [gym.vector.SyncVectorEnv, gym.vector.AsyncVectorEnv])
def test_vector_environments(vector):
    envs = vector([lambda: gym.make(HEXAPOD_ID, max_time_s=3.0)] * 2)
    obs, _ = envs.reset(seed=[1, 2])
    assert obs.shape == (2, 40)
    obs, rewards, terminated, truncated, infos = envs.step(envs.action_space.sample())
    assert rewards.shape == (2,) and obs.shape == (2, 40)
    envs.close()


def test_every_strategy_is_a_policy():
    for env_id, names in STRATEGIES.items():
        env = gym.make(env_id, max_time_s=3.0)
        obs, _ = env.reset(seed=0)
        for name in names:
            action = make_policy(env_id, name, seed=0)(env, obs)
            assert env.action_space.contains(np.asarray(action, dtype=env.action_space.dtype)
                                             if env_id == HEXAPOD_ID else action)
        env.close()
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
    from thermolimb.envs.evaluate import evaluate

    ray_eps = evaluate(HEXAPOD_ID, 1, seed=3, strategies=("vertical_only", "minimax"), backend="ray", max_time_s=2.0)
    local = evaluate(HEXAPOD_ID, 1, seed=3, strategies=("vertical_only", "minimax"), backend="process", max_time_s=2.0)
    assert [e.episode_return for e in ray_eps] == [e.episode_return for e in local]  # same seeds, same episodes


@pytest.mark.slow
def test_ppo_agent_trains_for_a_few_thousand_steps():
    pytest.importorskip("stable_baselines3")
    from demos.ppo_agent import evaluate_agent, train

    model = train(2048, seed=0)
    assert model.num_timesteps >= 2048
    returns = evaluate_agent(model, 1)
    assert np.isfinite(returns).all()
