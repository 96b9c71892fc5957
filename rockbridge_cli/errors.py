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
        self.reach: tuple[str, ...] = ()
        """Folders that a config's refused paths lead to (`config.loading.ConfigFolder`):
        naming them in ``ROCKBRIDGE_PATHS`` lets the input through."""
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
