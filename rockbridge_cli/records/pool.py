"""The candidates of a record selection (`selection`): the records of FEMA P695 sets and of
folders of record files, each with the earthquake and the recording it comes from (which the caps
of a selection count) and its provenance."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError
from .fema import read_fema_set
from .files import PROVENANCE, Record, read_record

_EVENT_NUMBER = re.compile(r"-\d+$")
"""NGA's number of an earthquake's event (``Northridge-01``, ``Imperial Valley-06``), which the
near-field sets give and the far-field set does not: the same earthquake, one name."""


@dataclass(frozen=True)
class PoolFolder:
    """A folder of record files, as a selection's config gives it.

    Attributes
    ----------
    path
        the folder.
    pattern
        glob of the files taken.
    units, time_step
        of files that do not state them (`files.read_record`) [-], [s].
    earthquake
        the earthquake all its files come from; None: each file its own.
    """

    path: Path
    pattern: str = "*"
    units: str | None = None
    time_step: float | None = None
    earthquake: str | None = None


@dataclass(frozen=True)
class FemaSource:
    """A FEMA P695 set as a selection's config names it (`fema.read_fema_set`'s arguments)."""

    name: str
    components: tuple[str, ...] = ("a", "b")
    normalize: bool = False
    records: tuple[int, ...] | None = None


@dataclass(frozen=True)
class Candidate:
    """A record of the pool.

    Attributes
    ----------
    record
        the record as read, SI; its metadata holds the provenance (`files.PROVENANCE`).
    earthquake
        the earthquake it comes from, its name without NGA's event number and its year
        (``Northridge 1994`` for the far-field set's Northridge and the near-field sets'
        Northridge-01).
    recording
        the recording (station) whose component it is: both horizontal components of one
        recording share it (``NGA 953``, or the file's stem).
    lowest_usable_frequency
        below this frequency the record's processing leaves no signal; NaN where unknown [Hz].
    """

    record: Record
    earthquake: str
    recording: str
    lowest_usable_frequency: float = float("nan")


def read_pool(fema: tuple[FemaSource, ...], folders: tuple[PoolFolder, ...]) -> list[Candidate]:
    """The candidates, in order: the FEMA P695 sets' (set order, record, component), then each
    folder's files sorted by name.

    Raises
    ------
    InputError
        A set cannot be read (the package is not installed), a folder holds no file matching its
        pattern, a file cannot be read, or two candidates have the same name.
    """
    found: list[Candidate] = []
    for source in fema:
        for record in read_fema_set(source.name, source.components, source.normalize,
                                    source.records):  # fmt: skip
            meta = record.metadata
            kept = {key: meta[key] for key in PROVENANCE if key in meta}
            found.append(Candidate(
                Record(record.name, record.time_step, record.acceleration, record.source, kept),
                f"{_EVENT_NUMBER.sub('', meta['earthquake'])} {meta['year']}",
                f"NGA {meta['nga_record']}",
                float(meta["lowest_usable_frequency_hz"]),
            ))  # fmt: skip
    for folder in folders:
        files = sorted(p for p in folder.path.glob(folder.pattern) if p.is_file())
        if not files:
            raise InputError(folder.path, [("", f"no file matches {folder.pattern!r}")])
        for path in files:
            record = read_record(path, units=folder.units, time_step=folder.time_step)
            name = re.sub(r"[^A-Za-z0-9_.+-]", "_", path.stem)
            meta = {"seed_file": path.name, "file_units": record.metadata.get("file_units")}
            found.append(Candidate(
                Record(name, record.time_step, record.acceleration, str(path), meta),
                folder.earthquake or name, name,
            ))  # fmt: skip
    names = [c.record.name for c in found]
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        raise InputError("pool", [("", f"two candidates are named {twice[0]}: rename a file")])
    return found
