"""The house is one-way: core -> robots -> environments -> demos, found from the source with ``ast``.

Inside the core every subpackage and top-level module is a node of its own
(``thermolimb.util``, ``thermolimb.model``, ...), and the core's graph has no
cycle either.  ``python tests/test_layers.py`` prints the import graph.
"""

from __future__ import annotations

import ast
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PARTS = ("thermolimb", "hexapod_pb", "humanoid_pb", "demos")
WATCHED = PARTS + ("thermolimb_demos", "gymnasium", "pybullet")
CORE = "thermolimb"


def _node(module: str) -> str:
    """A robot or the demos as one node; in the core, each subpackage or top-level module (``__init__``: the core)."""
    parts = module.split(".")
    if parts[0] == "thermolimb_demos":
        return "demos"
    if parts[0] == CORE and len(parts) > 1:
        return ".".join(parts[:2])
    return parts[0]


def _core(graph: dict[str, set[str]]) -> set[str]:
    """Every node of the core (``thermolimb.*``) except the command line and the environments' shared part."""
    nodes = set(graph) | set().union(*graph.values())
    return {n for n in nodes if n.split(".")[0] == CORE and n not in ("thermolimb.cli", "thermolimb.envs")}


def _imports(path: Path, module: str) -> list[str]:
    package = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            found.append(".".join(base + ([node.module] if node.module else [])))
    return found


def import_graph(root: Path = ROOT) -> dict[str, set[str]]:
    """``{part: parts it imports}`` over every module of the tree (imports inside functions included)."""
    edges: dict[str, set[str]] = defaultdict(set)
    for part in PARTS:
        for path in sorted((root / part).rglob("*.py")):
            module = ".".join(path.relative_to(root).with_suffix("").parts)
            for name in _imports(path, module):
                if name.split(".")[0] in WATCHED and _node(name) != _node(module):
                    edges[_node(module)].add(_node(name))
    return dict(edges)


def test_the_core_imports_no_robot_no_gymnasium_and_no_demo():
    graph = import_graph()
    for node in _core(graph):
        assert not graph.get(node, set()) & {"hexapod_pb", "humanoid_pb", "demos", "gymnasium", "thermolimb.envs",
                                             "thermolimb.cli"}, node


def test_the_core_has_no_cycle_between_its_rooms():
    """util, model, logs, plant, identification, workbench, plotting, ...: each imports only rooms below it."""
    graph = import_graph()
    core = _core(graph)
    edges = {n: {t for t in graph.get(n, set()) if t in core and t != n} for n in core}
    done, order = set(), []
    while len(done) < len(core):
        ready = sorted(n for n in core - done if edges[n] <= done)
        assert ready, f"a cycle among {sorted(core - done)}: {({n: sorted(edges[n] - done) for n in core - done})}"
        done |= set(ready)
        order += ready


def test_only_the_environments_import_gymnasium_and_nothing_imports_the_demos():
    graph = import_graph()
    for part, targets in graph.items():
        if "gymnasium" in targets:
            assert part in ("thermolimb.envs", "hexapod_pb", "humanoid_pb", "demos"), part
        if part != "demos":
            assert "demos" not in targets, part
    assert not graph.get("thermolimb.envs", set()) & {"hexapod_pb", "humanoid_pb"}
    assert "thermolimb.cli" not in graph.get("demos", set())


def test_robots_do_not_import_each_other():
    graph = import_graph()
    assert "humanoid_pb" not in graph.get("hexapod_pb", set())
    assert "hexapod_pb" not in graph.get("humanoid_pb", set())


def loaded_by(statement: str, modules: tuple[str, ...]) -> list[str]:
    """Which of ``modules`` a fresh interpreter has loaded after running ``statement``."""
    import subprocess

    code = f"import sys; {statement}; print([m for m in {modules!r} if m in sys.modules])"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    return ast.literal_eval(out)  # the list printed by the line above


def test_importing_the_core_registers_nothing_and_loads_no_gymnasium():
    statement = "import thermolimb, thermolimb.model, thermolimb.logs, thermolimb.workbench.validation, thermolimb.workbench.diagnosis"
    assert loaded_by(statement, ("gymnasium", "pybullet", "hexapod_pb", "humanoid_pb", "thermolimb_demos",
                                 "demos", "rosbags", "plotly")) == []


def test_the_command_line_starts_without_the_heavy_libraries():
    statement = "import thermolimb.cli.main as m; m.build_parser()"
    assert loaded_by(statement, ("gymnasium", "pybullet", "pinocchio", "matplotlib", "pandas", "scipy.signal",
                                 "scipy.stats", "scipy.optimize", "rosbags", "plotly", "threadpoolctl", "ray")) == []


# what a checkout holds at its top level: the package folders, the docs and tests, and the build and CI files
TOP_LEVEL = {".ci", ".gitignore", "Makefile", "README.md", "pyproject.toml", "setup.cfg", "benchmarks", "demos",
             "docs", "hexapod_pb", "humanoid_pb", "tests", "thermolimb", "urdf"}


def test_nothing_is_tracked_outside_the_known_folders():
    """A stray output (a fuzz run's plots written into ``*/`` or ``-1/`` at the root) is never committed."""
    import shutil
    import subprocess

    if shutil.which("git") is None or not (ROOT / ".git").exists():
        import pytest

        pytest.skip("not a git checkout: nothing to check")
    tracked = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
    stray = sorted({name.split("/")[0] for name in tracked.decode().split("\0") if name} - TOP_LEVEL)
    assert not stray, f"tracked outside the known folders: {stray}"


if __name__ == "__main__":
    for part, targets in sorted(import_graph(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT).items()):
        print(f"{part:18s} -> {', '.join(sorted(targets))}")
