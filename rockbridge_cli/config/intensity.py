"""The intensity section of a study: every record scaled to stated levels of an intensity
measure (multiple stripes), or to the levels an incremental dynamic analysis finds
(`assessment.ida`), and the ids of the scaled records."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, PositiveFloat, field_validator, model_validator

from ..core.quantities import LIMIT_STATES, check_limit_state
from ..motions.intensity import measure_value
from ..records.files import Record
from .loading import StrictModel

MAX_BISECTIONS = 20
"""Most halvings of the scan step an IDA may need (`Ida`)."""

MAX_SCAN_LEVELS = 1000
"""Most levels an IDA's upward scan may take per bridge × record, ``(max − start) / step``."""

SA_PERIODS_S = (0.01, 20.0)
"""The periods an ``sa_g`` or ``avgsa_g`` measure may name [s]: those of published spectra
(NGA-West2's); the response of an oscillator far shorter takes as many sub-steps as it is short."""

SaPeriod = Annotated[float, Field(ge=SA_PERIODS_S[0], le=SA_PERIODS_S[1])]
"""A period of a spectral measure [s] (`SA_PERIODS_S`)."""


class Ida(StrictModel):
    """Incremental dynamic analysis: for each bridge × record and limit state, the lowest level at
    which the state is reached (`assessment.ida`). Levels are in the section's measure."""

    start: PositiveFloat = Field(description="First level of the upward scan [the measure's unit]")
    step: PositiveFloat = Field(description="Increment of the scan [the measure's unit]")
    max: PositiveFloat = Field(description="Last level the scan may reach [the measure's unit]")
    tolerance: float = Field(
        0.02, gt=0.0, lt=1.0, description="Bisect to this width relative to the capacity [-]"
    )
    limit_states: list[str] = Field(
        default_factory=lambda: list(LIMIT_STATES),
        min_length=1,
        description="Limit states: gap_closure, backfill_<p>, abutment_failure, overturning; "
        "tendon_yield, tendon_rupture (bridges whose tendons state those limits)",
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
        if (self.max - self.start) / self.step > MAX_SCAN_LEVELS:
            raise ValueError(f"(max − start) / step must be at most {MAX_SCAN_LEVELS} scan "
                             "levels: raise step or lower max")  # fmt: skip
        if self.step / (self.tolerance * self.start) > 2.0**MAX_BISECTIONS:
            raise ValueError(f"step / (tolerance · start) must be at most 2^{MAX_BISECTIONS}: "
                             "raise start or tolerance")  # fmt: skip
        return self


class Intensity(StrictModel):
    """Every record scaled to stated levels of an intensity measure (multiple-stripe analysis), or
    to the levels an incremental dynamic analysis finds (``ida``). Give one of the two.

    The measures (`motions.intensity.MEASURES`): ``pga_g`` the scaled record's peak [g]; ``pgv``,
    ``pgd`` its peak ground velocity [m/s] and displacement [m]; ``sa_g`` its 5 %-damped (or
    ``damping``) pseudo-spectral acceleration at ``period`` [g]; ``avgsa_g`` the geometric mean of
    Sa over ``period_range`` [g]; ``arias`` its Arias intensity [m/s]; ``cav`` its cumulative
    absolute velocity [m/s]; ``scale`` the factor itself [-]. g is standard gravity, as for
    record files.
    """

    measure: Literal["pga_g", "pgv", "pgd", "sa_g", "avgsa_g", "arias", "cav", "scale"] = Field(
        description="Intensity measure, with the unit of its levels: pga_g, sa_g, avgsa_g [g]; "
        "pgv, arias, cav [m/s]; pgd [m]; scale [-], the factor on the record itself"
    )
    levels: list[PositiveFloat] | None = Field(
        None, min_length=1, max_length=MAX_SCAN_LEVELS,
        description="Levels of the measure (multiple stripes) [the measure's unit]",
    )  # fmt: skip
    ida: Ida | None = Field(None, description="Incremental dynamic analysis")
    period: SaPeriod | None = Field(None, description="Period of sa_g [s]")
    period_range: tuple[SaPeriod, SaPeriod] | None = Field(
        None, description="Shortest and longest period of avgsa_g [s]"
    )
    damping: float = Field(0.05, gt=0.0, lt=1.0, description="Damping ratio of Sa [-]")
    design: PositiveFloat | None = Field(
        None, description="The design level in the measure (a_g·S for pga_g): the fragility "
        "tables give each median's ratio to it, the margin of the paper's 'about twice the "
        "design earthquake' and, in spirit, FEMA P695's collapse margin ratio [the measure's "
        "unit]",
    )  # fmt: skip

    @model_validator(mode="after")
    def _period_for_sa(self) -> Intensity:
        if (self.measure == "sa_g") != (self.period is not None):
            raise ValueError("give period with measure sa_g, and only then")
        if (self.measure == "avgsa_g") != (self.period_range is not None):
            raise ValueError("give period_range with measure avgsa_g, and only then")
        if self.period_range is not None and not self.period_range[0] < self.period_range[1]:
            raise ValueError("period_range: the shortest period first")
        if (self.levels is None) == (self.ida is None):
            raise ValueError("give exactly one of levels (stripes) and ida")
        if self.levels is not None and len(set(self.levels)) != len(self.levels):
            raise ValueError("a level is listed twice")
        return self


def intensity_of(record: Record, intensity: Intensity) -> float:
    """A record's intensity in the section's measure (1 for ``scale``)."""
    return measure_value(
        intensity.measure, record.acceleration, record.time_step, intensity.period,
        intensity.period_range, intensity.damping,
    )  # fmt: skip
