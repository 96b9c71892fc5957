"""The spectrum section of a study: an overturning spectrum of one bridge (or frame, or block)
under one pulse shape, on a grid of ω_p/p × a_p/a_ref, as the rocking literature draws it
(Makris & Roussos 2000; Zhang & Makris 2001).

A spectrum is a study whose records are the pulse at each ω_p/p, at a_p = a_ref, and whose
levels are the amplitudes: an IDA (`assessment.ida`) on the measure ``scale`` = a_p/a_ref whose
scan runs the whole amplitude grid (the map, `study.plan.Plan`) and whose bisection finds, per
frequency and limit state, the lowest amplitude that reaches it (the boundary). It runs, resumes,
shards and merges as any study does.

The frequency parameter. For Housner's block p = √(3g/(4R)). A frame or a bridge rocks on its
tall pier; rockbridge takes the parameter of the symmetric frame of Makris & Vassiliou (2013),
which rocks exactly as a block of size R·(1 + 3γ)/(1 + 2γ):

    p = √(3g/(4·R1) · (1 + 2γ)/(1 + 3γ)),   γ = m_deck/(m_pier,1 + m_pier,2),

with R1 the tall pier's semi-diagonal (γ = 0 gives the block's). For an asymmetric bridge it is a
reference scale, not an exact law: the abutments and the short pier change its dynamics.

The reference acceleration a_ref: ``g_tan_alpha``, g·tan α1, the field's (the onset of a block
and of a symmetric frame); or ``onset``, the bridge's own onset acceleration (Eq. 8), the lower
of its two directions.
"""

from __future__ import annotations

import math
from typing import Any, Literal

from pydantic import Field, PositiveFloat, PositiveInt, field_validator, model_validator

from ..core.geometry import Model
from ..core.quantities import LIMIT_STATES, check_limit_state
from ..motions.pulses import SHAPES, Pulse
from ..records.files import Record
from ..records.pulses import pulse_record
from .intensity import MAX_BISECTIONS, MAX_SCAN_LEVELS
from .loading import StrictModel
from .sweep import Range

REFERENCES = ("g_tan_alpha", "onset")
"""What the amplitudes are given as multiples of (`reference_acceleration`)."""


class SpectrumPulse(StrictModel):
    """The pulse shape of a spectrum, with its phase and cycles; amplitude and period are the
    grid's."""

    shape: Literal[SHAPES] = Field(  # type: ignore[valid-type]
        description=f"Pulse shape: {', '.join(SHAPES)}"
    )
    phase: float = Field(0.0, description="φ, where the shape has a free phase [rad]")
    cycles: PositiveFloat | None = Field(None, description="N, n or γ (motions.pulses) [-]")

    @model_validator(mode="before")
    @classmethod
    def _shorthand(cls, data: Any) -> Any:
        return {"shape": data} if isinstance(data, str) else data

    @model_validator(mode="after")
    def _valid(self) -> SpectrumPulse:
        self.at(1.0, 1.0)  # the pulse's own checks
        return self

    def at(self, amplitude: float, period: float) -> Pulse:
        """The pulse of this shape at an amplitude [m/s²] and a period [s]."""
        return Pulse(self.shape, amplitude, period, self.phase, self.cycles)


class Spectrum(StrictModel):
    """An overturning spectrum: the bridge under the pulse at every ω_p/p × a_p/a_ref."""

    pulse: SpectrumPulse = Field(description="The pulse shape (a name, or shape, phase, cycles)")
    frequencies: Range = Field(description="ω_p/p, the pulse's frequency over the bridge's "
                               "frequency parameter p [-]")  # fmt: skip
    amplitudes: Range = Field(
        description="a_p/a_ref, evenly spaced: the map's rows and the boundary's scan [-]"
    )
    reference: Literal[REFERENCES] = Field(  # type: ignore[valid-type]
        "g_tan_alpha", description="a_ref: g_tan_alpha (g·tan α1) or onset (the bridge's Eq. 8)"
    )
    tolerance: float = Field(
        0.002, gt=0.0, lt=1.0, description="Bisect each boundary to this width, relative [-]"
    )
    limit_states: list[str] | None = Field(
        None, min_length=1, description="Boundaries to find: overturning, and for a bridge "
        "gap_closure, abutment_failure, backfill_<p>; default overturning (and gap_closure and "
        "abutment_failure with abutments)",
    )  # fmt: skip
    samples_per_period: PositiveInt = Field(
        100, ge=20, le=10_000, description="Time steps per pulse period T_p [-]"
    )
    rest: PositiveFloat = Field(
        2.0, le=100.0, description="Free vibration after the pulse, in periods 2π/p of the "
        "bridge [-]",
    )  # fmt: skip

    @field_validator("amplitudes")
    @classmethod
    def _linear_and_positive(cls, amplitudes: Range) -> Range:
        if amplitudes.spacing != "linear" or not 0.0 < amplitudes.start < amplitudes.stop:
            raise ValueError("amplitudes must be linear, from a positive start up to stop")
        if amplitudes.count > MAX_SCAN_LEVELS:  # the scan levels of each frequency's IDA
            raise ValueError(f"at most {MAX_SCAN_LEVELS} amplitudes, not {amplitudes.count}")
        return amplitudes

    @field_validator("frequencies")
    @classmethod
    def _positive(cls, frequencies: Range) -> Range:
        if min(frequencies.start, frequencies.stop) <= 0.0:
            raise ValueError("frequency ratios must be positive")
        if not frequencies.start < frequencies.stop:  # 10:1:40 ran, its axis reversed
            raise ValueError("frequency ratios must rise, from start up to stop")
        return frequencies

    @model_validator(mode="after")
    def _bisections(self) -> Spectrum:
        start, count = self.amplitudes.start, self.amplitudes.count
        step = (self.amplitudes.stop - start) / (count - 1)
        if step / (self.tolerance * start) > 2.0**MAX_BISECTIONS:
            raise ValueError(f"amplitude step / (tolerance · start) must be at most "
                             f"2^{MAX_BISECTIONS}: raise start, count or tolerance")  # fmt: skip
        return self

    @field_validator("limit_states")
    @classmethod
    def _known_states(cls, names: list[str] | None) -> list[str] | None:
        if names is not None and len(set(names)) != len(names):
            raise ValueError("a limit state is listed twice")
        return names if names is None else [check_limit_state(name) for name in names]

    def states(self, model: Model) -> list[str]:
        """The limit states whose boundaries are found."""
        if self.limit_states is not None:
            return self.limit_states
        return [s for s in LIMIT_STATES if s != "backfill_50"] if model.has_abutments else [
            "overturning"
        ]  # fmt: skip

    def amplitude_ratios(self) -> list[float]:
        """The amplitudes, start + step·k as the IDA's lattice computes its scan levels [-]."""
        start, count = self.amplitudes.start, self.amplitudes.count
        step = (self.amplitudes.stop - start) / (count - 1)
        return [start + step * k for k in range(count)]

    def ida(self, model: Model) -> dict[str, Any]:
        """The intensity section it runs as: an IDA on ``scale`` = a_p/a_ref whose scan levels
        are the amplitudes (`config.intensity.Intensity`)."""
        start, stop, count = self.amplitudes.start, self.amplitudes.stop, self.amplitudes.count
        return {
            "measure": "scale", "levels": None, "period": None, "damping": 0.05,
            "ida": {"start": start, "step": (stop - start) / (count - 1), "max": stop,
                    "tolerance": self.tolerance, "limit_states": self.states(model)},
        }  # fmt: skip

    def records(self, model: Model) -> list[Record]:
        """The pulse at each ω_p/p, at a_p = a_ref, sampled at about T_p/``samples_per_period``
        (`motions.pulses.Pulse.time_step`) and followed by ``rest`` periods 2π/p of rest; ids
        from the parameters (`records.pulses.pulse_id`)."""
        p, reference = frequency_parameter(model), reference_acceleration(model, self.reference)
        found = []
        for ratio in self.frequencies.values():
            pulse = self.pulse.at(reference, 2.0 * math.pi / (ratio * p))
            step = pulse.time_step(self.samples_per_period)
            found.append(pulse_record(pulse, step, self.rest * 2.0 * math.pi / p))
        return found

    def described(self, model: Model, records: list[Record]) -> dict[str, Any]:
        """What the results file keeps of the spectrum (`Study.spectrum`), JSON-ready."""
        return {
            **self.model_dump(mode="json"),
            "frequency_parameter": frequency_parameter(model),
            "reference_acceleration": reference_acceleration(model, self.reference),
            "frequency_ratios": self.frequencies.values(),
            "amplitude_ratios": self.amplitude_ratios(),
            "records": [record.name for record in records],
            "limit_states": self.states(model),
        }  # fmt: skip


def frequency_parameter(model: Model) -> float:
    """p of a block, frame or bridge: √(3g/(4R1)·(1 + 2γ)/(1 + 3γ)) (the module's docstring)
    [rad/s]."""
    gamma = model.md / (model.m1 + model.m2)
    return math.sqrt(3.0 * model.g / (4.0 * model.R1) * (1.0 + 2.0 * gamma) / (1.0 + 3.0 * gamma))


def reference_acceleration(model: Model, reference: str) -> float:
    """a_ref: g·tan α1, or the lower of the bridge's two onset accelerations (Eq. 8) [m/s²]."""
    if reference == "g_tan_alpha":
        return model.g * model.B / model.H1
    from ..core.impacts import onset_threshold  # the compiled kernels: only where asked for

    return min(abs(onset_threshold(model, s)) for s in (1.0, -1.0))
