"""``thermolimb compare-strategies``: evaluate the environments' strategies over seeded episodes."""

from __future__ import annotations

from pathlib import Path

from .fleet import local_workers
from .template import Command, Outcome
from .types import SEED, integer, names, number, output_dir


class Strategies(Command):
    name = "compare-strategies"
    help = "evaluate strategies of an environment over seeded episodes"
    description = ("Run every strategy of the environment over "
                    "--episodes seeds (the same seeds for each) and "
        "print mean +- std of the return, the recovery time (s, humanoid) or distance (m, hexapod), the time "
        "until an actuator reaches its limit (s) and the falls; write a plot.")

    def add_options(self, p):
        p.add_argument("--env", required=True, metavar="ID",
                       help="environment id: thermolimb/HumanoidThermalRecovery-v0, "
                            "thermolimb/HexapodLoadCarry-v0 or one "
                       "of another installed robot package")
        p.add_argument("--episodes", type=integer(1, 10_000), default=4, help="episodes per strategy "
                       "(default 4)")
        p.add_argument("--seed", type=SEED, default=0, help="first seed (default 0)")
        p.add_argument("--strategies", type=names, default=None, metavar="NAME,...",
                       help="subset of strategies (default all)")
        p.add_argument("--max-time", type=number(0.0, 1e7, low_open=True, unit="s"), default=None,
                       help="episode time limit in s (default the environment's)")
        p.add_argument("--scenario", default=None, metavar="NAME", help="the environment's scenario, for "
                       "one that has several (humanoid: ankle or walking; " "see docs/humanoid.md)")
        p.add_argument("--backend", choices=("process", "ray"), default="process",
                       help="local process pool (default) or Ray tasks (optional extra 'ray')")
        p.add_argument("--address", default=None, help="Ray cluster address (default: start a local Ray)")
        p.add_argument("--workers", type=integer(1, 1024), default=2, help="processes of the local pool "
                       "(default 2)")
        p.add_argument("--plot", type=output_dir, default="strategies", metavar="DIR",
                       help="folder for the plot (default strategies/ here: "
                            "never the report's out/, which make demo writes)")
        p.add_argument("--json", action="store_true", help="print the table and every episode as JSON")

    def work(self, args) -> Outcome:
        from ..envs import env_info
        from ..envs.episodes import run_episodes
        from ..envs.tables import episodes_json, format_table, plot_table, table

        env_info(args.env)  # an unknown environment is said before anything else (a lowered --workers, say)
        episodes = run_episodes(args.env, args.episodes, args.seed, args.strategies, backend=args.backend,
                                workers=local_workers(args), address=args.address, max_time_s=args.max_time,
                                scenario=args.scenario)
        rows = table(episodes)
        path = plot_table(rows, args.env, Path(args.plot) / f"{args.env.split('/')[-1]}.png")
        return Outcome(
            {"env": args.env, "table": rows, "episodes": episodes_json(episodes), "plot": str(path)},
            format_table(rows, args.env),
        )


add_parser = Strategies().add_parser
