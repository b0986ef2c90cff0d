"""Evaluate strategies over seeded episodes: a local process pool by default, Ray tasks on request."""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass

import numpy as np

from ..errors import UsageError
from . import HEXAPOD_ID, HUMANOID_ID
from .strategies import STRATEGIES, make_policy


@dataclass(frozen=True)
class Episode:
    env_id: str
    strategy: str
    seed: int
    episode_return: float
    length: int
    sim_time_s: float
    recovered: bool | None  # humanoid
    recovery_s: float | None  # humanoid: sim time to recovery
    distance_m: float | None  # hexapod
    time_to_limit_s: float | None  # hexapod: an actuator at its winding limit
    fell: bool


def run_episode(env_id: str, strategy: str, seed: int, max_time_s: float | None = None) -> Episode:
    """One episode of ``strategy`` from ``reset(seed=seed)``."""
    import gymnasium as gym

    import thermolimb  # noqa: F401  (registers the environments in a fresh worker process)

    kwargs = {} if max_time_s is None else {"max_time_s": max_time_s}
    env = gym.make(env_id, **kwargs)
    policy = make_policy(env_id, strategy, seed)
    obs, info = env.reset(seed=seed)
    total, length = 0.0, 0
    terminated = truncated = False
    while not (terminated or truncated):
        obs, reward, terminated, truncated, info = env.step(policy(env, obs))
        total += reward
        length += 1
    env.close()
    humanoid = env_id == HUMANOID_ID
    at_limit = (not humanoid) and terminated and not info["fell"]
    return Episode(env_id, strategy, seed, total, length, info["time_s"],
                   info.get("recovered") if humanoid else None,
                   info["time_s"] if humanoid and info.get("recovered") else None,
                   None if humanoid else info["distance_m"],
                   info["time_s"] if at_limit else None, bool(info["fell"]))


def evaluate(env_id: str, episodes: int, seed: int, strategies=None, backend: str = "process", workers: int = 2,
             address: str | None = None, max_time_s: float | None = None) -> list[Episode]:
    """Every strategy over ``episodes`` seeds (``seed``, ``seed + 1``, ...), the same seeds for each strategy."""
    if env_id not in (HUMANOID_ID, HEXAPOD_ID):
        raise UsageError(f"unknown environment {env_id!r}; expected {HUMANOID_ID} or {HEXAPOD_ID}")
    strategies = list(strategies or STRATEGIES[env_id])
    jobs = [(env_id, s, seed + k, max_time_s) for s in strategies for k in range(episodes)]
    if backend == "process":
        with ProcessPoolExecutor(max_workers=workers) as pool:
            return list(pool.map(run_episode, *zip(*jobs)))
    if backend == "ray":
        try:
            import ray
        except ImportError:
            raise UsageError("the ray backend needs Ray: pip install 'thermolimb[ray]'") from None
        started = not ray.is_initialized()
        ray.init(address=address, ignore_reinit_error=True, include_dashboard=False, log_to_driver=False)
        try:
            remote = ray.remote(run_episode)
            return ray.get([remote.remote(*job) for job in jobs])
        finally:
            if started:
                ray.shutdown()
    raise UsageError(f"backend must be 'process' or 'ray', got {backend!r}")


def table(episodes: list[Episode]) -> list[dict]:
    """Per strategy: mean and std of return, recovery time or distance, time to limit, falls."""
    rows = []
    for strategy in dict.fromkeys(e.strategy for e in episodes):
        eps = [e for e in episodes if e.strategy == strategy]

        def stat(values):
            values = [v for v in values if v is not None]
            return (float(np.mean(values)), float(np.std(values)), len(values)) if values else (None, None, 0)

        rows.append({
            "strategy": strategy, "episodes": len(eps),
            "return": stat([e.episode_return for e in eps]),
            "recovery_s": stat([e.recovery_s for e in eps]),
            "distance_m": stat([e.distance_m for e in eps]),
            "time_to_limit_s": stat([e.time_to_limit_s for e in eps]),
            "falls": sum(e.fell for e in eps),
        })
    return rows


def episodes_json(episodes: list[Episode]) -> list[dict]:
    return [asdict(e) for e in episodes]
