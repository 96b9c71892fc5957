"""Two horizontal components of a ground motion, combined: the component along any direction
(`project`), the orientation-independent spectra RotD50 and RotD100 (`compute_rotd_psa`), and
what a quantity does over the angles a study swept (`summarize_angles`).

A pair's first component a₁ points along angle 0 and its second a₂ along +90°; the ground
acceleration along the direction at angle θ from the first toward the second is

    a_θ(t) = a₁(t)·cos θ + a₂(t)·sin θ,

and a linear oscillator's response to a_θ is the same combination of its responses to a₁ and a₂.
RotDnn (Boore 2010) is the nn-th percentile, over θ in [0°, 180°), of the oscillator's peak
response along θ: RotD50 the median, RotD100 the largest, both independent of how the instrument
happened to be oriented (for angles on a grid the rotation maps onto itself). Angles are in
degrees, as the field states them; cos and sin are exact at multiples of 90°, so the projection
at 0° is the first component and at 90° the second, bit for bit.

References
----------
Boore, D. M. (2010). Orientation-independent, nongeometric-mean measures of seismic intensity
from two horizontal components of motion. Bulletin of the Seismological Society of America
100(4), 1830–1835. doi:10.1785/0120090400
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

#: Step of the angles over which RotDnn is taken, Boore (2010) §"Method": 0°, 1°, …, 179° [deg].
ROTD_STEP = 1.0


def direction_cosines(angle: float) -> tuple[float, float]:
    """cos θ and sin θ of an angle in degrees, exact (0, ±1) at multiples of 90° [-].

    Raises
    ------
    ValueError
        The angle is not finite.
    """
    if not math.isfinite(angle):
        raise ValueError(f"an angle must be finite, got {angle!r}")
    quarter, rest = divmod(angle, 90.0)
    if rest == 0.0:
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[int(quarter) % 4]
    radians = math.radians(angle)
    return math.cos(radians), math.sin(radians)


def project(first: np.ndarray, second: np.ndarray, angle: float) -> np.ndarray:
    """The ground acceleration along the direction at ``angle`` from the first component toward
    the second: a₁·cos θ + a₂·sin θ.

    Parameters
    ----------
    first, second
        the two horizontal components at the same samples, the second at +90° from the first
        [m/s²].
    angle
        θ, from the first component toward the second [deg].

    Returns
    -------
    numpy.ndarray
        a_θ at the samples [m/s²]; at 0° a copy of ``first``, at 90° of ``second``, bit for bit.

    Raises
    ------
    ValueError
        The components differ in shape, or the angle is not finite.
    """
    first, second = np.asarray(first, dtype=float), np.asarray(second, dtype=float)
    if first.shape != second.shape:
        raise ValueError(f"the components differ in shape: {first.shape} and {second.shape}")
    cos, sin = direction_cosines(angle)
    if sin == 0.0:  # the other component left out, not added times 0
        return cos * first
    if cos == 0.0:
        return sin * second
    return cos * first + sin * second


def rotd_angles(step: float = ROTD_STEP) -> np.ndarray:
    """The angles RotDnn is taken over: 0, step, … below 180 [deg]."""
    if not 0.0 < step <= 90.0:
        raise ValueError(f"the angle step must be in (0, 90] degrees, got {step!r}")
    return np.arange(0.0, 180.0, step)


def compute_rotd_psa(
    first: np.ndarray,
    second: np.ndarray,
    time_step: float,
    periods: np.ndarray,
    damping: float = 0.05,
    percentiles: tuple[float, ...] = (50.0, 100.0),
    step: float = ROTD_STEP,
) -> np.ndarray:
    """RotDnn pseudo-spectral accelerations of a pair of horizontal components (Boore 2010).

    Each angle's peak is the exact one of `spectra.compute_psa` for the ground motion projected
    on that angle (a linear oscillator's response to the projection is the projection of its
    responses, so this is Boore's rotation of the oscillator's responses, with the spectra
    module's sub-steps and interpolated crests).

    Parameters
    ----------
    first, second
        the two horizontal components, the second at +90° from the first [m/s²].
    time_step
        time step of both [s].
    periods
        oscillator periods; 0 gives RotDnn of the peak ground acceleration [s].
    damping
        oscillator damping ratio ξ [-].
    percentiles
        which RotDnn: 50 the median over angles, 100 the largest [-].
    step
        step of the angles over [0°, 180°) [deg].

    Returns
    -------
    numpy.ndarray
        shape (len(percentiles), len(periods)): RotDnn at each period [m/s²].
    """
    from .spectra import compute_psa  # numba: not loaded where only projections are taken

    periods = np.atleast_1d(np.asarray(periods, dtype=float))
    peaks = np.array(
        [
            compute_psa(project(first, second, a), time_step, periods, damping)
            for a in rotd_angles(step)
        ]
    )
    return np.percentile(peaks, percentiles, axis=0)


class AngleSummary(NamedTuple):
    """A quantity over the angles a pair was analysed at: the response counterpart of RotD50
    (``median``) and RotD100 (``worst``), and the angle of the worst (``critical``, the first
    such in the order given) [deg]."""

    median: float
    worst: float
    critical: float


def summarize_angles(angles: np.ndarray, values: np.ndarray) -> AngleSummary:
    """The median, the largest and its angle of a quantity over angles (NaN values, analyses
    that did not finish, are left out; all NaN gives NaN).

    Parameters
    ----------
    angles
        the angles analysed [deg].
    values
        the quantity at each angle (its unit).
    """
    angles, values = np.asarray(angles, dtype=float), np.asarray(values, dtype=float)
    if angles.shape != values.shape or angles.ndim != 1:
        raise ValueError("give one value per angle")
    finite = ~np.isnan(values)
    if not finite.any():
        return AngleSummary(math.nan, math.nan, math.nan)
    kept = values[finite]
    worst = int(np.argmax(kept))
    return AngleSummary(float(np.median(kept)), float(kept[worst]), float(angles[finite][worst]))
