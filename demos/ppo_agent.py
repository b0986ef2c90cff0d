"""Demo ``ppo-agent``: train a Stable-Baselines3 PPO agent briefly on the hexapod and compare it with the strategies.

Optional extra ``rl`` (``pip install 'thermolimb[rl]'``).  The agent chooses
the stance-force blend and the walking speed every 0.2 s; after a short
training it is evaluated on the same seeds as the fixed strategies.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from hexapod_pb import ENV_ID as HEXAPOD_ID
from thermolimb.demo_registry import DemoPage, demo_main, mean_std, register_demo
from thermolimb.envs.episodes import run_episodes
from thermolimb.envs.tables import table

NAME = "ppo-agent"
DECISION_S = 0.2


def train(timesteps: int, seed: int = 0):
    import gymnasium as gym
    from stable_baselines3 import PPO
    from stable_baselines3.common.logger import Logger

    env = gym.make(HEXAPOD_ID, max_time_s=6.0, decision_s=DECISION_S)
    model = PPO("MlpPolicy", env, n_steps=256, batch_size=64, n_epochs=4, seed=seed, verbose=0, device="cpu")
    model.set_logger(Logger(None, []))  # a logger of its own: SB3's default makes an empty SB3-<date> folder in /tmp
    model.learn(total_timesteps=timesteps)
    env.close()
    return model


def evaluate_agent(model, episodes: int, seed: int = 0) -> list[float]:
    import gymnasium as gym

    returns = []
    for k in range(episodes):
        env = gym.make(HEXAPOD_ID, max_time_s=6.0, decision_s=DECISION_S)
        obs, _ = env.reset(seed=seed + k)
        total, done = 0.0, False
        while not done:
            action, _ = model.predict(obs, deterministic=True)
            obs, reward, terminated, truncated, _ = env.step(action)
            total += reward
            done = terminated or truncated
        env.close()
        returns.append(total)
    return returns


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    import numpy as np

    returns = summary["ppo_returns"]
    rows = [(f"PPO after {summary['timesteps']} steps: return",
             f"{np.mean(returns):.3g} ± {np.std(returns):.2g} (n = {len(returns)})", "a briefly trained agent")]
    rows += [(f"{row['strategy']}: return", mean_std(row["return"]), "fixed strategy") for row in summary["strategies"]]
    return rows


def _finding(summary: dict) -> str:
    import numpy as np

    best = max(summary["strategies"], key=lambda r: r["return"][0])
    return (f"In this run PPO after {summary['timesteps']} steps returns {np.mean(summary['ppo_returns']):.3g}, "
            f"against {best['return'][0]:.3g} for the best fixed strategy ({best['strategy']}): a brief training, "
            f"not expected to beat it.")


PAGE = DemoPage(
    about="A PPO agent (Stable-Baselines3) trained briefly on the hexapod environment, against the fixed "
          "strategies on the same seeds. It shows the environment works for learning agents; a short training "
          "run is not expected to beat the model-based strategies.",
    headline=_headline,
    finding=_finding,
    captions={"ppo_vs_strategies.png": "Episode return of the agent and of each fixed strategy."})


@register_demo(NAME, "a briefly trained PPO agent on the hexapod against the fixed strategies (extra 'rl')",
               requires=("stable_baselines3", "torch"), page=PAGE, cost_s=17)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    timesteps = 512 if quick else 20_000
    model = train(timesteps)
    episodes = 2 if quick else 5
    agent = evaluate_agent(model, episodes)
    baselines = table(run_episodes(HEXAPOD_ID, episodes, seed=0, max_time_s=6.0,
                               strategies=("vertical_only", "minimax", "random")))
    from thermolimb.plotting.fits import plt, save

    fig, ax = plt.subplots(figsize=(6, 3.5))
    names = ["ppo"] + [r["strategy"] for r in baselines]
    means = [float(np.mean(agent))] + [r["return"][0] for r in baselines]
    ax.bar(names, means)
    ax.set_ylabel("episode return (mean over seeds)")
    ax.set_title(f"hexapod, 6 s episodes: return after {timesteps} PPO steps (decisions every {DECISION_S} s)", fontsize=9)
    save(fig, out / "ppo_vs_strategies.png")
    return {"timesteps": timesteps, "ppo_returns": agent, "strategies": baselines}


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
