"""The records of a study, resolved: read from files, a record set, the FEMA P695 sets or
analytic pulses (`resolve_records`), with their vertical components where the study asks for
them, each pair of horizontal components along the angles of an orientation section (`orient`),
and scaled to the levels of an intensity section (`scaled`; the vertical component by the
same factor). A record that cannot be read does not stop the study: its `StudyRecord` carries
the reason."""

from __future__ import annotations

import dataclasses
import functools
import hashlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..motions.intensity import scaled_id
from ..records.components import fema_pairs, oriented, with_second
from ..records.fema import read_fema_set
from ..records.files import MAX_RECORD_BYTES, Record, read_record
from ..records.set_files import check_set_file, read_manifest
from ..records.vertical import vertical_entry, with_vertical
from .intensity import Intensity, intensity_of
from .orientation import angle_id
from .records import Records


@dataclass(frozen=True)
class StudyRecord:
    """One resolved record: the `Record` (SI units), or why it could not be read.

    Attributes
    ----------
    id : record id in the results
    source : file as the study names it (relative to the study file)
    record : the record, None if it could not be read
    error : the reason, empty when ``record`` is there
    digest : SHA-256 of the record's samples (or of the file's bytes if unreadable)
    base : id of the record before scaling (the same id without an intensity section)
    level : the intensity level it is scaled to, in the study's measure; NaN without
    scale : the factor applied to the file's samples [-]
    as_read : a scaled record's record before scaling (``record`` is ``scale`` times it); None
        for a record as read
    """

    id: str
    source: str
    record: Record | None
    error: str
    digest: str
    base: str = ""
    level: float = float("nan")
    scale: float = 1.0
    as_read: Record | None = None


def scalable(item: StudyRecord, intensity: Intensity) -> StudyRecord:
    """The record, or, if its intensity is zero (no motion at all), the record that cannot run
    (`StudyRecord.error`): no factor scales it to a level."""
    if item.record is None or intensity_of(item.record, intensity) > 0.0:
        return item
    reason = f"{item.source}: its {intensity.measure} is 0: it cannot be scaled to a level"
    return dataclasses.replace(item, record=None, error=reason)


def scaled(records: list[StudyRecord], intensity: Intensity) -> list[StudyRecord]:
    """Every record at every level, record by record."""
    assert intensity.levels is not None
    scaled = []
    for item in records:
        native = intensity_of(item.record, intensity) if item.record is not None else 1.0
        for level in intensity.levels:
            scale = level / native
            record = None
            if item.record is not None:  # both components by the same factor
                up = item.record.vertical
                record = dataclasses.replace(
                    item.record, acceleration=scale * item.record.acceleration,
                    vertical=None if up is None else scale * up,
                )  # fmt: skip
            digest = hashlib.sha256(f"{item.digest} x{scale!r}".encode()).hexdigest()
            scaled.append(StudyRecord(
                scaled_id(item.id, level, intensity.measure), item.source, record, item.error,
                digest, base=item.id, level=level, scale=scale, as_read=item.record,
            ))  # fmt: skip
    return scaled


def resolve_records(records: Records, study: Path) -> list[StudyRecord]:
    """The study's records, read (a file that cannot be read is a `StudyRecord` with its error);
    with an orientation section, each pair along each of its angles (`orient`)."""
    read = _as_read(records, study)
    return read if records.orientation is None else orient(read, records.orientation.values())


def orient(pairs: list[StudyRecord], angles: list[float]) -> list[StudyRecord]:
    """Each pair along each angle, pair by pair: a record ``<pair>+<θ>deg`` of one component
    (`records.components.oriented`); an unreadable pair is unreadable at every angle."""
    return [
        dataclasses.replace(item, id=angle_id(item.id, angle)) if item.record is None
        else study_record(oriented(item.record, angle, item.id), item.source,
                          angle_id(item.id, angle))
        for item in pairs for angle in angles
    ]  # fmt: skip


def _as_read(records: Records, study: Path) -> list[StudyRecord]:
    """The study's records as read: pairs where the section has an orientation."""
    base = study.parent
    pairs = records.orientation is not None
    if records.fema_p695 is not None:
        fema = records.fema_p695
        try:
            fema_records = read_fema_set(fema.name, tuple(fema.components), fema.normalize,
                                 None if fema.records is None else tuple(fema.records))  # fmt: skip
        except InputError as exc:  # not installed, or a record id not in the set
            raise InputError(study, [(".".join(filter(None, ("records.fema_p695", where))), why)
                                     for where, why in exc.problems]) from None  # fmt: skip
        if pairs:
            fema_records = fema_pairs(fema_records)
        return [study_record(r, f"{r.source}/{r.name}", r.name) for r in fema_records]
    if records.pulses is not None:
        pulses = [entry.record() for entry in records.pulses]
        return [study_record(r, r.source, r.name) for r in pulses]
    files: list[tuple[str, Path, str | None, float | None, Path | None, Path | None]]
    if records.record_set is not None:
        folder = records.record_set
        manifest = read_manifest(base / folder)
        files = []
        for index, entry in enumerate(manifest["records"]):  # the files the set was written with
            check_set_file(base / folder, entry, index)
            companion = vertical_entry(base / folder, entry, index) if records.vertical else None
            up = None if companion is None else folder / companion["file"]
            name = entry.get("name") or Path(entry["file"]).stem
            files.append((name, folder / entry["file"], None, None, up, None))
    else:
        assert records.files is not None
        files = [(f.id or f.path.stem, f.path, f.units, f.time_step,
                  f.vertical if records.vertical else None, f.second if pairs else None)
                 for f in records.files]  # fmt: skip
    read = functools.cache(_read)  # a file listed several times is read once
    within = functools.partial(_within, base)
    return [
        dataclasses.replace(
            read(base / source, units, step, within(up), within(other)),
            id=name, source=source.as_posix(),
        )
        for name, source, units, step, up, other in files
    ]  # fmt: skip


def _within(base: Path, path: Path | None) -> Path | None:
    """A companion file's path from the study's folder ``base``; None for none."""
    return None if path is None else base / path


def _read(
    path: Path,
    units: str | None,
    time_step: float | None,
    vertical: Path | None,
    second: Path | None = None,
) -> StudyRecord:
    """A record file, with its ``vertical`` and ``second`` companions if given, as a
    `StudyRecord` (its id and source are set by the caller)."""
    try:
        record = read_record(path, units=units, time_step=time_step)
        if vertical is not None:
            record = with_vertical(record, vertical, units, time_step)
        if second is not None:
            record = with_second(record, second, units, time_step)
    except InputError as exc:
        return StudyRecord("", "", None, str(exc), _file_digest(path))
    return study_record(record)


def study_record(record: Record, source: str = "", id: str = "") -> StudyRecord:
    """A record read, as a `StudyRecord` whose digest is that of its samples and time step (and
    of its vertical component's samples, where it has one)."""
    digest = hashlib.sha256(np.float64(record.time_step).tobytes())
    digest.update(record.acceleration.tobytes())
    if record.vertical is not None:
        digest.update(b"vertical")
        digest.update(record.vertical.tobytes())
    return StudyRecord(id, source, record, "", digest.hexdigest())


def _file_digest(path: Path) -> str:
    """SHA-256 of an unreadable record file's bytes, if it is a regular file of at most
    `MAX_RECORD_BYTES` (a device or a huge file is never read); else ``unreadable``."""
    try:
        if path.is_file() and path.stat().st_size <= MAX_RECORD_BYTES:
            return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        pass
    return "unreadable"
