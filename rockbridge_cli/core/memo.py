"""A cache bounded by the bytes it holds, not by its number of entries: what a process keeps per
bridge (its tabulated kinematics, ≈ 2.3 MB) must stay within a budget whether a study has three
bridges or a sweep of ten thousand."""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Generic, TypeVar

Key = TypeVar("Key", bound=Hashable)
Value = TypeVar("Value")


class BoundedCache(Generic[Key, Value]):
    """The values of ``build``, the least recently used dropped once they pass ``max_bytes``.

    Parameters
    ----------
    build
        Computes the value of a key.
    max_bytes
        The most the values may hold together [bytes]; the value just built is always kept,
        even alone beyond it.
    size
        The bytes one value holds.
    """

    def __init__(
        self, build: Callable[[Key], Value], max_bytes: int, size: Callable[[Value], int]
    ) -> None:
        self.build, self.max_bytes, self.size = build, max_bytes, size
        self._values: OrderedDict[Key, tuple[Value, int]] = OrderedDict()
        self.bytes = 0

    def __call__(self, key: Key) -> Value:
        """The value of ``key``, built if it is not held."""
        if key in self._values:
            self._values.move_to_end(key)
            return self._values[key][0]
        value = self.build(key)
        nbytes = self.size(value)
        self._values[key] = (value, nbytes)
        self.bytes += nbytes
        while self.bytes > self.max_bytes and len(self._values) > 1:
            _, (_, dropped) = self._values.popitem(last=False)
            self.bytes -= dropped
        return value

    def __len__(self) -> int:
        return len(self._values)

    def clear(self) -> None:
        """Drop every value."""
        self._values.clear()
        self.bytes = 0
