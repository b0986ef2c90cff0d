"""Demo ``strategies``: every strategy of both environments over seeded episodes (the comparison table).

The same seeds for every strategy, episodes in a local process pool, as
``thermolimb compare-strategies`` runs them.
"""

from __future__ import annotations

from pathlib import Path

import hexapod_pb
import humanoid_pb
from thermolimb.demo_registry import DemoPage, demo_main, mean_std, register_demo
from thermolimb.envs.episodes import run_episodes
from thermolimb.envs.tables import format_table, plot_table, table

NAME = "strategies"


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    rows = []
    for env_id, record in summary.items():
        for row in record["table"]:
            outcome = (f"distance {mean_std(row['distance_m'], 'm')}" if row["distance_m"][2]
                       else f"recovery {mean_std(row['recovery_s'], 's')}")
            rows.append((f"{env_id.split('/')[-1]}: {row['strategy']}", f"return {mean_std(row['return'])}",
                         f"{outcome}; falls {row['falls']}"))
    return rows


def _finding(summary: dict) -> str:
    parts = []
    for env_id, record in summary.items():
        rows = {r["strategy"]: r for r in record["table"]}
        n = max(r["episodes"] for r in rows.values())
        if "thermal_aware" in rows and "minimum_effort" in rows:  # the humanoid: who recovers, how fast
            ta, me = rows["thermal_aware"]["recovery_s"], rows["minimum_effort"]["recovery_s"]
            parts.append(f"the humanoid's thermal-aware strategy recovers in {ta[2]} of {n} episodes "
                         f"(mean {ta[0]:.1f} s)" if ta[2] else "the humanoid's thermal-aware strategy never recovers")
            parts[-1] += (f", minimum effort in {me[2]} of {n}" + (f" (mean {me[0]:.1f} s)" if me[2] else ""))
        else:  # the hexapod: no actuator heats in a short episode, so the return is the distance
            best = max(rows.values(), key=lambda r: r["distance_m"][0] or 0.0)
            parts.append(f"the hexapod walks farthest with {best['strategy']} ({best['distance_m'][0]:.2f} m in "
                         f"{record['max_time_s']:.0f} s; no actuator nears its limit that soon, so the return is the "
                         f"distance)")
    return "In this run " + "; ".join(parts) + "."


PAGE = DemoPage(
    about="Every strategy of both Gymnasium environments over seeded episodes: the hexapod carrying a load and "
          "the humanoid recovering from hot actuators, minimum effort against thermal-aware, with a random "
          "policy as the floor. Look at the return and the outcome that matters (distance, recovery time) with "
          "their spread over seeds.",
    headline=_headline,
    finding=_finding,
    captions={"HexapodLoadCarry-v0.png": "Return and outcome per strategy, hexapod: the mean over seeded episodes "
                                         "(n under each name: the episodes the bar holds), with ± std bars when two "
                                         "or more episodes ran.",
              "HumanoidThermalRecovery-v0.png": "Return and outcome per strategy, humanoid: the mean over seeded "
                                                "episodes (n under each name: the episodes the bar holds), with ± std "
                                                "bars when two or more episodes ran."})


@register_demo(NAME, "minimum-effort against thermal-aware (and baselines) in both Gymnasium environments",
               page=PAGE, cost_s=17)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    summary = {}
    # the quick run: two seeds per strategy (a spread, however thin), episodes long enough for the humanoid's
    # thermal-aware recovery (about 10 s) and for the hexapod to walk half a metre
    for env_id, max_time in ((hexapod_pb.ENV_ID, 4.0 if quick else 60.0), (humanoid_pb.ENV_ID, 15.0 if quick else 90.0)):
        episodes = run_episodes(env_id, 2 if quick else 5, seed=0, max_time_s=max_time)
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
