"""One analysis's results, and the compact bytes they travel and wait in.

A worker packs its result (`AnalysisResult.pack`); the bytes go to the parent process and into
the journal unchanged, and the results file is written from them (`Packed`). The histories are
packed as HDF5 chunks already: byte-shuffled and deflated exactly as the results file's filters
(`layout.COMPRESSION`) would store them, so the workers compress in parallel and the parent
copies the chunks into the file without touching the samples.
"""

from __future__ import annotations

import json
import struct
import zlib
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from .layout import COMPRESSION, EVENT_COLUMNS, PEAK_COLUMNS, kind_codes, missing

if TYPE_CHECKING:
    from ..core.analysis import Response

_HEADER = struct.Struct("<I")
"""Length of the JSON header that starts a packed result [bytes]."""

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
        """The result as bytes: a JSON header (values, event count, history sizes), the numeric
        event columns as float64, the event kinds as int8 codes (`quantities.EVENT_NAMES`), then
        the histories (``time`` first) as `Chunk` s."""
        numeric = [name for name in EVENT_COLUMNS if name != "kind"]
        chunks = {"time": Chunk.of(self.time)} if self.histories else {}
        chunks.update((name, Chunk.of(values)) for name, values in self.histories.items())
        header = json.dumps(
            {
                "values": {name: _plain(value) for name, value in self.values.items()},
                "events": len(self.events["kind"]),
                "chunks": [[name, chunk.size, len(chunk.data)] for name, chunk in chunks.items()],
            }
        ).encode()
        kinds = kind_codes(self.events["kind"]).tobytes()
        parts = [_HEADER.pack(len(header)), header]
        parts += [np.asarray(self.events[name], dtype=_SAMPLE).tobytes() for name in numeric]
        parts += [kinds, *(chunk.data for chunk in chunks.values())]
        return b"".join(parts)


@dataclass(frozen=True)
class Packed:
    """A packed result read back: what the results file is written from.

    Attributes
    ----------
    bridge, record : ids
    values : the scalar columns of the peak table [SI]
    events : name → array (`EVENT_COLUMNS`); ``kind`` as the file stores it, int8 codes of
        `quantities.EVENT_NAMES`
    histories : name → `Chunk`, ``time`` first; empty when the study keeps no histories
    """

    bridge: str
    record: str
    values: dict[str, Any]
    events: dict[str, np.ndarray]
    histories: dict[str, Chunk]

    @property
    def status(self) -> str:
        """``ok``, ``solver_error`` or ``error`` (`layout.STATUSES`)."""
        return self.values["status"]

    @classmethod
    def unpack(cls, bridge: str, record: str, blob: bytes) -> Packed:
        """Read the bytes of `AnalysisResult.pack`."""
        (length,) = _HEADER.unpack_from(blob)
        start = _HEADER.size + length
        header = json.loads(blob[_HEADER.size : start])
        count = header["events"]
        events: dict[str, np.ndarray] = {}
        for name in EVENT_COLUMNS:
            if name != "kind":
                events[name] = np.frombuffer(blob, _SAMPLE, count, start)
                start += count * _SAMPLE.itemsize
        events["kind"] = np.frombuffer(blob, np.int8, count, start)
        start += count
        histories = {}
        for name, size, length in header["chunks"]:
            histories[name] = Chunk(size, blob[start : start + length])
            start += length
        return cls(bridge, record, header["values"], events, histories)


def _plain(value: Any) -> Any:
    """A JSON value: numpy scalars as Python ones (floats round-trip exactly, NaN included)."""
    return value.item() if isinstance(value, np.generic) else value
