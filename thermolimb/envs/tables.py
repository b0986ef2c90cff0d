"""Tables and plots of strategy evaluations: mean and spread per strategy, for the command line and the
demos."""

from __future__ import annotations

import textwrap
from dataclasses import asdict
from pathlib import Path

import numpy as np

from . import env_class
from .episodes import Episode


def outcome_key(env_id: str) -> str:
    """The episode outcome an environment is judged by (e.g. ``recovery_s`` or ``distance_m``)."""
    return env_class(env_id).OUTCOME


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
            "hot_recovery_s": stat([e.hot_recovery_s for e in eps]),
            "falls": sum(e.fell for e in eps),
        })
    return rows


def episodes_json(episodes: list[Episode]) -> list[dict]:
    return [asdict(e) for e in episodes]


def _cell(stat, fmt="{:.2f}"):
    mean, std, n = stat
    return "-" if mean is None else f"{fmt.format(mean)} ± {fmt.format(std)} ({n})"


def format_table(rows, env_id) -> str:
    outcome = outcome_key(env_id)
    hot = any(r["hot_recovery_s"][2] for r in rows) or outcome == "recovery_s"
    lines = [
        f"{'strategy':24s} {'return':>22s} {outcome:>22s} "
        + (f"{'hot_recovery_s':>22s} " if hot else "")
        + f"{'time_to_limit_s':>22s} {'falls':>6s}"
    ]
    for r in rows:
        lines.append(f"{r['strategy']:24s} {_cell(r['return']):>22s} {_cell(r[outcome]):>22s} "
                     + (f"{_cell(r['hot_recovery_s']):>22s} " if hot else "")
                     + f"{_cell(r['time_to_limit_s'], '{:.0f}'):>22s} {r['falls']:>6d}")
    return "\n".join(lines)


def plot_table(rows, env_id, path: Path) -> Path:
    from ..plotting.fits import plt, save

    outcome = outcome_key(env_id)
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8))
    names = [r["strategy"] for r in rows]
    readable = {"recovery_s": "time to recover (s)", "distance_m": "distance (m)"}
    for ax, key, title in (
        (axes[0], "return", "episode return"),
        (axes[1], outcome, readable.get(outcome, outcome)),
    ):
        ticks = []
        for k, r in enumerate(rows):
            mean, std, n = r[key]
            # how many episodes each bar holds, under its name (off the bars and their error bars)
            # "always double\nsupport": no label runs into the next
            words = textwrap.fill(names[k].replace("_", " "), 14)
            ticks.append(f"{words}\n(n = {n}" + (f" of {r['episodes']})" if n != r["episodes"] else ")"))
            if mean is None:  # never reached in any episode: said, not drawn as a zero bar
                ax.bar(k, 0.0, color="none")
                ax.annotate("not reached", (k, 0.0), ha="center", va="bottom", fontsize=8, color="0.4")
                continue
            # a spread needs two episodes or more: one episode gets no error bar
            ax.bar(k, mean, yerr=std if n >= 2 else None, capsize=4, color="tab:blue")
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_xticks(range(len(names)), ticks)
        spread = any(r[key][2] >= 2 for r in rows if r[key][0] is not None)
        ax.set_title(f"{title}, " + ("mean ± std over episodes" if spread else "one episode per strategy"),
                     fontsize=9)
        ax.tick_params(axis="x", labelsize=8)
    fig.suptitle(env_id, fontsize=10)
    return save(fig, path)
