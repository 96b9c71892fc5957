"""The journal: the analyses finished since the results file was last written, crash-safe.

An SQLite database (Python's standard library) next to the results file,
``<output>.journal.db``, in write-ahead-log mode. Whoever runs a batch of analyses commits it —
each local worker process for itself, or the parent for a Dask cluster's — and SQLite takes the
writers one at a time; a committed transaction survives any death of the process, SIGKILL
included (with ``synchronous=NORMAL`` only a power cut can undo the last ones, and it never
leaves the database damaged). The journal is tied to one study by its config hash, so results of
another study are never mixed in; it is removed once the results file holds its analyses.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from ..assessment.limit_states import Verdict
from ..errors import InputError
from ..paths import journal_path
from ..results.packing import DEVICE_RECORD, Packed, device_states
from .work import Finished

PAGE_BYTES = 65536
"""SQLite's page size for the journal, its largest: an analysis (≈ 5 kB without histories) fits in
one page instead of spilling over two, which makes reading the journal back twice as fast."""

_CHECKPOINT_PAGES = 1024
"""Pages the write-ahead log may hold before SQLite copies it into the database, the only step
that waits for the disk (fsync): every 64 MiB instead of SQLite's default 4 MiB."""

SCHEMA_VERSION = 7
"""The layout of the journal's tables (SQLite's ``user_version``): 2 added the verdicts, 3 packs
event kinds as codes, 4 the numeric values as one vector, 5 the packed parts in columns of their
own (`results.packing.Packed`), 6 a checksum after each history (`results.packing.Chunk`), 7 the
rows of the bridge's devices (`results.packing.Packed.devices`)."""

_VERDICT_COLUMNS = 3
"""The parts of a `Verdict` the journal stores in columns of their own (status, failure mode,
backfill ratio); its tendons' states come back from the devices' rows (`verdicts`)."""

BUSY_TIMEOUT_S = 60.0
"""How long a writer waits for another's transaction to end [s] (each takes about a
millisecond)."""

_SCHEMA = """
CREATE TABLE IF NOT EXISTS study (config_hash TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS analyses (
    cell INTEGER PRIMARY KEY,   -- position in the results (`grid.Cell.index`)
    bridge TEXT NOT NULL,
    record TEXT NOT NULL,
    status TEXT NOT NULL,       -- ok, solver_error or error
    failure_mode TEXT NOT NULL, -- with dcr_backfill, what decides the limit states (an IDA's)
    dcr_backfill REAL,
    texts TEXT NOT NULL,        -- `results.packing.Packed`
    numbers BLOB NOT NULL,
    events BLOB NOT NULL,
    histories BLOB NOT NULL,
    devices BLOB NOT NULL       -- empty without devices; with them, the tendons' limit states
);
"""


class Journal:
    """The journal of a results file, opened for one study.

    Parameters
    ----------
    output
        The results file; the journal is ``<output>.journal.db`` next to it.
    config_hash
        The study's hash.

    Raises
    ------
    InputError
        The journal belongs to another study, is not a journal, or is damaged: empty, cut short,
        or without its tables (its write-ahead log lost). A damaged journal is left as it is.
    """

    def __init__(self, output: Path, config_hash: str):
        self.output = output
        self.config_hash = config_hash
        self.path = journal_path(output)
        self._connect()

    def _connect(self) -> None:
        hint = "rerun with --overwrite to discard it"
        damaged = "is damaged ({}): the analyses it holds cannot be read; " + hint
        existed = self.path.exists()
        if existed and self.path.stat().st_size == 0:  # a journal starts with its header page
            raise InputError(self.path, [("", damaged.format("it is empty"))])
        try:
            self.connection = sqlite3.connect(
                self.path, timeout=BUSY_TIMEOUT_S, isolation_level=None
            )
            self.connection.execute(f"PRAGMA page_size={PAGE_BYTES}")  # a new journal's
            self.connection.execute("PRAGMA journal_mode=WAL")
            self.connection.execute("PRAGMA synchronous=NORMAL")
            self.connection.execute(f"PRAGMA wal_autocheckpoint={_CHECKPOINT_PAGES}")
            tables = self.connection.execute("SELECT name FROM sqlite_master").fetchall()
            if existed and ("study",) not in tables:  # its tables are in its first commit
                self.connection.close()
                reason = f"it has no tables: its write-ahead log ({self.path.name}-wal) is lost?"
                raise InputError(self.path, [("", damaged.format(reason))])
            self.connection.executescript(_SCHEMA)
            stored = self.connection.execute("SELECT config_hash FROM study").fetchone()
            (version,) = self.connection.execute("PRAGMA user_version").fetchone()
        except sqlite3.OperationalError as exc:  # cannot open, read or lock it: not damage
            raise InputError(self.path, [("", f"cannot open the journal ({exc})")]) from None
        except sqlite3.DatabaseError as exc:  # malformed, or not a database
            raise InputError(self.path, [("", damaged.format(exc))]) from None
        if stored is None:
            self.connection.execute(f"PRAGMA user_version={SCHEMA_VERSION}")
            self.connection.execute("INSERT INTO study VALUES (?)", (self.config_hash,))
        elif version != SCHEMA_VERSION:
            self.connection.close()
            reason = "was written by another version of rockbridge (an interrupted run)"
            raise InputError(self.path, [("", f"{reason}; {hint}")])
        elif stored[0] != self.config_hash:
            self.connection.close()
            reason = "holds analyses of a different study or different inputs (an interrupted run)"
            raise InputError(self.path, [("", f"{reason}; {hint}")])

    def add(self, analyzed: Iterable[tuple[Finished, Packed]]) -> None:
        """Commit finished analyses, each with its packed result, in one transaction (an analysis
        journalled again replaces the earlier entry).

        Raises
        ------
        OSError
            The journal cannot be written (a full disk, a removed folder): the message names it.
        """
        try:
            with self.connection:
                self.connection.execute("BEGIN")
                self.connection.executemany(
                    "INSERT OR REPLACE INTO analyses VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                    ((finished.cell.index, packed.bridge, packed.record,
                      *finished.verdict[:_VERDICT_COLUMNS], packed.texts, packed.numbers,
                      packed.events, packed.histories, packed.devices)
                     for finished, packed in analyzed),
                )  # fmt: skip
        except sqlite3.Error as exc:
            raise OSError(f"{self.path}: cannot write the journal ({exc})") from None

    def verdicts(self) -> dict[tuple[str, str], Verdict]:
        """The verdict of each journalled analysis, by (bridge, record)."""
        rows = self.connection.execute(
            "SELECT bridge, record, status, failure_mode, dcr_backfill, devices FROM analyses"
        )
        return {
            (bridge, record): Verdict(
                status, mode, float("nan") if ratio is None else ratio,
                *device_states(np.frombuffer(devices, DEVICE_RECORD)).values(),
            )
            for bridge, record, status, mode, ratio, devices in rows
        }  # fmt: skip

    def __len__(self) -> int:
        """How many analyses the journal holds."""
        return self.connection.execute("SELECT count(*) FROM analyses").fetchone()[0]

    def packed(self) -> Iterator[tuple[int, Packed]]:
        """The journalled analyses in the order of the results: (cell, packed result)."""
        rows = self.connection.execute(
            "SELECT cell, bridge, record, texts, numbers, events, histories, devices FROM "
            "analyses ORDER BY cell"
        )
        return ((cell, Packed(*parts)) for cell, *parts in rows)

    @contextmanager
    def released(self) -> Iterator[None]:
        """Close the connection for a while, then open it again: no SQLite connection may be
        open across a fork (the worker processes open their own)."""
        self.close()
        try:
            yield
        finally:
            self._connect()

    def close(self) -> None:
        """Close the database (what is committed stays)."""
        self.connection.close()

    def remove(self) -> None:
        """Delete the journal, then close it: SQLite does not copy the write-ahead log into a
        database that is gone, the last step of closing one (a tenth of a second per 10 000
        analyses)."""
        _delete(self.path)
        self.close()


def remove_journal(output: Path) -> None:
    """Delete the journal of a results file."""
    _delete(journal_path(output))


def _delete(database: Path) -> None:
    """Delete an SQLite database with its write-ahead log and shared-memory index."""
    for path in (database, Path(f"{database}-wal"), Path(f"{database}-shm")):
        path.unlink(missing_ok=True)
