"""The record-selection config that `rockbridge select-records` reads: the pool of candidates (the
FEMA P695 sets, folders of record files), the EN 1998-1 target, the period range, the rules and
the objective (`motions.selection`).

Every length of time is in seconds, accelerations given in g are named ``*_g``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import (
    Field,
    PositiveFloat,
    PositiveInt,
    ValidationInfo,
    field_validator,
    model_validator,
)

from ..core.quantities import STANDARD_GRAVITY
from ..errors import InputError
from ..motions import ec8
from ..records.pool import FemaSource as FemaPoolSource
from ..records.pool import PoolFolder as PoolFolderSource
from ..records.selection import SelectionRequest
from ..records.target import TargetDefinition, read_spectrum_file
from .loading import StrictModel, resolve_path
from .records import FemaSource

MIN_RECORDS = 3
"""EN 1998-1 §3.2.3.1.2(4)a: at least three records [-]."""

MEAN_RECORDS = 7
"""EN 1998-1 §4.3.3.4.3(3): with at least seven analyses the mean response may be used [-]."""


class PoolFolder(StrictModel):
    """A folder of record files, each file a candidate (`records.files.read_record`: PEER .AT2,
    rockbridge, two- or one-column text)."""

    path: Path = Field(description="Folder, relative to the config file")
    pattern: str = Field("*", min_length=1, description="Glob of the files taken, e.g. *.AT2")
    units: Literal["g", "m/s2", "cm/s2"] | None = Field(
        None, description="Units of the files that do not state them (g, m/s2 or cm/s2)"
    )
    time_step: PositiveFloat | None = Field(
        None, description="Sample interval of one-column files [s]"
    )
    earthquake: str | None = Field(
        None, min_length=1, description="The earthquake all its files come from (the cap per "
        "earthquake counts it); default: each file its own earthquake",
    )  # fmt: skip

    @field_validator("path")
    @classmethod
    def _is_folder(cls, path: Path, info: ValidationInfo) -> Path:
        resolved = resolve_path(path, info)
        if not resolved.is_dir():
            raise ValueError(f"folder not found: {path}")
        return resolved


class Pool(StrictModel):
    """The candidates: FEMA P695 sets, folders of record files, or both."""

    fema_p695: list[FemaSource] | None = Field(
        None, min_length=1, description="FEMA P695 sets (far-field, near-field-pulse, "
        "near-field-no-pulse), each a name or {set, components, records}",
    )  # fmt: skip
    folders: list[PoolFolder] | None = Field(None, min_length=1, description="Record folders")

    @model_validator(mode="after")
    def _something(self) -> Pool:
        if self.fema_p695 is None and self.folders is None:
            raise ValueError("give fema_p695, folders or both")
        names = [fema.name for fema in self.fema_p695 or ()]
        if len(set(names)) != len(names):
            raise ValueError("a FEMA P695 set is listed twice")
        return self


class SelectionTarget(StrictModel):
    """The EN 1998-1 §3.2.2.2 horizontal elastic spectrum the scaled records' mean must follow."""

    code: Literal["EN1998-1"] = Field("EN1998-1", description="Design code [-]")
    spectrum_type: Literal[1, 2] = Field(description="EN 1998-1 spectrum type, 1 or 2 [-]")
    ground_type: Literal["A", "B", "C", "D", "E"] = Field(
        description="EN 1998-1 ground type, Table 3.1 [-]"
    )
    agr_g: PositiveFloat = Field(
        le=3.0, description="Reference peak ground acceleration on type A ground, a_gR [g]"
    )
    importance: PositiveFloat = Field(
        1.0, le=3.0, description="Importance factor γ_I; a_g = γ_I·a_gR (EN 1998-1 §3.2.1(3)) [-]"
    )
    damping: float = Field(0.05, gt=0.0, le=0.3, description="Viscous damping ratio, 0.05 [-]")
    spectrum_file: Path | None = Field(
        None, description="A spectrum of your own that replaces Se(T) over the period range (the "
        "fit and (4)c): two columns, period in s and Sa in spectrum_units, interpolated in "
        "log-log, relative to the config file; (4)b keeps EN 1998-1's a_g*S",
    )  # fmt: skip
    spectrum_units: Literal["g", "m/s2", "cm/s2"] = Field(
        "g", description="Units of the spectrum file's Sa"
    )

    @field_validator("spectrum_file")
    @classmethod
    def _exists(cls, path: Path | None, info: ValidationInfo) -> Path | None:
        if path is None:
            return None
        resolved = resolve_path(path, info)
        if not resolved.is_file():
            raise ValueError(f"spectrum file not found: {path}")
        return resolved

    def resolve(self, gravity: float) -> TargetDefinition:
        """The target in SI units: a_g = γ_I·a_gR and a_g·S [m/s²]."""
        soil = ec8.get_spectrum_shape(self.spectrum_type, self.ground_type).soil_factor
        design = self.importance * self.agr_g * gravity
        return TargetDefinition(self.spectrum_type, self.ground_type, self.damping, design,
                                design * soil)  # fmt: skip


class Rules(StrictModel):
    """What the set must be."""

    count: int = Field(
        ge=MIN_RECORDS, le=100, description=f"Records in the set; EN 1998-1 asks >= "
        f"{MIN_RECORDS}, >= {MEAN_RECORDS} to use mean values [-]",
    )  # fmt: skip
    max_per_earthquake: PositiveInt = Field(1, description="Most records from one earthquake [-]")
    max_per_recording: PositiveInt = Field(
        1, le=2, description="Most horizontal components of one recording (station) [-]"
    )
    mean_ratio: float = Field(
        0.9, ge=0.9, le=2.0, description="The raise brings the mean spectrum to at least this "
        "share of the target over the range: EN 1998-1 (4)c's 0.9, or more for a margin [-]",
    )  # fmt: skip
    scale_factor: tuple[PositiveFloat, PositiveFloat] = Field(
        (0.25, 4.0), description="Lowest and highest scale factor of a record [-]"
    )

    @field_validator("scale_factor")
    @classmethod
    def _ordered(cls, bounds: tuple[float, float]) -> tuple[float, float]:
        if not bounds[0] <= bounds[1]:
            raise ValueError(f"give [lowest, highest], got {list(bounds)}")
        return bounds


class SelectionConfig(StrictModel):
    """A set of recorded motions chosen from a pool and scaled to an EN 1998-1 spectrum."""

    pool: Pool = Field(description="The candidates")
    target: SelectionTarget = Field(description="The target spectrum")
    periods: tuple[PositiveFloat, PositiveFloat] = Field(
        description="The period range [T_low, T_high] of the fit and of EN 1998-1's (4)c, "
        "0 < T_low < T_high <= 4 s. A rocking bridge has no fundamental period: take the periods "
        "where its rocking is sensitive (docs/records.md), or EC8's [0.2·T1, 2·T1] of a "
        "reference [s].",
    )  # fmt: skip
    period_count: int = Field(
        60, ge=10, le=1000, description="Log-spaced periods of the selection over the range [-]"
    )
    rules: Rules = Field(description="The rules of the set")
    dispersion_weight: float = Field(
        0.0, ge=0.0, le=100.0, description="w: the weight of the scaled spectra's dispersion "
        "beside the misfit of their mean (Baker & Lee 2018); 1 makes the objective each "
        "record's own mean squared log misfit [-]",
    )  # fmt: skip
    gravity: float = Field(STANDARD_GRAVITY, gt=0.0, description="Gravity, for g [m/s²]")

    @field_validator("periods")
    @classmethod
    def _range(cls, periods: tuple[float, float]) -> tuple[float, float]:
        if not 0.0 < periods[0] < periods[1] <= ec8.MAX_PERIOD:
            raise ValueError(f"give 0 < T_low < T_high <= {ec8.MAX_PERIOD:g} s (EN 1998-1 "
                             f"Eqs. 3.2-3.5), got {list(periods)}")  # fmt: skip
        return periods

    def request(self) -> SelectionRequest:
        """What `records.selection.select_record_set` takes: the pool's sources, the target and
        the rules, in SI units."""
        fema = tuple(
            FemaPoolSource(f.name, tuple(f.components), f.normalize,
                       None if f.records is None else tuple(f.records))
            for f in self.pool.fema_p695 or ()
        )  # fmt: skip
        folders = tuple(
            PoolFolderSource(f.path, f.pattern, f.units, f.time_step, f.earthquake)
            for f in self.pool.folders or ()
        )  # fmt: skip
        rules, target = self.rules, self.target
        spectrum = None
        if target.spectrum_file is not None:
            spectrum = read_spectrum_file(target.spectrum_file, target.spectrum_units)
            low, high = spectrum.periods[0], spectrum.periods[-1]
            if not (low <= self.periods[0] and self.periods[1] <= high):
                why = f"covers {low:g}-{high:g} s, not the period range {list(self.periods)}"
                raise InputError(target.spectrum_file, [("", why)])
        return SelectionRequest(
            fema, folders, self.target.resolve(self.gravity), self.periods, self.period_count,
            rules.count, rules.max_per_earthquake, rules.max_per_recording, rules.scale_factor,
            self.dispersion_weight, self.gravity, self.model_dump(mode="json", by_alias=True),
            spectrum, rules.mean_ratio,
        )  # fmt: skip
