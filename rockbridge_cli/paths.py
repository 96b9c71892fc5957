"""Output paths: check that a file can be written before any work is done on it, and replace a
file atomically."""

from __future__ import annotations

import os
from pathlib import Path

from .errors import InputError


def writable(path: str | Path, folder: bool = False) -> Path:
    """The path, once its folder exists and accepts a new file.

    Parameters
    ----------
    path
        The file to be written (or, with ``folder``, the folder to write files into).
    folder
        ``path`` is a folder.

    Raises
    ------
    InputError
        The folder cannot be created or written to, or ``path`` is a folder where a file is
        expected (or the other way round).
    """
    path = Path(path)
    where = path if folder else path.parent
    if folder != path.is_dir() and path.exists():
        kind = "a file: give a folder" if folder else "a folder: give a file name"
        raise InputError(path, [("", f"is {kind}")])
    try:
        where.mkdir(parents=True, exist_ok=True)
        probe = where / f".{path.name}.probe"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as exc:
        culprit = f" ({exc.filename})" if exc.filename else ""
        raise InputError(path, [("", f"cannot write here: {exc.strerror}{culprit}")]) from None
    return path


def replace_atomically(temporary: Path, target: Path) -> None:
    """Flush ``temporary`` to disk and rename it over ``target`` (atomic on POSIX and Windows)."""
    descriptor = os.open(temporary, os.O_RDONLY)
    try:
        os.fsync(descriptor)
    finally:
        os.close(descriptor)
    os.replace(temporary, target)
    if hasattr(os, "O_DIRECTORY"):  # make the rename itself durable
        folder = os.open(target.parent, os.O_RDONLY | os.O_DIRECTORY)
        try:
            os.fsync(folder)
        finally:
            os.close(folder)
