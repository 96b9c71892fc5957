"""The record-set config: what `rockbridge generate-records` reads.

Every length of time is in seconds, accelerations given in g are named ``*_g``.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, model_validator

from .loading import StrictModel

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
    """A set of artificial accelerograms matched to an EN 1998-1 elastic spectrum."""

    target: TargetSpectrum = Field(description="The target spectrum.")
    count: int = Field(ge=1, le=1000, description="Number of records [-]; EN 1998-1 asks >= 3.")
    duration: float = Field(gt=0.0, le=600.0, description="Duration of each record [s].")
    time_step: float = Field(gt=0.0, le=0.05, description="Time step of the records [s].")
    envelope: EnvelopeConfig = Field(
        description="Intensity envelope; rise + stationary + decay must equal the duration."
    )
    band: tuple[float, float] = Field(
        (0.05, 4.0),
        description="Shortest and longest period matched and checked, within 0 < T <= 4 s, the "
        "shortest at least 5 time steps [s]. EN 1998-1 checks 0.2*T1 to 2*T1.",
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
    seed: int = Field(ge=0, description="Seed of numpy.random.default_rng for the whole set [-].")
    name_prefix: str = Field(
        "AR",
        pattern=r"^[A-Za-z0-9_-]{1,20}$",
        description="Record names are the prefix and a two-digit number, e.g. AR01 [-].",
    )
    gravity: float = Field(9.81, gt=0.0, description="Acceleration of gravity [m/s^2].")

    @model_validator(mode="after")
    def _check_timing(self) -> RecordSetConfig:
        steps = self.duration / self.time_step
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
