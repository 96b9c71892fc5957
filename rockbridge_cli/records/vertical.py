"""Vertical components of records: read from companion files.

PEER NGA and ESM distribute each component of a recording in a file of its own, so the vertical
component of a record is a companion file, in any format `files.read_record` reads: a study's
record entry names it (``vertical: <file>``), a record set's manifest lists it beside its record
(``"vertical": {"file": ..., "sha256": ...}``, `vertical_entry`). It must share the horizontal
component's time step and number of samples (`with_vertical`, by `components.read_companion`).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from .components import read_companion
from .files import Record
from .set_files import MANIFEST, check_set_file


def peak_vertical(record: Record) -> float:
    """A record's peak vertical ground acceleration max|ü_v| [m/s²]; NaN without one."""
    return float("nan") if record.vertical is None else float(np.max(np.abs(record.vertical)))


def with_vertical(
    record: Record, path: str | Path, units: str | None = None, time_step: float | None = None
) -> Record:
    """The record with its vertical component, read from the companion file ``path`` (any
    format of `read_record`; ``units`` and ``time_step`` as there, for a file that does not
    state them).

    Raises
    ------
    InputError
        The companion cannot be read, or its time step or number of samples differ from the
        horizontal component's; the message names the companion file.
    """
    up = read_companion(record, path, units, time_step, "vertical")
    metadata = {**record.metadata, "vertical_source": str(path),
                "vertical_file_units": up.metadata["file_units"]}  # fmt: skip
    return dataclasses.replace(record, metadata=metadata, vertical=up.acceleration)


def vertical_entry(folder: Path, entry: dict[str, Any], index: int) -> dict[str, Any] | None:
    """The manifest's entry of a record's vertical companion (``file``, ``sha256``), checked
    like its record's (`check_set_file`), or None if the record has none.

    Raises
    ------
    InputError
        The entry is malformed, or its file is missing or differs from the manifest.
    """
    companion = entry.get("vertical")
    if companion is None:
        return None
    if not isinstance(companion, dict) or not isinstance(companion.get("file"), str):
        field = f"records[{index}].vertical.file"
        raise InputError(folder / MANIFEST, [(field, "missing or not a file name")])
    check_set_file(folder, companion, index, "vertical.file")
    return companion
