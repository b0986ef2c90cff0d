"""Progress bars for anything that takes more than a few seconds, on a terminal only: ``--quiet`` turns them
off, and standard error piped into a file or another program gets none (a bar's carriage returns would fill a
log)."""

from __future__ import annotations

import sys

from tqdm.auto import tqdm


def on_terminal() -> bool:
    """Whether standard error is a terminal (a bar would be seen, not stored)."""
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):  # replaced by an object without isatty, or closed
        return False


def progress(iterable=None, desc: str = "", disable: bool = False, **kwargs):
    """A tqdm bar on standard error when it is a terminal; otherwise (or with ``disable=True``) a plain
    iterator."""
    return tqdm(iterable, desc=desc, disable=disable or not on_terminal(), file=sys.stderr,
                dynamic_ncols=True, mininterval=0.5, leave=False, **kwargs)
