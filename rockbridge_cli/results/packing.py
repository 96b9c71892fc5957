"""One analysis's results, and the compact form they travel and wait in.

A worker packs its result (`AnalysisResult.pack`); the packed parts go into the journal unchanged,
and the results file is written from them (`results.writing.ResultsWriter`), many analyses at a
time. They are laid out the way the results file's tables take them, so that the parent process
joins the parts of a few thousand analyses and appends them without looking at any one of them:
the numeric values as one float64 vector in the order of `NUMBERS` (a row of the peak table), the
events as rows of `EVENT_RECORD` (the event table's columns side by side), the texts
NUL-separated. The histories are packed as HDF5 chunks already: byte-shuffled and deflated exactly
as the results file's filters (`layout.COMPRESSION`) would store them, so the workers compress in
parallel and the parent copies the chunks into the file without touching the samples.
"""

from __future__ import annotations

import json
import struct
import zlib
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from .layout import (
    COMPRESSION,
    COUNT_COLUMNS,
    EVENT_COLUMNS,
    PEAK_COLUMNS,
    TEXT_COLUMNS,
    kind_codes,
    missing,
)

if TYPE_CHECKING:
    from ..core.analysis import Response

NUMBERS = tuple(name for name in PEAK_COLUMNS if name not in TEXT_COLUMNS)
"""The numeric columns of the peak table, in the order a packed result stores them (counts too:
float64 holds them exactly)."""

TEXTS = tuple(name for name in TEXT_COLUMNS if name not in ("bridge", "record"))
"""The text columns a packed result stores (the ids travel beside it)."""

EVENT_RECORD = np.dtype([(name, "i1" if name == "kind" else "<f8") for name in EVENT_COLUMNS])
"""One event as a packed result stores it: the columns of `EVENT_COLUMNS`, float64 but the kind,
an int8 code of `quantities.EVENT_NAMES` (as the results file stores it)."""

_HEADER = struct.Struct("<I")
"""What starts packed histories: the length of their JSON header [bytes]."""

_SAMPLE = np.dtype("<f8")
"""Every history and every numeric event column is stored as little-endian float64."""


class Chunk(NamedTuple):
    """One history as a single HDF5 chunk: ``size`` float64 samples, shuffled and deflated."""

    size: int
    data: bytes

    @classmethod
    def of(cls, samples: np.ndarray) -> Chunk:
        """Shuffle the bytes of the samples (all first bytes, then all second bytes, …), deflate
        them and append their checksum: the HDF5 ``shuffle``, ``gzip`` and ``fletcher32``
        filters, in that order."""
        values = np.ascontiguousarray(samples, dtype=_SAMPLE)
        shuffled = values.view(np.uint8).reshape(-1, _SAMPLE.itemsize).T.tobytes()
        deflated = zlib.compress(shuffled, COMPRESSION["compression_opts"])
        return cls(values.size, deflated + fletcher32(deflated).to_bytes(4, "little"))

    def samples(self) -> np.ndarray:
        """The samples back (the inverse of `of`).

        Raises
        ------
        ValueError
            The chunk's checksum does not match its bytes: it is damaged.
        """
        deflated, checksum = self.data[:-4], self.data[-4:]
        if fletcher32(deflated) != int.from_bytes(checksum, "little"):
            raise ValueError("a history is damaged (its checksum does not match)")
        shuffled = np.frombuffer(zlib.decompress(deflated), dtype=np.uint8)
        return shuffled.reshape(_SAMPLE.itemsize, -1).T.copy().view(_SAMPLE).ravel()


def fletcher32(data: bytes) -> int:
    """HDF5's Fletcher-32 checksum of ``data`` (``H5_checksum_fletcher32``, which its
    ``fletcher32`` filter appends to a chunk, little-endian).

    Two sums of the data's big-endian 16-bit words (a last odd byte is the high byte of one),
    with end-around carry: the first sums the words, the second the running first sums, each
    reduced modulo 65535 to 1 … 65535 (0 only for data that are all zero bytes).
    """
    words = np.frombuffer(data + b"\0" * (len(data) % 2), dtype=">u2").astype(np.int64)
    if not words.any():
        return 0
    weights = np.arange(words.size, 0, -1, dtype=np.int64) % 65535  # word i is in n − i sums
    first = int(words.sum()) % 65535 or 65535
    second = int((words % 65535 * weights).sum()) % 65535 or 65535
    return second << 16 | first


@dataclass
class AnalysisResult:
    """What one bridge × record analysis produced, ready to store.

    Attributes
    ----------
    bridge, record : ids
    values : the scalar columns of the peak table (`PEAK_COLUMNS`, except the ids) [SI]
    time : sample times of the histories [s]
    histories : name → array at ``time``; units in `core.quantities.HISTORY_UNITS`
    events : name → array; units in `EVENT_COLUMNS`
    """

    bridge: str
    record: str
    values: dict[str, Any]
    time: np.ndarray = field(default_factory=lambda: np.zeros(0))
    histories: dict[str, np.ndarray] = field(default_factory=dict)
    events: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def status(self) -> str:
        """``ok``, ``solver_error`` or ``error`` (`layout.STATUSES`)."""
        return self.values["status"]

    @classmethod
    def from_response(
        cls, bridge: str, record: str, response: Response, keep: Sequence[str], wall_time: float
    ) -> AnalysisResult:
        """The result of a finished analysis, keeping the histories named in ``keep``."""
        values = {k: v for k, v in response.peak_row().items() if k in PEAK_COLUMNS}
        ok = response.status == "ok"
        values.update(
            status="ok" if ok else "solver_error",
            message="" if ok else response.status,
            wall_time_s=wall_time,
            n_events=len(response.events["time"]),
            rechecked=0,
            base_record=record,
            intensity=float("nan"),
            scale=1.0,
        )
        events = {**response.events, "kind": response.events["kind"].astype(str)}
        histories = {name: response.histories[name] for name in keep}
        return cls(
            bridge, record, values, response.time if keep else np.zeros(0), histories, events
        )

    @classmethod
    def failed(
        cls, bridge: str, record: str, message: str, wall_time: float = 0.0
    ) -> AnalysisResult:
        """An analysis that could not run: every value missing, status ``error``, no events."""
        values = {name: missing(name) for name in PEAK_COLUMNS if name not in ("bridge", "record")}
        values.update(status="error", message=message, wall_time_s=wall_time, n_events=0)
        events = {name: np.zeros(0) for name in EVENT_COLUMNS}
        return cls(bridge, record, values, events={**events, "kind": np.zeros(0, dtype=str)})

    def pack(self) -> Packed:
        """The result in its packed form (`Packed`)."""
        texts = "\0".join(self.values[name].replace("\0", "\ufffd") for name in TEXTS)
        numbers = np.array([self.values[name] for name in NUMBERS], dtype=_SAMPLE)
        events = np.empty(len(self.events["kind"]), EVENT_RECORD)
        for name in EVENT_COLUMNS:
            events[name] = self.events[name] if name != "kind" else kind_codes(self.events[name])
        chunks = {"time": Chunk.of(self.time)} if self.histories else {}
        chunks.update((name, Chunk.of(values)) for name, values in self.histories.items())
        histories = b""
        if chunks:
            header = json.dumps([[name, chunk.size, len(chunk.data)]
                                 for name, chunk in chunks.items()]).encode()  # fmt: skip
            histories = b"".join(
                [_HEADER.pack(len(header)), header, *(chunk.data for chunk in chunks.values())]
            )
        return Packed(self.bridge, self.record, texts, numbers.tobytes(), events.tobytes(),
                      histories)  # fmt: skip


class Packed(NamedTuple):
    """One analysis's results packed: what travels from a worker, waits in the journal and is
    written into the results file.

    Attributes
    ----------
    bridge, record : ids
    texts : the values of the text columns of `TEXTS`, NUL-separated (a NUL in a value, which
        HDF5 strings cannot hold, becomes U+FFFD)
    numbers : the values of the numeric columns as float64, in the order of `NUMBERS` [SI]
    events : one `EVENT_RECORD` row per event
    histories : empty when the study keeps none; else a length-prefixed JSON header of their
        names, sizes and lengths, then the histories (``time`` first) as `Chunk` s
    """

    bridge: str
    record: str
    texts: str
    numbers: bytes
    events: bytes
    histories: bytes

    @property
    def values(self) -> dict[str, Any]:
        """The scalar columns of the peak table by name (counts as int) [SI]."""
        numbers = {
            name: int(value) if name in COUNT_COLUMNS else float(value)
            for name, value in zip(NUMBERS, np.frombuffer(self.numbers, _SAMPLE).tolist(),
                                   strict=True)
        }  # fmt: skip
        return {**numbers, **dict(zip(TEXTS, self.texts.split("\0"), strict=True))}

    @property
    def event_rows(self) -> np.ndarray:
        """The events as `EVENT_RECORD` rows (a column by name: ``event_rows["time"]``)."""
        return np.frombuffer(self.events, EVENT_RECORD)

    @property
    def chunks(self) -> dict[str, Chunk]:
        """The histories by name, ``time`` first; empty when the study keeps none."""
        if not self.histories:
            return {}
        (length,) = _HEADER.unpack_from(self.histories)
        start = _HEADER.size + length
        chunks = {}
        for name, size, stored in json.loads(self.histories[_HEADER.size : start]):
            chunks[name] = Chunk(size, self.histories[start : start + stored])
            start += stored
        return chunks
