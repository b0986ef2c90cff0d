"""Evaluate strategies over seeded episodes: a local process pool by default, Ray tasks on request."""

from __future__ import annotations

from dataclasses import dataclass

from ..util.errors import UsageError
from ..util.parallel import run_jobs
from . import env_class, env_info
from .policies import make_policy
from .policies import strategies as env_strategies


@dataclass(frozen=True)
class Episode:
    env_id: str
    strategy: str
    seed: int
    episode_return: float
    length: int
    sim_time_s: float
    recovered: bool | None  # environments with a recovery goal
    recovery_s: float | None  # sim time to recovery
    distance_m: float | None  # environments that travel
    time_to_limit_s: float | None  # sim time until an actuator reached its winding limit
    fell: bool
    hot_recovery_s: float | None = None  # sim time until the hot group (the humanoid's hot leg) recovered


OUTCOMES = ("recovered", "recovery_s", "distance_m", "time_to_limit_s", "hot_recovery_s")


def run_episode(env_id: str, strategy: str, seed: int, max_time_s: float | None = None,
                scenario: str | None = None) -> Episode:
    """One episode of ``strategy`` from ``reset(seed=seed)``; the environment says what its outcome was."""
    import gymnasium as gym

    env_info(env_id)  # registers the environments in a fresh worker process
    kwargs = {} if max_time_s is None else {"max_time_s": max_time_s}
    if scenario is not None:
        kwargs["scenario"] = scenario
    env = gym.make(env_id, **kwargs)
    try:
        policy = make_policy(env_id, strategy, seed)
        obs, info = env.reset(seed=seed)
        total, length = 0.0, 0
        terminated = truncated = False
        while not (terminated or truncated):
            obs, reward, terminated, truncated, info = env.step(policy(env, obs))
            total += reward
            length += 1
    finally:
        env.close()
    outcome = dict.fromkeys(OUTCOMES) | env.unwrapped.episode_outcome(info, terminated)
    return Episode(env_id, strategy, seed, total, length, info["time_s"], **outcome, fell=bool(info["fell"]))


def run_episodes(
    env_id: str,
    episodes: int,
    seed: int,
    strategies=None,
    backend: str = "process",
    workers: int = 2,
    address: str | None = None,
    max_time_s: float | None = None,
    scenario: str | None = None,
) -> list[Episode]:
    """Every strategy over ``episodes`` seeds (``seed``, ``seed + 1``, ...), the same seeds for each strategy;
    ``scenario``: the environment's ``scenario`` argument, for an environment that takes one."""
    offered = env_strategies(env_id)
    strategies = list(strategies or offered)
    unknown = [s for s in strategies if s not in offered]
    if unknown:
        raise UsageError(f"no strategy {', '.join(map(repr, unknown))} "
                         f"for {env_id}; available: {', '.join(offered)}")
    if scenario is not None:
        check_scenario(env_id, scenario)
    jobs = [(env_id, s, seed + k, max_time_s, scenario) for s in strategies for k in range(episodes)]
    return run_jobs(run_episode, jobs, backend, workers, address)


def check_scenario(env_id: str, scenario: str) -> None:
    """One clear error when the environment takes no ``scenario`` or not this one (before any worker
    starts)."""
    import inspect

    cls = env_class(env_id)
    if "scenario" not in inspect.signature(cls.__init__).parameters:
        raise UsageError(f"{env_id} takes no scenario; --scenario is for environments that have several")
    try:
        cls(scenario=scenario)
    except ValueError as exc:
        raise UsageError(f"{env_id}: {exc}") from None
