"""Exceptions that carry a user-facing message (the command line maps them to exit codes)."""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from pathlib import Path


class InputError(Exception):
    """A file or value the user supplied cannot be used.

    Parameters
    ----------
    source
        The file (or other named input) at fault.
    problems
        One ``(where, reason)`` pair per problem; ``where`` is a dotted field path, a line number
        or an empty string when the whole input is at fault.
    """

    def __init__(self, source: str | Path, problems: list[tuple[str, str]]):
        self.source = str(source)
        self.problems = problems
        super().__init__(str(self))

    def __str__(self) -> str:
        if len(self.problems) == 1:
            where, reason = self.problems[0]
            return f"{self.source}: {where + ': ' if where else ''}{reason}"
        lines = [f"{self.source}: {len(self.problems)} problems"]
        lines += [f"  {where + ': ' if where else ''}{reason}" for where, reason in self.problems]
        return "\n".join(lines)


def nearest(word: str, choices: Iterable[str], what: str, shown: int = 3) -> str:
    """What to say of a mistyped id: the few closest ``choices`` (difflib's ratio), or, where
    none is close, the first few, with how many there are: ``nearest: AR01, AR10 (of 140
    records)``. Never the whole list: a file may hold ten thousand ids."""
    unique = list(dict.fromkeys(choices))
    close = difflib.get_close_matches(word, unique, n=shown, cutoff=0.6)
    if close:
        return f"nearest: {', '.join(close)} (of {len(unique)} {what})"
    if not unique:
        return f"there are no {what}"
    more = ", …" if len(unique) > shown else ""
    return f"the {len(unique)} {what}: {', '.join(unique[:shown])}{more}"


def check_path_argument(value: object, function: str, what: str) -> None:
    """Raise a TypeError that names ``function`` and what it takes where ``value`` is not a path
    (a ``str`` or an ``os.PathLike``): ``load_study(42)`` said "expected str, bytes or
    os.PathLike object, not int", the internals of ``open``."""
    import os

    if not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"{function} takes the path of {what}, not {type(value).__name__}")
