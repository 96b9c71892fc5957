"""The orientation section of a study's records: which horizontal direction the bridge feels.

The bridge's one degree of freedom feels the ground along its longitudinal axis. Without this
section a record is analysed as given (one component: a file, a FEMA P695 set's ``a`` or
``b``), today's behaviour. With it, every record is a pair of horizontal components (a file and
its ``second``, or a FEMA P695 record's ``a`` and ``b``) and the bridge feels the projection on
its axis, at an angle θ from the pair's first component toward its second:

- ``angle: 30``: one stated angle of incidence;
- ``angles: [0, 45, 90]`` or ``angles: {start: 0, stop: 180, step: 15}``: a sweep; each angle is
  a record of its own, whose median and worst over the angles (the response counterparts of
  RotD50 and RotD100, `motions.orientation.summarize_angles`) say how much orientation matters.

A projection is named ``<pair>+<θ>deg`` (``FF01+30deg``) and holds its pair and angle
(``pair``, ``angle_deg``) in the results; at 0° its samples are the first component's, at 90°
the second's, bit for bit. An intensity section scales each projection like any record, by its
own measure. A bridge with unequal piers answers a and −a differently: a sweep over 0–360°
covers both senses of every direction, one over 0–180° each direction once.
"""

from __future__ import annotations

import math
from typing import Annotated

from pydantic import Discriminator, Field, Tag, field_validator, model_validator

from .loading import StrictModel, kind_of

MAX_ANGLES = 360
"""Most angles a sweep may take (each multiplies the study's records)."""

Angle = Annotated[float, Field(ge=-360.0, le=360.0, allow_inf_nan=False)]
"""An angle from a pair's first component toward its second [deg]."""


class AngleRange(StrictModel):
    """Angles from ``start`` to ``stop`` by ``step``, ``stop`` included where a step lands on it."""

    start: Angle = Field(description="First angle [deg]")
    stop: Angle = Field(description="Last angle, included where a step lands on it [deg]")
    step: float = Field(gt=0.0, le=360.0, description="Step between angles [deg]")

    @model_validator(mode="after")
    def _ordered(self) -> AngleRange:
        if self.stop < self.start:
            raise ValueError("stop must not be below start")
        if len(self.values()) > MAX_ANGLES:
            raise ValueError(f"at most {MAX_ANGLES} angles: raise step")
        return self

    def values(self) -> list[float]:
        """The angles, in order [deg] (each start + k·step, rounded to 1e-9°, so that 0.1° steps
        land on their stop)."""
        count = math.floor((self.stop - self.start) / self.step + 1e-9) + 1
        return [round(self.start + k * self.step, 9) for k in range(count)]


AngleValues = Annotated[
    Annotated[list[Angle], Tag("=list")] | Annotated[AngleRange, Tag("=mapping")],
    Discriminator(
        kind_of, custom_error_type="angles",
        custom_error_message="expected a list of angles or a range {start, stop, step}",
    ),
]  # fmt: skip


class Orientation(StrictModel):
    """The direction the bridge feels each record's pair of horizontal components in: one stated
    angle, or a sweep of angles (`config.orientation`). Give one."""

    angle: Angle | None = Field(
        None, description="The bridge's axis, from each pair's first component toward its "
        "second [deg]",
    )  # fmt: skip
    angles: AngleValues | None = Field(
        None, description="A sweep: a list of angles or {start, stop, step} [deg]; each angle is "
        "a record of its own",
    )  # fmt: skip

    @field_validator("angles")
    @classmethod
    def _distinct(cls, angles: list[float] | AngleRange | None) -> list[float] | AngleRange | None:
        listed = angles.values() if isinstance(angles, AngleRange) else angles
        if listed is not None and not listed:
            raise ValueError("give at least one angle")
        if listed is not None and len(set(listed)) != len(listed):
            raise ValueError("an angle is listed twice")
        if listed is not None and len(listed) > MAX_ANGLES:
            raise ValueError(f"at most {MAX_ANGLES} angles")
        return angles

    @model_validator(mode="after")
    def _one(self) -> Orientation:
        if (self.angle is None) == (self.angles is None):
            raise ValueError("give exactly one of angle (one direction) and angles (a sweep)")
        return self

    def values(self) -> list[float]:
        """The angles analysed, in order [deg]."""
        if self.angle is not None:
            return [self.angle]
        assert self.angles is not None
        return self.angles.values() if isinstance(self.angles, AngleRange) else list(self.angles)


def angle_id(pair: str, angle: float) -> str:
    """The id of a pair's projection at ``angle`` [deg]: ``FF01+30deg``, ``R1+-15deg``,
    ``R1+7.5deg``."""
    return f"{pair}+{angle:.10g}deg"
