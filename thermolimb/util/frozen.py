"""A read-only, hashable mapping for the fields of frozen parameter sets."""

from __future__ import annotations

from collections.abc import Mapping


class FrozenMapping(Mapping):
    """A mapping that cannot be changed after construction, hashable when its values are."""

    __slots__ = ("_data",)

    def __init__(self, data=(), **kwargs):
        self._data = dict(data, **kwargs)

    def __getitem__(self, key):
        return self._data[key]

    def __iter__(self):
        return iter(self._data)

    def __len__(self) -> int:
        return len(self._data)

    def __hash__(self) -> int:
        return hash(frozenset(self._data.items()))

    def __repr__(self) -> str:
        return f"FrozenMapping({self._data!r})"
