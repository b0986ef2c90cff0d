"""The suite's user errors, every one of them here: each says, in one sentence, what is wrong and what is
expected.

Each package re-exports its own (``thermolimb.logs.LogError``,
``thermolimb.model.saved.ModelFileError``, ...).

The command line prints these without a traceback and exits with status 2; anything else is an internal error
and keeps its traceback. A message carries what the user gave (a column, an actuator, a file name) whatever
its length, so :func:`bounded` cuts any over-long word of it before it is printed.
"""

import errno
import re

WORD_LIMIT = 200  # characters of one word (a name, a path) a message shows: its start and its end


def bounded(text: str, limit: int = WORD_LIMIT) -> str:
    """``text`` with every word longer than ``limit`` shown as its start and end around an ellipsis."""
    half = limit // 2

    def shortened(m):
        return f"{m.group(0)[:half]}…{m.group(0)[-half:]} ({len(m.group(0))} characters)"

    return re.sub(r"\S{%d,}" % (limit + 1), shortened, text)


# the errors of a write the user can act on (free space, a quota, a read-only disk), in words
WRITE_FAULTS = {errno.ENOSPC: "the disk is full", errno.EDQUOT: "the disk quota is exceeded",
                errno.EROFS: "the file system is read-only", errno.ENAMETOOLONG: "the file name is too long",
                errno.EFBIG: "the file is too large for the file system"}


class OutputLost(OSError):
    """An output of a long run (the monitor's recording) that can no longer be written: said once in
    ``words``, its file left as the sentence says; the run goes on with its other outputs."""

    def __init__(self, errno_: int, path, words: str):
        super().__init__(errno_, WRITE_FAULTS.get(errno_, "write failed"), str(path))
        self.words = words


class ThermolimbError(ValueError):
    """Base class of every error a user can act on."""


class UsageError(ThermolimbError):
    """An option or argument out of its range, named with what is expected."""


class LogError(ThermolimbError):
    """A log cannot be used; the message says which file, which column and what is expected."""


class ModelSpecError(ThermolimbError):
    """A model description names an unknown term or cannot be run on the data."""


class ModelFileError(ThermolimbError):
    """A model file that cannot be read: one sentence naming the file and what is wrong."""


class TermError(ThermolimbError):
    """A user's term broke its contract (the message names the term and the method)."""

    def __init__(self, message: str, term: str):
        super().__init__(message)
        self.term = term

    def __reduce__(self):
        return type(self), (str(self), self.term)


class IdentifiabilityError(ThermolimbError):
    """The data cannot determine a parameter (e.g. effort held constant); ``parameter`` names it when known,
    ``partners`` the parameters it cannot be told from."""

    def __init__(self, message: str, parameter: str | None = None, partners: tuple[str, ...] = ()):
        super().__init__(message)
        self.parameter = parameter
        self.partners = tuple(partners)

    def __reduce__(self):
        return type(self), (str(self), self.parameter, self.partners)


def check_range(owner: str, name: str, value, low: float, high: float, unit: str = "") -> float:
    """``value`` as a float within ``[low, high]``, or a ValueError naming ``owner.name``, the value and the
    range."""
    import math

    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if isinstance(value, bool) or not (math.isfinite(number) and low <= number <= high):
        unit = f" {unit}" if unit else ""
        raise ValueError(f"{owner}: {name} = {value!r} is outside the "
                         f"range expected, {low:g} to {high:g}{unit}")
    return number
