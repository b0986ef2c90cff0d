"""No output lands on a file the same command reads: checked once, before any work, for every command.

A recording is the one thing a user cannot make again.  Each output a command was given (``--html``,
``--table``, ``--propose``, ``--save``, ``--mcap``, ``--layout``, ``simulate`` and ``export --out``; a
``--plot`` or ``demo --out`` folder that is itself an input file) is compared with each input (the logs,
``--validate-on``, ``--terms``, the model file, ``--follow``; every file of a folder given as a log) by device
and inode when both exist -- a hard or symbolic link to a log is that log -- and by resolved path otherwise.
"""

from __future__ import annotations

import glob
import os
from pathlib import Path

from ..util.errors import UsageError

INPUTS = ("logs", "validate_on", "terms", "model_file", "follow")
OUTPUT_FILES = {
    "html": "--html",
    "table": "--table",
    "propose": "--propose",
    "save": "--save",
    "mcap": "--mcap",
    "layout": "--layout",
}
OUTPUT_FOLDERS = {"plot": "--plot"}


def inputs_of(args) -> list[Path]:
    paths: list[Path] = []
    for name in INPUTS:
        value = getattr(args, name, None)
        for item in ([] if value is None else value if isinstance(value, list) else [value]):
            text = str(item)
            matches = glob.glob(text) if any(c in text for c in "*?[") else [text]
            for match in matches:
                path = Path(match)
                paths += [p for p in path.rglob("*") if p.is_file()] if path.is_dir() else [path]
    return paths


def outputs_of(args) -> list[tuple[str, Path]]:
    out = [
        (flag, Path(getattr(args, name))) for name, flag in OUTPUT_FILES.items() if getattr(args, name, None)
    ]
    out += [
        (flag, Path(getattr(args, name)))
        for name, flag in OUTPUT_FOLDERS.items()
        if getattr(args, name, None)
    ]
    if getattr(args, "out", None):  # simulate's log, export's snippet, demo's folder
        out.append(("--out", Path(args.out)))
    return out


def same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:  # one does not exist yet: the paths, resolved through links
        return os.path.realpath(a) == os.path.realpath(b)


def check_outputs(args) -> None:
    """Refuse, in one sentence and before anything is read or written, an output that is an input."""
    inputs = inputs_of(args)
    for flag, output in outputs_of(args):
        for source in inputs:
            if same_file(output, source):
                what = (
                    "the model file"
                    if source == Path(str(getattr(args, "model_file", "") or ""))
                    else "the input"
                )
                raise UsageError(f"{flag} {output} is {what} {source} this "
                                 "command reads; an output never replaces "
                                 f"an input: write it elsewhere (nothing was written)")
