"""One analysis's results, and the compact bytes they travel and wait in.

A worker packs its result (`AnalysisResult.pack`); the bytes go to the parent process and into
the journal unchanged, and the results file is written from them (`Packed`). They are laid out the
way the results file's tables take them, so that reading them back costs the parent about a
microsecond: the numeric values as one float64 vector in the order of `NUMBERS` (the row of the
peak table), the events as rows of `EVENT_RECORD` (the event table's columns side by side), the
few texts NUL-separated. The histories are packed as HDF5 chunks already: byte-shuffled and
deflated exactly as the results file's filters (`layout.COMPRESSION`) would store them, so the
workers compress in parallel and the parent copies the chunks into the file without touching
the samples.
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

_PREFIX = struct.Struct("<III")
"""What starts a packed result: the lengths of its texts and of its histories' JSON header
[bytes], and its event count."""

_SAMPLE = np.dtype("<f8")
"""Every history and every numeric event column is stored as little-endian float64."""


class Chunk(NamedTuple):
    """One history as a single HDF5 chunk: ``size`` float64 samples, shuffled and deflated."""

    size: int
    data: bytes

    @classmethod
    def of(cls, samples: np.ndarray) -> Chunk:
        """Shuffle the bytes of the samples (all first bytes, then all second bytes, …) and deflate
        them: the HDF5 ``shuffle`` and ``gzip`` filters, in that order."""
        values = np.ascontiguousarray(samples, dtype=_SAMPLE)
        shuffled = values.view(np.uint8).reshape(-1, _SAMPLE.itemsize).T.tobytes()
        return cls(values.size, zlib.compress(shuffled, COMPRESSION["compression_opts"]))

    def samples(self) -> np.ndarray:
        """The samples back (the inverse of `of`)."""
        shuffled = np.frombuffer(zlib.decompress(self.data), dtype=np.uint8)
        return shuffled.reshape(_SAMPLE.itemsize, -1).T.copy().view(_SAMPLE).ravel()


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

    def pack(self) -> bytes:
        """The result as bytes: a prefix of lengths, the texts of `TEXTS` (UTF-8, NUL-separated:
        a NUL, which HDF5 strings cannot hold, becomes U+FFFD), the values of `NUMBERS` as
        float64, the events as `EVENT_RECORD` rows, then, if it keeps histories, a JSON header
        of their names and sizes and the histories (``time`` first) as `Chunk` s."""
        texts = "\0".join(self.values[name].replace("\0", "\ufffd") for name in TEXTS).encode()
        numbers = np.array([self.values[name] for name in NUMBERS], dtype=_SAMPLE)
        events = np.empty(len(self.events["kind"]), EVENT_RECORD)
        for name in EVENT_COLUMNS:
            events[name] = self.events[name] if name != "kind" else kind_codes(self.events[name])
        chunks = {"time": Chunk.of(self.time)} if self.histories else {}
        chunks.update((name, Chunk.of(values)) for name, values in self.histories.items())
        sizes = [[name, chunk.size, len(chunk.data)] for name, chunk in chunks.items()]
        header = json.dumps(sizes).encode() if chunks else b""
        parts = [_PREFIX.pack(len(texts), len(header), events.size), texts, numbers.tobytes()]
        parts += [events.tobytes(), header, *(chunk.data for chunk in chunks.values())]
        return b"".join(parts)


@dataclass(frozen=True)
class Packed:
    """A packed result read back: what the results file is written from.

    Attributes
    ----------
    bridge, record : ids
    numbers : the values of the numeric columns, in the order of `NUMBERS` [SI]
    texts : the values of the text columns of `TEXTS`
    events : one `EVENT_RECORD` row per event (a column by name: ``events["time"]``)
    histories : name → `Chunk`, ``time`` first; empty when the study keeps no histories
    """

    bridge: str
    record: str
    numbers: np.ndarray
    texts: tuple[str, ...]
    events: np.ndarray
    histories: dict[str, Chunk]

    @property
    def values(self) -> dict[str, Any]:
        """The scalar columns of the peak table by name (counts as int) [SI]."""
        numbers = {
            name: int(value) if name in COUNT_COLUMNS else float(value)
            for name, value in zip(NUMBERS, self.numbers.tolist(), strict=True)
        }
        return {**numbers, **dict(zip(TEXTS, self.texts, strict=True))}

    @classmethod
    def unpack(cls, bridge: str, record: str, blob: bytes) -> Packed:
        """Read the bytes of `AnalysisResult.pack` (the arrays are views of ``blob``)."""
        text_length, header_length, count = _PREFIX.unpack_from(blob)
        start = _PREFIX.size + text_length
        texts = tuple(blob[_PREFIX.size : start].decode().split("\0"))
        numbers = np.frombuffer(blob, _SAMPLE, len(NUMBERS), start)
        start += numbers.nbytes
        events = np.frombuffer(blob, EVENT_RECORD, count, start)
        start += events.nbytes
        histories = {}
        if header_length:
            header = json.loads(blob[start : start + header_length])
            start += header_length
            for name, size, length in header:
                histories[name] = Chunk(size, blob[start : start + length])
                start += length
        return cls(bridge, record, numbers, texts, events, histories)

    @classmethod
    def of(cls, result: AnalysisResult) -> Packed:
        """A result as its packed form (what the results file is written from)."""
        return cls.unpack(result.bridge, result.record, result.pack())
