"""Where the results live on disk: the journal of finished analyses and the results file.

The results file is never written in place. Each finished analysis is first journalled: written
to a small HDF5 file of its own, ``<output>.journal/<bridge>/<record>.h5`` (a temporary file,
flushed to disk, then renamed over the entry with `os.replace`, which is atomic). The results file
is assembled from the earlier results file and the journal into a temporary file in the same
folder, flushed, and renamed over the output; only then is the journal removed. A kill at any
moment (even SIGKILL) therefore leaves the previous results file intact and loses only the
analyses in flight. Journal entries and results files carry the hash of the resolved study
(`Study.config_hash`), so results of another study are never mixed in.
"""

from __future__ import annotations

import os
from datetime import datetime, timezone
from pathlib import Path
from typing import NamedTuple

import h5py

from . import results
from .config.study import Study
from .errors import InputError
from .paths import writable
from .results import AnalysisResult

Pair = tuple[str, str]
"""(bridge id, record id) of an analysis."""


class Stored(NamedTuple):
    """An analysis already in a file: the file (results or journal entry) and its status."""

    path: Path
    status: str


class Journal:
    """The analyses finished since the results file was last assembled, one file each.

    Parameters
    ----------
    output
        The results file; the journal is the folder ``<output>.journal`` next to it.
    """

    def __init__(self, output: Path):
        self.folder = output.with_name(f"{output.name}.journal")

    def write(self, result: AnalysisResult, config_hash: str) -> None:
        """Journal one result atomically (safe from several processes: one file each)."""
        entry = self.folder / result.bridge / f"{result.record}.h5"
        entry.parent.mkdir(parents=True, exist_ok=True)
        temporary = entry.with_name(f"{entry.name}.tmp")
        with h5py.File(temporary, "w") as file:
            file.attrs["config_hash"] = config_hash
            group = file.create_group("analyses").create_group(result.bridge)
            results.write_analysis(group, result)
        replace_atomically(temporary, entry)

    def entries(self, config_hash: str) -> dict[Pair, Stored]:
        """The journalled analyses, by (bridge, record).

        Raises
        ------
        InputError
            The journal belongs to another study.
        """
        found = {}
        for entry in sorted(self.folder.glob("*/*.h5")):
            try:
                file = h5py.File(entry, "r")
            except OSError:  # damaged outside our control (disk): run the analysis again
                entry.unlink()
                continue
            with file:
                if file.attrs["config_hash"] != config_hash:
                    raise InputError(
                        self.folder,
                        [("", "holds analyses of a different study or different inputs (an "
                          "interrupted run); rerun with --overwrite to discard them")],
                    )  # fmt: skip
                found.update(_stored(entry, file))
        return found

    def remove_temporary(self) -> None:
        """Remove entries a killed run left half-written (never renamed into place)."""
        for stale in self.folder.glob("*/*.tmp"):
            stale.unlink()

    def clear(self) -> None:
        """Remove the journal."""
        if not self.folder.exists():
            return
        for entry in self.folder.glob("*/*"):
            entry.unlink()
        for folder in self.folder.iterdir():
            folder.rmdir()
        self.folder.rmdir()


def prepare(output: Path, journal: Journal) -> None:
    """Check that the output can be written before any work; remove stale temporary files."""
    writable(output)
    for stale in output.parent.glob(f".{output.name}.*.tmp"):
        stale.unlink()
    journal.remove_temporary()


def stored_in_output(output: Path, study: Study) -> dict[Pair, Stored]:
    """The analyses an earlier results file of the same study holds.

    Raises
    ------
    InputError
        The file cannot be read or belongs to another study.
    """
    if not output.exists():
        return {}
    hint = "rerun with --overwrite to replace it, or choose another output"
    try:
        with results.open_results(output) as file:
            same = file.attrs.get("config_hash") == study.config_hash
            stored = _stored(output, file) if same else {}
    except InputError as exc:  # unreadable or not a results file
        raise InputError(output, [("", f"{exc.problems[0][1]}; {hint}")]) from None
    if not same:
        reason = f"holds results of a different study or different inputs; {hint}"
        raise InputError(output, [("", reason)])
    return stored


def _stored(path: Path, file: h5py.File) -> dict[Pair, Stored]:
    return {
        pair: Stored(path, node.attrs["status"])
        for pair, node in results.stored_analyses(file).items()
    }


def assemble(output: Path, study: Study, sources: list[Path | None], created: str) -> None:
    """Write the results file from its sources into a temporary file, then rename it over."""
    temporary = output.with_name(f".{output.name}.{os.getpid()}.tmp")
    try:
        with h5py.File(temporary, "w") as file:
            results.write_results(file, study, sources, created, timestamp())
        replace_atomically(temporary, output)
    finally:
        temporary.unlink(missing_ok=True)


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


def timestamp() -> str:
    """The current time in UTC, ISO 8601 to the second."""
    return datetime.now(timezone.utc).isoformat(timespec="seconds")
