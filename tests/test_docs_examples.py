"""Every command and Python block in README.md and docs/ runs (issue 81, item 8): a documented option or import
cannot break unseen.

Two checks.  The fast one parses every documented ``thermolimb`` command line with the command line's own parser
and imports every documented Python block's imports.  The slow one runs each page's blocks in order, as a reader
would, in a fresh folder where the repository's bundled data sits at its documented path; the few commands that
need what is not bundled (a user's folder of logs, a Ray cluster) or that take hours, and those another test runs
as they are documented, are listed in :data:`NOT_RUN` with the reason.
"""

from __future__ import annotations

import ast
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from thermolimb.cli.main import build_parser

ROOT = Path(__file__).resolve().parents[1]
PAGES = ["README.md", *sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs").glob("*.md"))]
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)

# (page, what the command line starts with): why it is not run here
DEMOS_RUN = "tests/test_demos.py runs each demo in quick mode"
BENCHMARK = "a benchmark: minutes, run by hand (its page names it)"
STRATEGIES = "tests/test_envs.py compares the strategies"
NOT_RUN = {
    ("README.md", "make "): "the README's own setup; CI runs `make test` and the demo tests run `make demo`'s demos",
    ("README.md", "source "): "a shell's own setting",
    **{(page, "thermolimb demo"): DEMOS_RUN for page in ("README.md", "docs/environments.md", "docs/hexapod.md",
                                                          "docs/humanoid.md", "docs/workbench.md")},
    ("docs/workbench.md", "thermolimb report "): "tests/test_demos.py builds the report from the demos' runs",
    **{(page, "thermolimb compare-strategies "): STRATEGIES for page in ("README.md", "docs/environments.md")},
    **{(page, "python benchmarks/"): BENCHMARK for page in ("docs/environments.md", "docs/hexapod.md",
                                                             "docs/humanoid.md")},
    ("docs/logs.md", "thermolimb fit --fleet logs/"): "a user's folder of logs (tests/test_fleet.py runs --fleet)",
    ("docs/logs.md", "thermolimb diagnose --fleet"): "a user's folder of runs (tests/test_fleet.py runs --fleet)",
    ("docs/model-file.md", "thermolimb monitor "): "follows a live file until stopped (tests/test_monitor.py)",
}
# what a page takes as the reader's own files, made here first: a model file and the log it came from
GIVEN = {
    "docs/travel.md": [
        "thermolimb simulate --profile random --duration 1800 --dt 1 --network first_order --effects sensor_noise "
        "--actuators knee:X8-9 --seed 3 --out calibration.csv",
        "thermolimb fit calibration.csv --actuator knee --save model.json --quiet",
        "thermolimb simulate --profile random --duration 1800 --dt 1 --network first_order --effects sensor_noise "
        "--actuators right_knee:X8-9,left_knee:X8-9 --seed 4 --out both.csv",
        "thermolimb fit both.csv --save models.json --quiet",
    ],
    "docs/model-file.md": ["thermolimb simulate --profile random --duration 1800 --dt 1 --out run.csv"],
}


def blocks(page: str) -> list[tuple[int, str, str]]:
    """``(line, language, text)`` of each fenced block of ``page``."""
    text = (ROOT / page).read_text(encoding="utf-8")
    return [(text[:m.start()].count("\n") + 1, m.group(1), m.group(2)) for m in FENCE.finditer(text)]


def shell_lines(text: str) -> list[str]:
    """A shell block's command lines: continuations joined, comment lines dropped, output lines (``##``, ``#``
    after a command) left out."""
    joined = re.sub(r"\\\n\s*", " ", text)
    return [line for line in (raw.strip() for raw in joined.splitlines()) if line and not line.startswith("#")]


def not_run(page: str, line: str) -> str | None:
    return next((why for (p, start), why in NOT_RUN.items() if p == page and line.startswith(start)), None)


def documented_commands() -> list[tuple[str, int, list[str]]]:
    """Every documented ``thermolimb`` command line: ``(page, block's line, argv)`` (a block's variables put in)."""
    out = []
    for page in PAGES:
        for line, lang, text in blocks(page):
            if lang != "sh":
                continue
            variables = {}
            for command in shell_lines(text):
                assignment = re.fullmatch(r"(\w+)=(\S+)", command)
                if assignment:
                    variables[assignment[1]] = assignment[2]
                    continue
                for name, value in variables.items():
                    command = command.replace(f"${name}", value)
                words = shlex.split(command, comments=True)
                if ">" in words:  # the shell's redirection of its output, not an argument
                    words = words[:words.index(">")]
                if words and words[0] == "thermolimb":
                    out.append((page, line, words[1:]))
    return out


WRITTEN = ("--out", "--save", "--mcap", "--propose", "--table", "--html", "--layout", "--plot")
FILE = re.compile(r"\.(csv|json|py|parquet|mcap|bag|xml)$")


def test_every_documented_command_line_parses(tmp_path, monkeypatch):
    """Each documented command and its options are the command line's own (a renamed option fails here); the
    files a page's earlier commands write (a plan, a model file) stand in as empty files."""
    commands = documented_commands()
    assert len(commands) >= 40, len(commands)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "thermolimb").symlink_to(ROOT / "thermolimb")
    for page, line, argv in commands:
        for before, word in zip(["", *argv], argv):
            if FILE.search(word) and not before.startswith(WRITTEN) and not Path(word).exists():
                Path(word).parent.mkdir(parents=True, exist_ok=True)
                Path(word).touch()
        parser = build_parser(argv[0])
        try:
            args, unknown = parser.parse_known_args(argv)
        except SystemExit as exc:  # argparse's refusal
            raise AssertionError(f"{page}:{line}: thermolimb {shlex.join(argv)} does not parse") from exc
        assert not unknown, f"{page}:{line}: thermolimb {shlex.join(argv)}: unknown {unknown}"


def test_every_documented_import_imports():
    """Each Python block's imports import (the rest runs in the slow check)."""
    checked = 0
    for page in PAGES:
        for line, lang, text in blocks(page):
            if lang != "python":
                continue
            imports = [node for node in ast.parse(text).body if isinstance(node, (ast.Import, ast.ImportFrom))]
            assert imports, f"{page}:{line}: a Python block without an import"
            exec(compile(ast.Module(body=imports, type_ignores=[]), f"{page}:{line}", "exec"), {})
            checked += 1
    assert checked >= 4


def _script(page: str) -> tuple[str, list[str]]:
    """The page's blocks as one script in the page's order, and what it leaves out with why."""
    lines, left = ["set -euo pipefail", *GIVEN.get(page, [])], []
    for line, lang, text in blocks(page):
        if lang == "python":
            lines.append(f"{shlex.quote(sys.executable)} - <<'PYTHON'\n{text}PYTHON")
        elif lang == "sh":
            for command in shell_lines(text):
                why = not_run(page, command)
                if why:
                    left.append(f"{page}:{line}: {command[:60]} ({why})")
                else:
                    lines.append(command.replace("python ", f"{shlex.quote(sys.executable)} ", 1)
                                 if command.startswith("python ") else command)
    return "\n".join(lines) + "\n", left


@pytest.mark.slow  # every page's commands in turn: minutes
@pytest.mark.parametrize("page", [p for p in PAGES if any(lang in ("sh", "python") for _, lang, _ in blocks(p))])
def test_every_documented_block_runs(page, tmp_path):
    """The page's blocks, run in order as a reader would, in a fresh folder where the bundled data sits at its
    documented path (``thermolimb/data/...``, ``benchmarks/``): every command ends with status 0."""
    script, left = _script(page)
    for name in ("thermolimb", "benchmarks", "demos"):
        (tmp_path / name).symlink_to(ROOT / name)
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}",
           "MPLBACKEND": "Agg"}
    done = subprocess.run(["bash", "-c", script], cwd=tmp_path, env=env, capture_output=True, text=True,
                          timeout=1800)
    assert done.returncode == 0, f"{page}: {done.stderr[-3000:]}\n(left out: {left})"
