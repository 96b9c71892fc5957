"""Writing a results file in one streaming pass: the study's description first, then the
analyses in the study's order, the peak and event tables appended a few thousand rows at a time.

Memory stays flat in the number of analyses: a batch of rows at a time, and each analysis's
histories go into the file as soon as it is added.
"""

from __future__ import annotations

import json
import platform
from collections import Counter
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import Any

import h5py
import numpy as np
import scipy

from .. import __version__
from ..core.quantities import EVENT_NAMES, NO_FAILURE, history_unit
from .description import Attributes, Description, RecordGroup
from .layout import (
    COMPRESSION,
    COUNT_COLUMNS,
    DEVICE_COLUMNS,
    DEVICE_FLAGS,
    DEVICE_TEXTS,
    EVENT_COLUMNS,
    FORMAT,
    FORMAT_VERSION,
    PEAK_COLUMNS,
    TEXT_COLUMNS,
    TEXT_DIGEST,
    digest_update,
    history_description,
    text_digests,
)
from .packing import DEVICE_NUMBERS, DEVICE_RECORD, EVENT_RECORD, NUMBERS, TEXTS, Chunk, Packed

PEAK_ROWS = 4096
"""The HDF5 chunk length of the peak table."""

PEAKS_HELD = 4 * PEAK_ROWS
"""Rows of the peak table held in memory before they are appended to the file (about 6 MB): each
append costs HDF5 and h5py about 0.2 ms a column whatever its length."""

ADDED_AT_ONCE = 1024
"""Analyses the writer takes at a time (column by column, not one by one)..."""

ADDED_BYTES = 4 * 2**20
"""... or fewer, as soon as their events and histories reach this size [bytes] (a thousand
analyses that keep their histories would hold 200 MB; without histories, ≈ 800 analyses)."""

EVENT_ROWS = 65536
"""The HDF5 chunk length of the event table (about 150 events an analysis)."""

DEVICE_ROWS = 4096
"""The HDF5 chunk length of the device table."""

EVENTS_HELD = 4 * EVENT_ROWS
"""Rows of the event table held in memory before they are appended (about 8.7 MB): each append costs
HDF5 about 8 ms whatever its length, 18 µs an analysis when it came every 65 536 events."""


class ResultsWriter:
    """Fills a results file whose description is written (`write_description`, `copy_description`)
    with analyses in the study's order.

    Parameters
    ----------
    file
        The file, open for writing.
    total
        The analyses the file is meant to hold (the study's, or a shard's).

    Attributes
    ----------
    added : analyses added so far
    statuses : how many of them ended with each status
    failures : how many of them ended with a failure of the bridge
    """

    def __init__(self, file: h5py.File, total: int):
        self.file = file
        self.total = total
        self.added = 0
        self.statuses: Counter[str] = Counter()
        self.failures = 0
        text = "one row per analysis that ran, in the study's order (bridge × record)"
        self.peaks = _table(file.create_group("peaks"), PEAK_COLUMNS, PEAK_ROWS, text)
        self.peaks["n_events"].attrs["sample_dimension"] = "events"
        self.events = _table(file.create_group("events"), EVENT_COLUMNS, EVENT_ROWS, "the events "
                             "of every analysis, in the order of /peaks; /peaks/n_events counts "
                             "each analysis's rows (CF contiguous ragged array)")  # fmt: skip
        self._bridges: list[str] = []
        self._records: list[str] = []
        self._texts: list[str] = []  # `Packed.texts`
        self._numbers: list[bytes] = []  # `Packed.numbers`
        self._events = bytearray()  # `EVENT_RECORD` rows
        self.devices: h5py.Group | None = None  # created with the first analysis that has some
        self._device_ids: list[tuple[str, str]] = []  # (bridge, record) of each device row
        self._devices = bytearray()  # `DEVICE_RECORD` rows
        self._templates = h5py.File(f"templates-{id(self)}", "w", driver="core",
                                    backing_store=False)  # fmt: skip
        self._digests = text_digests(PEAK_COLUMNS)  # text has no HDF5 checksum: its SHA-256

    def add(self, analyses: Iterable[Packed], written: Callable[[int], None] | None = None) -> None:
        """Append analyses, in the study's order: their rows of /peaks, their events, their
        histories; ``written`` is called with the analyses added so far after each block of
        them (`ADDED_AT_ONCE`, `ADDED_BYTES`)."""
        for block in _blocks(analyses):
            bridges, records, texts, numbers, events, _, _ = zip(*block, strict=True)
            self._bridges += bridges
            self._records += records
            self._texts += texts
            self._numbers += numbers
            self._events += b"".join(events)
            for packed in block:
                if packed.devices:
                    self._devices += packed.devices
                    self._device_ids += [(packed.bridge, packed.record)] * len(packed.device_rows)
                if packed.histories:
                    parent = self.file.require_group(f"analyses/{packed.bridge}")
                    _write_histories(parent.create_group(packed.record), packed.chunks,
                                     self._templates)  # fmt: skip
            self.added += len(block)
            if len(self._numbers) >= PEAKS_HELD:
                self._flush_peaks()
                self._flush_devices()
            if len(self._events) >= EVENTS_HELD * EVENT_RECORD.itemsize:
                self._flush_events()
            if written is not None:
                written(self.added)

    def close(self, finished: str) -> None:
        """Append what is buffered and state how complete the file is."""
        self._templates.close()
        self._flush_peaks()
        self._flush_events()
        self._flush_devices()
        digests = {name: digest.hexdigest() for name, digest in self._digests.items()}
        self.peaks.attrs[TEXT_DIGEST] = json.dumps(digests)
        self.file.attrs.update(
            {"finished": finished, "complete": self.added == self.total,
             "n_analyses": self.total, "n_complete": self.added}
        )  # fmt: skip

    def _flush_peaks(self) -> None:
        rows = len(self._numbers)
        numbers = np.frombuffer(b"".join(self._numbers), np.float64).reshape(rows, len(NUMBERS))
        for column, name in enumerate(NUMBERS):
            _append(self.peaks[name], numbers[:, column])
        texts = "\0".join(self._texts).split("\0") if rows else []
        columns = {"bridge": self._bridges, "record": self._records}
        columns.update((name, texts[k :: len(TEXTS)]) for k, name in enumerate(TEXTS))
        for name, values in columns.items():
            _append(self.peaks[name], values)
            digest_update(self._digests[name], values)
        self.statuses.update(columns["status"])
        self.failures += sum(mode not in ("", NO_FAILURE) for mode in columns["failure_mode"])
        for buffered in (self._bridges, self._records, self._texts, self._numbers):
            buffered.clear()

    def _flush_events(self) -> None:
        events = np.frombuffer(self._events, EVENT_RECORD)
        for name in EVENT_COLUMNS:
            _append(self.events[name], events[name])
        del events  # a view of the buffer, which cannot be cleared while it exists
        self._events.clear()

    def _flush_devices(self) -> None:
        """Append the buffered device rows to /devices, created at the first (a study without
        devices has none, and its file is what it was before devices existed)."""
        if not self._device_ids:
            return
        if self.devices is None:
            text = ("one row per device of each analysis that ran, in the order of /peaks; "
                    "only where a bridge has tendons or dampers")  # fmt: skip
            self.devices = _table(self.file.create_group("devices"), DEVICE_COLUMNS,
                                  DEVICE_ROWS, text, DEVICE_TEXTS)  # fmt: skip
        rows = np.frombuffer(self._devices, DEVICE_RECORD)
        bridges, records = zip(*self._device_ids, strict=True)
        _append(self.devices["bridge"], list(bridges))
        _append(self.devices["record"], list(records))
        _append(self.devices["device"], [name.decode() for name in rows["device"]])
        for name in DEVICE_NUMBERS:
            _append(self.devices[name], rows[name])
        del rows  # a view of the buffer, which cannot be cleared while it exists
        self._devices.clear()
        self._device_ids.clear()


def _blocks(analyses: Iterable[Packed]) -> Iterator[list[Packed]]:
    """The analyses a block at a time: `ADDED_AT_ONCE` of them, or `ADDED_BYTES`."""
    block: list[Packed] = []
    size = 0
    for packed in analyses:
        block.append(packed)
        size += len(packed.events) + len(packed.histories)
        if len(block) == ADDED_AT_ONCE or size >= ADDED_BYTES:
            yield block
            block, size = [], 0
    if block:
        yield block


def _table(
    group: h5py.Group,
    columns: dict[str, tuple[str, str]],
    chunk: int,
    text: str,
    texts: tuple[str, ...] = TEXT_COLUMNS,
) -> h5py.Group:
    """Empty, extendable columns: ``texts`` as UTF-8 strings, counts as int64, the event kind
    and the device flags as int8, the rest float64."""
    group.attrs["description"] = text
    group.attrs["columns"] = json.dumps(list(columns))
    for name, (unit, description) in columns.items():
        if name in texts:
            dtype: Any = h5py.string_dtype()
        elif name == "kind" or name in DEVICE_FLAGS:
            dtype = np.int8
        else:
            dtype = np.int64 if name in COUNT_COLUMNS else np.float64
        dataset = group.create_dataset(  # numbers with a checksum HDF5 verifies on every read
            name, shape=(0,), maxshape=(None,), chunks=(chunk,), dtype=dtype,
            fletcher32=name not in texts,  # (HDF5 filters cannot take text)
        )  # fmt: skip
        dataset.attrs["units"] = unit
        dataset.attrs["description"] = description
        if name == "kind":  # a CF flag (§3.5)
            dataset.attrs["flag_values"] = np.arange(len(EVENT_NAMES), dtype=np.int8)
            dataset.attrs["flag_meanings"] = " ".join(EVENT_NAMES)
    return group


def _append(dataset: h5py.Dataset, values: list | np.ndarray) -> None:
    if not len(values):
        return
    start = dataset.shape[0]
    dataset.resize((start + len(values),))
    dataset[start:] = np.asarray(values, dtype=dataset.dtype)  # text: str already


def _write_histories(parent: h5py.Group, histories: dict[str, Chunk], templates: h5py.File) -> None:
    """The ``histories`` group of one analysis: a copy of an empty one with the same columns and
    length from ``templates`` (an HDF5 object copy costs a quarter of creating and describing
    the datasets), then its chunks written in as they are."""
    size = next(iter(histories.values())).size
    key = f"{size}:{','.join(histories)}"
    if key not in templates:
        _describe_histories(templates.create_group(key), histories, size)
    templates.copy(templates[key], parent, "histories")
    group = parent["histories"]
    for name, history in histories.items() if size else ():
        group[name].id.write_direct_chunk((0,), history.data)


def _describe_histories(group: h5py.Group, names: Iterable[str], size: int) -> None:
    """Empty histories of ``size`` samples, one HDF5 chunk each, compressed, with units."""
    for name in names:
        unit, text = ("s", "sample times") if name == "time" else (
            history_unit(name), history_description(name))  # fmt: skip
        dataset = group.create_dataset(
            name, shape=(size,), maxshape=(max(size, 1),), chunks=(max(size, 1),), dtype="<f8",
            **COMPRESSION,
        )  # fmt: skip
        dataset.attrs["units"] = unit
        dataset.attrs["description"] = text


ROOT_UNITS = {
    "output_step": "s", "significant_impact_rate": "rad/s", "n_analyses": "-", "n_complete": "-",
}  # fmt: skip
"""Units of the root's scalar attributes (its ``units`` attribute)."""


def write_description(
    file: h5py.File, description: Description, created: str, shard: tuple[int, int] | None = None
) -> None:
    """Write what the results rest on (`description.Description`, computed by the study layer):
    the format, the versions of what wrote it and the study (root attributes), its records and
    its bridges.

    Parameters
    ----------
    created
        When the run started (ISO 8601).
    shard
        (index, count) when the file holds one shard of the study (0-based index).
    """
    file.attrs.update(
        {
            "format": FORMAT,
            "format_version": FORMAT_VERSION,
            "rockbridge_version": __version__,
            "python_version": platform.python_version(),
            "numpy_version": np.__version__,
            "scipy_version": scipy.__version__,
            "h5py_version": h5py.__version__,
            "hdf5_version": h5py.version.hdf5_version,
            "host": platform.node(),
            "created": created,
            **description.root,
        }
    )
    _describe_attrs(file, ROOT_UNITS)
    if shard is not None:
        file.attrs.update({"shard_index": shard[0], "shard_count": shard[1]})
    _write_records(file.create_group("records"), description.records)
    group = file.create_group("bridges")
    for bridge, attributes in description.bridges.items():
        _write_attributes(group.create_group(bridge), attributes)


def copy_description(file: h5py.File, source: h5py.File, skip: tuple[str, ...]) -> None:
    """Copy the description of another results file of the same study (root attributes except
    ``skip``, records, bridges)."""
    file.attrs.update({k: v for k, v in source.attrs.items() if k not in skip})
    for name in ("records", "bridges"):
        source.copy(source[name], file, name=name)


def _write_records(group: h5py.Group, records: Sequence[RecordGroup]) -> None:
    """One group per record, named by its id. Records of one content are one group (HDF5 hard
    links: its attributes are written once), and samples of one key one dataset (a hard link
    too)."""
    described: dict[tuple[str, str], h5py.Group] = {}
    written: dict[str, h5py.Dataset] = {}
    for record in records:
        if record.key in described:  # h5py's low-level call: a third of ``group[id] = node``
            group.id.links.create_hard(record.id.encode(), described[record.key].id, b".")
            continue
        node = described[record.key] = group.create_group(record.id)
        _write_attributes(node, record.attributes)
        for samples in record.samples:
            if samples.key in written:
                node[samples.name] = written[samples.key]
            else:
                written[samples.key] = _write_samples(node, samples.name, samples.values)


def _write_samples(node: h5py.Group, name: str, acceleration: np.ndarray) -> h5py.Dataset:
    """A record's samples, ``acceleration`` (as analyzed) or ``base_acceleration`` (as read, of
    a record scaled by the group's ``scale``); ``vertical_acceleration`` and
    ``base_vertical_acceleration`` its vertical component's."""
    dataset = node.create_dataset(name, data=acceleration, **COMPRESSION)
    dataset.attrs["units"] = "m/s2"
    direction = "vertical, positive up" if "vertical" in name else "positive to the right"
    dataset.attrs["description"] = (
        f"ground acceleration, {direction}, from t = 0 at time_step"
        + ("" if not name.startswith("base_") else "; of the record as read: the group's scale "
           "times it is the motion analyzed")
    )  # fmt: skip
    return dataset


def _write_attributes(node: h5py.Group, attributes: Attributes) -> None:
    node.attrs.update(attributes.values)
    if attributes.units is not None:
        _describe_attrs(node, attributes.units)


def _describe_attrs(node: h5py.Group | h5py.File, units: dict[str, str]) -> None:
    node.attrs["units"] = json.dumps(units)
