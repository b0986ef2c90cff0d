"""The suite's user errors: each says, in one sentence, what is wrong and what is expected.

The command line prints these without a traceback and exits with status 2;
anything else is an internal error and keeps its traceback.  A message
carries what the user gave (a column, an actuator, a file name) whatever its
length, so :func:`bounded` cuts any over-long word of it before it is printed.
"""

import re

WORD_LIMIT = 200  # characters of one word (a name, a path) a message shows: its start and its end


def bounded(text: str, limit: int = WORD_LIMIT) -> str:
    """``text`` with every word longer than ``limit`` shown as its start and end around an ellipsis."""
    half = limit // 2
    return re.sub(r"\S{%d,}" % (limit + 1),
                  lambda m: f"{m.group(0)[:half]}…{m.group(0)[-half:]} ({len(m.group(0))} characters)", text)


class ThermolimbError(ValueError):
    """Base class of every error a user can act on."""


class UsageError(ThermolimbError):
    """An option or argument out of its range, named with what is expected."""


def check_range(owner: str, name: str, value, low: float, high: float, unit: str = "") -> float:
    """``value`` as a float within ``[low, high]``, or a ValueError naming ``owner.name``, the value and the range."""
    import math

    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if isinstance(value, bool) or not (math.isfinite(number) and low <= number <= high):
        unit = f" {unit}" if unit else ""
        raise ValueError(f"{owner}: {name} = {value!r} is outside the range expected, {low:g} to {high:g}{unit}")
    return number
