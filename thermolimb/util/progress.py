"""Progress bars for anything that takes more than a few seconds (``--quiet`` turns them off)."""

from __future__ import annotations

import sys

from tqdm.auto import tqdm


def progress(iterable=None, desc: str = "", disable: bool = False, **kwargs):
    """A tqdm bar on standard error; ``disable=True`` makes it a plain iterator."""
    return tqdm(iterable, desc=desc, disable=disable, file=sys.stderr, dynamic_ncols=True,
                mininterval=0.5, leave=False, **kwargs)
