"""The house is one-way: core -> robots -> environments -> demos, found from the source with ``ast``.

``python tests/test_layers.py`` prints the import graph between the parts
(core subpackages that matter for layering are shown on their own).
"""

from __future__ import annotations

import ast
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PARTS = ("thermolimb", "hexapod_pb", "humanoid_pb", "demos")
WATCHED = PARTS + ("thermolimb_demos", "gymnasium", "pybullet")
SHOWN_APART = ("envs", "cli")  # core subpackages drawn as their own node


def _node(module: str) -> str:
    parts = module.split(".")
    if parts[0] == "thermolimb_demos":
        return "demos"
    if parts[0] == "thermolimb" and len(parts) > 1 and parts[1] in SHOWN_APART:
        return ".".join(parts[:2])
    return parts[0]


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
    assert not graph.get("thermolimb", set()) & {"hexapod_pb", "humanoid_pb", "demos", "gymnasium", "thermolimb.envs"}


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
    statement = "import thermolimb, thermolimb.model, thermolimb.logs, thermolimb.evaluation, thermolimb.diagnosis"
    assert loaded_by(statement, ("gymnasium", "pybullet", "hexapod_pb", "humanoid_pb", "thermolimb_demos",
                                 "demos", "rosbags", "plotly")) == []


def test_the_command_line_starts_without_the_heavy_libraries():
    statement = "import thermolimb.cli.main as m; m.build_parser()"
    assert loaded_by(statement, ("gymnasium", "pybullet", "pinocchio", "matplotlib", "pandas", "scipy.signal",
                                 "scipy.stats", "scipy.optimize", "rosbags", "plotly", "threadpoolctl", "ray")) == []


if __name__ == "__main__":
    for part, targets in sorted(import_graph(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT).items()):
        print(f"{part:18s} -> {', '.join(sorted(targets))}")
