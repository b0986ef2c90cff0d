"""Where the suite's robot descriptions are: one resolver for checkouts and installed wheels."""

from __future__ import annotations

import os
import sys
import sysconfig
from pathlib import Path

from .atomic import write_text

_ENV = "THERMOLIMB_URDF_DIR"


def urdf_dir() -> Path:
    """The folder holding the suite's URDF files.

    Looked up in order: ``$THERMOLIMB_URDF_DIR``; ``urdf/`` beside the package
    in a source checkout (editable install); ``<prefix>/share/thermolimb/urdf``
    where a wheel installs it.
    """
    candidates = []
    if os.environ.get(_ENV):
        candidates.append(Path(os.environ[_ENV]))
    candidates.append(Path(__file__).resolve().parents[2] / "urdf")
    candidates.append(Path(sysconfig.get_path("data")) / "share" / "thermolimb" / "urdf")
    for path in candidates:
        if (path / "README.md").is_file():
            return path
    raise FileNotFoundError(
        "thermolimb cannot find its urdf/ folder; looked in " + ", ".join(str(p) for p in candidates)
        + f"; set {_ENV} to the folder"
    )


def write_urdf(name: str, text: str) -> Path:
    """Write a generated URDF into :func:`urdf_dir` (what each robot's ``python -m <robot>.urdf_model``
    does)."""
    path = write_text(urdf_dir() / name, text)
    print(f"wrote {path}", file=sys.stderr)
    return path
