"""Follow a CSV log while another program still appends to it, through the same parsing and checks as
:func:`~thermolimb.logs.read_log`.

What ``fit`` reads, the monitor reads -- a byte-order mark, semicolons with decimal commas, a preamble, ISO or
epoch time stamps, units in the headers, a wide file named by ``--map`` -- and what ``fit`` refuses, the
monitor refuses, line by line, without stopping:

* the dialect, the header and the units are found on the log's first rows (:data:`PROBE_ROWS` of them, or what
  there is when the writer pauses), read whole by :func:`~.validate.from_frame`; every later piece is read by
  the same decisions (:class:`~.validate.Reading`);
* a line that cannot be read -- another number of fields than the header names (a column inserted without a
  new header), text where a number belongs, a time that does not increase, a temperature that jumps by about
  273 K (a switch to kelvin) -- is said with its line number and skipped; a header written again is said, a
  new one read from there on;
* a pause longer than the run rule (:func:`~.series.gaps`: 20 sampling intervals and a minute) starts a new
  run: the monitor's filter starts again from the reading after it;
* a file replaced under the same name (rotated) is said and followed from its start.

Only complete lines are read: a row still being written waits for its newline.
"""

from __future__ import annotations

import csv
import io
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..util.errors import LogError
from ..util.lazy import pandas as pd
from .dialect import Dialect, csv_dialect
from .mapping import OPTIONAL, REQUIRED
from .plausible import KELVIN_JUMP
from .series import GAP_FACTOR, GAP_MIN_S, MIN_SAMPLES
from .validate import Reading, from_frame

ODD_LINES = 3  # lines of one other shape in a row, from which the shape is said once for the run
# rows the dialect, header and units are decided on (fewer when the writer pauses)
PROBE_ROWS = 4 * MIN_SAMPLES


@dataclass
class Run:
    """New samples of one actuator: ``arrays`` (``time``, ``effort``, ``temperature`` and the channels the log
    has), and whether they start a new run (the first ones, or the first after a pause)."""

    arrays: dict[str, np.ndarray]
    new_run: bool


@dataclass
class _Last:
    """Where an actuator's readings stand: its last time and temperature, and its sampling interval."""

    time_s: float
    temperature_C: float
    step_s: float


class CsvFollower:
    """The complete rows appended to ``path`` since the last :meth:`poll`, read as ``fit`` reads the file.

    ``mapping`` and ``read`` are :func:`~thermolimb.logs.read_log`'s (``--map``, and ``velocity_unit``,
    ``effort_unit``, ``sep``, ``decimal``, ``drop_incomplete``); ``actuator``: the name of a file of one
    actuator. :meth:`poll` returns each actuator's new :class:`Run` pieces and adds to :attr:`notes` what it
    has to say.
    """

    def __init__(self, path: str | Path, actuator: str | None = None, mapping: dict | None = None,
                 read: dict | None = None):
        self.path = Path(path)
        self.actuator = actuator
        self.mapping = mapping or None
        self.read = dict(read or {})
        self.notes: list[str] = []
        self.units: dict[str, str] = {}  # the channels' units, once the first rows are read
        self.last: dict[str, _Last] = {}
        self.rows = 0  # rows read
        self.skipped = 0  # lines said and skipped
        self._odd: dict | None = None  # consecutive lines of one other number of fields: where, how many
        self._inode: int | None = None
        self._restart()

    def _restart(self) -> None:
        self.offset = 0
        self.line = 0  # lines read so far
        self.partial = b""
        self.pending: list[tuple[int, str]] = []  # the first lines, until the dialect is decided
        self.dialect: Dialect | None = None
        self.reading = Reading()
        self._said: set[str] = set()  # what the notes have said of this file (a replaced file says it again)

    @property
    def started(self) -> bool:
        """Whether the dialect, header and units are decided (the first rows read)."""
        return self.dialect is not None

    def poll(self, final: bool = False) -> dict[str, list[Run]]:
        """What complete rows the file gained since the last poll.  ``final``: the writer has stopped (the
        monitor idles out), so a log shorter than :data:`PROBE_ROWS` is read as it is."""
        try:
            stat = os.stat(self.path)
        except FileNotFoundError:
            return {}
        if self._inode is not None and (stat.st_ino != self._inode or stat.st_size < self.offset):
            self.notes.append(f"{self.path}: the file was replaced under "
                              "the same name (rotated, or cut short and "
                              f"written again) after line "
                              f"{self.line}; following the new file from its start")
            self._restart()
        self._inode = stat.st_ino
        numbered = self._new_lines(stat.st_size)
        if self.dialect is None:
            self.pending += numbered
            data = [n for n, t in self.pending if t.strip() and not t.lstrip().startswith("#")]
            if len(data) <= PROBE_ROWS and not (final and len(data) > 1):
                return {}
            if not final and len(data) <= self._probe_rows():
                return {}  # a log of many actuators: the start waits until each has its rows
            return self._start()
        return self._lines(numbered)

    def _new_lines(self, size: int) -> list[tuple[int, str]]:
        if size <= self.offset:
            return []
        with open(self.path, "rb") as f:
            f.seek(self.offset)
            data = self.partial + f.read(size - self.offset)
        if self.offset == 0:
            data = data.removeprefix(b"\xef\xbb\xbf")  # a byte-order mark, as read_log reads past it
        self.offset = size
        cut = data.rfind(b"\n") + 1
        self.partial = data[cut:]
        lines = data[:cut].decode("utf-8", errors="replace").splitlines()
        numbered = [(self.line + 1 + i, text) for i, text in enumerate(lines)]
        self.line += len(lines)
        return numbered

    def _start(self) -> dict[str, list[Run]]:
        """The first rows read whole, as ``fit`` reads a file: the dialect, the header and the units decided;
        the lines after them read as every later line is."""
        probe = self._probe_rows()
        lines, self.pending = self.pending, []
        data = [k for k, (_, t) in enumerate(lines) if t.strip() and not t.lstrip().startswith("#")]
        first, rest = (
            (lines, []) if len(data) <= probe + 1 else (lines[: data[probe] + 1], lines[data[probe] + 1 :])
        )
        dialect = csv_dialect("\n".join(t for _, t in first) + "\n", self.path, self.read.get("sep"),
                              self.read.get("decimal"))
        self.dialect = dialect
        header_at = next(k for k, (_, t) in enumerate(first) if t == dialect.header_line)
        first = first[:header_at + 1] + self._checked(first[header_at + 1:])
        text = "\n".join(t for _, t in first) + "\n"
        names = [h.strip() for h in dialect.header]
        if (
            self.mapping is None
            and "actuator" not in names
            and {"time", "effort", "temperature"} <= set(names)
        ):
            # a canonical log of one actuator: its columns by name, the actuator named by --actuator (or the
            # file)
            self.mapping = {c: c for c in REQUIRED + OPTIONAL if c in names}
        try:
            frame = pd.read_csv(io.StringIO(text), **dialect.options)
        except (ValueError, pd.errors.ParserError) as exc:
            raise LogError(f"{self.path}: the log's first rows cannot be read as a CSV file: {exc}") from None
        frame.columns = [str(c).strip() for c in frame.columns]
        frame.attrs["duplicate_columns"] = dialect.duplicates
        log = self._validate(frame)
        self.units = dict(log.units)
        self._say(log.notes)
        self.rows += len(frame)
        out = self._take({name: log.arrays(name) for name in log.actuators})
        for name, runs in self._lines(rest).items():
            out.setdefault(name, []).extend(runs)
        return out

    def _probe_rows(self) -> int:
        """The rows the start reads whole: :data:`PROBE_ROWS` for each actuator the pending rows name (a log
        of six joints is read as six logs of one would be), as far as its actuator column can be read yet."""
        text = "\n".join(t for _, t in self.pending) + "\n"
        column = (self.mapping or {}).get("actuator", "actuator")
        try:
            dialect = csv_dialect(text, self.path, self.read.get("sep"), self.read.get("decimal"))
            if column not in [h.strip() for h in dialect.header]:
                return PROBE_ROWS
            start = text.index(dialect.header_line)
            frame = pd.read_csv(io.StringIO(text[start:]), **dialect.options)
            frame.columns = [str(c).strip() for c in frame.columns]
            return PROBE_ROWS * max(int(frame[column].nunique()), 1)
        except (LogError, ValueError, KeyError, pd.errors.ParserError):
            return PROBE_ROWS  # what cannot be read yet is refused by the start, in its words

    def _validate(self, frame: pd.DataFrame):
        return from_frame(frame, source=str(self.path), mapping=self.mapping,
                          velocity_unit=self.read.get("velocity_unit"),
                          actuator_name=self.actuator or self.path.stem,
                          drop_incomplete=self.read.get("drop_incomplete", False),
                          units={"effort": self.read.get("effort_unit")}, reading=self.reading)

    def _lines(self, numbered: list[tuple[int, str]]) -> dict[str, list[Run]]:
        """Later lines: each checked against the header, then read in batches (module docstring)."""
        good = self._checked(numbered)
        if self.dialect is None:  # a new header: read from there on as a new log
            out = self._batch(good)
            for name, runs in self.poll().items():
                out.setdefault(name, []).extend(runs)
            return out
        return self._batch(good)

    def _checked(self, numbered: list[tuple[int, str]]) -> list[tuple[int, str]]:
        """The lines that can be read by the header: a repeated header, a line of another number of fields,
        said and left out; at a new header, the lines from it wait to be read as a new log's first rows."""
        sep, header = self.dialect.options["sep"], [h.strip() for h in self.dialect.header]
        good: list[tuple[int, str]] = []
        for k, (number, text) in enumerate(numbered):
            if not text.strip() or text.lstrip().startswith("#"):
                continue
            if text == self.dialect.units_line:  # kept in its place: the dialect's options skip it
                good.append((number, text))
                continue
            fields = [f.strip() for f in next(csv.reader([text], delimiter=sep), [])]
            if len(fields) == len(header) + 1 and not fields[-1]:  # a separator at the end of the line
                fields.pop()
            if fields == header:
                self.notes.append(f"{self.path}: line {number} repeats the "
                                  "header (the writer started again?); "
                                  f"read on")
                continue
            if _is_header(fields) and len(fields) > 2:
                self.notes.append(f"{self.path}: line {number} is a new header "
                                  f"({text[:120]}); the log is read by it "
                                  f"from here on")
                self.dialect, self.reading, self.pending = None, Reading(), numbered[k:]
                return good
            if len(fields) != len(header):
                self._odd_line(number, text, len(fields), len(header))
                continue
            if self._odd is not None and self._odd["count"] >= ODD_LINES:
                odd = self._odd
                self.notes.append(f"{self.path}: line {number}: rows of {len(header)} fields again, after "
                                  f"{odd['count']} lines of {odd['fields']} fields from line {odd['first']}, "
                                  f"skipped")
            self._odd = None
            good.append((number, text))
        return good

    def _odd_line(self, number: int, text: str, fields: int, named: int) -> None:
        """A line of another number of fields than the header names: said and skipped; from the
        :data:`ODD_LINES`-th of a run of such lines of one shape, said once for the run (a column inserted for
        good, written without a new header: the rest of the log would say it on every line), and again when
        rows of the header's shape come back."""
        self.skipped += 1
        odd = self._odd
        if odd is not None and odd["fields"] == fields:
            odd["count"] += 1
        else:
            odd = self._odd = {"fields": fields, "first": number, "count": 1}
        if odd["count"] < ODD_LINES:
            guess = " (a column inserted without a new header?)" if fields > named else ""
            self.notes.append(f"{self.path}: line {number} has {fields} fields where the header names {named}"
                              f"{guess}: {text[:60]!r}; skipped")
        elif odd["count"] == ODD_LINES:
            said = (f"from line {odd['first']} the rows have {fields} fields where the header names "
                    f"{named}: the row's shape changed without a new header, so the log cannot be read by "
                    f"it; such lines are skipped without a word each until rows of {named} fields or a new "
                    f"header line come (write one to read them)")
            self.notes.append(f"{self.path}: {said}")

    def _batch(self, good: list[tuple[int, str]]) -> dict[str, list[Run]]:
        """Lines validated together; a batch that does not validate is halved until each bad line is found,
        said and skipped (a bad line costs the logarithm of the batch's length in validations)."""
        out: dict[str, list[Run]] = {}
        queue = [good] if good else []
        while queue:
            lines = queue.pop(0)
            try:
                arrays, notes = self._read(lines)
            except LogError as exc:
                if len(lines) == 1:
                    self.notes.append(f"{self.path}: line {lines[0][0]}: {_reason(exc, self.path)}; skipped")
                    self.skipped += 1
                    continue
                half = len(lines) // 2
                queue[:0] = [lines[:half], lines[half:]]
                continue
            self.rows += len(lines)
            self._say(notes, (lines[0][0], lines[-1][0]))
            for name, runs in self._take(arrays).items():
                out.setdefault(name, []).extend(runs)
        return out

    def _read(self, lines: list[tuple[int, str]]) -> tuple[dict[str, dict[str, np.ndarray]], list[str]]:
        """The lines' samples by actuator, validated as a later piece of the log and against the readings
        before them (time goes on; no jump between degC and K), and what reading them said."""
        text = self.dialect.header_line + "\n" + "\n".join(t for _, t in lines) + "\n"
        options = {k: v for k, v in self.dialect.options.items() if k != "skiprows"}
        try:
            frame = pd.read_csv(io.StringIO(text), **options)
        except (ValueError, pd.errors.ParserError) as exc:
            raise LogError(f"{self.path}: {exc}") from None
        frame.columns = [str(c).strip() for c in frame.columns]
        log = self._validate(frame)
        self.units = dict(log.units)
        out = {name: log.arrays(name) for name in log.actuators}
        for name, arrays in out.items():
            last = self.last.get(name)
            if last is None:
                continue
            if arrays["time"][0] <= last.time_s:
                raise LogError(
                    f"time {arrays['time'][0]:g} s of {name} does not come after {last.time_s:g} s"
                )
            jump = arrays["temperature"][0] - last.temperature_C
            if KELVIN_JUMP[0] <= abs(jump) <= KELVIN_JUMP[1]:
                raise LogError(f"the temperature of {name} jumps by "
                               f"{jump:+.1f} K from the reading before: part of "
                               f"the log reads kelvin, part degC")
        return out, list(log.notes)

    def _say(self, notes, lines: tuple[int, int] | None = None) -> None:
        """Each of a piece's notes once: a later piece's that an earlier one said already (a unit converted,
        said again for every line appended) is not said again; a new one names the lines it comes from."""
        prefix = f"{self.path}: "
        for note in notes:
            body = note.removeprefix(prefix)
            if body not in self._said:
                self._said.add(body)
                self.notes.append(prefix + (f"lines {lines[0]} to {lines[1]}: " if lines else "") + body)

    def _take(self, samples: dict[str, dict[str, np.ndarray]]) -> dict[str, list[Run]]:
        """Each actuator's samples cut into runs at pauses longer than the run rule; the readings they end on
        kept for the next lines."""
        out = {}
        for name, arrays in samples.items():
            t = arrays["time"]
            last = self.last.get(name)
            step = last.step_s if last else (float(np.median(np.diff(t))) if t.size > 1 else GAP_MIN_S)
            limit = max(GAP_FACTOR * step, GAP_MIN_S)
            cuts = [int(k) + 1 for k in np.flatnonzero(np.diff(t) > limit)]
            pauses = [(t[k - 1], t[k]) for k in cuts]
            if last is not None and t[0] - last.time_s > limit:
                pauses.insert(0, (last.time_s, t[0]))
            for a, b in pauses:
                self.notes.append(f"{self.path}: {name} paused for {b - a:.0f} "
                                  f"s (from t = {a:g} s): a new run, its "
                                  f"estimate started again from the reading after the pause")
            back = last is not None and t[0] <= last.time_s  # a file written again from its start (truncated)
            if back:
                self.notes.append(f"{self.path}: {name}'s time starts again "
                                  f"at t = {t[0]:g} s after {last.time_s:g} "
                                  f"s: a new run, its estimate started again from its first reading")
            runs, lo = [], 0
            for k in cuts + [t.size]:
                first_new = last is None or (lo == 0 and (t[0] - last.time_s > limit or back))
                runs.append(Run({key: v[lo:k] for key, v in arrays.items()}, bool(lo > 0 or first_new)))
                lo = k
            self.last[name] = _Last(float(t[-1]), float(arrays["temperature"][-1]), step)
            out[name] = runs
        return out


def _is_header(fields: list[str]) -> bool:
    """A line of names, not numbers: no field reads as a number (a decimal comma included)."""
    def number(text: str) -> bool:
        try:
            float(text.replace(",", "."))
            return True
        except ValueError:
            return False

    present = [f for f in fields if f]
    return len(present) > 1 and not any(number(f) for f in present)


def _reason(exc: LogError, path: Path) -> str:
    """A validation's sentence without the file's name (the note names it) and the row within a batch."""
    return re.sub(r" at row \d+", "", str(exc).removeprefix(f"{path}: "))
