"""A module imported on first use, so that ``thermolimb --help`` and ``import thermolimb.model`` stay fast."""

from __future__ import annotations

import importlib


class LazyModule:
    """Stands for a module; the first attribute looked up imports it (pandas takes about 0.4 s to import)."""

    def __init__(self, name: str):
        self._name = name
        self._module = None

    def __getattr__(self, attribute: str):
        if self._module is None:
            self._module = importlib.import_module(self._name)
        return getattr(self._module, attribute)


pandas = LazyModule("pandas")
