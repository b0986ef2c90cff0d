"""Environment throughput: steps per wall second and simulated-to-wall time, one process and two.

For each environment: a single instance stepped with a fixed strategy's
actions (the hexapod's stance optimiser runs every control step), then a
two-process ``AsyncVectorEnv`` (two instances), in the same run.  Each
figure is the fastest of ``--repeats`` runs of ``--steps`` steps, each run
from a fresh reset: on a shared machine the fastest run is the one least
disturbed by others, so it is the figure that repeats (the spread is printed).

    python benchmarks/envs.py [--steps 20] [--repeats 3] [--json]
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


def single(env_id: str, steps: int) -> tuple[float, float, dict]:
    env = make(env_id)
    env.reset(seed=0)
    start = time.perf_counter()
    info = {}
    for _ in range(steps):
        _, _, _, _, info = env.step(ACTIONS[env_id])
    wall = time.perf_counter() - start
    sim = info["time_s"]
    env.close()
    return steps / wall, sim / wall, info


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
    return 2 * steps / wall, sim / wall, {}


def fastest(measure, env_id: str, steps: int, repeats: int) -> tuple[float, float, list[float], dict]:
    """The fastest of ``repeats`` runs of ``measure``: (steps/s, simulated/wall, every run's simulated/wall, its
    last info)."""
    runs = [measure(env_id, steps) for _ in range(repeats)]
    best = max(runs, key=lambda r: r[1])
    return best[0], best[1], [r[1] for r in runs], best[2]


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20, help="environment steps per run")
    parser.add_argument("--repeats", type=int, default=3, help="runs per figure; the fastest is reported")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    record = {"method": f"fastest of {args.repeats} runs of {args.steps} steps, each from a fresh reset"}
    print(record["method"])
    for env_id in (HEXAPOD_ID, HUMANOID_ID):
        sps, rtf, runs, info = fastest(single, env_id, args.steps, args.repeats)
        vsps, vrtf, vruns, _ = fastest(vector, env_id, args.steps, args.repeats)
        record[env_id] = {"steps_per_s": sps, "sim_per_wall": rtf, "vector2_steps_per_s": vsps,
                          "vector2_sim_per_wall": vrtf, "vector_gain": vsps / sps,
                          "sim_per_wall_runs": runs, "vector2_sim_per_wall_runs": vruns}
        target = 10.0 if env_id == HEXAPOD_ID else 5.0
        print(f"{env_id}: one process {sps:5.2f} steps/s, {rtf:4.1f}x real time (target >= {target:.0f}x; runs "
              f"{min(runs):.1f}-{max(runs):.1f}x); two-process AsyncVectorEnv {vsps:5.2f} steps/s, {vrtf:4.1f}x: "
              f"{vsps / sps:.2f}x the single throughput (target >= 1.6x)")
        if "stance_solver" in info:
            record[env_id]["stance_solver"] = info["stance_solver"]
            record[env_id]["stance_fallbacks"] = info["stance_fallbacks"]
            print(f"  stance forces of the last control period: {info['stance_solver']}; control periods solved by "
                  f"a fallback: {info['stance_fallbacks']}")
    if args.json:
        print(json.dumps(record))
    return record


if __name__ == "__main__":
    main()
