"""Output paths: check that a file can be written before any work is done on it, and replace a
file atomically."""

from __future__ import annotations

import os
import stat
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


HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"
"""The first bytes of every HDF5 file."""


def read_input_text(path: str | Path, limit: int, what: str) -> str:
    """The text of an input file, read only if it is a regular file of at most ``limit`` bytes.

    A device (``/dev/urandom``), a pipe or a huge file would otherwise hang the command or
    exhaust the memory.

    Raises
    ------
    InputError
        Missing, a folder, not a regular file, larger than ``limit``, or not UTF-8 text.
    """
    path = Path(path)
    try:
        info = path.stat()
    except FileNotFoundError:
        raise InputError(path, [("", "file not found")]) from None
    except OSError as exc:
        raise InputError(path, [("", f"cannot read the file ({exc.strerror})")]) from None
    if stat.S_ISDIR(info.st_mode):
        raise InputError(path, [("", f"is a folder, not {what}")])
    if not stat.S_ISREG(info.st_mode):
        raise InputError(path, [("", f"is not a regular file (a device or a pipe?), not {what}")])
    if info.st_size > limit:
        size = f"{info.st_size / 2**20:.0f} MiB"
        raise InputError(path, [("", f"is {size}, more than {what} can be ({limit // 2**20} MiB)")])
    try:
        return path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(path, [("", f"cannot read the file as text ({exc})")]) from None


def not_an_input(path: str | Path, *inputs: str | Path) -> Path:
    """The output path, once it is checked not to be one of the inputs a command is reading.

    Raises
    ------
    InputError
        ``path`` is (a link to) one of ``inputs``, or an HDF5 file (results of another study):
        writing it would destroy what is being read, or a study's results.
    """
    path = Path(path)
    for source in inputs:
        if path.exists() and Path(source).exists() and path.samefile(source):
            raise InputError(path, [("", "is the file being read: choose another output")])
    if path.is_file():
        with open(path, "rb") as file:
            if file.read(len(HDF5_SIGNATURE)) == HDF5_SIGNATURE:
                reason = "is an HDF5 file (results?): not replaced; choose another output"
                raise InputError(path, [("", reason)])
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
