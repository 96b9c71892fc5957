"""The study config: which bridges meet which records, at which fidelity, and where results go.

A study file is validated in two stages. `StudyConfig` (`config.study_models`) checks the file
itself (keys, types, that the files and folders it names exist); `load_study` then resolves it
into a `Study`: every bridge config loaded, every record read, the fidelity knobs settled and the
output path chosen. Paths inside the study file are relative to the study file; the default
output, ``results/<stem>.h5``, is relative to the current folder, like a path given on the
command line.

A record that cannot be read does not stop the study: the `StudyRecord` carries the reason and
the run records it as the status of that record's analyses.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..core.fidelity import Fidelity, check_work, resolve
from ..errors import InputError, check_path_argument
from ..kinds import expecting
from ..results.sections import IntensitySection
from . import loading
from .bridge import BridgeConfig, load_bridge
from .intensity import Intensity, unrecorded_levels
from .loading import ConfigFolder
from .plausibility import bridge_warnings, record_warnings, scale_warning
from .spectrum import Spectrum
from .study_checks import (
    check_ids,
    check_levels,
    check_map,
    check_orientation,
    check_size,
    check_states,
)
from .study_models import InlineBridge, StudyConfig
from .study_records import StudyRecord, resolve_records, scalable, scaled, study_record
from .sweep import Sweep, field_value, variant_id, varied
from .uncertainty import Uncertainty, record_pairs, sampled_configs


@dataclass(frozen=True)
class StudyBridge:
    """One resolved bridge: its id in the results, its validated config and where it came from.

    Attributes
    ----------
    swept : in a sweep, the value of every swept field in this bridge (path → value); in a
        study with an uncertainty section, of every sampled field
    varied : the swept (or sampled) fields this bridge changes from its bridge file
    sample : a sampled bridge's place in the design (`config.uncertainty.Sample.described`),
        empty for any other
    """

    id: str
    config: BridgeConfig
    source: str
    swept: dict[str, float] = dataclasses.field(default_factory=dict)
    varied: tuple[str, ...] = ()
    sample: dict[str, Any] = dataclasses.field(default_factory=dict)


@dataclass(frozen=True)
class Study:
    """A study ready to run: bridges × records, fidelity knobs and the output file.

    Attributes
    ----------
    path : the study file
    text : the study file as written; empty for a study built in code (`single_analysis`)
    bridges, records : resolved, in the study's order (the order of the results)
    fidelity : the preset and every knob, settled once and checked with each record
        (`core.fidelity.resolve`, `check_work`): what every analysis runs at
    histories : names of the histories to store
    output : the HDF5 file
    warnings : legal but implausible inputs (`plausibility`), ``source: field: reason`` each
    intensity : the intensity section (measure, levels or ida, period, damping), None without;
        with ``ida``, ``records`` are the records as read, and the levels are found as the study
        runs (`assessment.ida`)
    spectrum : the spectrum section resolved (`config.spectrum.Spectrum.described`), None
        without; ``records`` are then its pulses and ``intensity`` the IDA it runs as
    uncertainty : the uncertainty section (`config.uncertainty.Uncertainty.described`), None
        without
    pairs : the (bridge, record) index pairs analysed, in the order of the results, where not
        every bridge meets every record (``pairing: one``); None for every pair
    """

    path: Path
    text: str
    bridges: tuple[StudyBridge, ...]
    records: tuple[StudyRecord, ...]
    fidelity: Fidelity
    histories: tuple[str, ...]
    output: Path
    warnings: tuple[str, ...] = ()
    intensity: dict[str, Any] | None = None
    spectrum: dict[str, Any] | None = None
    uncertainty: dict[str, Any] | None = None
    pairs: tuple[tuple[int, int], ...] | None = None

    def resolved(self) -> dict[str, Any]:
        """Everything that determines the results, as JSON-ready data (stored in the file)."""
        return {
            "bridges": [
                {
                    "id": b.id,
                    "source": b.source,
                    "config": b.config.model_dump(mode="json"),
                    **({"swept": b.swept} if b.swept else {}),
                    **({"sample": b.sample} if b.sample else {}),
                }
                for b in self.bridges
            ],  # fmt: skip
            "records": [{"id": r.id, "source": r.source, "sha256": r.digest} for r in self.records],
            "fidelity": {"preset": self.fidelity.preset, "knobs": self.fidelity.knobs},
            "histories": list(self.histories),
            **({"intensity": self.intensity} if self.intensity is not None else {}),
            **({"spectrum": self.spectrum} if self.spectrum is not None else {}),
            **({"uncertainty": self.uncertainty} if self.uncertainty is not None else {}),
            **({"pairs": [list(p) for p in self.pairs]} if self.pairs is not None else {}),
        }

    @property
    def intensity_section(self) -> IntensitySection | None:
        """The intensity section, typed as a results file's readers take it (validated with the
        study: `config.intensity.Intensity`)."""
        return None if self.intensity is None else IntensitySection.of(self.intensity)

    def with_knobs(self, **changed: Any) -> Study:
        """The study with more fidelity knobs changed (a command line's ``--tail``), checked as
        the study's own are (`InputError` naming the study)."""
        knobs = {**self.fidelity.knobs, **changed}
        return dataclasses.replace(
            self, fidelity=_settled(self.fidelity.preset, knobs, self.records, self.path)
        )

    @property
    def config_hash(self) -> str:
        """SHA-256 of `resolved` without the sources: equal inputs give equal hashes wherever the
        files live."""
        data = self.resolved()
        for item in data["bridges"] + data["records"]:
            del item["source"]
        text = json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=True)
        return hashlib.sha256(text.encode()).hexdigest()


def load_study(
    path: str | Path, preset: str | None = None, output: str | Path | None = None
) -> Study:
    """Read, validate and resolve a study file.

    Parameters
    ----------
    path
        The study YAML file.
    preset
        Replaces the study's fidelity preset (its knob overrides still apply).
    output
        Replaces the study's output file (relative to the current folder).

    Raises
    ------
    InputError
        The study file, a bridge file it names or a record set's manifest is missing or invalid,
        or a path in it lies outside the folders it may reach (`loading.ConfigFolder`: its own
        folder's tree, the working folder's, those in ``ROCKBRIDGE_PATHS``); the message names
        the file and the dotted field path.
    TypeError
        ``path`` is not a path.
    """
    check_path_argument(path, "load_study", "a study YAML file")
    path = Path(path)
    with expecting(path, "study"):
        data = loading.read_yaml(path)
        return study_from_data(data, path, path.read_text(encoding="utf-8"), preset, output)


def single_analysis(
    bridge: Path,
    record: Path,
    units: str | None,
    time_step: float | None,
    preset: str,
    output: Path | None,
    tail: float = 0.0,
    vertical: Path | None = None,
) -> Study:
    """The study of one bridge under one record (``rockbridge analyze``; `study.single`).

    Parameters
    ----------
    bridge, record
        The bridge YAML file and the record file.
    units, time_step
        As for a study's ``records.files`` entry (None: what the file says).
    preset
        Fidelity preset.
    output
        The HDF5 results file, None for none. The study has no file of its own: messages and
        the results file name it by ``output`` (every path in it is absolute), or by the
        bridge's file without one.
    tail
        Free vibration after the record [s] (`core.fidelity`).
    vertical
        The record's vertical component, a companion file; None for none.
    """
    record_id = re.sub(r"[^A-Za-z0-9_.+-]", "_", Path(record).stem)
    entry: dict[str, Any] = {"path": str(Path(record).resolve()), "id": record_id}
    entry.update({k: v for k, v in (("units", units), ("time_step", time_step)) if v is not None})
    if vertical is not None:
        entry["vertical"] = str(Path(vertical).resolve())
    data = {
        "bridges": [str(Path(bridge).resolve())],
        "records": {"files": [entry], **({"vertical": True} if vertical is not None else {})},
        "fidelity": {"preset": preset, **({"tail": tail} if tail else {})},
    }
    named = Path(bridge) if output is None else Path(output)
    return study_from_data(data, named, "", None, output, confined=False)


def study_from_data(
    data: dict[str, Any],
    path: Path,
    text: str,
    preset: str | None = None,
    output: str | Path | None = None,
    confined: bool = True,
) -> Study:
    """Validate and resolve a study given as data; ``path`` names it in messages and anchors its
    relative paths, ``text`` is stored in the results; ``confined``: its paths must lie where a
    study file's may (`loading.ConfigFolder`), False for paths from the command line. Other
    parameters as for `load_study`."""
    if preset is not None:
        fidelity = data.get("fidelity")
        data["fidelity"] = {**(fidelity if isinstance(fidelity, dict) else {}), "preset": preset}
    folder = ConfigFolder.of(path) if confined else ConfigFolder(path.parent, None)
    with loading.reaching(folder):
        return _study(data, path, text, output, folder)


def _study(
    data: dict[str, Any], path: Path, text: str, output: str | Path | None, folder: ConfigFolder
) -> Study:
    config = loading.validate(StudyConfig, data, path, folder=folder)
    bridges = _resolve_bridges(config.bridges, path, folder)
    if config.sweep is not None:
        bridges = _swept(bridges, config.sweep, path)
    if config.uncertainty is not None:
        bridges = _sampled(bridges, config.uncertainty, path)
    if config.intensity is not None:
        check_levels(config.intensity, path)
        check_orientation(config.intensity, config.records, path)
    intensity = None if config.intensity is None else _intensity_section(config.intensity)
    spectrum = None
    if config.spectrum is not None:
        check_map(len(bridges), config.spectrum, path)
        check_states(bridges, config.spectrum.limit_states, "spectrum.limit_states", path)
        try:
            records, intensity, spectrum = _spectrum(config.spectrum, bridges[0].config)
        except ValueError as exc:  # a pulse too finely sampled
            raise InputError(path, [("spectrum.frequencies", str(exc))]) from None
    else:
        assert config.records is not None
        records = resolve_records(config.records, path)
    warnings = _warnings(bridges, records)  # of the files, not of their scaled copies
    overrides = config.fidelity.overrides()
    if config.output.output_step is not None:
        overrides["output_step"] = config.output.output_step
    settled = _settled(config.fidelity.preset, overrides, records, path)
    one_each = config.uncertainty is not None and config.uncertainty.pairing == "one"
    check_size(len(bridges), len(records), one_each, config.intensity, path)
    ida = config.intensity.ida if config.intensity is not None else None
    if ida is not None and "limit_states" in ida.model_fields_set:  # the default: all there are
        where = "intensity.ida.limit_states"
        check_states(bridges, ida.limit_states, where, path)
    if config.intensity is not None:
        records = [scalable(item, config.intensity) for item in records]
    if config.intensity is not None:
        warnings += tuple(f"{path}: {w}" for w in unrecorded_levels(config.intensity))
    if config.intensity is not None and config.intensity.levels is not None:
        records = scaled(records, config.intensity)
        warnings += tuple(w for r in records if r.record for w in scale_warning(r.id, r.scale))
    pairs = None
    if config.uncertainty is not None and one_each:
        pairs = record_pairs(len(bridges), [r.base or r.id for r in records], config.uncertainty)
    problems = check_ids("bridges", [b.id for b in bridges])
    problems += check_ids("records", [r.id for r in records])
    problems += [("records", "holds no records to analyze")] if not records else []
    if problems:
        raise InputError(path, problems)
    if output is not None:
        target = Path(output)
    elif config.output.path is not None:  # (``output``, from -o, replaces it unchecked)
        try:
            target = folder.path(config.output.path)
        except ValueError as exc:
            raise InputError(path, [("output.path", str(exc))]) from None
    else:
        target = Path("results") / f"{path.stem}.h5"
    return Study(
        path=path,
        text=text,
        bridges=tuple(bridges),
        records=tuple(records),
        fidelity=settled,
        histories=(
            () if spectrum and "histories" not in config.output.model_fields_set
            else config.output.kept()
        ),
        output=target,
        warnings=warnings,
        intensity=intensity,
        spectrum=spectrum,
        uncertainty=None if config.uncertainty is None else config.uncertainty.described(),
        pairs=pairs,
    )  # fmt: skip


def _spectrum(
    spectrum: Spectrum, bridge: BridgeConfig
) -> tuple[list[StudyRecord], dict[str, Any], dict[str, Any]]:
    """A spectrum's records (its pulse at each frequency), the IDA it runs as, and what the
    results keep of it (`config.spectrum`)."""
    model = bridge.to_bridge().model
    records = spectrum.records(model)  # each refused before it is sampled (`Pulse.check_samples`)
    studied = [study_record(record, record.source, record.name) for record in records]
    return studied, spectrum.ida(model), spectrum.described(model, records)


def _intensity_section(intensity: Intensity) -> dict[str, Any]:
    """The intensity section as the study states it, without the parts its measure and kind do
    not use (so that a study's hash is the same as before they existed)."""
    unused = {"ida"} if intensity.ida is None else set()
    unused |= {key for key in ("period_range", "design", "orientation")
               if getattr(intensity, key) is None}  # fmt: skip
    return intensity.model_dump(exclude=unused)


def _settled(
    preset: str, overrides: dict[str, Any], records: Sequence[StudyRecord], study: Path
) -> Fidelity:
    """The study's fidelity (`core.fidelity.resolve`), once checked in range and, with each
    record, within what an analysis can do (`core.fidelity.check_work`)."""
    try:
        settled = resolve(preset, **overrides)
    except ValueError as exc:
        raise InputError(study, [("fidelity", str(exc))]) from None
    problems = []
    for item in records:
        if item.record is not None:
            try:
                check_work(settled.knobs, item.record.acceleration.size, item.record.time_step)
            except ValueError as exc:
                problems.append((f"records ({item.id})", str(exc)))
    if problems:
        more = f" (and {len(problems) - 1} more records)" if len(problems) > 1 else ""
        raise InputError(study, [(problems[0][0], problems[0][1] + more)])
    return settled


def _swept(bridges: list[StudyBridge], sweep: Sweep, study: Path) -> list[StudyBridge]:
    """Every bridge in every variation of the sweep, bridge by bridge (`config.sweep`)."""
    found, problems = [], []
    for bridge in bridges:
        try:
            base = {path: field_value(bridge.config, path) for path in sweep.fields}
            for changes in sweep.variations():
                config = varied(bridge.config, changes)
                found.append(StudyBridge(
                    variant_id(bridge.id, changes), config, bridge.source, {**base, **changes},
                    tuple(changes),
                ))  # fmt: skip
        except ValueError as exc:
            problems.append(("sweep.fields", f"bridge {bridge.id}: {exc}"))
    if problems:
        raise InputError(study, problems)
    return found


def _sampled(
    bridges: list[StudyBridge], uncertainty: Uncertainty, study: Path
) -> list[StudyBridge]:
    """Every bridge in every sample of the design, bridge by bridge (`config.uncertainty`)."""
    found = []
    for bridge in bridges:
        try:
            drawn = sampled_configs(bridge.config, uncertainty)
        except ValueError as exc:
            why = f"bridge {bridge.id}: {exc}"
            raise InputError(study, [("uncertainty.fields", why)]) from None
        found += [
            StudyBridge(f"{bridge.id}+{sample.label}", config, bridge.source, dict(sample.values),
                        tuple(sample.values), sample.described())
            for sample, config in drawn
        ]  # fmt: skip
    return found


def _warnings(bridges: list[StudyBridge], records: list[StudyRecord]) -> tuple[str, ...]:
    """The plausibility warnings of every bridge and record, once per input file."""
    found = [f"{b.source}: {w}" for b in bridges for w in bridge_warnings(b.config)]
    found += [
        f"{r.source}: {w}"
        for r in records
        if r.record is not None
        for w in record_warnings(r.record)
    ]
    return tuple(dict.fromkeys(found))


def _resolve_bridges(
    entries: list[str | dict[str, Any]], study: Path, folder: ConfigFolder
) -> list[StudyBridge]:
    """Load bridge files and validate inline bridges; problems in the study file are collected."""
    bridges, problems = [], []
    for index, entry in enumerate(entries):
        where = f"bridges.{index}"
        if isinstance(entry, str):
            try:
                file = folder.path(entry)
            except ValueError as exc:
                problems.append((where, str(exc)))
                continue
            if not file.is_file():
                problems.append((where, f"bridge file not found: {entry}"))
                continue
            config = load_bridge(file)
            bridges.append(StudyBridge(Path(entry).stem, config, entry))
            continue
        try:
            inline = loading.validate(InlineBridge, entry, study)
        except InputError as exc:
            problems += [
                (f"{where}.{field}" if field else where, why) for field, why in exc.problems
            ]
            continue
        config = BridgeConfig.model_validate(inline.model_dump(exclude={"id"}))
        bridges.append(StudyBridge(inline.id, config, "inline"))
    if problems:
        raise InputError(study, problems)
    return bridges
