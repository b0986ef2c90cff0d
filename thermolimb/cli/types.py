"""Argument types for the command line: each checks its range at parse time and names what it expects.

argparse turns the ``ArgumentTypeError`` into one line naming the option,
and exit status 2, before any work is done.
"""

from __future__ import annotations

import argparse
import math

from ..util.atomic import check_output_dir, check_output_file
from ..util.errors import UsageError


def number(low: float = -math.inf, high: float = math.inf, low_open: bool = False, unit: str = "",
           high_open: bool = False):
    """A finite float in ``[low, high]`` (open at ``low`` with ``low_open``, at ``high`` with
    ``high_open``)."""
    what = f"a number {'>' if low_open else '>='} {low:g}" if math.isfinite(low) else "a finite number"
    if math.isfinite(high):
        what += f" and {'<' if high_open else '<='} {high:g}"
    what += f" {unit}".rstrip()

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}") from None
        if (not math.isfinite(value) or value > high or value < low or (low_open and value == low)
                or (high_open and value == high)):
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}")
        return value

    return parse


def integer(low: int = 0, high: int | None = None):
    """A whole number in ``[low, high]``."""
    what = f"a whole number >= {low}" + (f" and <= {high}" if high is not None else "")

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}") from None
        if value < low or (high is not None and value > high):
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}")
        return value

    return parse


def fraction(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number between 0 and 1, got {text!r}") from None
    if not 0.0 < value < 1.0:
        raise argparse.ArgumentTypeError(f"expected a number between 0 and 1 (exclusive), got {text!r}")
    return value


def folds(text: str):
    if text in ("runs", "interleaved", "parts"):
        return text
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError("expected a number of folds (2 or more), "
                                         "'runs', 'interleaved' or 'parts', "
                                         f"got {text!r}") from None
    if value < 2:
        raise argparse.ArgumentTypeError("expected 2 or more folds (or 'runs', "
                                         f"'interleaved', 'parts'), got {text!r}")
    return value


def names(text: str) -> list[str]:
    """A comma-separated list of one or more names, each once (a name repeated is the same thing asked
    twice)."""
    items = [item.strip() for item in text.split(",")]
    if not all(items):
        raise argparse.ArgumentTypeError(f"expected one or more names separated by commas, got {text!r}")
    return list(dict.fromkeys(items))


def assignments(text: str) -> dict[str, float]:
    """``NAME=VALUE,...``: parameter values by name (``RC_s=600,T_offset_C=25``), each named once."""
    values = {}
    for item in text.split(","):
        name, sep, value = item.partition("=")
        name = name.strip()
        try:
            number_ = float(value)
        except ValueError:
            number_ = math.nan
        if not (sep and name and math.isfinite(number_)):
            raise argparse.ArgumentTypeError("expected NAME=VALUE,... with "
                                             "finite numbers (e.g. RC_s=600), got "
                                             f"{item.strip()!r}")
        if name in values:
            raise argparse.ArgumentTypeError(f"{name} is given twice")
        values[name] = number_
    return values


def _checked(check, text: str):
    try:
        return check(text)
    except UsageError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def output_file(text: str):
    """A file to write: not a directory, in a folder that can be made and written."""
    return _checked(lambda t: check_output_file(t, "file"), text)


def output_dir(text: str):
    """A folder to write into: not a file, and writable."""
    return _checked(lambda t: check_output_dir(t, "folder"), text)


SEED = integer(0, 2**32 - 1)
AMBIENT_C = number(-60.0, 150.0, unit="degC")
TEMPERATURE_C = number(-60.0, 400.0, unit="degC")  # a winding's: a limit, a start, a threshold


def names_list(text: str) -> tuple[str, ...]:
    """Comma-separated names (``--columns time,effort,temperature``), each given once."""
    names = tuple(n.strip() for n in text.split(","))
    if not all(names) or len(set(names)) != len(names):
        raise argparse.ArgumentTypeError(f"expected comma-separated names, each once, got {text!r}")
    return names
