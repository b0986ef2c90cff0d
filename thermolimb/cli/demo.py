"""``thermolimb demo`` and ``thermolimb report``."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from ..demo_registry import demo_names, in_tour_order, load_demos, timed_demo
from ..report import build_report
from ..util.errors import UsageError
from ..util.parallel import Runner, worker_limit
from .template import Command, Outcome
from .types import integer, output_dir


class Demo(Command):
    name = "demo"
    help = "run a demo (or all) and write its plots and summary.json"
    description = "Run a registered demo into OUT/NAME/: PNG plots and summary.json."
    plots = None

    @property
    def parser_options(self):
        return {
            "formatter_class": argparse.RawDescriptionHelpFormatter,
            "epilog": "demos (in the order to read them; 'thermolimb demo' with no name describes each):\n  "
            + "\n  ".join(demo_names()),
        }

    def add_options(self, p):
        p.add_argument("name", nargs="?", default=None, help="demo name, or 'all'; omit to list them")
        p.add_argument("--quick", action="store_true", help="short mode (what make demo and the tests run)")
        p.add_argument("--out", type=output_dir, default="out", help="output folder (default out)")
        p.add_argument("--json", action="store_true", help="print the summary record(s)")
        p.add_argument("--workers", type=integer(1, 256), default=None, help="demos run side by side on "
                       "this many processes (default: every core; 1 with --live)")
        p.add_argument("--live", type=integer(0, 65535), nargs="?", const=8765, default=None, metavar="PORT",
                       help="stream the simulated robots live to Foxglove on the monitor's channels "
                       "(default port " "8765; extra 'live')")

    def work(self, args) -> Outcome:
        demos = load_demos()
        if args.name is None:
            return Outcome(
                None, "\n".join(f"{name:22s} {demos[name].description}" for name in in_tour_order(demos))
            )
        if args.name != "all" and args.name not in demos:
            raise UsageError(f"unknown demo {args.name!r}; available: {', '.join(in_tour_order(demos))}")
        names = in_tour_order(demos) if args.name == "all" else [args.name]
        if args.name == "all":
            for name in [n for n in names if demos[n].missing]:
                print(f"demo {name}: skipped (needs {', '.join(demos[name].missing)}: "
                      f"pip install 'thermolimb[{demos[name].extra}]')")
            names = [n for n in names if not demos[n].missing]
        if args.live is not None:
            from ..monitor.live import ENV_VARIABLE

            os.environ[ENV_VARIABLE] = str(args.live)
        # the longest first, so that the pool ends soonest; one process when streaming live (one port) or one
        # demo
        order = sorted(names, key=lambda n: -demos[n].cost_s)
        workers = 1 if args.live is not None else (args.workers or worker_limit(os.cpu_count() or 1)[0])
        workers = min(workers, len(names))
        summaries = {}
        with Runner("process" if workers > 1 else "serial", workers) as runner:
            jobs = [(name, Path(args.out), args.quick, args.quiet) for name in order]
            for i, (summary, seconds) in runner.as_completed(timed_demo, jobs):
                summaries[order[i]] = summary
                if not args.json:  # each demo as it ends
                    print(f"demo {order[i]}: wrote {Path(args.out) / order[i]} in {seconds:.1f} s",
                          flush=True)
        return Outcome({n: summaries[n] for n in names} if len(names) > 1 else summaries[names[0]])


class Report(Command):
    name = "report"
    help = "build OUT/index.html from the demos' results"
    description = "Write a static page showing every demo's plots and summary tables."
    plots = None

    def add_options(self, p):
        p.add_argument("out", nargs="?", type=output_dir, default="out",
                       help="folder holding the demos' results (default out)")

    def work(self, args) -> Outcome:
        return Outcome(None, f"wrote {build_report(Path(args.out))}")


def add_parser(sub):
    Demo().add_parser(sub)
    Report().add_parser(sub)
