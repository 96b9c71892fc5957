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
import math
import struct
import zlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from ..core.devices import Damper, Device, Tendon, names
from ..core.quantities import DEVICE_LIMIT_STATES, PEAK_NAMES, kept_history
from .layout import (
    COMPRESSION,
    COUNT_COLUMNS,
    DEVICE_COLUMNS,
    DEVICE_FLAGS,
    DEVICE_TEXTS,
    EVENT_COLUMNS,
    PEAK_COLUMNS,
    TEXT_COLUMNS,
    kind_codes,
    missing,
)

if TYPE_CHECKING:
    from ..core.analysis import Response, Summary
    from ..core.batch import Summaries

NUMBERS = tuple(name for name in PEAK_COLUMNS if name not in TEXT_COLUMNS)
"""The numeric columns of the peak table, in the order a packed result stores them (counts too:
float64 holds them exactly)."""

TEXTS = tuple(name for name in TEXT_COLUMNS if name not in ("bridge", "record"))
"""The text columns a packed result stores (the ids travel beside it)."""

EVENT_RECORD = np.dtype([(name, "i1" if name == "kind" else "<f8") for name in EVENT_COLUMNS])
"""One event as a packed result stores it: the columns of `EVENT_COLUMNS`, float64 but the kind,
an int8 code of `quantities.EVENT_NAMES` (as the results file stores it)."""

DEVICE_NUMBERS = tuple(name for name in DEVICE_COLUMNS if name not in DEVICE_TEXTS)
"""The numeric columns of the device table, in the order a packed result stores them."""

DEVICE_RECORD = np.dtype(
    [("device", "S16")]
    + [(name, "i1" if name in DEVICE_FLAGS else "<f8") for name in DEVICE_NUMBERS]
)
"""One device's row of an analysis as a packed result stores it: its name (ASCII), then the
device table's columns (`layout.DEVICE_COLUMNS`) but the ids."""

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
    histories : name → array at ``time``; units as `core.quantities.history_unit` gives them
    events : name → array; units in `EVENT_COLUMNS`
    devices : one `DEVICE_RECORD` row per device of the bridge (none without devices, or
        without results)
    """

    bridge: str
    record: str
    values: dict[str, Any]
    time: np.ndarray = field(default_factory=lambda: np.zeros(0))
    histories: dict[str, np.ndarray] = field(default_factory=dict)
    events: dict[str, np.ndarray] = field(default_factory=dict)
    devices: np.ndarray = field(default_factory=lambda: np.zeros(0, DEVICE_RECORD))

    @property
    def status(self) -> str:
        """``ok``, ``solver_error`` or ``error`` (`layout.STATUSES`)."""
        return self.values["status"]

    @classmethod
    def from_response(
        cls,
        bridge: str,
        record: str,
        response: Response,
        keep: Sequence[str],
        wall_time: float,
        devices: tuple[Device, ...] = (),
    ) -> AnalysisResult:
        """The result of a finished analysis, keeping the histories named in ``keep``; with the
        bridge's ``devices`` (`core.devices`), their rows (`device_rows`)."""
        values = {k: v for k, v in response.peak_row().items() if k in PEAK_COLUMNS}
        values.update(
            outcome(response.status),
            wall_time_s=wall_time,
            n_events=len(response.events["time"]),
            rechecked=0,
            base_record=record,
            intensity=float("nan"),
            scale=1.0,
        )
        events = {**response.events, "kind": response.events["kind"].astype(str)}
        histories = {
            name: values for name, values in response.histories.items() if kept_history(name, keep)
        }
        return cls(
            bridge,
            record,
            values,
            response.time if keep else np.zeros(0),
            histories,
            events,
            device_rows(devices, response.peaks),
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
        texts = _texts(self.values)
        numbers = np.array([self.values[name] for name in NUMBERS], dtype=_SAMPLE)
        events = event_rows({**self.events, "kind": kind_codes(self.events["kind"])})
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
                      histories, self.devices.astype(DEVICE_RECORD).tobytes())  # fmt: skip


def outcome(status: str) -> dict[str, str]:
    """The ``status`` and ``message`` columns of an analysis that ran, from its solver's status
    (``ok``, or why it stopped early)."""
    ok = status == "ok"
    return {"status": "ok" if ok else "solver_error", "message": "" if ok else status}


def event_rows(columns: Mapping[str, np.ndarray]) -> np.ndarray:
    """The `EVENT_RECORD` rows of an analysis's events, given by column (`EVENT_COLUMNS`; the
    kinds as codes of `core.quantities.EVENT_NAMES`)."""
    rows = np.empty(len(columns["kind"]), EVENT_RECORD)
    for name in EVENT_COLUMNS:
        rows[name] = columns[name]
    return rows


def _texts(values: Mapping[str, Any]) -> str:
    """The text columns of `TEXTS` among an analysis's ``values``, as a packed result stores
    them (`Packed.texts`)."""
    return "\0".join(values[name].replace("\0", "\ufffd") for name in TEXTS)


_PEAKS_AT = [NUMBERS.index(f"{name}_{part}") for name in PEAK_NAMES for part in ("max", "time")]
"""Where each peak and its time go in `NUMBERS`, in the order of `Summary.peaks`' values."""

_SUMMARY_NUMBERS = (
    "t_onset", "n_impacts", "n_poundings", "failure_time", "n_impacts_significant",
    "dcr_backfill", "dcr_overturning", "steps", "rejected_steps",
)  # fmt: skip
"""The numeric fields of a `core.analysis.Summary` that are columns of the peak table."""

_OTHER_NUMBERS = ("solve_time_s", "wall_time_s", "n_events", "rechecked", "intensity", "scale")
"""The numeric columns a packed summary (`pack_summary`) takes besides the summary's."""

_SUMMARY_AT = [NUMBERS.index(name) for name in _SUMMARY_NUMBERS + _OTHER_NUMBERS]
assert sorted(_PEAKS_AT + _SUMMARY_AT) == list(range(len(NUMBERS))), "a column left unfilled"


def pack_summary(
    bridge: str,
    record: str,
    summary: Summary,
    devices: np.ndarray,
    scaled: tuple[str, float, float],
    timings: tuple[float, float],
    rechecked: int = 0,
) -> Packed:
    """The packed result (`Packed`) of an analysis that ran and keeps no histories, straight
    from its summary (`core.analysis.Summary`): the same bytes as its `AnalysisResult`'s
    `pack`, without building the result.

    Parameters
    ----------
    bridge, record
        The ids.
    summary
        What the analysis says.
    devices
        The devices' rows (`device_rows`), none without devices.
    scaled
        The record before scaling, the intensity level and the factor (the columns
        ``base_record``, ``intensity`` and ``scale``).
    timings
        The wall times of the integration and of the analysis [s].
    rechecked
        The ``rechecked`` column: 0, or 1 and 2 for an analysis run again at ``reference``
        (`study.work.analyze_cell`).
    """
    base_record, intensity, scale = scaled
    numbers = np.empty(len(NUMBERS), _SAMPLE)
    numbers[_PEAKS_AT] = summary.peaks.ravel()
    numbers[_SUMMARY_AT] = [
        *(getattr(summary, name) for name in _SUMMARY_NUMBERS),
        *timings, len(summary.events.time), rechecked, intensity, scale,
    ]  # fmt: skip
    texts = _texts(
        {"base_record": base_record, "failure_mode": summary.failure_mode,
         "model": summary.model, **outcome(summary.status)}
    )  # fmt: skip
    events = event_rows(summary.events._asdict())
    return Packed(bridge, record, texts, numbers.tobytes(), events.tobytes(), b"",
                  devices.astype(DEVICE_RECORD).tobytes())  # fmt: skip


def pack_summaries(
    bridge: str,
    records: Sequence[tuple[str, str, float, float]],
    summaries: Summaries,
    timings: np.ndarray,
) -> list[Packed]:
    """The packed results of a batch of analyses of one bridge without devices that ran and keep
    no histories, straight from their summaries (`core.batch.Summaries`): each the same bytes as
    `pack_summary` of its analysis (``rechecked`` 0), the numbers and events packed by column
    for the whole batch.

    Parameters
    ----------
    bridge
        The bridge's id.
    records
        Each analysis's record: its id, the record before scaling, the intensity level and the
        factor (the columns ``record``, ``base_record``, ``intensity`` and ``scale``).
    summaries
        What the analyses say, in the order of ``records``.
    timings
        (n, 2) the wall times of each integration and of each analysis [s].
    """
    count = len(records)
    numbers = np.empty((count, len(NUMBERS)), _SAMPLE)
    numbers[:, _PEAKS_AT] = summaries.peaks.reshape(count, -1)
    starts = summaries.event_starts
    levels, scales = [r[2] for r in records], [r[3] for r in records]
    numbers[:, _SUMMARY_AT] = np.column_stack(
        [
            *(getattr(summaries, name) for name in _SUMMARY_NUMBERS),
            timings[:, 0], timings[:, 1], np.diff(starts), np.zeros(count), levels, scales,
        ]
    )  # fmt: skip
    rows = event_rows(summaries.events._asdict())
    packed, model = [], summaries.model
    for (record, base, _, _), row, failure_mode, status, start, end in zip(
        records, numbers, summaries.failure_mode, summaries.status, starts[:-1].tolist(),
        starts[1:].tolist(), strict=True,
    ):  # fmt: skip
        texts = {"base_record": base, "failure_mode": failure_mode, "model": model}
        packed.append(Packed(bridge, record, _texts(texts | outcome(status)), row.tobytes(),
                             rows[start:end].tobytes(), b"", b""))  # fmt: skip
    return packed


def device_rows(devices: tuple[Device, ...], peaks: dict[str, tuple[float, float]]) -> np.ndarray:
    """The `DEVICE_RECORD` rows of a bridge's ``devices`` from an analysis's peaks (name →
    (value, time), `core.analysis.Response.peaks`): a tendon's strain is ε0 + Δ_max/L_free
    (`core.devices.Tendon.strain` of P0 + k·Δ_max), a dissipator's Δ_max/L_d; whether it yielded
    and broke (ruptured, fractured) is the solver's state (``<name>_yielded``, ``<name>_broken``),
    −1 where the device states no such limit."""
    rows = np.zeros(len(devices), DEVICE_RECORD)
    if not devices:
        return rows
    for row, device, name in zip(rows, devices, names(devices), strict=True):
        (length, length_time), (force, force_time) = (
            peaks[f"{name}_elongation"], peaks[f"{name}_force"]
        )  # fmt: skip
        row["device"] = name.encode()
        row["elongation_max"], row["elongation_time"] = length, length_time
        row["force_max"], row["force_time"] = force, force_time
        row["strain_max"], row["yielded"], row["ruptured"] = math.nan, -1, -1  # a damper's
        if isinstance(device, Damper):
            continue
        yielded, broken = peaks[f"{name}_yielded"][0], peaks[f"{name}_broken"][0]
        if isinstance(device, Tendon):
            stated = (device.yield_force, device.rupture_strain)
            elastic = device.prestress + device.stiffness * length
            row["strain_max"] = (
                device.strain(elastic) if math.isfinite(device.rigidity) else math.nan
            )
        else:
            stated = (device.yield_force, device.fracture)
            row["strain_max"] = length / device.length if math.isfinite(device.length) else math.nan
        row["yielded"] = _flag(yielded, stated[0])
        row["ruptured"] = _flag(broken, stated[1])
    return rows


def device_states(rows: np.ndarray) -> dict[str, float]:
    """What an analysis's device rows (`DEVICE_RECORD` s) say of the tendons' limit states
    (`core.quantities.DEVICE_LIMIT_STATES`): 1.0 where a tendon reached it, 0.0 where the
    bridge's tendons state that limit and none reached it, NaN where none states it."""
    if not rows.size:  # no devices: no state
        return dict.fromkeys(DEVICE_LIMIT_STATES, math.nan)
    found = {}
    for state, flag in DEVICE_LIMIT_STATES.items():
        kind = state.split("_")[0].encode()  # tendon_yield: the tendons' rows
        mine = rows[np.char.startswith(rows["device"], kind)] if rows.size else rows
        stated = mine[flag][mine[flag] >= 0] if mine.size else np.zeros(0)
        found[state] = float(stated.max()) if stated.size else math.nan
    return found


def _flag(state: float, limit: float) -> int:
    """The flag of a limit the solver's ``state`` says was reached (1.0) or not (0.0): −1
    without a limit (inf) or a state (NaN)."""
    if math.isinf(limit) or math.isnan(state):
        return -1
    return int(state)


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
    devices : one `DEVICE_RECORD` row per device of the bridge; empty without devices
    """

    bridge: str
    record: str
    texts: str
    numbers: bytes
    events: bytes
    histories: bytes
    devices: bytes = b""

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
    def device_rows(self) -> np.ndarray:
        """The devices' rows as `DEVICE_RECORD` s (none without devices)."""
        return np.frombuffer(self.devices, DEVICE_RECORD)

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
