"""The intensity section of a study: every record scaled to stated levels of an intensity
measure (multiple stripes), or to the levels an incremental dynamic analysis finds
(`assessment.ida`), and the ids of the scaled records."""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import Field, PositiveFloat, field_validator, model_validator

from ..core.quantities import LIMIT_STATES, check_limit_state
from ..motions.intensity import MEASURES, measure_value
from ..records.files import ABSURD_PGA_G, Record
from .loading import StrictModel

MAX_BISECTIONS = 20
"""Most halvings of the scan step an IDA may need (`Ida`)."""

MAX_SCAN_LEVELS = 1000
"""Most levels an IDA's upward scan may take per bridge × record, ``(max − start) / step``."""

SA_PERIODS_S = (0.01, 20.0)
"""The periods an ``sa_g`` or ``avgsa_g`` measure may name [s]: those of published spectra
(NGA-West2's); the response of an oscillator far shorter takes as many sub-steps as it is short."""

ABSURD_PGV_M_S = 75.0
"""Largest PGV a level may state [m/s]: 25 times the largest recorded (about 3 m/s, Chi-Chi 1999),
as `records.files.ABSURD_PGA_G` is of PGA. A level above it is cm/s typed as m/s."""

ABSURD_PGD_M = 250.0
"""Largest PGD a level may state [m]: 25 times the largest recorded (about 10 m, with a fault's
offset: Chi-Chi 1999). A level above it is cm or mm typed as m."""

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
        "tendon_yield, tendon_rupture, dissipator_fracture (bridges whose devices state those "
        "limits)",
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
    orientation: Literal["median", "worst"] | None = Field(
        None, description="Of records swept over angles (records.orientation): the fragility the "
        "run stores, the report's and plot fragility's take each pair of horizontal components "
        "as one record, reaching a state where the median over its angles does (at least half "
        "of them; the default) or its worst angle does",
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


def sa_amplification(damping: float) -> float:
    """The most an oscillator of damping ratio ζ turns a ground motion's peak into pseudo-spectral
    acceleration, whatever the motion: ω²∫|h(t)| dt over its impulse response
    h = e^(−ζωt)·sin(ω_d t)/ω_d, which is coth(πζ / (2√(1 − ζ²))) (12.7 at ζ = 0.05) [-]."""
    return 1.0 / math.tanh(math.pi * damping / (2.0 * math.sqrt(1.0 - damping**2)))


def absurd_level(intensity: Intensity) -> tuple[float, str, str] | None:
    """The level of the section's measure beyond any ground motion [the measure's unit], where
    that bound comes from, and the slip of units a level above it likely is; None for a measure
    without one: ``arias`` and ``cav`` grow with a record's length without bound, and
    ``scale``'s bound is a record's own (the scale-factor warning, `plausibility.scale_warning`).
    """
    slip = "cm/s² typed as g?"
    if intensity.measure == "pga_g":
        return ABSURD_PGA_G, "25 times the largest recorded, about 4 g, as for a record file", slip
    if intensity.measure in ("sa_g", "avgsa_g"):
        factor = sa_amplification(intensity.damping)
        basis = (f"the {ABSURD_PGA_G:g} g a record file may peak at times {factor:.3g}, the most "
                 f"an oscillator damped at {intensity.damping:g} amplifies any motion")  # fmt: skip
        return ABSURD_PGA_G * factor, basis, slip
    if intensity.measure == "pgv":
        return ABSURD_PGV_M_S, "25 times the largest recorded, about 3 m/s", "cm/s typed as m/s?"
    if intensity.measure == "pgd":
        return ABSURD_PGD_M, "25 times the largest recorded, about 10 m", "cm or mm typed as m?"
    return None


def absurd_levels(intensity: Intensity) -> list[tuple[str, str]]:
    """Levels (stripes, an IDA's start and max, the design level) beyond any ground motion
    (`absurd_level`), as ``(field, reason)``: refused, where a level that merely scales a record
    by an implausible factor is warned of (`plausibility.scale_warning`)."""
    bound = absurd_level(intensity)
    if bound is None:
        return []
    limit, basis, slip = bound
    measure = MEASURES[intensity.measure]
    name = measure.label.split(" [")[0]
    return [
        (field, f"{level:g} {measure.unit} is beyond any ground motion's {name} ({limit:.4g} "
                f"{measure.unit} at most: {basis}): {slip}")
        for field, level in _levels(intensity)
        if level > limit
    ]  # fmt: skip


def unrecorded_levels(intensity: Intensity) -> list[str]:
    """Warnings for stripes or a design level above the largest ground motion recorded (a 25th
    of `absurd_level`'s bound: about 4 g of PGA, 3 m/s of PGV, 10 m of PGD) but within that
    bound, where a slip of units (m/s² typed as g, cm/s typed as m/s) still runs: legal, and
    implausible. An IDA's scan is left alone: it scales records up to collapse by design."""
    bound = absurd_level(intensity)
    if bound is None:
        return []
    limit, _, slip = bound
    largest, unit = limit / 25.0, MEASURES[intensity.measure].unit
    return [
        f"{field}: {level:g} {unit} exceeds the largest ground motion recorded (about "
        f"{largest:.3g} {unit}): {slip.replace('cm/s² typed as g', 'm/s² typed as g')}"
        for field, level in _levels(intensity)
        if largest < level <= limit and not field.startswith("intensity.ida")
    ]


def _levels(intensity: Intensity) -> list[tuple[str, float]]:
    """The levels a section states, by field: its stripes, an IDA's start and max, the design
    level."""
    fields = [(f"intensity.levels.{k}", level) for k, level in enumerate(intensity.levels or ())]
    if intensity.ida is not None:
        fields += [("intensity.ida.start", intensity.ida.start),
                   ("intensity.ida.max", intensity.ida.max)]  # fmt: skip
    if intensity.design is not None:
        fields.append(("intensity.design", intensity.design))
    return fields
