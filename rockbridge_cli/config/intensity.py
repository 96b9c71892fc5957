"""The intensity section of a study: every record scaled to stated levels of an intensity
measure (multiple stripes), or to the levels an incremental dynamic analysis finds
(`assessment.ida`), and the ids of the scaled records."""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field, PositiveFloat, field_validator, model_validator

from ..core.quantities import LIMIT_STATES, STANDARD_GRAVITY, check_limit_state
from ..records.files import Record
from .loading import StrictModel

MAX_BISECTIONS = 20
"""Most halvings of the scan step an IDA may need (`Ida`)."""


class Ida(StrictModel):
    """Incremental dynamic analysis: for each bridge × record and limit state, the lowest level at
    which the state is reached (`assessment.ida`). Levels are in the section's measure."""

    start: PositiveFloat = Field(description="First level of the upward scan")
    step: PositiveFloat = Field(description="Increment of the scan")
    max: PositiveFloat = Field(description="Last level the scan may reach")
    tolerance: float = Field(
        0.02, gt=0.0, lt=1.0, description="Bisect to this width relative to the capacity [-]"
    )
    limit_states: list[str] = Field(
        default_factory=lambda: list(LIMIT_STATES),
        min_length=1,
        description="Limit states: gap_closure, backfill_<p>, abutment_failure, overturning",
    )

    @field_validator("limit_states")
    @classmethod
    def _known_states(cls, names: list[str]) -> list[str]:
        if len(set(names)) != len(names):
            raise ValueError("a limit state is listed twice")
        return [check_limit_state(name) for name in names]

    @model_validator(mode="after")
    def _scan(self) -> Ida:
        if self.max < self.start:
            raise ValueError("max must not be below start")
        if self.step / (self.tolerance * self.start) > 2.0**MAX_BISECTIONS:
            raise ValueError(f"step / (tolerance · start) must be at most 2^{MAX_BISECTIONS}: "
                             "raise start or tolerance")  # fmt: skip
        return self


class Intensity(StrictModel):
    """Every record scaled to stated levels of an intensity measure (multiple-stripe analysis), or
    to the levels an incremental dynamic analysis finds (``ida``). Give one of the two.

    ``pga_g``: the scaled record's peak [g]; ``sa_g``: its 5 %-damped (or ``damping``) pseudo-
    spectral acceleration at ``period`` [g]; ``scale``: the factor itself [-]. g is standard
    gravity, as for record files.
    """

    measure: Literal["pga_g", "sa_g", "scale"] = Field(description="Intensity measure")
    levels: list[PositiveFloat] | None = Field(
        None, min_length=1, description="Levels of the measure (multiple stripes)"
    )
    ida: Ida | None = Field(None, description="Incremental dynamic analysis")
    period: PositiveFloat | None = Field(None, description="Period of sa_g [s]")
    damping: float = Field(0.05, gt=0.0, lt=1.0, description="Damping ratio of sa_g [-]")

    @model_validator(mode="after")
    def _period_for_sa(self) -> Intensity:
        if (self.measure == "sa_g") != (self.period is not None):
            raise ValueError("give period with measure sa_g, and only then")
        if (self.levels is None) == (self.ida is None):
            raise ValueError("give exactly one of levels (stripes) and ida")
        if self.levels is not None and len(set(self.levels)) != len(self.levels):
            raise ValueError("a level is listed twice")
        return self


LEVEL_UNITS = {"pga_g": "g", "sa_g": "g", "scale": "x"}
"""What follows the level in a scaled record's id: AR01+0.6g, AR01+1.5x."""


def intensity_of(record: Record, intensity: Intensity) -> float:
    """A record's intensity in the section's measure (1 for ``scale``)."""
    if intensity.measure == "pga_g":
        return record.peak_acceleration / STANDARD_GRAVITY
    if intensity.measure == "sa_g":
        from ..motions.spectra import compute_psa  # compiled: loaded only where a study needs it

        assert intensity.period is not None
        psa = compute_psa(record.acceleration, record.time_step, np.array([intensity.period]),
                          intensity.damping)  # fmt: skip
        return float(psa[0]) / STANDARD_GRAVITY
    return 1.0


def scaled_id(base: str, level: float, measure: str) -> str:
    """The id of a record scaled to an intensity level: ``AR01+0.6g``, ``AR01+1.5x``."""
    return f"{base}+{level:.10g}{LEVEL_UNITS[measure]}"
