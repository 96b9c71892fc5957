"""IDA capacities in any intensity measure.

A record scaled by λ has every amplitude measure scaled by λ and its Arias intensity by λ²
(`motions.intensity.MEASURES`), so the level at which an IDA finds a capacity, in the study's
measure, is a level of any other measure too: `Conversion` maps it record by record, and the
fragility is fitted again (`fragility.fragilities` with ``measure``) without running anything.
Capacities censored at the first or the last level are censored at those levels converted, which
differ from record to record.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from ..core.quantities import STANDARD_GRAVITY
from ..errors import InputError
from ..motions.intensity import MEASURES, convert, measure_value
from ..results.reading import read_intensity
from ..results.sections import IntensitySection

Spectral = tuple[float | None, Any, float]
"""(period [s], period range [s], damping [-]) of a spectral measure."""


@dataclass(frozen=True)
class Conversion:
    """Levels of a study's intensity measure as levels of another, record by record.

    Attributes
    ----------
    measure : the other measure (`MEASURES`)
    study_measure : the study's
    natives, targets : each record's own value of the study's measure and of the other
    per_bridge : bridge → factor on the other measure (``pga_tan_alpha``: 1/(g·tan α1)); 1 if
        absent
    """

    measure: str
    study_measure: str
    natives: dict[str, float]
    targets: dict[str, float]
    per_bridge: dict[str, float]

    @classmethod
    def of(
        cls,
        file: h5py.File,
        path: str | Path,
        measure: str,
        period: float | None = None,
        period_range: tuple[float, float] | None = None,
    ) -> Conversion:
        """The conversion of an open results file of an IDA to ``measure``.

        Raises
        ------
        InputError
            The measure is unknown, lacks its period, or the study is not an IDA.
        """
        intensity = read_intensity(file)
        if measure not in MEASURES:
            raise InputError(path, [("measure", f"unknown {measure!r}: choose one of "
                                     f"{', '.join(MEASURES)}")])  # fmt: skip
        if measure == "sa_g" and period is None or measure == "avgsa_g" and period_range is None:
            raise InputError(path, [("measure", f"{measure} needs its period (--period, "
                                     "--period-range)")])  # fmt: skip
        if intensity is None or intensity.ida is None:
            why = "only an IDA's capacities convert (stripes are fitted in the study's measure)"
            raise InputError(path, [("measure", why)])
        base = "pga_g" if measure == "pga_tan_alpha" else measure
        records = file["records"]
        natives, targets = {}, {}
        for name in records:
            node = records[name]
            if "acceleration" not in node:  # a record that could not be read: no analyses
                continue
            natives[name] = _value(node, intensity.measure, intensity.spectral, intensity)
            spectral = (period, period_range, intensity.damping)
            targets[name] = _value(node, base, spectral, intensity)
        per_bridge = {}
        if measure == "pga_tan_alpha":  # PGA over the tall pier's rocking threshold g·tan α1
            for name, node in file["bridges"].items():
                threshold = float(node.attrs["model_g"]) * math.tan(float(node.attrs["alpha1"]))
                per_bridge[name] = STANDARD_GRAVITY / threshold
        return cls(measure, intensity.measure, natives, targets, per_bridge)

    def value(self, bridge: str, record: str, level: float) -> float:
        """The level of the other measure of ``record`` scaled to ``level`` of the study's."""
        base = "pga_g" if self.measure == "pga_tan_alpha" else self.measure
        converted = convert(
            level, self.natives[record], self.study_measure, self.targets[record], base
        )
        return converted * self.per_bridge.get(bridge, 1.0)


def _value(node: h5py.Group, name: str, spectral: Spectral, intensity: IntensitySection) -> float:
    """A stored record's value of a measure at ``spectral`` (period, period range, damping):
    the attribute the run wrote (at the study's ``intensity``) where it is the same measure (Sa
    at the same period), else computed from the stored samples."""
    stored = name in node.attrs and (
        name not in ("sa_g", "avgsa_g") or _same_periods(name, spectral, intensity)
    )
    if stored:
        return float(node.attrs[name])
    return measure_value(name, node["acceleration"][()], float(node.attrs["time_step"]), *spectral)


def _same_periods(name: str, spectral: Spectral, intensity: IntensitySection) -> bool:
    """Whether the Sa or AvgSa stored with a record (at the study's ``intensity``) is at the
    periods asked."""
    which = 0 if name == "sa_g" else 1
    asked, stored = spectral[which], intensity.spectral[which]
    same = stored is not None and asked is not None and np.array_equal(stored, asked)
    return same and intensity.damping == spectral[2]
