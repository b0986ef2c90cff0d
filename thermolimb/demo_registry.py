"""Demos register themselves here; ``thermolimb demo NAME`` runs them.

A demo is a function ``run(out: Path, quick: bool, quiet: bool) -> dict``
that writes its PNG plots into ``out`` and returns its summary, which the
registry writes as ``out/summary.json``.  A top-level ``"details"`` entry, if
any, goes to ``out/details.json`` instead, so that ``summary.json`` keeps the
shape its issue specifies.  Decorate it with
:func:`register_demo`; :func:`load_demos` imports the modules named in the
``thermolimb.demos`` entry-point group (the suite's own live in the
``thermolimb_demos`` package, the repository's ``demos/`` folder), so other
packages can add demos the same way.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import json
from dataclasses import dataclass
from importlib.metadata import entry_points
from pathlib import Path
from typing import Callable

from .atomic import check_output_dir, write_text
from .errors import UsageError
from .jsonutil import to_jsonable


@dataclass(frozen=True)
class Demo:
    name: str
    description: str
    run: Callable[..., dict]
    requires: tuple[str, ...] = ()  # optional packages (an extra) the demo imports

    @property
    def missing(self) -> tuple[str, ...]:
        return tuple(m for m in self.requires if importlib.util.find_spec(m) is None)


DEMOS: dict[str, Demo] = {}


def register_demo(name: str, description: str, requires: tuple[str, ...] = ()):
    """Decorator registering ``run(out, quick, quiet) -> summary`` under ``name``."""

    def wrap(func):
        DEMOS[name] = Demo(name, description, func, tuple(requires))
        return func

    return wrap


ENTRY_POINT_GROUP = "thermolimb.demos"


def load_demos() -> dict[str, Demo]:
    """Import every demo module named in the ``thermolimb.demos`` entry-point group so that it registers."""
    for ep in entry_points(group=ENTRY_POINT_GROUP):
        importlib.import_module(ep.value)
    return DEMOS


def run_demo(name: str, out: Path, quick: bool = False, quiet: bool = False) -> dict:
    """Run one demo into ``out/<name>/`` and write its ``summary.json``."""
    demos = load_demos()
    if name not in demos:
        raise UsageError(f"unknown demo {name!r}; available: {', '.join(sorted(demos))}")
    if demos[name].missing:
        raise UsageError(f"demo {name!r} needs {', '.join(demos[name].missing)}: pip install 'thermolimb[rl]'")
    folder = check_output_dir(Path(out) / name, "demo output folder")
    folder.mkdir(parents=True, exist_ok=True)
    summary = to_jsonable(demos[name].run(folder, quick=quick, quiet=quiet))
    details = summary.pop("details", None)
    for filename, record in (("summary.json", summary), ("details.json", details)):
        if record is not None:
            write_text(folder / filename, json.dumps(record, indent=2))
    return summary


def demo_main(name: str, argv=None) -> dict:
    """``main(argv)`` of a demo module: ``--quick``, ``--out DIR``, ``--quiet``."""
    parser = argparse.ArgumentParser(prog=f"demo {name}", description=DEMOS[name].description)
    parser.add_argument("--quick", action="store_true", help="short run (used by the tests and make demo)")
    parser.add_argument("--out", default="out", help="output folder (default: out)")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    args = parser.parse_args(argv)
    return run_demo(name, Path(args.out), quick=args.quick, quiet=args.quiet)
