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
import time
from dataclasses import dataclass, field
from importlib.metadata import entry_points
from pathlib import Path
from typing import Callable, Mapping

from .util.atomic import check_output_dir, made_folder, replaces, write_text
from .util.errors import UsageError
from .util.jsonutil import to_jsonable
from .util.numbers import plus_minus


@dataclass(frozen=True)
class DemoPage:
    """How ``out/index.html`` presents a demo.

    ``about``: one paragraph, what the demo shows and what to look at.
    ``headline(summary)``: the few numbers that matter, as rows
    ``(quantity, value with unit, what it is compared with)``.
    ``captions``: figure file name -> caption.
    ``finding(summary)``: the section's first sentence, built from the run's numbers: what this run shows, or
    why it shows nothing.
    """

    about: str
    headline: Callable[[dict], list[tuple[str, str, str]]]
    captions: Mapping[str, str] = field(default_factory=dict)
    finding: Callable[[dict], str] | None = None


# Captions of the figures a diagnosis writes (``plot_diagnosis``), by file-name prefix.
DIAGNOSIS_CAPTIONS = {
    "residuals_": "The residual of the starting model (measured − "
                  "model) over time, its autocorrelation, and its "
                  "cross-correlation with each input at ± lags; bars "
                  "beyond the band (95 % for white noise) point at "
                  "the missing physics.",
    "candidates_": "Every change the diagnosis tried, by how much it lowers the held-out error (an effect is "
                   "recommended at ≥ 10 % if plausible and identifiable), and those it set aside and why.",
    "waterfall_": "Validation RMSE after each step of the stepwise search (red: a fitted value is flagged).",
}


def caption(page: "DemoPage | None", filename: str) -> str:
    """The caption a demo gives a figure: by exact name, else by the longest matching prefix."""
    captions = {**DIAGNOSIS_CAPTIONS, **(page.captions if page else {})}
    if filename in captions:
        return captions[filename]
    prefixes = [k for k in captions if filename.startswith(k)]
    return captions[max(prefixes, key=len)] if prefixes else ""


def kelvin(value) -> str:
    return "—" if value is None else f"{value:.3f} K"


def seconds(value) -> str:
    """A time for a headline; ``not reached`` when there is none."""
    return "not reached" if value is None else f"{value:.1f} s"


def yes_no(flag: bool) -> str:
    """A flag as a headline says it."""
    return "yes" if flag else "no"


def mean_std(triple, unit: str = "", digits: int = 3) -> str:
    """``[mean, std, n]`` as ``mean ± std unit (n)``; ``—`` when nothing was measured."""
    mean, std, n = triple
    if mean is None or not n:
        return "—"
    return f"{plus_minus(mean, std, digits)}{(' ' + unit) if unit else ''} (n = {n})"


@dataclass(frozen=True)
class Demo:
    name: str
    description: str
    run: Callable[..., dict]
    requires: tuple[str, ...] = ()  # optional packages (an extra) the demo imports
    page: DemoPage | None = None
    extra: str = "rl"  # the extra that installs ``requires``
    # about how long the quick run takes on one core: ``demo all`` starts the longest first
    cost_s: float = 5.0

    @property
    def missing(self) -> tuple[str, ...]:
        return tuple(m for m in self.requires if importlib.util.find_spec(m) is None)


DEMOS: dict[str, Demo] = {}


def register_demo(name: str, description: str, requires: tuple[str, ...] = (), page: DemoPage | None = None,
                  extra: str = "rl", cost_s: float = 5.0):
    """Decorator registering ``run(out, quick, quiet) -> summary`` under ``name``; ``cost_s``: about how long
    its quick run takes on one core (``demo all`` starts the longest first)."""

    def wrap(func):
        DEMOS[name] = Demo(name, description, func, tuple(requires), page, extra, cost_s)
        return func

    return wrap


ENTRY_POINT_GROUP = "thermolimb.demos"
# the order a newcomer reads the suite's demos in (the report and `thermolimb demo` list them so); others
# follow by name
TOUR = (
    "thermal-fit",
    "diagnose",
    "custom-effect",
    "discovery",
    "real-logs",
    "pmsm-real-data",
    "fleet-drift",
    "forecast",
    "hexapod-walk",
    "strategies",
    "hexapod-endurance",
    "humanoid-recovery",
    "thermal-audit",
    "ppo-agent",
)


def in_tour_order(names) -> list[str]:
    """``names`` in :data:`TOUR`'s order, the rest after them alphabetically."""
    return sorted(names, key=lambda n: (TOUR.index(n) if n in TOUR else len(TOUR), n))


def demo_names() -> list[str]:
    """The registered demos' names, from the entry points alone (nothing imported), in tour order."""
    return in_tour_order({ep.name for ep in entry_points(group=ENTRY_POINT_GROUP)})


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
        raise UsageError(f"demo {name!r} needs {', '.join(demos[name].missing)}: "
                         f"pip install 'thermolimb[{demos[name].extra}]'")
    folder = check_output_dir(Path(out) / name, "demo output folder")
    # a summary the demo did not write is not replaced
    replaces(folder / "summary.json", _demo_wrote, "--out")
    with made_folder(folder):
        summary = to_jsonable(demos[name].run(folder, quick=quick, quiet=quiet))
        details = summary.pop("details", None)
        for filename, record in (("summary.json", summary), ("details.json", details)):
            if record is not None:
                write_text(folder / filename, json.dumps(record, indent=2))
    return summary


def _demo_wrote(summary: Path) -> bool:
    """Whether a ``summary.json`` is a demo's: a JSON object beside a figure the suite drew (its
    inventory)."""
    from .plotting.inventory import read_inventory

    if not isinstance(json.loads(summary.read_text(encoding="utf-8", errors="replace")), dict):
        return False
    return any(read_inventory(png) is not None for png in summary.parent.glob("*.png"))


def timed_demo(name: str, out: Path, quick: bool, quiet: bool) -> tuple[dict, float]:
    """:func:`run_demo` and how long it took (s): what ``demo all`` runs on each worker."""
    start = time.perf_counter()
    summary = run_demo(name, out, quick=quick, quiet=quiet)
    return summary, time.perf_counter() - start


def demo_main(name: str, argv=None) -> dict:
    """``main(argv)`` of a demo module: ``--quick``, ``--out DIR``, ``--quiet``."""
    parser = argparse.ArgumentParser(prog=f"demo {name}", description=DEMOS[name].description)
    parser.add_argument("--quick", action="store_true", help="short run (used by the tests and make demo)")
    parser.add_argument("--out", default="out", help="output folder (default: out)")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    args = parser.parse_args(argv)
    return run_demo(name, Path(args.out), quick=args.quick, quiet=args.quiet)
