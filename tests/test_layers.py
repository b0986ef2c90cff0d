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
    """Every node of the core (``thermolimb.*``) except the command line (``python -m thermolimb`` too) and the
    environments' shared part."""
    nodes = set(graph) | set().union(*graph.values())
    return {n for n in nodes if n.split(".")[0] == CORE and n not in ("thermolimb.cli", "thermolimb.__main__",
                                                                        "thermolimb.envs")}


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


def test_a_diagnosis_loads_neither_scipy_signal_nor_scipy_stats(tmp_path):
    """Half a second of every command line went to importing them for a filter, a convolution and a distribution
    the suite now computes with what the fit loads anyway (LAPACK, scipy.fft, scipy.special): a whole ``diagnose
    --auto`` on a plant log, its low-pass start and score tests included, loads neither, nor the other commands."""
    log = tmp_path / "run.csv"

    def command(*words: str) -> str:  # the command line in this interpreter, what it prints put aside
        return (f"import os; from thermolimb.cli.main import main; shown, sys.stdout = sys.stdout, open(os.devnull, "
                f"'w'); main({list(words)!r}); sys.stdout = shown")

    assert loaded_by(command("simulate", "--profile", "random", "--duration", "900", "--dt", "1", "--network",
                             "first_order", "--quiet", "--out", str(log)), ("scipy.signal",)) == []
    assert loaded_by(command("diagnose", str(log), "--actuator", "knee", "--auto", "--quiet", "--stability", "0"),
                     ("scipy.signal", "scipy.stats", "scipy.interpolate", "thermolimb.plant.plant",
                      "thermolimb.cli.audit", "scipy.optimize")) == ["scipy.optimize"]


# what a checkout holds at its top level: the package folders, the docs and tests, and the build and CI files
TOP_LEVEL = {".ci", ".gitignore", "Makefile", "README.md", "pyproject.toml", "setup.cfg", "benchmarks", "demos",
             "docs", "hexapod_pb", "humanoid_pb", "tests", "thermolimb", "urdf"}


def module_graph(root: Path = ROOT) -> dict[str, set[str]]:
    """``{module: modules of the same top package it imports}``, file by file, imports inside functions included
    (``from . import x`` counts as importing the module ``x`` when it is one)."""
    modules = {}
    for part in ("thermolimb", "hexapod_pb", "humanoid_pb"):
        for path in sorted((root / part).rglob("*.py")):
            name = ".".join(path.relative_to(root).with_suffix("").parts).removesuffix(".__init__")
            modules[name] = path
    edges: dict[str, set[str]] = defaultdict(set)
    for name, path in modules.items():
        package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            targets = []
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = ".".join((package[: len(package) - node.level + 1] if node.level else [])
                                + ([node.module] if node.module else []))
                targets = [f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base
                           for alias in node.names]
            for target in targets:
                while target and target not in modules:
                    target = target.rpartition(".")[0]
                # a package's face re-exports its modules: importing it is not a circle through them
                if target and target != name and not modules[target].name == "__init__.py":
                    edges[name].add(target)
    return dict(edges)


def test_no_module_imports_itself_back_through_others():
    """No circle between modules, function-level imports included: a module that needs another's code imports it,
    and that one never needs the first (``thermolimb.model.model`` and ``.saved``, ``logs.series`` and
    ``.writing``, the diagnosis and its stability check each had one)."""
    graph = module_graph()
    state: dict[str, int] = {}
    path: list[str] = []

    def visit(node):
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                raise AssertionError(f"import circle: {' -> '.join(path[path.index(nxt):] + [nxt])}")
            if nxt not in state:
                visit(nxt)
        path.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node)


def graph_text(root: Path = ROOT) -> str:
    """The rooms' import graph as ``python tests/test_layers.py`` prints it and docs/architecture.md shows it."""
    return "\n".join(f"{part:24s} -> {', '.join(sorted(targets))}" for part, targets in sorted(import_graph(root).items()))


def test_the_architecture_page_shows_the_graph_as_it_is():
    """docs/architecture.md's graph is this test's, so it cannot go stale (``python tests/test_layers.py`` prints
    it), and every room of the core is named in the page's table."""
    page = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    assert graph_text() in page, "docs/architecture.md: paste the output of `python tests/test_layers.py`"
    rooms = {n for n in _core(import_graph()) | {"thermolimb.cli", "thermolimb.envs"} if n != CORE}
    unnamed = sorted(room for room in rooms if f"`{room}`" not in page)
    assert not unnamed, f"docs/architecture.md does not name the rooms {unnamed}"


LARGEST_MODULE_LINES = 500


def test_no_module_is_over_500_lines():
    sizes = {path.relative_to(ROOT).as_posix(): len(path.read_text(encoding="utf-8").splitlines())
             for part in ("thermolimb", "hexapod_pb", "humanoid_pb") for path in (ROOT / part).rglob("*.py")}
    assert {p: n for p, n in sizes.items() if n > LARGEST_MODULE_LINES} == {}


def test_both_robots_share_one_shape():
    """Grouped folders (model, control, experiments) beside the same top-level modules, at most 12 of them; an
    environment does not import its package's experiments."""
    shapes = {}
    for robot in ("hexapod_pb", "humanoid_pb"):
        top = {p.stem for p in (ROOT / robot).glob("*.py")}
        folders = {p.name for p in (ROOT / robot).iterdir() if (p / "__init__.py").exists()}
        assert len(top) <= 12, (robot, sorted(top))
        assert {"model", "control", "experiments"} <= folders, (robot, folders)
        shapes[robot] = top
        env = (ROOT / robot / "env.py").read_text(encoding="utf-8")
        assert "experiments" not in env.split('"""', 2)[-1].split("class ", 1)[0], robot
    common = {"__init__", "constants", "params", "limits", "thermal", "calibration", "readings", "sim", "env",
              "policies"}
    assert all(common <= top for top in shapes.values()), shapes


def test_a_module_name_means_one_thing_in_the_core():
    """No two modules of the core share a name, but for the house's conventions: a subcommand of the command line
    (``cli/fleet.py``) and a figure (``plotting/drift.py``) are named for what they serve, and ``base.py`` is a
    pluggable axis's base class."""
    paths = [p.relative_to(ROOT / "thermolimb") for p in (ROOT / "thermolimb").rglob("*.py") if p.name != "__init__.py"]
    named: dict[str, list[str]] = defaultdict(list)
    for p in paths:
        if p.name != "base.py" and p.parts[0] not in ("cli", "plotting"):
            named[p.name].append(p.as_posix())
    assert {name: places for name, places in named.items() if len(places) > 1} == {}


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
    print(graph_text(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT))


def test_the_catalog_keeps_its_order():
    """The catalog's order is the order changes are tried in (ties between candidates keep it): a new effect joins at
    the end of its family, and no tool sorting imports reorders it (thermolimb/effects/__init__.py's MODULES)."""
    from thermolimb.model import TERMS

    assert list(TERMS)[:15] == ["joule", "effort_bias", "current_heating", "power_heating", "housing_boundary",
                                "winding_tempco", "speed_losses", "neighbor_coupling", "ambient_variation",
                                "motion_cooling", "second_node", "housing_motion_cooling", "housing_friction",
                                "third_node", "sensor_lag"]
