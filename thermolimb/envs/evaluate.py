"""Evaluate strategies over seeded episodes: a local process pool by default, Ray tasks on request."""

from __future__ import annotations

import socket
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass

from ..errors import UsageError
from . import env_info
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


OUTCOMES = ("recovered", "recovery_s", "distance_m", "time_to_limit_s")


def run_episode(env_id: str, strategy: str, seed: int, max_time_s: float | None = None) -> Episode:
    """One episode of ``strategy`` from ``reset(seed=seed)``; the environment says what its outcome was."""
    import gymnasium as gym

    env_info(env_id)  # registers the environments in a fresh worker process
    kwargs = {} if max_time_s is None else {"max_time_s": max_time_s}
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


RAY_CONNECT_TIMEOUT_S = 10.0


def _check_ray_address(address: str | None, timeout_s: float = RAY_CONNECT_TIMEOUT_S) -> None:
    """Refuse, within ``timeout_s``, a Ray address ``[ray://]host:port`` where nothing answers (Ray would wait)."""
    if address in (None, "auto", "local"):
        return
    host, sep, port = address.removeprefix("ray://").rpartition(":")
    if not sep or not port.isdigit():
        raise UsageError(f"--address {address!r}: expected HOST:PORT (or ray://HOST:PORT, or 'auto')")
    try:
        socket.create_connection((host, int(port)), timeout=timeout_s).close()
    except OSError as exc:
        raise UsageError(f"no Ray cluster answers at {address} (tried for {timeout_s:g} s: {exc})") from None


def evaluate(env_id: str, episodes: int, seed: int, strategies=None, backend: str = "process", workers: int = 2,
             address: str | None = None, max_time_s: float | None = None) -> list[Episode]:
    """Every strategy over ``episodes`` seeds (``seed``, ``seed + 1``, ...), the same seeds for each strategy."""
    offered = env_strategies(env_id)
    strategies = list(strategies or offered)
    unknown = [s for s in strategies if s not in offered]
    if unknown:
        raise UsageError(f"no strategy {', '.join(map(repr, unknown))} for {env_id}; available: {', '.join(offered)}")
    jobs = [(env_id, s, seed + k, max_time_s) for s in strategies for k in range(episodes)]
    if backend == "process":
        with ProcessPoolExecutor(max_workers=workers) as pool:
            return list(pool.map(run_episode, *zip(*jobs)))
    if backend == "ray":
        try:
            import ray
        except ImportError:
            raise UsageError("the ray backend needs Ray: pip install 'thermolimb[ray]'") from None
        _check_ray_address(address)
        started = not ray.is_initialized()
        ray.init(address=address, ignore_reinit_error=True, include_dashboard=False, log_to_driver=False)
        try:
            remote = ray.remote(run_episode)
            return ray.get([remote.remote(*job) for job in jobs])
        finally:
            if started:
                ray.shutdown()
    raise UsageError(f"backend must be 'process' or 'ray', got {backend!r}")
