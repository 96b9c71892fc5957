"""Which kind of rockbridge file a path holds — a bridge, a study, a record-set config, a record, a
results file — so that a file given where another kind is expected (``run`` given a bridge,
``analyze RECORD BRIDGE``) is named for what it is, instead of failing as a malformed one.

The kind is read from the file's first 8 KiB: the HDF5 signature, a YAML file's top-level keys,
or a record's layout (a header stating its format, PEER's ``NPTS``, lines of numbers).
"""

from __future__ import annotations

import os
import re
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from .errors import InputError

KINDS = {
    "bridge": ("a bridge file", "rockbridge describe BRIDGE, analyze BRIDGE RECORD, a study's "
               "bridges"),
    "study": ("a study file", "rockbridge run STUDY"),
    "record set": ("a record-set config", "rockbridge generate-records CONFIG"),
    "record selection": ("a record-selection config", "rockbridge select-records CONFIG"),
    "record": ("a record file", "rockbridge analyze BRIDGE RECORD, a study's records"),
    "results": ("a results file", "rockbridge peaks, fragility, plot, report RESULTS"),
    "hazard curve": ("a hazard curve", "rockbridge risk RESULTS --hazard CURVE"),
}  # fmt: skip
"""Each kind: how a message names it, and what takes it."""

HEAD_BYTES = 8192
"""What is read of a file to tell its kind [bytes]."""

_KEY = re.compile(r"^([A-Za-z_]+)\s*:", re.MULTILINE)
_NUMBERS = re.compile(r"^\s*[-+0-9.eE]+(?:[\s,]+[-+0-9.eE]+)*\s*$")


def file_kind(path: str | Path) -> str | None:
    """The kind of file at ``path`` (a key of `KINDS`), or None where it cannot be told.

    Only a regular file is read: a pipe (a FIFO) or a device is never opened, since opening a
    FIFO waits for a writer that may never come (and reading a device may never end)."""
    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError:
        return None
    try:
        if not stat.S_ISREG(os.fstat(descriptor).st_mode):
            return None
        head = os.read(descriptor, HEAD_BYTES)
    except OSError:
        return None
    finally:
        os.close(descriptor)
    if head.startswith(b"\x89HDF\r\n\x1a\n"):
        return "results"
    text = head.decode("utf-8", errors="replace")
    keys = set(_KEY.findall(text))
    if "piers" in keys:
        return "bridge"
    if {"bridges", "records"} & keys and "piers" not in keys:
        return "study"
    if "pool" in keys:
        return "record selection"
    if {"target", "envelope", "seeds"} & keys:
        return "record set"
    lines = [line for line in text.splitlines() if line.strip()]
    if re.search(r"^#\s*format\s*:", text, re.MULTILINE) or "NPTS" in text.upper():
        return "record"
    data = [line for line in lines[:-1] if not line.lstrip().startswith("#")][:20]
    numbers = [line for line in data if _NUMBERS.match(line)]
    if len(numbers) >= 2 and len(numbers) >= len(data) - 2:  # a heading line or two
        return "record"
    return None


@contextmanager
def expecting(path: str | Path, kind: str) -> Iterator[None]:
    """Read ``path`` as a file of ``kind``: a refusal of the file itself becomes, where the file
    is of another kind, one message naming what it is and what takes it.

    Raises
    ------
    InputError
        As raised inside, or ``… is a study file, not a bridge file (a study file is for …)``.
    """
    try:
        yield
    except InputError as exc:
        found = file_kind(path) if exc.source == str(path) else None
        if found is None or found == kind:
            raise
        name, uses = KINDS[found]
        reason = f"this is {name}, not {KINDS[kind][0]} ({name} is for {uses})"
        raise InputError(path, [("", reason)]) from None
