"""Demo ``strategies``: every strategy of both environments over seeded episodes (the comparison table).

The same seeds for every strategy, episodes in a local process pool, as
``thermolimb compare-strategies`` runs them.
"""

from __future__ import annotations

from pathlib import Path

import hexapod_pb
import humanoid_pb
from thermolimb.demo_registry import demo_main, register_demo
from thermolimb.envs.evaluate import evaluate
from thermolimb.envs.report import format_table, plot_table, table

NAME = "strategies"


@register_demo(NAME, "minimum-effort against thermal-aware (and baselines) in both Gymnasium environments")
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    summary = {}
    for env_id, max_time in ((hexapod_pb.ENV_ID, 10.0 if quick else 60.0), (humanoid_pb.ENV_ID, 30.0 if quick else 90.0)):
        episodes = evaluate(env_id, 1 if quick else 5, seed=0, max_time_s=max_time)
        rows = table(episodes)
        plot_table(rows, env_id, out / f"{env_id.split('/')[-1]}.png")
        if not quiet:
            print(format_table(rows, env_id))
        summary[env_id] = {"max_time_s": max_time, "table": rows}
    return summary


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
