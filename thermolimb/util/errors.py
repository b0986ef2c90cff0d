"""The suite's user errors: each says, in one sentence, what is wrong and what is expected.

The command line prints these without a traceback and exits with status 2;
anything else is an internal error and keeps its traceback.
"""


class ThermolimbError(ValueError):
    """Base class of every error a user can act on."""


class UsageError(ThermolimbError):
    """An option or argument out of its range, named with what is expected."""
