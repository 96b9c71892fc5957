"""The description of a study that its results file stores (`results.description.Description`):
its resolved inputs; each record's provenance, intensity measures and velocity pulse; each
bridge's config, model, summary and swept fields with their units. It is computed here, so that
the results writer only writes.

What takes the compiled kernels or time (the bridges' summaries, the measures, a recorded
motion's pulse: 40 ms each) is computed by a worker while the analyses run (`numerics`, of the
samples `motions_of` lists); the rest, in the parent, in `describe`.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple, cast

import numpy as np

from ..config.sweep import field_unit
from ..core.geometry import Model
from ..core.quantities import SIGNIFICANT_RATE, STANDARD_GRAVITY
from ..core.summary import SUMMARY_UNITS, summarize_all
from ..motions.intensity import MEASURES, record_measures
from ..motions.pulse_identification import pulse_provenance
from ..records.files import PROVENANCE
from ..records.vertical import peak_vertical
from ..results.description import Attributes, Description, RecordGroup, Samples

if TYPE_CHECKING:
    from ..config.study import Study
    from ..config.study_records import StudyRecord
    from ..core.bridge import Bridge
    from ..records.files import Record

MODEL_UNITS = {
    "B": "m", "H1": "m", "H2": "m", "L1": "m", "L2": "m", "h": "m",
    "m1": "kg", "m2": "kg", "md": "kg", "I1": "kg m2", "I2": "kg m2", "Id": "kg m2",
    "g": "m/s2", "has_abutments": "-", "u_jo": "m", "k": "N/m", "c": "N s/m", "u_ab": "m",
    "e": "-", "m_abut": "kg",
}  # fmt: skip
"""Units of the model's constants (`core.geometry.Model`), ``model_<name>`` in ``/bridges``."""

Key = tuple[str, str]
"""A record's content, (source, digest): records of one content share one group."""


class Motions(NamedTuple):
    """The samples the description measures: each record content's as analyzed, by `Key`, for
    its intensity measures (Sa and AvgSa at the study's ``spectral`` period, period range and
    damping); and each recorded motion's as read, by (source, base record id), for its velocity
    pulse."""

    measured: dict[Key, tuple[np.ndarray, float]]
    pulsed: dict[Key, tuple[np.ndarray, float]]
    spectral: tuple[float | None, Any, float]


class Numerics(NamedTuple):
    """What a worker computes for the description: the bridges' summaries
    (`core.summary.summarize_all`), the records' measures (`motions.intensity.record_measures`)
    and pulses (`motions.pulse_identification.pulse_provenance`), keyed as `Motions`."""

    summaries: list[dict[str, object]]
    measures: dict[Key, dict[str, float]]
    pulses: dict[Key, dict[str, float]]


def motions_of(study: Study) -> Motions:
    """The samples of a study's records that its description measures (`Motions`)."""
    intensity = study.intensity_section
    spectral = (None, None, 0.05) if intensity is None else intensity.spectral
    measured: dict[Key, tuple[np.ndarray, float]] = {}
    pulsed: dict[Key, tuple[np.ndarray, float]] = {}
    for item in study.records:
        key = (item.source, item.digest)
        if key in measured or item.record is None:
            continue
        measured[key] = (item.record.acceleration, item.record.time_step)
        base = (item.source, item.base or item.id)
        if base not in pulsed and _recorded(item.record):
            record = item.as_read or item.record
            pulsed[base] = (record.acceleration, record.time_step)
    return Motions(measured, pulsed, spectral)


def numerics(bridges: Sequence[Bridge], motions: Motions) -> Numerics:
    """The summaries of ``bridges`` and the measures and pulses of ``motions`` (`Numerics`)."""
    return Numerics(
        summarize_all(bridges),
        {key: record_measures(a, step, *motions.spectral) for key, (a, step) in
         motions.measured.items()},
        {key: pulse_provenance(a, step) for key, (a, step) in motions.pulsed.items()},
    )  # fmt: skip


def describe(
    study: Study, bridges: Sequence[Bridge], computed: Numerics | None = None
) -> Description:
    """The description of a study whose ``bridges`` are built (`Grid.bridges`, in order), with
    the numerics a worker ``computed`` (default: computed here)."""
    if computed is None:
        computed = numerics(bridges, motions_of(study))
    return Description(
        _root(study), _records(study, computed), _bridges(study, bridges, computed.summaries)
    )


def _root(study: Study) -> dict[str, Any]:
    """The study and its inputs, as the root's attributes."""
    resolved = study.resolved()
    return {
        "study_file": study.path.as_posix(),
        "study_yaml": study.text,
        "config": json.dumps(resolved),  # one line: the C encoder, 10x faster
        "config_hash": study.config_hash,
        "fidelity": study.fidelity.preset,
        "knobs": json.dumps(resolved["fidelity"]["knobs"]),
        "output_step": float(study.fidelity.knobs["output_step"]),
        "significant_impact_rate": SIGNIFICANT_RATE,
        "histories": json.dumps(list(study.histories)),
        "warnings": json.dumps(list(study.warnings)),
        "intensity": json.dumps(study.intensity),
    }


def _recorded(record: Record) -> bool:
    """Whether a record is a recorded motion, whose velocity pulse is identified and stored (a
    PEER file, or one whose provenance names its earthquake); a synthetic record, a stationary
    process under an envelope, has none to find, and skipping it keeps 40 ms a record out of a
    study's start."""
    return record.metadata.get("format") == "PEER NGA AT2" or "earthquake" in record.metadata


def _records(study: Study, computed: Numerics) -> tuple[RecordGroup, ...]:
    """A group per record. A record an intensity section scales holds its factor (``scale``)
    and its base record's samples as read (``base_acceleration``, one dataset for every level),
    not a scaled copy. A record analyzed with its vertical component holds it beside them
    (``vertical_acceleration``, ``base_vertical_acceleration``)."""
    described: dict[Key, Attributes] = {}
    groups = []
    for item in study.records:
        key = (item.source, item.digest)
        if key not in described:
            pulse = computed.pulses.get((item.source, item.base or item.id), {})
            described[key] = _record_attributes(item, computed.measures.get(key, {}), pulse)
        samples = item.record if item.as_read is None else item.as_read
        prefix = "" if item.as_read is None else "base_"
        digest = item.digest if item.as_read is None else f"{item.source} as read"
        components = {} if samples is None else {"acceleration": samples.acceleration}
        if samples is not None and samples.vertical is not None:
            components["vertical_acceleration"] = samples.vertical
        groups.append(RecordGroup(item.id, key, described[key], tuple(
            Samples(prefix + name, digest if name == "acceleration" else f"{digest} {name}", values)
            for name, values in components.items()
        )))  # fmt: skip
    return tuple(groups)


def _record_attributes(
    item: StudyRecord, measures: dict[str, float], pulse: dict[str, float]
) -> Attributes:
    """What a record is, where it comes from, its velocity ``pulse`` (of the record as read,
    before an intensity section scales it) and its intensity ``measures`` (as analyzed)."""
    values: dict[str, Any] = {"source": item.source, "sha256": item.digest, "error": item.error}
    if item.as_read is not None:
        values.update({"base_record": item.base, "scale": item.scale})
    record = item.record
    if record is None:
        return Attributes(values)
    values.update(
        {
            "name": record.name,
            "time_step": record.time_step,
            "n_samples": record.acceleration.size,
            "duration": record.duration,
            "pga": record.peak_acceleration,
            "file_units": record.metadata.get("file_units", "m/s2"),
            "standard_gravity": STANDARD_GRAVITY,  # what a file's g was converted with
        }
    )
    if record.vertical is not None:
        source = Path(record.metadata.get("vertical_source", "")).name
        values.update(vertical_pga=peak_vertical(record), vertical_file=source)
    provenance = {key: record.metadata[key] for key in PROVENANCE if key in record.metadata}
    provenance |= pulse
    values.update({**provenance, **measures})
    units = {
        "time_step": "s", "n_samples": "-", "duration": "s", "pga": "m/s2", "file_units": "-",
        "standard_gravity": "m/s2",
        **({"scale": "-"} if item.as_read is not None else {}),
        **({"vertical_pga": "m/s2", "vertical_file": "-"} if record.vertical is not None else {}),
        **{key: PROVENANCE[key] for key in provenance},
        **{name: MEASURES[name].unit for name in measures},
    }  # fmt: skip
    return Attributes(values, units)


def _bridges(
    study: Study, bridges: Sequence[Bridge], summaries: Sequence[dict[str, object]]
) -> dict[str, Attributes]:
    """Per bridge: its name, config, model constants, summary, failure rotations and swept
    fields, with their units."""
    found = {}
    for item, bridge, summary in zip(study.bridges, bridges, summaries, strict=True):
        values: dict[str, Any] = {
            "name": item.config.label(item.id),
            "source": item.source,
            "config": json.dumps(item.config.model_dump(mode="json"), indent=1),
            "model": summary["model"],
            "mirrored": bridge.mirrored,
            "governing_failure": summary["governing_failure"],
            "swept": json.dumps(item.swept),
            "swept_units": json.dumps({path: field_unit(path) for path in item.swept}),
            "varied": json.dumps(list(item.varied)),
            **({"sample": json.dumps(item.sample)} if item.sample else {}),
        }
        units = {}
        for name, unit in SUMMARY_UNITS.items():
            values[name] = np.nan if summary[name] is None else summary[name]
            units[name] = unit
        capacities = cast(dict[str, dict[str, float]], summary["failure_rotations"])
        for limit, rotations in capacities.items():  # failure_rotation_<limit>_<p|n>
            for mode, value in rotations.items():
                values[f"failure_rotation_{limit}_{mode}"] = value
                units[f"failure_rotation_{limit}_{mode}"] = "rad"
        for name in Model._fields:
            values[f"model_{name}"] = getattr(bridge.model, name)
            units[f"model_{name}"] = MODEL_UNITS[name]
        found[item.id] = Attributes(values, units)
    return found
