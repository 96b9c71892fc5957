"""The record-set config that `rockbridge generate-records` reads (`RecordSetConfig`): its target
spectrum, the envelope of its artificial records, or the recorded seeds it adjusts.

Every length of time is in seconds, accelerations given in g are named ``*_g``.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import (
    BeforeValidator,
    Discriminator,
    Field,
    Tag,
    ValidationInfo,
    field_validator,
    model_validator,
)

from ..core.fidelity import MAX_GROUND_SAMPLES
from .loading import StrictModel, kind_of, resolve_path
from .records import FemaSet, RecordFile, set_name_or_mapping


def _fema_seeds(value: Any) -> Any:
    """Seeds given as ``{fema_p695: <set>}``: the set, validated as `FemaSet`."""
    if isinstance(value, dict) and set(value) == {"fema_p695"}:
        return FemaSet.model_validate(set_name_or_mapping(value["fema_p695"]))
    return value


def _seeds_kind(value: Any) -> str | None:
    """`loading.kind_of` for a list of files or a FEMA P695 set (``{fema_p695: ...}``, which
    `_fema_seeds` has read); None for anything else."""
    return kind_of(value) if isinstance(value, (list, tuple, FemaSet)) else None


def _seeds_schema(schema: dict[str, Any]) -> None:
    """The JSON schema of ``seeds`` as a file writes it: its FEMA P695 form is ``{fema_p695:
    <set>}`` (which `_fema_seeds` reads), not the set's own keys. (The set's ``$ref`` is, at this
    point, pydantic's inner name of it, such as ``...FemaSet-Input__1``.)"""
    for option in [*schema.get("anyOf", ()), *schema.get("oneOf", ())]:
        if FemaSet.__name__ in option.get("$ref", ""):
            ref = option.pop("$ref")
            fema_p695 = {
                "anyOf": [{"$ref": ref}, {"type": "string"}],
                "description": "The set: its name, short for {set: <name>}, or its keys",
            }
            option.update(
                type="object", properties={"fema_p695": fema_p695},
                required=["fema_p695"], additionalProperties=False,
            )  # fmt: skip
        else:
            _seeds_schema(option)


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
        json_schema_extra=_seeds_schema,
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
    gravity: float = Field(9.81, gt=0.0, description="Acceleration of gravity [m/s²].")
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
