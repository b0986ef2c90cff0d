"""Giving freed memory back to the operating system.

glibc's ``malloc`` keeps the pages of freed blocks below its mmap threshold (which
grows to 32 MB as large blocks are freed) for the next allocation; reading a
large log in pieces frees hundreds of such blocks, whose pages would stay in the
process's resident memory for the rest of the command.  ``malloc_trim`` returns
every free page.  Elsewhere (macOS, musl, Windows) this does nothing.
"""

from __future__ import annotations

import ctypes
import ctypes.util
from functools import cache


@cache
def _libc():
    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name) if name else None
        return libc if libc is not None and hasattr(libc, "malloc_trim") else None
    except OSError:
        return None


def release_freed() -> None:
    """Return the pages of freed memory to the operating system (glibc ``malloc_trim(0)``), where it can."""
    libc = _libc()
    if libc is not None:
        libc.malloc_trim(0)
