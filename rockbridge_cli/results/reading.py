"""Reading a results file back: the peak table, one analysis's events and histories, the bridges,
the intensity and spectrum sections (typed: `sections`).

Reading needs h5py and numpy only; the readers that return pandas DataFrames import pandas when
they are called, so that a command printing a table starts quickly.
"""

from __future__ import annotations

import json
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import h5py
import numpy as np

from ..core.quantities import DEVICE_LIMIT_STATES, HISTORY_UNITS, history_unit, is_device_history
from ..errors import InputError, did_you_mean, nearest
from ..paths import journal_path
from .layout import (
    COUNT_COLUMNS,
    EVENT_COLUMNS,
    FORMAT,
    FORMAT_VERSION,
    READABLE_VERSIONS,
    TEXT_DIGEST,
    digest_update,
    text_digests,
)
from .packing import DEVICE_NUMBERS, DEVICE_RECORD, AnalysisResult, device_states
from .sections import IntensitySection, SpectrumSection

if TYPE_CHECKING:
    import pandas as pd


@contextmanager
def open_results(path: str | Path) -> Iterator[h5py.File]:
    """Open a results file for reading.

    Raises
    ------
    InputError
        The file is missing, not HDF5, or not a rockbridge results file; or a part the reader
        needs is missing or cannot be read.
    """
    path = Path(path)
    if path.exists() and not path.is_file():  # a folder, a FIFO (opening one waits), a device
        kind = "a folder" if path.is_dir() else "not a regular file (a device or a pipe?)"
        raise InputError(path, [("", f"is {kind}, not a results file")])
    if not path.is_file():
        if journal_path(path).is_file():  # a run stopped before it wrote the file
            reason = (f"file not found, but the journal of a run that was stopped before writing "
                      f"it is beside it ({journal_path(path).name}): run the study again to "
                      "resume and write the file")  # fmt: skip
            raise InputError(path, [("", reason)])
        raise InputError(path, [("", f"file not found{did_you_mean(path)}")])
    try:
        file = h5py.File(path, "r")
    except OSError as exc:
        from ..kinds import expecting

        with expecting(path, "results"):  # a study or a bridge given for its results is named
            reason = f"not a readable HDF5 file, or damaged ({exc})"
            raise InputError(path, [("", reason)]) from None
    with file:
        if file.attrs.get("format") != FORMAT:
            raise InputError(path, [("", "not a rockbridge results file (no 'format' attribute)")])
        version = int(file.attrs.get("format_version", 0))
        if version not in READABLE_VERSIONS:
            which = "newer" if version > FORMAT_VERSION else "older"
            advice = "please upgrade" if version > FORMAT_VERSION else "run the study again"
            raise InputError(
                path, [("", f"written by an {which} rockbridge (format {version}); {advice}")]
            )
        try:
            yield file
        except (OSError, KeyError) as exc:  # a part is missing or cannot be read
            raise InputError(path, [("", f"damaged or incomplete results file ({exc})")]) from None


def incompleteness(attributes: Mapping[str, Any]) -> str | None:
    """What a results file that its run did not finish lacks, from its root's attributes:
    ``incomplete: 24 of 30 analyses``, or for an IDA stopped before every curve reached its end
    ``incomplete: the IDA stopped after 120 analyses``; None for a finished file (or one written
    before files said it)."""
    if bool(attributes.get("complete", True)):
        return None
    done, total = int(attributes.get("n_complete", 0)), int(attributes.get("n_analyses", 0))
    if done < total:
        return f"incomplete: {done} of {total} analyses"
    return f"incomplete: the IDA stopped after {done} analyses, before every curve ended"


OWN_HEAD = 65536
"""Bytes at the start of a results file that hold its root's ``format`` attribute (written
first, in the root's object header, at about 2 KiB) [bytes]."""


def is_results_file(path: str | Path) -> bool:
    """Whether a file is a rockbridge results file, of any format version (its root's ``format``
    attribute), or one damaged (cut short, say) that still starts with HDF5's signature and holds
    that attribute in its first `OWN_HEAD` bytes: what ``run --overwrite`` and ``merge
    --overwrite`` may replace."""
    try:
        with h5py.File(path, "r") as file:
            return file.attrs.get("format") == FORMAT
    except OSError:  # not HDF5, or damaged beyond its root
        pass
    try:
        with open(path, "rb") as stream:
            head = stream.read(OWN_HEAD)
    except OSError:
        return False
    return head.startswith(b"\x89HDF\r\n\x1a\n") and FORMAT.encode() in head


def verify(file: h5py.File) -> None:
    """Read every dataset of an open results file, so that HDF5 verifies the checksum of each
    (Fletcher-32: every numeric dataset, the peaks, events, histories and records' samples), and
    compare the text columns of ``/peaks`` with their stored SHA-256 (`layout.TEXT_DIGEST`,
    where the file has it). What `study.run` does before it calls the analyses of a file done.

    Raises
    ------
    OSError
        A dataset fails its checksum or cannot be read, or a text column differs from its
        digest (`open_results` names the file: damaged).
    """

    def read(name: str, node: Any) -> None:
        if isinstance(node, h5py.Dataset) and node.shape and node.size:  # (no chunk in 0 rows)
            try:
                for chunk in node.iter_chunks() if node.chunks else (Ellipsis,):
                    node[chunk]  # HDF5 checks each chunk's checksum as it reads it
            except (ValueError, RuntimeError) as exc:  # h5py's words for a damaged structure
                raise OSError(f"/{name}: {exc}") from None

    file.visititems(read)
    stored = json.loads(file["peaks"].attrs.get(TEXT_DIGEST, "{}"))
    digests = text_digests(stored)
    for name, digest in digests.items():
        try:
            digest_update(digest, file["peaks"][name].asstr()[()].tolist())
        except UnicodeDecodeError:
            raise OSError(f"/peaks/{name} is not UTF-8 text") from None
        if digest.hexdigest() != stored[name]:
            raise OSError(f"/peaks/{name} differs from its SHA-256 ({TEXT_DIGEST})")


def peak_columns(file: h5py.File) -> dict[str, np.ndarray]:
    """The columns of the peak table of an open results file: text as ``str`` arrays, counts as
    int64 (−1 where the analysis could not run), the rest float64 [SI]; in a sweep, then one
    column per swept field (its dotted path) with each row's bridge's value (`swept_values`)."""
    group = file["peaks"]
    columns = {}
    for name in json.loads(group.attrs["columns"]):
        values = group[name][()]
        if values.dtype.kind in "OS":
            values = np.array([v.decode() if isinstance(v, bytes) else str(v) for v in values])
        columns[name] = values
    if "devices" in file:  # the tendons' limit states of each analysis (`device_states`)
        tables = device_tables(file)
        states = [device_states(tables.get(pair, _NO_DEVICES))
                  for pair in zip(columns["bridge"], columns["record"], strict=True)]  # fmt: skip
        for state in DEVICE_LIMIT_STATES:
            columns[state] = np.array([found[state] for found in states], dtype=float)
    swept = swept_values(file)
    for path in dict.fromkeys(path for values in swept.values() for path in values):
        columns[path] = np.array([swept[b].get(path, np.nan) for b in columns["bridge"]])
    return columns


_NO_DEVICES = np.zeros(0, DEVICE_RECORD)


def device_tables(file: h5py.File) -> dict[tuple[str, str], np.ndarray]:
    """The device table of an open results file (`layout.DEVICE_COLUMNS`) as each analysis's
    rows (`packing.DEVICE_RECORD`), by (bridge, record); empty without ``/devices``."""
    if "devices" not in file:
        return {}
    group = file["devices"]
    rows = np.zeros(len(group["device"]), DEVICE_RECORD)
    rows["device"] = group["device"][()]
    for name in DEVICE_NUMBERS:
        rows[name] = group[name][()]
    pairs = list(zip(group["bridge"].asstr()[()], group["record"].asstr()[()], strict=True))
    tables: dict[tuple[str, str], np.ndarray] = {}
    start = 0
    for stop in range(1, len(pairs) + 1):  # each analysis's rows are one run of the table
        if stop == len(pairs) or pairs[stop] != pairs[start]:
            tables[pairs[start]] = rows[start:stop]
            start = stop
    return tables


def swept_values(file: h5py.File) -> dict[str, dict[str, float]]:
    """Per bridge, the value of every swept field (path → value; empty outside a sweep)."""
    return {
        name: json.loads(node.attrs.get("swept", "{}")) for name, node in file["bridges"].items()
    }


UNFINISHED = "finish the study (rockbridge run), or merge its shards (rockbridge merge), first"
"""What a file that lacks some of its study's analyses needs, where a command needs them all
(`partial`)."""


def partial(file: h5py.File) -> bool:
    """Whether an open results file holds part of its study: a shard, or a run stopped before
    its end."""
    return stored_shard_of(file) is not None or incompleteness(file.attrs) is not None


def bridge_samples(file: h5py.File) -> dict[str, dict[str, Any]]:
    """Per sampled bridge, its place in the design (``index``; ``matrix`` and ``field`` in a
    saltelli design: `config.uncertainty.Sample`); bridges that were not sampled are left out."""
    return {
        name: json.loads(node.attrs["sample"])
        for name, node in file["bridges"].items()
        if "sample" in node.attrs
    }


def peak_units(file: h5py.File) -> dict[str, str]:
    """The unit of each column of the peak table."""
    group = file["peaks"]
    units = {name: group[name].attrs["units"] for name in json.loads(group.attrs["columns"])}
    if "devices" in file:
        units.update(dict.fromkeys(DEVICE_LIMIT_STATES, "-"))
    for node in file["bridges"].values():
        units.update(json.loads(node.attrs.get("swept_units", "{}")))
    return units


def read_peaks(path: str | Path) -> pd.DataFrame:
    """The peak table: one row per bridge × record, SI values; units in ``DataFrame.attrs``.

    Counts are nullable integers (``<NA>`` where the analysis could not run).
    """
    import pandas as pd

    with open_results(path) as file:
        columns, units = peak_columns(file), peak_units(file)
    frame = pd.DataFrame(
        {
            name: pd.array(_missing_below_zero(values), dtype="Int64")
            if name in COUNT_COLUMNS
            else values
            for name, values in columns.items()
        }
    )
    frame.attrs["units"] = units
    return frame


def stored_shard_of(file: h5py.File) -> tuple[int, int] | None:
    """(index, count) of the shard an open results file holds (0-based), None for a whole study."""
    if "shard_index" not in file.attrs:
        return None
    return int(file.attrs["shard_index"]), int(file.attrs["shard_count"])


def history_arrays(
    file: h5py.File, path: str | Path, bridge: str, record: str
) -> dict[str, np.ndarray]:
    """The stored histories of one analysis of an open results file, ``time`` first [SI].

    Raises
    ------
    InputError
        No such analysis, or the study kept no histories.
    """
    row = _row(file, path, bridge, record)
    group = file.get(f"analyses/{bridge}/{record}/histories")
    if group is None:
        reason = file["peaks/message"].asstr()[row] or (
            "the study kept no histories (output.histories)")  # fmt: skip
        raise InputError(path, [(f"analyses/{bridge}/{record}", f"no histories: {reason}")])
    return {name: group[name][()] for name in ["time", *_history_names(group)]}


def _history_names(group: h5py.Group) -> list[str]:
    """The histories a ``histories`` group holds: those of `HISTORY_UNITS` in its order, then
    the devices' (`core.quantities.is_device_history`)."""
    return [
        *(name for name in HISTORY_UNITS if name in group),
        *(name for name in group if is_device_history(name)),
    ]


def event_arrays(
    file: h5py.File, path: str | Path, bridge: str, record: str
) -> dict[str, np.ndarray]:
    """The events of one analysis of an open results file (`EVENT_COLUMNS`) [SI].

    Raises
    ------
    InputError
        No such analysis.
    """
    starts = _event_starts(file["peaks/n_events"][()])
    return _events(file, starts, _row(file, path, bridge, record))


def ground_motion(
    file: h5py.File, path: str | Path, bridge: str, record: str
) -> tuple[float, np.ndarray]:
    """The ground motion of one analysis of an open results file: the time step [s] and the
    acceleration from t = 0 [m/s²], scaled by the analysis's factor where an IDA scales the
    stored record per analysis, or by the record's where stripes store their records as read.

    Raises
    ------
    InputError
        No such analysis, or its record was not read.
    """
    row = _row(file, path, bridge, record)
    node, scale, samples = file.get(f"records/{record}"), 1.0, "acceleration"
    if node is None and "base_record" in file["peaks"]:  # an IDA's: the base record × scale
        node = file.get(f"records/{file['peaks/base_record'].asstr()[row]}")
        scale = float(file["peaks/scale"][row])
    elif node is not None and "base_acceleration" in node:  # stripes' (format 4): × its scale
        scale, samples = float(node.attrs["scale"]), "base_acceleration"
    if node is None or samples not in node:
        reason = "no ground motion (the record was not read)"
        raise InputError(path, [(f"records/{record}", reason)])
    return float(node.attrs["time_step"]), scale * node[samples][()]


def read_history(path: str | Path, bridge: str, record: str) -> pd.DataFrame:
    """The stored histories of one analysis, indexed by time [s]; units in ``DataFrame.attrs``.

    Raises
    ------
    InputError
        No such analysis, or the study kept no histories.
    """
    import pandas as pd

    with open_results(path) as file:
        arrays = history_arrays(file, path, bridge, record)
    time = arrays.pop("time")
    frame = pd.DataFrame(arrays, index=pd.Index(time, name="time"))
    frame.attrs["units"] = {"time": "s", **{name: history_unit(name) for name in arrays}}
    return frame


def read_events(path: str | Path, bridge: str, record: str) -> pd.DataFrame:
    """The events of one analysis (`EVENT_COLUMNS`); units in ``DataFrame.attrs``."""
    import pandas as pd

    with open_results(path) as file:
        events = event_arrays(file, path, bridge, record)
    frame = pd.DataFrame(events)
    frame.attrs["units"] = {name: unit for name, (unit, _) in EVENT_COLUMNS.items()}
    return frame


def stored_results(file: h5py.File) -> Iterator[AnalysisResult]:
    """Every analysis an open results file holds, as the result that was stored, in the order
    of the file (for a run that resumes and writes a new file from the old one)."""
    columns = peak_columns(file)
    starts = _event_starts(columns["n_events"])
    devices = device_tables(file)
    for row, (bridge, record) in enumerate(zip(columns["bridge"], columns["record"], strict=True)):
        values = {name: _item(values[row]) for name, values in columns.items()}
        del values["bridge"], values["record"]
        events = _events(file, starts, row)
        group = file.get(f"analyses/{bridge}/{record}/histories")
        names = [] if group is None else _history_names(group)
        yield AnalysisResult(
            bridge, record, values,
            time=group["time"][()] if names else np.zeros(0),
            histories={name: group[name][()] for name in names},
            events=events,
            devices=devices.get((bridge, record), _NO_DEVICES),
        )  # fmt: skip


def bridge_attributes(file: h5py.File) -> dict[str, dict[str, Any]]:
    """Per bridge of an open results file, in the study's order: its name, model constants and
    summary values [SI] (the attributes of ``/bridges/<id>`` but its config and units)."""
    order = [item["id"] for item in json.loads(file.attrs["config"])["bridges"]]
    return {
        bridge: {k: _item(v) for k, v in file["bridges"][bridge].attrs.items()
                 if k not in ("config", "units")}
        for bridge in order
    }  # fmt: skip


def read_bridges(path: str | Path) -> pd.DataFrame:
    """One row per bridge (index: id) with its name, model constants and summary values [SI]."""
    import pandas as pd

    with open_results(path) as file:
        rows = bridge_attributes(file)
    return pd.DataFrame.from_dict(rows, orient="index")


def read_intensity(file: h5py.File) -> IntensitySection | None:
    """The intensity section of an open results file (`sections.IntensitySection`), None where
    its study has none.

    Raises
    ------
    InputError
        The file's ``intensity`` attribute is not an intensity section.
    """
    stored = json.loads(file.attrs.get("intensity", "null"))
    if stored is None:
        return None
    try:
        return IntensitySection.of(stored)
    except (KeyError, TypeError, ValueError) as exc:
        reason = f"not an intensity section ({exc})"
        raise InputError(file.filename, [("intensity", reason)]) from None


def read_spectrum_section(file: h5py.File) -> SpectrumSection | None:
    """The spectrum section of an open results file (`sections.SpectrumSection`), None where its
    study is not an overturning spectrum.

    Raises
    ------
    InputError
        The spectrum in the file's ``config`` attribute is not a spectrum section.
    """
    stored = json.loads(file.attrs.get("config", "{}")).get("spectrum")
    if stored is None:
        return None
    try:
        return SpectrumSection.of(stored)
    except (KeyError, TypeError, ValueError) as exc:
        reason = f"not a spectrum section ({exc})"
        raise InputError(file.filename, [("config.spectrum", reason)]) from None


def read_config_hash(path: str | Path) -> str:
    """The hash of the resolved study a results file was made from (`Study.config_hash`)."""
    with open_results(path) as file:
        return str(file.attrs["config_hash"])


def _row(file: h5py.File, path: str | Path, bridge: str, record: str) -> int:
    """The row of an analysis in the peak table."""
    bridges, records = file["peaks/bridge"].asstr()[()], file["peaks/record"].asstr()[()]
    found = np.flatnonzero((bridges == bridge) & (records == record))
    if not found.size:
        if bridge not in bridges:
            why = f"no bridge {bridge}; {nearest(bridge, bridges.tolist(), 'bridges')}"
        else:
            mine = records[bridges == bridge].tolist()
            why = f"no record {record} under {bridge}; {nearest(record, mine, 'records')}"
        raise InputError(path, [("", f"no analysis {bridge}/{record}: {why}")])
    return int(found[0])


def _event_starts(counts: np.ndarray) -> np.ndarray:
    """Where each row's events start in /events, from /peaks/n_events (one more: the end)."""
    return np.concatenate([[0], np.cumsum(counts)])


def _events(file: h5py.File, starts: np.ndarray, row: int) -> dict[str, np.ndarray]:
    """The events of the analysis in ``row`` of the peak table."""
    start, stop = int(starts[row]), int(starts[row + 1])
    return {name: _event_column(file["events"][name], start, stop) for name in EVENT_COLUMNS}


def _event_column(dataset: h5py.Dataset, start: int, stop: int) -> np.ndarray:
    """Rows ``start:stop`` of an /events column; kinds by name (format 3 stores CF flag codes,
    format 2 strings)."""
    values = dataset[start:stop]
    if "flag_meanings" not in dataset.attrs:
        return _decoded(values)
    meanings = np.array(str(dataset.attrs["flag_meanings"]).split())
    return meanings[np.searchsorted(dataset.attrs["flag_values"], values)]


def _decoded(values: np.ndarray) -> np.ndarray:
    if values.dtype.kind in "OS":
        return np.array([v.decode() if isinstance(v, bytes) else str(v) for v in values], dtype=str)
    return values


def _item(value: Any) -> Any:
    return value.item() if isinstance(value, np.generic) else value


def _missing_below_zero(counts: np.ndarray) -> np.ndarray:
    """A count column with None where the file stores −1 (no result)."""
    out = counts.astype(object)
    out[counts < 0] = None
    return out
