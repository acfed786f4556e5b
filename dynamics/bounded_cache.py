"""A small cache of values made once per key, the oldest dropped past a
few: what a study's variants share (a sampled input's spline, a mount
graph's pattern) without holding every scene ever seen."""

from __future__ import annotations

from typing import Callable, Hashable

__all__ = ["BoundedCache"]


class BoundedCache:
    """Values by key, at most ``keep`` of them (the least recently used
    dropped first: a value every call asks for stays while others come and
    go, as a study's base entries stay while each point's own pass).

    Safe where threads race: two may make the same value once each, and
    whichever is stored last is kept; nothing raises.
    """

    def __init__(self, keep: int):
        self.keep = int(keep)
        self._values: dict = {}

    def get(self, key: Hashable, make: Callable[[], object]):
        """The value stored for ``key``, made by ``make()`` and stored if absent."""
        found = self._values.get(key)
        if found is not None:                       # used: now the most recent
            self._values.pop(key, None)
            self._values[key] = found
        else:
            found = make()
            while len(self._values) >= self.keep:
                try:
                    self._values.pop(next(iter(self._values)), None)
                except (RuntimeError, StopIteration):      # another thread changed it
                    break
            self._values[key] = found
        return found

    def __len__(self) -> int:
        return len(self._values)
