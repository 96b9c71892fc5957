"""Matching a recorded accelerogram (a seed) to a target spectrum, keeping what makes it a record:
its phases and envelope, its ground displacement and velocity, its duration and build-up.

`match_seed` runs steps 3–4 of `matching` (wavelets, baseline correction, exact PGA) on the
seed itself, with four changes that each answer a measured failure (ten FEMA P695 far-field
seeds, EN 1998-1 type 1, ground C, a_g = 0.6 g; docs/records.md):

1. It starts from the seed linearly scaled to the target PGA, without the frequency-domain step
   of artificial records: scaling the Fourier amplitudes by target/spectrum moves the energy of
   each band with that band's own timing in the record, and alone made D5–95 1.13–1.75 × the
   seed's.
2. The baseline correction leaves the least displacement away from the scaled seed's
   (`baseline.BaselineCorrection.anchored`), not the least displacement: the seed's own slow
   motion stays, and what the long-period wavelets add cannot wander (with the two-term
   correction alone, PGD grew to up to 5.4 × the scaled seed's; towards zero, a seed's own
   1.2 m of ground displacement fell to 0.36 m).
3. The wavelet system also keeps the times at which the seed builds up 5, 25, 50, 75 and 95 % of
   its Arias intensity (`wavelets.AriasGoal`), and iterates rank by their change of D5–95 and
   D5–75 too (`matching.MatchProblem.rank`): wavelets sit where oscillators peak, which
   concentrated the shaking (D5–75 of Chi-Chi TCU045 7.4 → 1.7 s).
4. The fit is checked on the dense grid of `spectral_fit`; the periods where it misses the
   tolerance join the matching periods and the matching goes on, up to
   `MatchSettings.dense_rounds` times.

Corrections are tapered where the seed is quiet (`QUIET`), so its lead-in and tail stay quiet.
A seed whose time step cannot resolve the band is first resampled (`resample_for_band`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from scipy import signal

from .baseline import (
    BaselineCorrection,
    compute_arias_times,
    compute_significant_duration,
    correction_terms,
)
from .intensity import peak_motion
from .matching import (
    MatchedRecord,
    MatchProblem,
    MatchSettings,
    compute_matching_periods,
    match_in_time_domain,
)
from .spectral_fit import measure_fit
from .wavelets import AriasGoal

QUIET = 0.05
"""Where a seed's envelope is below this share of its peak, corrections are tapered in
proportion, so that its quiet lead-in and tail stay quiet [-]."""

STEPS_PER_PERIOD = 5
"""A record resolves a period of at least this many of its time steps [-]."""

MARGIN = 0.9
"""At the matching periods a seed is matched to this share of the tolerance, so that the fit
between them, checked on the dense grid, has room [-]."""


def match_seed(
    spectrum: Callable[[np.ndarray], np.ndarray],
    band: tuple[float, float],
    peak_acceleration: float,
    seed: np.ndarray,
    time_step: float,
    settings: MatchSettings | None = None,
    check_periods: int = 100,
) -> MatchedRecord:
    """Match a seed to a target spectrum over a band, its PGA scaled exactly to the target's.

    Parameters
    ----------
    spectrum
        the target pseudo-spectral acceleration at given periods, also a little beyond the band
        [m/s²].
    band
        shortest and longest period to match, the shortest at least `STEPS_PER_PERIOD` time
        steps [s].
    peak_acceleration
        target PGA [m/s²].
    seed
        the accelerogram to match, at uniform steps [m/s²].
    time_step
        its time step, kept by the matched record [s].
    settings
        tolerance (on the dense grid) and iteration controls (default `MatchSettings()`);
        ``max_attempts`` is not used: there are no phases to draw again.
    check_periods
        the matching periods are this grid's, refined twice (`compute_matching_periods`) [-].

    Returns
    -------
    MatchedRecord
        its ``misfit`` is max |computed/target − 1| on the dense grid; ``iterations`` counts
        every round's.
    """
    settings = settings or MatchSettings()
    seed = np.asarray(seed, dtype=float)
    if seed.ndim != 1 or seed.size < 8 or not np.all(np.isfinite(seed)) or not seed.any():
        raise ValueError("the seed must be a finite, non-zero record of at least 8 samples")
    shape = seed_envelope(seed, time_step)
    scaled = seed * (peak_acceleration / np.max(np.abs(seed)))
    correction = _anchored_correction(shape, time_step, scaled, band[1], settings)
    arias = AriasGoal.of(seed, time_step)
    periods = compute_matching_periods(band, check_periods, time_step)
    aim = replace(settings, tolerance=MARGIN * settings.tolerance)
    acceleration, total = scaled, 0
    for _ in range(settings.dense_rounds):
        problem = MatchProblem.of(
            periods, spectrum(periods), peak_acceleration, time_step, shape,
            np.minimum(1.0, shape / QUIET), aim, band, correction, arias,
        )  # fmt: skip
        acceleration, iterations, _ = match_in_time_domain(problem, acceleration)
        total += iterations
        fit = measure_fit(acceleration, time_step, spectrum, band, settings.damping)
        misses = fit.misses(settings.tolerance)
        if misses.size == 0:
            break
        periods = np.union1d(periods, misses)
    misfit = max(1.0 - fit.min_ratio, fit.max_ratio - 1.0)
    return MatchedRecord(acceleration, time_step, 1, total, misfit)


def _anchored_correction(shape, time_step, scaled, longest_period, settings) -> BaselineCorrection:
    """The least-displacement correction away from the scaled seed's (final velocity and
    displacement zeroed first by the enveloped linear trend), its polynomials over the part of
    the record where the seed is not quiet."""
    reference = BaselineCorrection.of(shape, time_step)(scaled)
    active = np.flatnonzero(shape >= QUIET)
    span = (int(active[0]), int(active[-1]))
    terms = correction_terms((span[1] - span[0]) * time_step, longest_period,
                             settings.baseline_reach)  # fmt: skip
    return BaselineCorrection.of(shape, time_step, terms, span).anchored(reference)


def seed_envelope(acceleration: np.ndarray, time_step: float, window: float = 1.0) -> np.ndarray:
    """A record's intensity envelope: the moving RMS of the acceleration over ``window`` [s],
    normalised to a peak of 1 [-]."""
    width = max(1, int(round(window / time_step)))
    power = np.convolve(acceleration**2, np.ones(width) / width, mode="same")
    envelope = np.sqrt(power)
    return envelope / envelope.max()


def resample_for_band(
    acceleration: np.ndarray, time_step: float, shortest_period: float
) -> tuple[np.ndarray, float]:
    """A record at a time step that resolves ``shortest_period`` (`STEPS_PER_PERIOD` steps).

    The step is divided by the smallest whole factor that does it, and the record interpolated
    band-limited: zeros inserted, then a Kaiser-windowed low-pass at the old Nyquist frequency
    (`scipy.signal.resample_poly`), so it gains no content the record did not have.

    Parameters
    ----------
    acceleration
        the record [m/s²].
    time_step
        its time step [s].
    shortest_period
        the shortest period it must resolve [s].

    Returns
    -------
    tuple
        the record [m/s²] and its time step [s]; unchanged when the step already resolves it.
    """
    factor = math.ceil(STEPS_PER_PERIOD * time_step / shortest_period - 1e-9)
    if factor <= 1:
        return acceleration, time_step
    return signal.resample_poly(acceleration, factor, 1), time_step / factor


@dataclass(frozen=True)
class MotionTraits:
    """What matching should keep of a seed, measured on a record.

    Attributes
    ----------
    pgv, pgd
        peak ground velocity [m/s] and displacement [m] (`intensity.peak_motion`).
    d5_95, d5_75
        significant durations between 5 % and 95 %, 75 % of the Arias intensity [s].
    arias_time
        when half the Arias intensity is reached, the centre of the shaking [s].
    """

    pgv: float
    pgd: float
    d5_95: float
    d5_75: float
    arias_time: float

    @classmethod
    def of(cls, acceleration: np.ndarray, time_step: float) -> MotionTraits:
        """The traits of a record [m/s²] at ``time_step`` [s]."""
        _, pgv, pgd = peak_motion(acceleration, time_step)
        return cls(
            pgv,
            pgd,
            compute_significant_duration(acceleration, time_step),
            compute_significant_duration(acceleration, time_step, end=0.75),
            float(compute_arias_times(acceleration, time_step, np.array([0.5]))[0]),
        )
