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
            return f"{self.source}: {where + ': ' if where else ''}{reason}{_entry(where)}"
        lines = [f"{self.source}: {len(self.problems)} problems"]
        lines += [f"  {where + ': ' if where else ''}{reason}{_entry(where)}"
                  for where, reason in self.problems]  # fmt: skip
        return "\n".join(lines)


def _entry(where: str) -> str:
    """Which entry of a list a dotted field path names, counted as a reader counts: the paths
    count from 0 (as a sweep's fields do), so ``records.files.1`` is `` (the 2nd entry of
    records.files)``; "" for a path without a list."""
    parts = where.split(".")
    last = max((k for k, part in enumerate(parts) if part.isdigit() and k > 0), default=None)
    if last is None:
        return ""
    n = int(parts[last]) + 1
    suffix = "th" if 10 <= n % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(n % 10, "th")
    return f" (the {n}{suffix} entry of {'.'.join(parts[:last])})"


def nearest(word: str, choices: Iterable[str], what: str, shown: int = 3) -> str:
    """What to say of a mistyped id: the few closest ``choices`` (difflib's ratio, case left
    aside: ``ar07`` is ``AR07`` alone), or, where none is close, the first few, with how many
    there are: ``nearest: AR01, AR10 (of 140 records)``. Never the whole list: a file may hold
    ten thousand ids."""
    unique = list(dict.fromkeys(choices))
    folded: dict[str, list[str]] = {}
    for choice in unique:
        folded.setdefault(choice.casefold(), []).append(choice)
    keys = [word.casefold()] if word.casefold() in folded else difflib.get_close_matches(
        word.casefold(), folded, n=shown, cutoff=0.6)  # fmt: skip
    close = [choice for key in keys for choice in folded[key]][:shown]
    if close:
        return f"nearest: {', '.join(close)} (of {len(unique)} {what})"
    if not unique:
        return f"there are no {what}"
    more = ", …" if len(unique) > shown else ""
    return f"the {len(unique)} {what}: {', '.join(unique[:shown])}{more}"


def did_you_mean(path: str | Path) -> str:
    """For a file not found: `` (did you mean paper-fig9.h5?)`` naming the names in its folder
    nearest to the one given, "" where none is close (a mistyped name is the likeliest cause)."""
    path = Path(path)
    try:
        names = [p.name for p in path.parent.iterdir()] if path.parent.is_dir() else []
    except OSError:
        names = []
    close = difflib.get_close_matches(path.name, names, n=3, cutoff=0.75)
    return f" (did you mean {' or '.join(close)}?)" if close else ""


def check_path_argument(value: object, function: str, what: str) -> None:
    """Raise a TypeError that names ``function`` and what it takes where ``value`` is not a path
    (a ``str`` or an ``os.PathLike``): ``load_study(42)`` said "expected str, bytes or
    os.PathLike object, not int", the internals of ``open``."""
    import os

    if not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"{function} takes the path of {what}, not {type(value).__name__}")
