"""The typed sections of a results file's root: the intensity section its study scaled the records
by (`IntensitySection`, with its IDA's `IdaSection`) and an overturning spectrum's
(`SpectrumSection`). A file stores them as JSON attributes (``intensity``, and ``spectrum`` in
``config``), as the study states them (`config.intensity.Intensity`, validated when the study was
read); every reader takes them from `reading.read_intensity` and `reading.read_spectrum_section`,
checked once, with their fields by name."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

MEASURE_NAMES = ("pga_g", "pgv", "pgd", "sa_g", "avgsa_g", "arias", "cav", "scale")
"""The intensity measures a section may name (`motions.intensity.MEASURES`)."""


@dataclass(frozen=True)
class IdaSection:
    """The rule of an incremental dynamic analysis (`assessment.ida`): scan from ``start`` by
    ``step`` up to ``max``, bisect to ``tolerance`` (relative) [-]; levels in the section's
    measure."""

    start: float
    step: float
    max: float
    tolerance: float
    limit_states: tuple[str, ...]

    @classmethod
    def of(cls, data: Mapping[str, Any]) -> IdaSection:
        """The ``ida`` part of an intensity section as stored (a JSON object)."""
        return cls(
            _number(data, "start"), _number(data, "step"), _number(data, "max"),
            _number(data, "tolerance"), tuple(str(state) for state in data["limit_states"]),
        )  # fmt: skip


@dataclass(frozen=True)
class IntensitySection:
    """A study's records scaled to ``levels`` of an intensity ``measure`` (multiple stripes), or
    to the levels its ``ida`` finds; exactly one of the two.

    Attributes
    ----------
    measure : the intensity measure (`MEASURE_NAMES`)
    levels : the stripes' levels, None for an IDA
    ida : the IDA's rule, None for stripes
    period : the period of ``sa_g`` [s], None for another measure
    period_range : the shortest and longest period of ``avgsa_g`` [s], None for another measure
    damping : the damping ratio of Sa [-]
    design : the design level in the measure, None where the study states none
    orientation : how a fragility takes each pair of a swept orientation as one record,
        "median" or "worst" over its angles; None where the study states none (the median,
        `assessment.orientation.study_orientation`)
    """

    measure: str
    levels: tuple[float, ...] | None = None
    ida: IdaSection | None = None
    period: float | None = None
    period_range: tuple[float, float] | None = None
    damping: float = 0.05
    design: float | None = None
    orientation: str | None = None

    @classmethod
    def of(cls, data: Mapping[str, Any]) -> IntensitySection:
        """The section as a study states it (`config.study.Study.intensity`), or as a results
        file stores it (its ``intensity`` attribute, parsed).

        Raises
        ------
        ValueError, KeyError, TypeError
            Not an intensity section.
        """
        measure = data["measure"]
        if measure not in MEASURE_NAMES:
            raise ValueError(f"unknown intensity measure {measure!r}")
        levels, ida, period_range = data.get("levels"), data.get("ida"), data.get("period_range")
        if (levels is None) == (ida is None):
            raise ValueError("an intensity section has exactly one of levels and ida")
        return cls(
            measure,
            None if levels is None else tuple(float(level) for level in levels),
            None if ida is None else IdaSection.of(ida),
            _optional(data, "period"),
            None if period_range is None else (float(period_range[0]), float(period_range[1])),
            float(data.get("damping", 0.05)),
            _optional(data, "design"),
            _combine(data.get("orientation")),
        )

    @property
    def spectral(self) -> tuple[float | None, tuple[float, float] | None, float]:
        """(period, period range, damping): what an ``sa_g`` or ``avgsa_g`` measure is computed
        with (`motions.intensity.measure_value`)."""
        return self.period, self.period_range, self.damping


@dataclass(frozen=True)
class SpectrumSection:
    """An overturning spectrum's section (`config.spectrum.Spectrum.described`): the study's one
    bridge under ``pulse`` at each frequency ratio (one record each), at amplitude ratios of a
    reference acceleration.

    Attributes
    ----------
    pulse : shape, phase [rad], cycles (`config.spectrum.SpectrumPulse`)
    frequency_parameter : p [rad/s]
    reference : ``g_tan_alpha`` or ``onset``; ``reference_acceleration`` its value a_ref [m/s²]
    frequency_ratios : ω_p/p, one per record [-]
    amplitude_ratios : a_p/a_ref, the map's scan levels [-]
    records : the record (a pulse) of each frequency ratio
    limit_states : the limit states whose boundaries are found
    """

    pulse: dict[str, Any]
    frequency_parameter: float
    reference: str
    reference_acceleration: float
    frequency_ratios: tuple[float, ...]
    amplitude_ratios: tuple[float, ...]
    records: tuple[str, ...]
    limit_states: tuple[str, ...]

    @classmethod
    def of(cls, data: Mapping[str, Any]) -> SpectrumSection:
        """The ``spectrum`` of a study's resolved config (`config.study.Study.spectrum`)."""
        return cls(
            dict(data["pulse"]), _number(data, "frequency_parameter"), str(data["reference"]),
            _number(data, "reference_acceleration"),
            tuple(float(x) for x in data["frequency_ratios"]),
            tuple(float(x) for x in data["amplitude_ratios"]),
            tuple(str(record) for record in data["records"]),
            tuple(str(state) for state in data["limit_states"]),
        )  # fmt: skip


def _number(data: Mapping[str, Any], key: str) -> float:
    value = data[key]
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise TypeError(f"{key} is not a number: {value!r}")
    return float(value)


def _optional(data: Mapping[str, Any], key: str) -> float | None:
    return None if data.get(key) is None else _number(data, key)


def _combine(value: Any) -> str | None:
    """An intensity section's ``orientation``: None, "median" or "worst"."""
    if value is not None and value not in ("median", "worst"):
        raise ValueError(f"orientation must be median or worst, not {value!r}")
    return value
