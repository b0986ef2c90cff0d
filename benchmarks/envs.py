"""Environment throughput: steps per wall second and simulated-to-wall time, one process and two.

For each environment: a single instance stepped with a fixed strategy's
actions, then a two-process ``AsyncVectorEnv`` (two instances), in the same run.

    python benchmarks/envs.py [--steps 20] [--json]
"""

from __future__ import annotations

import argparse
import json
import time

import gymnasium as gym
import numpy as np

from hexapod_pb import ENV_ID as HEXAPOD_ID  # importing the robot packages registers their environments
from humanoid_pb import ENV_ID as HUMANOID_ID

ACTIONS = {HEXAPOD_ID: np.array([0.0, 1.0, 0.0, 1.0], dtype=np.float32), HUMANOID_ID: 0}


def make(env_id):
    return gym.make(env_id, max_time_s=1e9)


def single(env_id: str, steps: int) -> tuple[float, float]:
    env = make(env_id)
    env.reset(seed=0)
    start = time.perf_counter()
    info = {}
    for _ in range(steps):
        _, _, _, _, info = env.step(ACTIONS[env_id])
    wall = time.perf_counter() - start
    sim = info["time_s"]
    env.close()
    return steps / wall, sim / wall


def vector(env_id: str, steps: int) -> tuple[float, float]:
    envs = gym.vector.AsyncVectorEnv([lambda: make(env_id)] * 2)
    envs.reset(seed=[0, 1])
    action = np.stack([ACTIONS[env_id]] * 2) if env_id == HEXAPOD_ID else np.array([0, 0])
    start = time.perf_counter()
    for _ in range(steps):
        _, _, _, _, infos = envs.step(action)
    wall = time.perf_counter() - start
    sim = float(np.sum(infos["time_s"]))
    envs.close()
    return 2 * steps / wall, sim / wall


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20, help="environment steps per measurement")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    record = {}
    for env_id in (HEXAPOD_ID, HUMANOID_ID):
        sps, rtf = single(env_id, args.steps)
        vsps, vrtf = vector(env_id, args.steps)
        record[env_id] = {"steps_per_s": sps, "sim_per_wall": rtf, "vector2_steps_per_s": vsps,
                          "vector2_sim_per_wall": vrtf, "vector_gain": vsps / sps}
        print(f"{env_id}: one process {sps:5.2f} steps/s, {rtf:4.1f}x real time (target >= 5x); "
              f"two-process AsyncVectorEnv {vsps:5.2f} steps/s, {vrtf:4.1f}x: {vsps / sps:.2f}x the single "
              f"throughput (target >= 1.6x)")
    if args.json:
        print(json.dumps(record))
    return record


if __name__ == "__main__":
    main()
