"""Output paths: check that a file can be written before any work is done on it, and replace a
file atomically; where a results file's journal lives."""

from __future__ import annotations

import os
import stat
from collections.abc import Callable
from pathlib import Path

from .errors import InputError, did_you_mean


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


def read_input_text(path: str | Path, limit: int, what: str) -> str:
    """The text of an input file, read only if it is a regular file of at most ``limit`` bytes.

    A device (``/dev/urandom``), a pipe or a huge file would otherwise hang the command or
    exhaust the memory. A UTF-8 byte-order mark at the start (as Excel writes) is dropped.

    Raises
    ------
    InputError
        Missing, a folder, not a regular file, larger than ``limit``, or not UTF-8 text.
    """
    path = Path(path)
    try:
        info = path.stat()
    except FileNotFoundError:
        raise InputError(path, [("", f"file not found{did_you_mean(path)}")]) from None
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
        return path.read_text(encoding="utf-8-sig")  # a byte-order mark (Excel's) is dropped
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(path, [("", f"cannot read the file as text ({exc})")]) from None


MARK = "rockbridge"
"""How a file rockbridge writes names its maker: a figure's PNG ``Software`` or PDF and SVG
``Creator``, a page's ``<meta name="generator">`` (`maker_metadata`, `written_by_rockbridge`)."""

MARKED_HEAD = 8192
"""Bytes at the start of a PNG, SVG or HTML file that hold its maker's mark [bytes]."""

MARKED_TAIL = 262144
"""Bytes at the end of a PDF file that hold its information dictionary [bytes]."""


def maker_metadata(suffix: str) -> dict[str, str]:
    """The metadata that marks a figure of that format (``.png``, ``.pdf``, ``.svg``) as
    rockbridge's, for Matplotlib's ``savefig``."""
    from . import __version__

    return {("Software" if suffix.lower() == ".png" else "Creator"): f"{MARK} {__version__}"}


def written_by_rockbridge(path: str | Path) -> bool:
    """Whether a file is a figure (PNG, PDF, SVG), a page (HTML) or an OpenQuake fragility model
    (NRML) that rockbridge wrote: its maker's mark (`MARK`) where its format keeps it."""
    mark = MARK.encode()
    with open(path, "rb") as file:
        head = file.read(MARKED_HEAD)
        if head.startswith(b"%PDF-"):
            file.seek(0, os.SEEK_END)
            file.seek(max(0, file.tell() - MARKED_TAIL))
            return b"/Creator (" + mark in file.read()
    return any(
        signature in head and marked in head
        for signature, marked in (
            (b"\x89PNG", b"tEXtSoftware\x00" + mark),
            (b"<svg", b"<dc:title>" + mark),
            (b"<html", b'<meta name="generator" content="' + mark),
            (b"<nrml", b"<description>" + mark),  # an OpenQuake fragility model
        )
    )


def checked_output(
    path: str | Path,
    *inputs: str | Path,
    ours: Callable[[Path], bool] = written_by_rockbridge,
    what: str = "a file rockbridge wrote",
) -> Path:
    """The output path, once it is checked that writing it destroys nothing: its folder accepts a
    new file, and nothing is there yet, or a regular file that rockbridge wrote (``ours``) and
    that the command does not read (``inputs``). Whatever else is there is left alone, whatever
    the command's options.

    Parameters
    ----------
    ours
        Whether an existing regular file is one rockbridge wrote, and may be replaced.
    what
        What ``ours`` recognises, for the message (``a results file``).

    Raises
    ------
    InputError
        A folder, a device, a pipe or a socket; one of ``inputs``; a file that ``ours`` does not
        recognise; or a folder that cannot be written.
    """
    path = Path(path)
    try:
        info = path.stat()
    except OSError:  # nothing there (or a folder on the way is a file): the folder decides
        return writable(path)
    if stat.S_ISDIR(info.st_mode):
        raise InputError(path, [("", "is a folder: give a file name")])
    if not stat.S_ISREG(info.st_mode):
        reason = "is not a regular file (a device, a pipe?): not written; choose another output"
        raise InputError(path, [("", reason)])
    for source in inputs:
        if Path(source).exists() and path.samefile(source):
            raise InputError(path, [("", "is the file being read: choose another output")])
    try:
        recognised = ours(path)
    except OSError as exc:
        raise InputError(path, [("", f"cannot be checked ({exc.strerror})")]) from None
    if not recognised:
        reason = f"exists and is not {what}: not replaced; choose another output"
        raise InputError(path, [("", reason)])
    return writable(path)


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


def replace_folder(staging: Path, target: Path, keep: Callable[[Path], bool]) -> None:
    """Swap a folder written in full beside ``target`` in for it, so that a reader finds the old
    folder whole, or the new one, or none: never a mix of the two.

    Parameters
    ----------
    staging
        The new folder, on the same file system as ``target`` (its sibling).
    target
        The folder to replace; it may not exist yet.
    keep
        Whether an existing, non-empty ``target`` may be replaced (e.g. it is a record set);
        otherwise the staging folder is removed and nothing changes.

    Raises
    ------
    InputError
        ``target`` exists and may not be replaced.
    """
    import shutil

    if target.exists() and not (target.is_dir() and (not any(target.iterdir()) or keep(target))):
        shutil.rmtree(staging)
        raise InputError(target, [("", "holds files this would replace: give a new or empty "
                                   "folder")])  # fmt: skip
    old = target.with_name(f".{target.name}.old-{os.getpid()}")
    if target.exists():
        os.replace(target, old)  # a crash from here to the next line leaves no set, and the old
    os.replace(staging, target)  # one aside: a study then refuses a missing manifest
    if old.exists():
        shutil.rmtree(old)


def journal_path(output: str | Path) -> Path:
    """Where the journal of a results file lives (`study.journal`: its path made absolute,
    without ``..``: SQLite cannot open a path whose ``..`` climbs above ``/``)."""
    output = Path(os.path.abspath(output))
    return output.with_name(f"{output.name}.journal.db")
