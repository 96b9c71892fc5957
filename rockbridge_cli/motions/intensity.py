"""Intensity measures of a ground motion: the one table of their names, units and labels, and
their values for a record, exact for a piecewise-linear acceleration.

Scaling a record by λ scales every amplitude measure by λ, Arias intensity by λ² (`Measure.power`):
so the capacities an IDA finds in one measure convert exactly to any other (`convert`).

References
----------
Arias, A. (1970). A measure of earthquake intensity. In Seismic Design for Nuclear Power Plants,
MIT Press, 438–483: I_A = π/(2g)·∫a² dt.
EPRI (1988). A criterion for determining exceedance of the operating basis earthquake, EPRI
NP-5930: CAV = ∫|a| dt.
Eads, L., Miranda, E., Lignos, D. (2015). Average spectral acceleration as an intensity measure
for collapse risk assessment. Earthquake Eng. Struct. Dyn. 44(12): AvgSa, the geometric mean of
Sa over a range of periods.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..core.quantities import STANDARD_GRAVITY
from .baseline import integrate_motion


class Measure(NamedTuple):
    """An intensity measure.

    Attributes
    ----------
    name : as configs, results and commands name it
    unit : of its values (g is standard gravity)
    power : a record scaled by λ has the measure scaled by λ**power
    label : for tables and figures, with the unit
    suffix : what follows the level in a scaled record's id (``AR01+0.6g``); ids hold no slash
    runs : a study can scale records to it (False: only converted to, as a per-bridge measure)
    """

    name: str
    unit: str
    power: int
    label: str
    suffix: str
    runs: bool = True


MEASURES = {
    m.name: m
    for m in (
        Measure("pga_g", "g", 1, "PGA [g]", "g"),
        Measure("pgv", "m/s", 1, "PGV [m/s]", "mps"),
        Measure("pgd", "m", 1, "PGD [m]", "m"),
        Measure("sa_g", "g", 1, "Sa(T) [g]", "g"),
        Measure("avgsa_g", "g", 1, "AvgSa [g]", "g"),
        Measure("arias", "m/s", 2, "Arias intensity [m/s]", "mps"),
        Measure("cav", "m/s", 1, "CAV [m/s]", "mps"),
        Measure("pga_tan_alpha", "-", 1, "PGA/(g·tan α) [-]", "", runs=False),
        Measure("scale", "-", 1, "scale factor [-]", "x"),
    )
}
"""Every intensity measure rockbridge knows, by name. ``pga_tan_alpha`` is PGA over the tall
pier's rocking threshold g·tan α: a constant per bridge times PGA, so its β is PGA's; it is
converted to, not run (a study's records are scaled once for every bridge)."""

AVGSA_PERIODS = 10
"""Periods, log-spaced over the range given, whose Sa the geometric mean AvgSa takes."""


def peak_motion(acceleration: np.ndarray, time_step: float) -> tuple[float, float, float]:
    """PGA [m/s²], PGV [m/s] and PGD [m] of a record, its velocity and displacement integrated
    from rest (`baseline.integrate_motion`). PGV is exact between samples (velocity is quadratic
    within a step, its extreme where the acceleration changes sign); PGD is taken at the
    samples."""
    a = np.asarray(acceleration, dtype=float)
    velocity, displacement = integrate_motion(a, time_step)
    crossing = np.sign(a[:-1]) * np.sign(a[1:]) < 0.0
    start, end = a[:-1][crossing], a[1:][crossing]
    turning = velocity[:-1][crossing] + 0.5 * start * time_step * start / (start - end)
    pgv = max(float(np.max(np.abs(velocity))), float(np.max(np.abs(turning), initial=0.0)))
    return float(np.max(np.abs(a))), pgv, float(np.max(np.abs(displacement)))


def arias_intensity(acceleration: np.ndarray, time_step: float) -> float:
    """Arias intensity π/(2g)·∫a² dt [m/s], exact for a piecewise-linear acceleration."""
    a = np.asarray(acceleration, dtype=float)
    with np.errstate(over="ignore"):  # a record beyond floating point has an infinite one
        squares = a[:-1] ** 2 + a[:-1] * a[1:] + a[1:] ** 2
        return math.pi / (2.0 * STANDARD_GRAVITY) * time_step / 3.0 * float(np.sum(squares))


def cumulative_absolute_velocity(acceleration: np.ndarray, time_step: float) -> float:
    """CAV = ∫|a| dt [m/s], exact for a piecewise-linear acceleration (a step whose ends differ
    in sign contributes two triangles)."""
    a = np.asarray(acceleration, dtype=float)
    start, end = np.abs(a[:-1]), np.abs(a[1:])
    same = np.sign(a[:-1]) * np.sign(a[1:]) >= 0.0
    with np.errstate(over="ignore"):  # a record beyond floating point has an infinite one
        total = start + end
        crossing = 0.5 * (start**2 + end**2) / np.where(same, 1.0, total)
        areas = np.where(same, 0.5 * total, crossing)
    return time_step * float(np.sum(areas))


def spectral_periods(period_range: tuple[float, float]) -> np.ndarray:
    """The periods of AvgSa over a range [s]: `AVGSA_PERIODS` log-spaced, both ends included."""
    return np.geomspace(period_range[0], period_range[1], AVGSA_PERIODS)


def measure_value(
    name: str,
    acceleration: np.ndarray,
    time_step: float,
    period: float | None = None,
    period_range: tuple[float, float] | None = None,
    damping: float = 0.05,
) -> float:
    """A record's intensity in one measure, in the measure's unit (`MEASURES`).

    Parameters
    ----------
    name
        a measure of `MEASURES` that a study runs (not ``pga_tan_alpha``).
    acceleration, time_step
        the record [m/s²] and its sample interval [s].
    period, period_range, damping
        of ``sa_g`` [s] and of ``avgsa_g`` [s], and their damping ratio [-].
    """
    if name == "scale":
        return 1.0
    if name in ("sa_g", "avgsa_g"):
        from .spectra import compute_psa  # compiled: loaded only where a spectrum is needed

        if name == "sa_g":
            psa = compute_psa(acceleration, time_step, np.array([period]), damping)
            return float(psa[0]) / STANDARD_GRAVITY
        assert period_range is not None
        psa = compute_psa(acceleration, time_step, spectral_periods(period_range), damping)
        return float(np.exp(np.mean(np.log(psa / STANDARD_GRAVITY))))
    if name == "arias":
        return arias_intensity(acceleration, time_step)
    if name == "cav":
        return cumulative_absolute_velocity(acceleration, time_step)
    pga, pgv, pgd = peak_motion(acceleration, time_step)
    values = {"pga_g": pga / STANDARD_GRAVITY, "pgv": pgv, "pgd": pgd}
    if name not in values:
        raise ValueError(f"{name!r} is not an intensity measure a record has alone")
    return values[name]


def record_measures(
    acceleration: np.ndarray,
    time_step: float,
    period: float | None = None,
    period_range: tuple[float, float] | None = None,
    damping: float = 0.05,
) -> dict[str, float]:
    """A record's values of every measure it has alone (`MEASURES` but ``scale`` and
    ``pga_tan_alpha``), Sa and AvgSa where their periods are given, in the measures' units."""
    names = ["pga_g", "pgv", "pgd", "arias", "cav"]
    names += ["sa_g"] if period is not None else []
    names += ["avgsa_g"] if period_range is not None else []
    return {
        name: measure_value(name, acceleration, time_step, period, period_range, damping)
        for name in names
    }


def convert(
    level: float, native: float, native_measure: str, target: float, target_measure: str
) -> float:
    """The intensity, in another measure, of a record scaled to ``level`` of its study's measure.

    Parameters
    ----------
    level
        the level in the study's measure.
    native, target
        the record's own (unscaled) values of the study's measure and of the other one.
    native_measure, target_measure
        their names (`MEASURES`).

    Returns
    -------
    float
        λ**power · target, with λ = (level / native)**(1 / native's power) the factor that scaled
        the record.
    """
    factor = (level / native) ** (1.0 / MEASURES[native_measure].power)
    return factor ** MEASURES[target_measure].power * target


def scaled_id(base: str, level: float, measure: str) -> str:
    """The id of a record scaled to an intensity level: ``AR01+0.6g``, ``AR01+1.5x``,
    ``FF01a+0.4mps``."""
    return f"{base}+{level:.10g}{MEASURES[measure].suffix}"
