"""``thermolimb demo`` and ``thermolimb report``."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from ..demo_registry import demo_names, in_tour_order, load_demos, run_demo
from ..report import build_report
from .output import print_json
from .types import integer, output_dir


def add_parser(sub):
    p = sub.add_parser("demo", help="run a demo (or all) and write its plots and summary.json",
                       description="Run a registered demo into OUT/NAME/: PNG plots and summary.json.",
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="demos (in the order to read them; 'thermolimb demo' with no name describes each):\n  "
                              + "\n  ".join(demo_names()))
    p.add_argument("name", nargs="?", default=None, help="demo name, or 'all'; omit to list them")
    p.add_argument("--quick", action="store_true", help="short mode (what make demo and the tests run)")
    p.add_argument("--out", type=output_dir, default="out", help="output folder (default out)")
    p.add_argument("--json", action="store_true", help="print the summary record(s)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.add_argument("--live", type=integer(0, 65535), nargs="?", const=8765, default=None, metavar="PORT",
                   help="stream the simulated robots live to Foxglove on the monitor's channels (default port 8765; "
                        "extra 'live')")
    p.set_defaults(func=run)

    r = sub.add_parser("report", help="build OUT/index.html from the demos' results",
                       description="Write a static page showing every demo's plots and summary tables.")
    r.add_argument("out", nargs="?", type=output_dir, default="out",
                   help="folder holding the demos' results (default out)")
    r.set_defaults(func=run_report)


def run(args) -> int:
    demos = load_demos()
    if args.name is None:
        for name in in_tour_order(demos):
            print(f"{name:22s} {demos[name].description}")
        return 0
    names = in_tour_order(demos) if args.name == "all" else [args.name]
    if args.name == "all":
        for name in [n for n in names if demos[n].missing]:
            print(f"demo {name}: skipped (needs {', '.join(demos[name].missing)}: "
                  f"pip install 'thermolimb[{demos[name].extra}]')")
        names = [n for n in names if not demos[n].missing]
    if args.live is not None:
        import os

        from ..monitor.live import ENV_VARIABLE

        os.environ[ENV_VARIABLE] = str(args.live)
    summaries = {}
    for name in names:
        start = time.perf_counter()
        summaries[name] = run_demo(name, Path(args.out), quick=args.quick, quiet=args.quiet)
        if not args.json:
            print(f"demo {name}: wrote {Path(args.out) / name} in {time.perf_counter() - start:.1f} s")
    if args.json:
        print_json(summaries if len(names) > 1 else summaries[names[0]])
    return 0


def run_report(args) -> int:
    index = build_report(Path(args.out))
    print(f"wrote {index}")
    return 0
