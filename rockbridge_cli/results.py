"""The results file: an HDF5 layout any HDF5 reader understands, and the readers of it.

::

    /                               study, versions, timestamps, config hash, fidelity knobs
    /records/<record>               acceleration [m/s2], time step, PGA, source file
    /bridges/<bridge>               bridge config, model constants and summarize() values
    /analyses/<bridge>/<record>     status, peaks, counts; histories/<name>, events/<name>
    /peaks/<column>                 one row per bridge × record, in the study's order

Every dataset has ``units`` and ``description`` attributes; a group's scalar attributes are
described by its ``units`` attribute, a JSON object mapping attribute names to units. All values
are SI. An analysis group is self-contained, so the runner can journal each one in a file of its
own and copy it into the results file unchanged (`write_analysis`, `write_results`).
"""

from __future__ import annotations

import json
import platform
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pandas as pd
import scipy

from . import __version__
from .config.study import Study
from .core.analysis import HISTORY_UNITS, PEAK_UNITS, Response
from .core.geometry import Model
from .core.summary import SUMMARY_UNITS, summarize
from .errors import InputError

FORMAT = "rockbridge-results"
FORMAT_VERSION = 1

STATUSES = {
    "ok": "the analysis ran to the end of the record or to a failure of the bridge",
    "solver_error": "the integrator stopped early (message says why); results up to there",
    "error": "the analysis could not run (message says why); no results",
}

HISTORY_TEXT = {
    "theta1": "rotation of the tall pier (pier 1), counter-clockwise positive",
    "theta1_rate": "angular velocity of the tall pier",
    "mode": "rocking mode: +1 p (counter-clockwise), -1 n, 0 at rest",
    "theta2": "rotation of the short pier (pier 2)",
    "theta_deck": "rotation of the deck, counter-clockwise positive",
    "u_deck": "horizontal displacement of the deck's centre of gravity",
    "v_deck": "vertical displacement (uplift) of the deck's centre of gravity",
    "u_pier1": "horizontal displacement of the tall pier's centre of gravity",
    "v_pier1": "vertical displacement of the tall pier's centre of gravity",
    "u_pier2": "horizontal displacement of the short pier's centre of gravity",
    "v_pier2": "vertical displacement of the short pier's centre of gravity",
}

EVENT_COLUMNS = {
    "time": ("s", "time of the event"),
    "kind": ("-", "onset, impact, pounding, reopening, rest or a failure"),
    "mode": ("-", "rocking mode after the event: +1 p, -1 n, 0 at rest"),
    "rate_before": ("rad/s", "angular velocity of the tall pier before the event"),
    "rate_after": ("rad/s", "angular velocity of the tall pier after the event"),
}


def _peak_columns() -> dict[str, tuple[str, str]]:
    columns = {"bridge": ("-", "bridge id"), "record": ("-", "record id")}
    for name, unit in PEAK_UNITS.items():
        how = "largest" if name == "v_deck" else "largest absolute"
        columns[f"{name}_max"] = (unit, f"{how} {name}: {HISTORY_TEXT[name]}")
        columns[f"{name}_time"] = ("s", f"time of {name}_max")
    columns.update(
        t_onset=("s", "first onset of rocking; NaN if the bridge never rocks"),
        n_impacts=("-", "impacts at the rocking interfaces; -1 without results"),
        n_poundings=("-", "deck-backwall poundings; -1 without results"),
        failure_mode=("-", "none, abutment, overturning_pier1 or overturning_pier2"),
        failure_time=("s", "time of failure; NaN without"),
        dcr=("-", "peak demand/capacity of the governing failure mode"),
        dcr_mode=("-", "the failure mode dcr refers to: abutment or overturning"),
        status=("-", "; ".join(f"{k}: {v}" for k, v in STATUSES.items())),
        message=("-", "why the analysis stopped early or could not run; empty if ok"),
        model=("-", "the model that ran (asymmetric-bridge, symmetric-frame, ...)"),
        solve_time_s=("s", "wall time of the integration"),
        wall_time_s=("s", "wall time of the whole analysis"),
        steps=("-", "accepted integration steps; -1 without results"),
        rejected_steps=("-", "rejected integration steps; -1 without results"),
    )
    return columns


PEAK_COLUMNS = _peak_columns()
"""Columns of the peak table: name → (unit, description)."""

_TEXT_COLUMNS = ("bridge", "record", "failure_mode", "dcr_mode", "status", "message", "model")
_COUNT_COLUMNS = ("n_impacts", "n_poundings", "steps", "rejected_steps")

_MODEL_UNITS = {
    "B": "m", "H1": "m", "H2": "m", "L1": "m", "L2": "m", "h": "m",
    "m1": "kg", "m2": "kg", "md": "kg", "I1": "kg m2", "I2": "kg m2", "Id": "kg m2",
    "g": "m/s2", "has_abutments": "-", "u_jo": "m", "k": "N/m", "c": "N s/m", "u_ab": "m",
    "e": "-", "m_abut": "kg",
}  # fmt: skip

_COMPRESSION = {"compression": "gzip", "compression_opts": 4, "shuffle": True}


@dataclass
class AnalysisResult:
    """What one bridge × record analysis produced, ready to store.

    Attributes
    ----------
    bridge, record : ids
    values : the scalar columns of the peak table (`PEAK_COLUMNS`, except the ids) [SI]
    time : sample times of the histories [s]
    histories : name → array at ``time``; units in `HISTORY_UNITS`
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
        """``ok``, ``solver_error`` or ``error`` (`STATUSES`)."""
        return self.values["status"]

    @classmethod
    def from_response(
        cls, bridge: str, record: str, response: Response, keep: Sequence[str], wall_time: float
    ) -> AnalysisResult:
        """The result of a finished analysis, keeping the histories named in ``keep``."""
        values = {k: v for k, v in response.summary().items() if k in PEAK_COLUMNS}
        ok = response.status == "ok"
        values.update(
            status="ok" if ok else "solver_error",
            message="" if ok else response.status,
            wall_time_s=wall_time,
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
        """An analysis that could not run: every value missing, status ``error``."""
        values = {name: _missing(name) for name in PEAK_COLUMNS if name not in ("bridge", "record")}
        values.update(status="error", message=message, wall_time_s=wall_time)
        return cls(bridge, record, values)


def _missing(column: str) -> Any:
    if column in _TEXT_COLUMNS:
        return ""
    return -1 if column in _COUNT_COLUMNS else float("nan")


# ---------------------------------------------------------------------------------------------
# Writing


def write_analysis(parent: h5py.Group, result: AnalysisResult) -> h5py.Group:
    """Write one analysis as the group ``parent/<record>``: attributes, histories and events."""
    group = parent.create_group(result.record)
    group.attrs["bridge"] = result.bridge
    group.attrs["record"] = result.record
    for name, value in result.values.items():
        group.attrs[name] = value
    _describe_attrs(group, {name: PEAK_COLUMNS[name][0] for name in result.values})
    if result.histories:
        histories = group.create_group("histories")
        _dataset(histories, "time", result.time, "s", "sample times", compress=True)
        for name, values in result.histories.items():
            _dataset(
                histories, name, values, HISTORY_UNITS[name], HISTORY_TEXT[name], compress=True
            )
    if result.status != "error":
        events = group.create_group("events")
        for name, (unit, text) in EVENT_COLUMNS.items():
            _dataset(events, name, result.events[name], unit, text)
    return group


def write_results(
    file: h5py.File, study: Study, sources: Sequence[Path | None], created: str, finished: str
) -> None:
    """Fill an empty results file.

    Parameters
    ----------
    file
        The new file, open for writing.
    study
        The study the results belong to.
    sources
        One entry per bridge × record in the study's order (`study_pairs`): the file (a journal
        entry or an earlier results file) whose ``/analyses/<bridge>/<record>`` group, written by
        `write_analysis`, is copied unchanged; None if the analysis has not run yet.
    created, finished
        Timestamps (ISO 8601).
    """
    done = sum(source is not None for source in sources)
    _write_header(file, study, created, finished, done, len(sources))
    _write_records(file.create_group("records"), study)
    _write_bridges(file.create_group("bridges"), study)
    root = file.create_group("analyses")
    copied = []
    for (bridge, record), source in zip(study_pairs(study), sources, strict=True):
        if source is None:
            continue
        parent = root.require_group(bridge)
        with h5py.File(source, "r") as origin:
            file.copy(origin[f"analyses/{bridge}/{record}"], parent, name=record)
        copied.append(parent[record])
    _write_peaks(file.create_group("peaks"), copied)


def study_pairs(study: Study) -> list[tuple[str, str]]:
    """(bridge id, record id) of every analysis of a study, in the order of the results."""
    return [(b.id, r.id) for b in study.bridges for r in study.records]


def _write_header(
    file: h5py.File, study: Study, created: str, finished: str, done: int, total: int
) -> None:
    knobs = study.resolved()["fidelity"]["knobs"]
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
            "created": created,
            "finished": finished,
            "complete": done == total,
            "n_analyses": total,
            "n_complete": done,
            "study_file": study.path.as_posix(),
            "study_yaml": study.text,
            "config": json.dumps(study.resolved(), indent=1),
            "config_hash": study.config_hash,
            "fidelity": study.preset,
            "knobs": json.dumps(knobs),
            "output_step": float(study.knobs["output_step"]),
            "histories": json.dumps(list(study.histories)),
        }
    )
    _describe_attrs(file, {"output_step": "s", "n_analyses": "-", "n_complete": "-"})


def _write_records(group: h5py.Group, study: Study) -> None:
    for item in study.records:
        node = group.create_group(item.id)
        node.attrs.update({"source": item.source, "sha256": item.digest, "error": item.error})
        record = item.record
        if record is None:
            continue
        node.attrs.update(
            {
                "name": record.name,
                "time_step": record.time_step,
                "n_samples": record.acceleration.size,
                "duration": record.duration,
                "pga": record.peak_acceleration,
            }
        )
        _describe_attrs(node, {"time_step": "s", "n_samples": "-", "duration": "s", "pga": "m/s2"})
        _dataset(node, "acceleration", record.acceleration, "m/s2", "ground acceleration, "
                 "positive to the right, from t = 0 at time_step", compress=True)  # fmt: skip


def _write_bridges(group: h5py.Group, study: Study) -> None:
    for item in study.bridges:
        model = item.config.to_model()
        summary = summarize(model, mirrored=item.config.mirrored)
        node = group.create_group(item.id)
        node.attrs.update(
            {
                "name": item.config.label(item.id),
                "source": item.source,
                "config": json.dumps(item.config.model_dump(mode="json"), indent=1),
                "model": summary["model"],
                "mirrored": item.config.mirrored,
                "governing_failure": summary["governing_failure"],
            }
        )
        units = dict(_flat_summary(summary, node))
        for name in Model._fields:
            node.attrs[f"model_{name}"] = getattr(model, name)
            units[f"model_{name}"] = _MODEL_UNITS[name]
        _describe_attrs(node, units)


def _flat_summary(summary: dict[str, Any], node: h5py.Group) -> Iterator[tuple[str, str]]:
    """Store the numbers of `summarize` (capacities as capacity_<limit>_<p|n>), yield units."""
    for name, unit in SUMMARY_UNITS.items():
        node.attrs[name] = np.nan if summary[name] is None else summary[name]
        yield name, unit
    for limit, rotations in summary["capacities"].items():
        for mode, value in rotations.items():
            node.attrs[f"capacity_{limit}_{mode}"] = value
            yield f"capacity_{limit}_{mode}", "rad"


def _write_peaks(group: h5py.Group, analyses: list[h5py.Group]) -> None:
    group.attrs["description"] = "one row per bridge × record in the study's order"
    group.attrs["columns"] = json.dumps(list(PEAK_COLUMNS))
    for name, (unit, text) in PEAK_COLUMNS.items():
        values = [node.attrs[name] for node in analyses]
        if name in _TEXT_COLUMNS:
            data = np.array(values, dtype=h5py.string_dtype())
        else:
            data = np.array(values, dtype=np.int64 if name in _COUNT_COLUMNS else float)
        _dataset(group, name, data, unit, text)


def _dataset(
    group: h5py.Group, name: str, data: np.ndarray, unit: str, text: str, compress: bool = False
) -> None:
    if data.dtype == object or data.dtype.kind == "U":
        data = np.array(data, dtype=h5py.string_dtype())
    options = _COMPRESSION if compress and data.size else {}
    dataset = group.create_dataset(name, data=data, **options)
    dataset.attrs["units"] = unit
    dataset.attrs["description"] = text


def _describe_attrs(node: h5py.Group | h5py.File, units: dict[str, str]) -> None:
    node.attrs["units"] = json.dumps(units)


# ---------------------------------------------------------------------------------------------
# Reading


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
    if not path.is_file():
        raise InputError(path, [("", "file not found")])
    try:
        file = h5py.File(path, "r")
    except OSError as exc:
        raise InputError(path, [("", f"not a readable HDF5 file, or damaged ({exc})")]) from None
    with file:
        if file.attrs.get("format") != FORMAT:
            raise InputError(path, [("", "not a rockbridge results file (no 'format' attribute)")])
        version = int(file.attrs.get("format_version", 0))
        if version > FORMAT_VERSION:
            raise InputError(
                path, [("", f"written by a newer rockbridge (format {version}); please upgrade")]
            )
        try:
            yield file
        except (OSError, KeyError) as exc:  # a part is missing or cannot be read
            raise InputError(path, [("", f"damaged or incomplete results file ({exc})")]) from None


def stored_analyses(file: h5py.File) -> dict[tuple[str, str], h5py.Group]:
    """The analysis groups of an open results (or journal) file, by (bridge, record)."""
    found = {}
    for bridge in file.get("analyses", {}).values():
        for node in bridge.values():
            found[(node.attrs["bridge"], node.attrs["record"])] = node
    return found


def read_peaks(path: str | Path) -> pd.DataFrame:
    """The peak table: one row per bridge × record, SI values; units in ``DataFrame.attrs``.

    Counts are nullable integers (``<NA>`` where the analysis could not run).
    """
    with open_results(path) as file:
        group = file["peaks"]
        columns = {name: group[name][()] for name in json.loads(group.attrs["columns"])}
        units = {name: group[name].attrs["units"] for name in columns}
    frame = pd.DataFrame({name: _column(name, values) for name, values in columns.items()})
    frame.attrs["units"] = units
    return frame


def _column(name: str, values: np.ndarray) -> Any:
    if values.dtype.kind in "OS":
        return [v.decode() if isinstance(v, bytes) else str(v) for v in values]
    if name in _COUNT_COLUMNS:
        return pd.array(np.where(values < 0, None, values), dtype="Int64")
    return values


def read_history(path: str | Path, bridge: str, record: str) -> pd.DataFrame:
    """The stored histories of one analysis, indexed by time [s]; units in ``DataFrame.attrs``.

    Raises
    ------
    InputError
        No such analysis, or the study kept no histories.
    """
    with open_results(path) as file:
        node = _analysis(file, path, bridge, record)
        if "histories" not in node:
            reason = node.attrs["message"] or "the study kept no histories (output.histories)"
            raise InputError(path, [(f"analyses/{bridge}/{record}", f"no histories: {reason}")])
        group = node["histories"]
        names = [name for name in HISTORY_UNITS if name in group]
        frame = pd.DataFrame(
            {name: group[name][()] for name in names},
            index=pd.Index(group["time"][()], name="time"),
        )
        frame.attrs["units"] = {name: group[name].attrs["units"] for name in ("time", *names)}
    return frame


def read_events(path: str | Path, bridge: str, record: str) -> pd.DataFrame:
    """The events of one analysis (`EVENT_COLUMNS`); units in ``DataFrame.attrs``."""
    with open_results(path) as file:
        node = _analysis(file, path, bridge, record)
        group = node.get("events")
        data = {name: (_column(name, group[name][()]) if group else []) for name in EVENT_COLUMNS}
    frame = pd.DataFrame(data)
    frame.attrs["units"] = {name: unit for name, (unit, _) in EVENT_COLUMNS.items()}
    return frame


def read_bridges(path: str | Path) -> pd.DataFrame:
    """One row per bridge (index: id) with its name, model constants and summary values [SI]."""
    with open_results(path) as file:
        rows = {
            bridge_id: {k: v for k, v in node.attrs.items() if k not in ("config", "units")}
            for bridge_id, node in file["bridges"].items()
        }
        order = [item["id"] for item in json.loads(file.attrs["config"])["bridges"]]
    return pd.DataFrame.from_dict(rows, orient="index").loc[order]


def read_config_hash(path: str | Path) -> str:
    """The hash of the resolved study a results file was made from (`Study.config_hash`)."""
    with open_results(path) as file:
        return str(file.attrs["config_hash"])


def _analysis(file: h5py.File, path: str | Path, bridge: str, record: str) -> h5py.Group:
    node = file.get(f"analyses/{bridge}/{record}")
    if node is None:
        pairs = [f"{b}/{r}" for b, r in stored_analyses(file)]
        raise InputError(
            path,
            [("", f"no analysis {bridge}/{record}; the file has {', '.join(pairs) or 'none'}")],
        )
    return node
