"""How a CSV file is written: its text encoding (UTF-8, UTF-16 with its byte-order mark, or Windows-1252 as
Windows tools write "°C"), its separator (a character, or runs of spaces in columns aligned by a program's
``%10.3f``), decimal mark, header line (after a preamble, or none: a logger that writes numbers from the first
line), a row of units under the header, and the names ``--columns`` gives a file without a header.
:func:`csv_dialect` finds it from the file's first lines, as every reader of a CSV log takes it."""

from __future__ import annotations

import codecs
import csv
import functools
import re
from collections import Counter
from dataclasses import dataclass, replace
from pathlib import Path

from ..util.errors import LogError
from .units import header_unit

SEPARATORS = (",", ";", "\t", "|")
WHITESPACE = r"\s+"  # columns aligned with spaces: pandas' separator for runs of white space
SNIFF_LINES = 200
_DECIMAL_COMMA = re.compile(r"(^|[;\t|])\s*-?\d+,\d+\s*(?=[;\t|]|$)")


@dataclass(frozen=True)
class Dialect:
    """How a CSV file is written: ``pandas.read_csv``'s keyword arguments for it, the column names its header
    repeats (name -> count), and its header line."""

    options: dict
    duplicates: dict[str, int]
    header_line: str
    units_line: str | None = None  # a row of units under the header, skipped by ``options``
    headerless: bool = False  # the first line holds data (numbers), not names: ``options`` name the columns
    read_as: str | None = None  # how the file was read where it is not plain UTF-8, for a note

    @property
    def header(self) -> list[str]:
        if self.headerless:
            return list(self.options["names"])
        return fields_of(self.header_line, self.options["sep"])

    def named(self, names, path) -> dict:
        """``options`` with the columns named ``names`` (``--columns``), checked against the file."""
        if not names:
            return self.options
        header = None if self.headerless else [name.strip() for name in self.header]
        check_names(names, header or list(self.options["names"]), header, path)
        return {**self.options, "names": list(names)} if self.headerless else self.options


def check_names(names, columns: list[str], header, path) -> None:
    """``--columns`` checked: as many names as the file has columns, each once, and the header's own names
    where the file has a header row (the option names the columns of a file written without one)."""
    if not names:
        return
    names = list(names)
    if len(set(names)) != len(names) or not all(names):
        raise LogError(f"--columns {','.join(names)}: expected a name for each column, each name once")
    if header is not None and [str(c) for c in header] != names:
        raise LogError(f"{path}: --columns names the columns of a file "
                       "without a header row, and this file has one "
                       f"({shown_names(header)}); leave --columns out for it, or give its header's names")
    if len(names) != len(columns):
        raise LogError(f"{path}: --columns gives {len(names)} name(s) "
                       f"and the file has {len(columns)} column(s); "
                       f"expected a name for each column, in the file's order")


def fields_of(line: str, sep: str) -> list[str]:
    """A line's fields: split at ``sep`` as the csv module does (quotes kept together), or at runs of white
    space."""
    if sep == WHITESPACE:
        return line.split()
    return next(csv.reader([line], delimiter=sep), [])


def file_dialect(path: Path, sep: str | None, decimal: str | None) -> Dialect:
    """The file's dialect (guessed where not given)."""
    encoding = text_encoding(path)
    _refuse_binary(path, encoding)
    head, comments = _scan(path, encoding)
    dialect = _dialect(head, comments, path, sep, decimal, encoding)
    if encoding == "cp1252":
        return replace(dialect, read_as=f"{path}: not UTF-8 text: read as Windows-1252 (cp1252), as Windows "
                                        "tools write it")
    return dialect


def text_encoding(path: Path) -> str:
    """The file's text encoding: UTF-16 where it starts with that byte-order mark, UTF-8 where every byte of
    it decodes so, else Windows-1252, which Windows tools write ("°C" as the one byte 0xB0).  Read once for
    each version of the file (a log is asked for its dialect by each of its readers)."""
    stat = Path(path).stat()
    return _encoding(str(path), stat.st_mtime_ns, stat.st_size)


@functools.lru_cache(maxsize=16)
def _encoding(path: str, mtime_ns: int, size: int) -> str:
    decoder = codecs.getincrementaldecoder("utf-8")()
    with open(path, "rb") as f:
        first = f.read(4)
        if first.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
            return "utf-16"
        f.seek(0)
        try:
            while chunk := f.read(1 << 20):
                decoder.decode(chunk)
            decoder.decode(b"", final=True)
        except UnicodeDecodeError:
            return "cp1252"
    return "utf-8-sig"


def csv_dialect(text: str, source, sep: str | None = None, decimal: str | None = None) -> Dialect:
    """The dialect of a CSV file's first lines (a file being written, read so far), as :func:`read_table`
    finds it."""
    if "\x00" in text:
        raise LogError(f"{source}: not a text file (it holds NUL bytes); expected a CSV log")
    lines = [line.removeprefix("\ufeff") if i == 0 else line for i, line in enumerate(text.splitlines())]
    comments = {i for i, line in enumerate(lines) if line.lstrip().startswith("#")}
    return _dialect(lines[:SNIFF_LINES], comments, source, sep, decimal)


def _dialect(head: list[str], comments: set[int], path, sep: str | None, decimal: str | None,
             encoding: str | None = None) -> Dialect:
    content = [(i, line) for i, line in enumerate(head) if i not in comments and line.strip()]
    if not content:
        raise LogError(f"{path}: the file has no header line and no data")
    sep = sep or _guess_separator([line for _, line in content])
    header_at = _header_line(content, sep)
    data = [line for i, line in content if i > header_at]
    comma = sep not in (",", WHITESPACE) and any(_DECIMAL_COMMA.search(line) for line in data)
    decimal = decimal or ("," if comma else ".")
    skip = comments | set(range(header_at))
    header_line = next(line for i, line in content if i == header_at)
    header = fields_of(header_line, sep)
    options = dict(sep=sep, decimal=decimal, skiprows=skip or None, skip_blank_lines=True)
    if encoding is not None:  # a file's (text already decoded has none)
        options.update(encoding=encoding, encoding_errors="replace")
    after = next((line for i, line in content if i > header_at), None)
    following = None if after is None else fields_of(after, sep)
    if _holds_data(header, following):  # no header row: the first line is a sample (a logger's, a drive's)
        names = [f"column{k + 1}" for k in range(_split(header_line, sep))]
        options.update(header=None, names=names, index_col=False)
        return Dialect(options, {}, header_line, headerless=True)
    counts = Counter(name.strip() for name in header)
    if sum(line.rstrip().endswith(sep) for line in data) * 2 > len(
        data
    ) and not header_line.rstrip().endswith(sep):
        options["index_col"] = False  # data lines end with a separator the header lacks: not an index column
    names, units_line = [name.strip() for name in header], None
    units_at, units = _units_row(content, header_at, sep, names)
    if units and len(set(names)) == len(names):
        # a row of units under the header (a DAQ's export): read as the header's own "name [unit]"
        names = [
            f"{n} [{u}]" if u and n != "actuator" and not header_unit(n) else n for n, u in zip(names, units)
        ]
        options.update(names=names, header=0, skiprows=sorted(skip | {units_at}))
        units_line = next(line for i, line in content if i == units_at)
    if "actuator" in names:
        # an actuator named NA, None or nan is a name, not a missing value, and 1 and 01 are two actuators
        from pandas._libs.parsers import STR_NA_VALUES

        options.update(keep_default_na=False, dtype={"actuator": str},
                       na_values={name: sorted(STR_NA_VALUES) for name in names if name != "actuator"}
                       | {"actuator": [""]})
    return Dialect(options, {name: k for name, k in counts.items() if k > 1 and name}, header_line,
                   units_line)


_NUMBER = re.compile(r"^[-+]?(\d+([.,]\d*)?|[.,]\d+)([eE][-+]?\d+)?$")
_MISSING = {"", "nan", "na", "n/a", "null", "none", "-", "inf", "-inf"}


def _holds_data(fields: list[str], following: list[str] | None = None) -> bool:
    """Whether a would-be header line is a sample: every field a number or a missing value, and two numbers or
    more (a header names its columns; a line of numbers is data); or, beside text fields (an actuator's name),
    numbers in at least half of them, exactly where the ``following`` line has its numbers (a header of names
    has none where the data has them)."""
    fields = [f.strip().strip('"') for f in fields]
    numeric = [bool(_NUMBER.match(f)) for f in fields]
    if sum(numeric) >= 2 and all(n or f.lower() in _MISSING for n, f in zip(numeric, fields)):
        return True
    if following is None or len(following) != len(fields) or 2 * sum(numeric) < len(fields):
        return False
    return numeric == [bool(_NUMBER.match(f.strip().strip('"'))) for f in following]


def _units_row(content: list[tuple[int, str]], header_at: int, sep: str,
               names: list[str]) -> tuple[int | None, list[str] | None]:
    """The line under the header and its units, where it holds units: no number and no date in any field,
    short words ("s", "N m", "[degC]", "-" for none), and numbers on the line after it."""
    after = [(i, line) for i, line in content if i > header_at][:2]
    if len(after) < 2:
        return None, None
    (at, line), (_, data) = after
    fields = [f.strip() for f in fields_of(line, sep)]
    values = [v.strip() for v in fields_of(data, sep)]
    if len(fields) != len(names) or not any(fields) or any(
            _NUMBER.match(f) or re.search(r"\d{2}", f) or len(f) > 16 for f in fields):
        return None, None
    if sum(bool(_NUMBER.match(v)) for v in values) * 2 < len(values):
        return None, None
    units = [f.strip("[]() ") for f in fields]
    return at, ["" if u in ("", "-") else u for u in units]


def _refuse_binary(path: Path, encoding: str = "utf-8-sig", sniff_bytes: int = 65536) -> None:
    """A file with NUL bytes, or more than 5 % (and 16) control bytes, in its first 64 KiB (as text, for
    UTF-16) is not a CSV log."""
    with open(path, "rb") as f:
        head = f.read(sniff_bytes)
    if encoding == "utf-16":
        head = head.decode("utf-16", errors="replace").encode("utf-8", errors="replace")
    control = sum(head.count(bytes([b])) for b in range(32) if b not in (9, 10, 12, 13))
    if b"\x00" in head or control > max(16, 0.05 * len(head)):
        raise LogError(f"{path}: not a text file ({control} control "
                       f"bytes in its first {len(head)}); expected a "
                       "CSV log, or a .parquet, .bag or .mcap file named as such")


def _scan(path: Path, encoding: str) -> tuple[list[str], set[int]]:
    """The first ``SNIFF_LINES`` lines, and the indices of every ``#`` comment line in the file."""
    head, comments = [], set()
    with open(path, encoding=encoding, errors="replace", newline="") as f:
        for i, line in enumerate(f):
            if i < SNIFF_LINES:
                head.append(line.rstrip("\r\n"))
            if line.lstrip().startswith("#"):
                comments.add(i)
    return head, comments


def _guess_separator(lines: list[str]) -> str:
    """The separator that splits the most lines into the same number (>1) of fields; runs of white space only
    where they split more lines so than any character does (columns aligned with spaces)."""
    best, best_score = ",", -1.0
    for sep in (*SEPARATORS, WHITESPACE):
        counts = [_split(line, sep) for line in lines]
        modal = max(set(counts), key=counts.count)
        if modal < 2:
            continue
        score = counts.count(modal) + 1e-3 * modal
        if score > best_score:
            best, best_score = sep, score
    return best


def _header_line(content: list[tuple[int, str]], sep: str) -> int:
    """Index of the header: the first line with as many fields as most lines after it (skips a preamble)."""
    counts = [_split(line, sep) for _, line in content]
    tail = counts[len(counts) // 2:] or counts
    modal = max(set(tail), key=tail.count)
    for (i, _), c in zip(content, counts):
        if c >= modal:
            return i
    return content[0][0]


def _split(line: str, sep: str) -> int:
    """Number of fields, ignoring separators inside double quotes and one at the end of the line (a logger
    that ends every line with a separator writes no field after it)."""
    if sep == WHITESPACE:
        return len(line.split())
    return len(re.sub(r'"[^"]*"', "", line.rstrip()).removesuffix(sep).split(sep))


def separator_name(sep: str) -> str:
    return {",": "comma", ";": "semicolon", "\t": "tab", "|": "bar", WHITESPACE: "space"}.get(sep, repr(sep))


def shown_names(names, limit: int = 300) -> str:
    """Column names for a one-line message: a name with unprintable characters quoted, the list cut at
    ``limit``."""
    text = ", ".join(str(n) if str(n).isprintable() else repr(str(n)) for n in names)
    return text if len(text) <= limit else text[:limit] + f"... ({len(names)} columns)"
