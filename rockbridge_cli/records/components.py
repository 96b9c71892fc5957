"""Pairs of horizontal components: a record's second horizontal component read from a companion
file (`with_second`), as `vertical` reads the vertical one, or the FEMA P695 sets' ``a`` and
``b`` joined (`fema_pairs`); and a pair seen along one direction (`oriented`).

PEER NGA and ESM distribute each component of a recording in a file of its own: a study's
record entry names the second (``second: <file>``), in any format `files.read_record` reads,
sharing the first's time step and number of samples (`read_companion`, which the vertical
component's reader uses too). The second component is taken at +90° from the first: the
projection at θ is a₁·cos θ + a₂·sin θ (`motions.orientation.project`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..motions.orientation import project
from .files import TIME_STEP_TOLERANCE, Record, read_record


def read_companion(
    record: Record, path: str | Path, units: str | None, time_step: float | None, what: str
) -> Record:
    """The companion file ``path`` of ``record`` (its ``what`` component: vertical, second),
    read by `read_record` (``units`` and ``time_step`` for a file that does not state them).

    Raises
    ------
    InputError
        The companion cannot be read, or its time step or number of samples differ from the
        record's; the message names the companion file.
    """
    path = Path(path)
    companion = read_record(path, units=units, time_step=time_step)
    first = record.source or record.name
    if not math.isclose(companion.time_step, record.time_step, rel_tol=TIME_STEP_TOLERANCE):
        reason = (
            f"the {what} component steps by {companion.time_step:g} s, the record it belongs to "
            f"({first}) by {record.time_step:g} s: they must share their samples"
        )
        raise InputError(path, [("time_step", reason)])
    if companion.acceleration.size != record.acceleration.size:
        reason = (
            f"the {what} component has {companion.acceleration.size} samples, the record it "
            f"belongs to ({first}) {record.acceleration.size}: they must share their samples"
        )
        raise InputError(path, [("points", reason)])
    return companion


def with_second(
    record: Record, path: str | Path, units: str | None = None, time_step: float | None = None
) -> Record:
    """The record with its second horizontal component (at +90° from its first), read from the
    companion file ``path`` (`read_companion`).

    Raises
    ------
    InputError
        As `read_companion`.
    """
    other = read_companion(record, path, units, time_step, "second")
    metadata = {**record.metadata, "second_source": str(path),
                "second_file_units": other.metadata["file_units"]}  # fmt: skip
    return dataclasses.replace(record, metadata=metadata, second=other.acceleration)


def fema_pairs(records: Sequence[Record]) -> list[Record]:
    """The FEMA P695 records (`fema.read_fema_set` with both components) as pairs, named by
    their record (``FF01``): ``a`` first, ``b`` second. The sets' components share their time
    step; where one ends before the other (far-field 15, Manjil), the ground along it is taken
    at rest to the other's end, as a response spectrum takes it after a record.

    Raises
    ------
    ValueError
        A record has not both components, next to each other, ``a`` then ``b``.
    """
    pairs = []
    for first, other in zip(records[::2], records[1::2], strict=True):
        if (first.name[-1], other.name[-1]) != ("a", "b") or first.name[:-1] != other.name[:-1]:
            raise ValueError(f"{first.name} and {other.name} are not one record's a and b")
        if first.time_step != other.time_step:
            raise ValueError(f"{first.name} and {other.name} differ in their time step")
        size = max(first.acceleration.size, other.acceleration.size)
        a, b = (np.pad(r.acceleration, (0, size - r.acceleration.size)) for r in (first, other))
        metadata = {**first.metadata, "component": f"{first.metadata.get('component', 'a')} + "
                    f"{other.metadata.get('component', 'b')}"}  # fmt: skip
        pairs.append(dataclasses.replace(
            first, name=first.name[:-1], acceleration=a, second=b, metadata=metadata
        ))  # fmt: skip
    return pairs


def oriented(record: Record, angle: float, pair: str = "") -> Record:
    """A pair seen along the direction at ``angle`` from its first component toward its second
    [deg]: one component, a₁·cos θ + a₂·sin θ (its vertical one kept), with the ``pair``'s name
    (default the record's) and ``angle_deg`` in its metadata. At 0° its samples are the first
    component's, at 90° the second's, bit for bit.

    Raises
    ------
    ValueError
        The record has no second component.
    """
    if record.second is None:
        raise ValueError(f"record {record.name} has no second horizontal component")
    along = project(record.acceleration, record.second, angle)
    metadata = {**record.metadata, "pair": pair or record.name, "angle_deg": float(angle)}
    return dataclasses.replace(record, acceleration=along, second=None, metadata=metadata)
