"""Follow a CSV log while another program still appends to it, as ``tail -f`` does, one piece at a time.

The file is the canonical long format the suite writes (``thermolimb simulate``, the rig):
``time,actuator,effort,temperature`` and optional ``velocity``, ``current``, ``ambient``; a file without an
``actuator`` column is one actuator's (named by ``--actuator``).  Only complete lines are read (a row still
being written waits for its newline); a line that does not parse is one clear error naming its line.
"""

from __future__ import annotations

import csv
import io
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..logs import LogError

REQUIRED = ("time", "effort", "temperature")
OPTIONAL = ("velocity", "current", "ambient")


@dataclass
class Piece:
    """New samples of one actuator (each array in time order)."""

    time_s: list = field(default_factory=list)
    effort: list = field(default_factory=list)
    temperature_C: list = field(default_factory=list)
    channels: dict = field(default_factory=dict)  # optional channel -> list


class CsvFollower:
    """The complete rows appended to ``path`` since the last :meth:`poll`, by actuator."""

    def __init__(self, path: str | Path, actuator: str | None = None):
        self.path = Path(path)
        self.actuator = actuator
        self.offset = 0
        self.line = 0
        self.header: list[str] | None = None
        self.partial = b""
        self.last_time: dict[str, float] = {}

    def poll(self) -> dict[str, Piece]:
        """What complete rows the file gained since the last poll (nothing when it has not grown)."""
        try:
            size = os.path.getsize(self.path)
        except FileNotFoundError:
            return {}
        if size < self.offset:
            raise LogError(f"{self.path}: the file shrank from {self.offset} to {size} bytes while being followed; "
                           f"the writer started it again? follow the new file from its start")
        if size == self.offset:
            return {}
        with open(self.path, "rb") as f:
            f.seek(self.offset)
            data = self.partial + f.read(size - self.offset)
        self.offset = size
        cut = data.rfind(b"\n") + 1
        self.partial = data[cut:]
        return self._parse(data[:cut].decode("utf-8", errors="replace"))

    def _parse(self, text: str) -> dict[str, Piece]:
        pieces: dict[str, Piece] = {}
        for row in csv.reader(io.StringIO(text)):
            self.line += 1
            if not row:
                continue
            if self.header is None:
                self._set_header(row)
                continue
            self._add(pieces, row)
        return pieces

    def _set_header(self, row: list[str]) -> None:
        names = [c.strip() for c in row]
        missing = [c for c in REQUIRED if c not in names]
        if missing or ("actuator" not in names and self.actuator is None):
            want = "time,actuator,effort,temperature[,velocity,current,ambient]"
            raise LogError(f"{self.path}: monitor follows the canonical CSV ({want}; or without the actuator column "
                           f"with --actuator NAME); this header is {','.join(names)}")
        self.header = names
        self.index = {c: names.index(c) for c in REQUIRED + OPTIONAL + ("actuator",) if c in names}

    def _add(self, pieces: dict[str, Piece], row: list[str]) -> None:
        ix = self.index
        name = row[ix["actuator"]].strip() if "actuator" in ix else self.actuator
        try:
            t, effort, temp = (float(row[ix[c]]) for c in REQUIRED)
            extra = {c: float(row[ix[c]]) for c in OPTIONAL if c in ix}
        except (ValueError, IndexError):
            raise LogError(f"{self.path}: line {self.line} does not parse as numbers in the columns "
                           f"{','.join(self.header)}: {','.join(row)[:80]}") from None
        if not all(math.isfinite(v) for v in (t, effort, temp, *extra.values())):
            raise LogError(f"{self.path}: line {self.line} holds a value that is not finite (NaN or inf); "
                           f"a followed log needs finite readings")
        if name in self.last_time and t <= self.last_time[name]:
            raise LogError(f"{self.path}: line {self.line}: time {t:g} s of {name} does not come after "
                           f"{self.last_time[name]:g} s")
        self.last_time[name] = t
        piece = pieces.setdefault(name, Piece())
        piece.time_s.append(t)
        piece.effort.append(effort)
        piece.temperature_C.append(temp)
        for c, v in extra.items():
            piece.channels.setdefault(c, []).append(v)


def as_arrays(piece: Piece) -> dict[str, np.ndarray]:
    """A piece's lists as arrays: ``time``, ``effort``, ``temperature`` and each optional channel."""
    out = {"time": np.array(piece.time_s), "effort": np.array(piece.effort),
           "temperature": np.array(piece.temperature_C)}
    out.update({c: np.array(v) for c, v in piece.channels.items()})
    return out
