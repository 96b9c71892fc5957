"""Artificial accelerograms whose response spectrum matches a target spectrum.

A record is built in four steps, all deterministic for a given random generator:

1. a stationary Gaussian process with random phases whose Fourier amplitudes follow the target,
   multiplied by a compound envelope (Jennings, Housner & Tsai 1968);
2. a few frequency-domain iterations that scale the Fourier amplitudes of the stationary part by
   the ratio target / computed spectrum (Gasparini & Vanmarcke 1976, SIMQKE);
3. time-domain iterations that add small wavelets, each tuned to one oscillator and placed at the
   time of a crest of its response, with amplitudes from the linear system that links the
   wavelets to the crests (Lilhanand & Tseng 1988; Abrahamson 1992; Al Atik & Abrahamson 2010);
   the same system holds the peak ground acceleration at its target; a step is halved until it
   lowers the RMS misfit;
4. after each step, a baseline correction that zeroes the final velocity and displacement with
   the least ground displacement (an enveloped slow trend, in the spirit of Boore 2001) and an
   exact scaling to the target PGA, so that every iterate is a finished record; the best one is
   kept.

Step 3's wavelets and their linear system are in `wavelets`, step 4's baseline correction in
`baseline`; a recorded seed goes through steps 3–4 alone, with what keeps its ground and its
duration (`seeds`). The wavelet system uses the exact response of the discrete
(piecewise-linear) record, so it stays accurate for periods of a few time steps. When the best
misfit stays above the tolerance, a new set of random phases is drawn from the same generator (a
bounded number of attempts).

References
----------
Abrahamson, N. A. (1992). Non-stationary spectral matching. Seismological Research Letters
63(1), 30.
Al Atik, L. and Abrahamson, N. (2010). An improved method for nonstationary spectral matching.
Earthquake Spectra 26(3), 601–617.
Boore, D. M. (2001). Effect of baseline corrections on displacements and response spectra for
several recordings of the 1999 Chi-Chi, Taiwan, earthquake. BSSA 91(5), 1199–1211.
Gasparini, D. A. and Vanmarcke, E. H. (1976). SIMQKE: a program for artificial motion generation.
MIT, Department of Civil Engineering.
Jennings, P. C., Housner, G. W. and Tsai, N. C. (1968). Simulated earthquake motions. EERL,
Caltech.
Lilhanand, K. and Tseng, W. S. (1988). Development and application of realistic earthquake time
histories compatible with multiple-damping design spectra. Proc. 9th WCEE, Tokyo, II, 819–824.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import fft

from .baseline import BaselineCorrection, correction_terms
from .spectra import compute_psa, find_peak_responses
from .wavelets import (
    AriasGoal,
    build_baseline_basis,
    build_peak_patterns,
    build_wavelets,
    compute_influence,
    compute_pattern_motion,
    find_peak_samples,
    find_wavelet_delay,
    select_crests,
    solve_regularised,
    stack_patterns,
    superpose,
)


@dataclass(frozen=True)
class Envelope:
    """Compound intensity envelope of Jennings, Housner & Tsai (1968).

    I(t) = (t/rise)² while building up, 1 over the stationary part, then exp(−c·(t − t2)) with c
    such that I falls to ``end_level`` at the end of the decay.

    Attributes
    ----------
    rise
        build-up time [s].
    stationary
        duration of the stationary (strong) part, >= 10 s for EN 1998-1 §3.2.3.1.2(3) [s].
    decay
        duration of the exponential decay [s].
    end_level
        envelope value at the end of the decay [-].
    """

    rise: float
    stationary: float
    decay: float
    end_level: float = 0.05

    @property
    def duration(self) -> float:
        """Total duration rise + stationary + decay [s]."""
        return self.rise + self.stationary + self.decay


def compute_envelope(times: np.ndarray, envelope: Envelope) -> np.ndarray:
    """Value of the compound envelope at the given times [-].

    Parameters
    ----------
    times
        times from the start of the record [s].
    envelope
        the envelope's shape.
    """
    times = np.asarray(times, dtype=float)
    end_of_rise = envelope.rise
    end_of_plateau = envelope.rise + envelope.stationary
    rate = -math.log(envelope.end_level) / envelope.decay
    rising = (times / end_of_rise) ** 2 if end_of_rise > 0.0 else np.ones_like(times)
    decaying = np.exp(-rate * np.maximum(times - end_of_plateau, 0.0))
    return np.where(times < end_of_rise, rising, np.where(times <= end_of_plateau, 1.0, decaying))


@dataclass(frozen=True)
class MatchSettings:
    """How closely and how hard to match.

    Attributes
    ----------
    tolerance
        target for max |computed / target − 1| over the matching periods [-].
    max_iterations
        cap on time-domain iterations per attempt [-].
    max_attempts
        fresh random phases are drawn while the best misfit exceeds ``tolerance``, up to this
        many attempts; the best attempt is kept [-].
    damping
        damping ratio of the target spectrum [-].
    frequency_iterations
        SIMQKE iterations that shape the stationary process first [-].
    wavelet_width
        Gaussian half-width of a wavelet, in periods of its oscillator [-].
    crests
        crests per oscillator that may be constrained: the peak, and the next largest when they
        also exceed the target [-].
    regularisation
        Tikhonov weight of the wavelet system, relative to its largest entries [-].
    initial_regularisation
        weight of the first iteration, halved at each one down to ``regularisation``: large early
        steps stay smooth across periods [-].
    halvings
        how many times a step that does not lower the RMS misfit is halved [-].
    patience
        an attempt stops after this many iterations without a new best [-].
    baseline_reach
        the baseline correction's functions stay at periods above this multiple of the longest
        period of the band (`baseline.correction_terms`) [-].
    duration_weight
        weight of a seed's Arias times in the wavelet system (`wavelets.AriasGoal`): a shift of
        1 % of its D5–95 counts as a miss of 1 % of the mean target times this [-].
    duration_tolerance
        the change of a seed's D5–95 and D5–75 that counts as much as a worst misfit equal to
        ``tolerance`` when iterates are ranked (`MatchProblem.rank`) [-].
    dense_rounds
        a seed's fit is then checked on the dense grid (`spectral_fit`), and its misses join the
        matching periods, up to this many times [-].
    """

    tolerance: float = 0.05
    max_iterations: int = 20
    max_attempts: int = 2
    damping: float = 0.05
    frequency_iterations: int = 6
    wavelet_width: float = 0.75
    crests: int = 2
    regularisation: float = 0.01
    initial_regularisation: float = 0.3
    halvings: int = 2
    patience: int = 6
    baseline_reach: float = 1.5
    duration_weight: float = 1.0
    duration_tolerance: float = 0.2
    dense_rounds: int = 4


@dataclass(frozen=True)
class MatchedRecord:
    """A generated accelerogram and how well it matches.

    Attributes
    ----------
    acceleration
        ground acceleration at uniform steps, peak exactly the target PGA [m/s²].
    time_step
        time step [s].
    attempts
        sets of random phases tried [-].
    iterations
        time-domain iterations of the kept attempt [-].
    misfit
        max |computed / target − 1| over the matching periods [-].
    """

    acceleration: np.ndarray
    time_step: float
    attempts: int
    iterations: int
    misfit: float


def compute_matching_periods(band: tuple[float, float], count: int, time_step: float) -> np.ndarray:
    """Periods to match at: the checking grid refined twice, with margins past the band.

    The checking grid is ``count`` log-spaced periods over ``band``; every other matching period
    is one of them. Three extra periods below the band (not below 4 time steps) and six beyond
    it keep the band's ends from being edges of the correction.

    Parameters
    ----------
    band
        shortest and longest period of the checking grid [s].
    count
        number of periods of the checking grid, >= 2 [-].
    time_step
        time step of the record [s].
    """
    low, high = band
    if not 0.0 < low < high or count < 2:
        raise ValueError(f"need 0 < low < high and count >= 2, got {band!r} and {count!r}")
    ratio = (high / low) ** (1.0 / (2 * (count - 1)))
    periods = low * ratio ** np.arange(-3, 2 * (count - 1) + 7)
    return periods[periods >= min(4.0 * time_step, low)]


def generate_matched_record(
    periods: np.ndarray,
    target: np.ndarray,
    peak_acceleration: float,
    time_step: float,
    envelope: Envelope,
    rng: np.random.Generator,
    settings: MatchSettings = MatchSettings(),
    band: tuple[float, float] | None = None,
) -> MatchedRecord:
    """Generate one accelerogram matched to a target spectrum and scaled to a target PGA.

    Parameters
    ----------
    periods
        matching periods, increasing, each at least 4 time steps [s].
    target
        target pseudo-spectral acceleration at ``periods`` [m/s²].
    peak_acceleration
        target peak ground acceleration [m/s²].
    time_step
        time step of the record [s].
    envelope
        intensity envelope; its duration is the record's [s].
    rng
        the random generator (seeded ``numpy.random.default_rng``) that draws the phases.
    settings
        tolerance and iteration controls.
    band
        periods outside [band[0], band[1]] are matched but do not count in the misfit that is
        compared with the tolerance (default: all count) [s].
    """
    times = np.arange(int(round(envelope.duration / time_step)) + 1) * time_step
    shape = compute_envelope(times, envelope)
    taper = np.where(times < envelope.rise, shape, 1.0)
    problem = MatchProblem.of(periods, target, peak_acceleration, time_step, shape, taper, settings,
                              band)  # fmt: skip
    periods, target = problem.periods, problem.target
    best = None
    for attempt in range(1, settings.max_attempts + 1):
        start = _shape_stationary_process(periods, target, times, shape, rng, settings)
        matched = match_in_time_domain(problem, start)
        if best is None or matched[2] < best[2]:
            best = (*matched, attempt)
        if best[2] <= settings.tolerance:
            break
    assert best is not None  # attempts ≥ 1
    acceleration, iterations, misfit, _ = best
    return MatchedRecord(acceleration, time_step, attempt, iterations, misfit)


def _check_matching_inputs(periods, target, peak_acceleration, time_step) -> None:
    if periods.ndim != 1 or periods.size < 2 or np.any(np.diff(periods) <= 0.0):
        raise ValueError("matching periods must be a 1-D increasing array of two or more values")
    if target.shape != periods.shape or np.any(~(target > 0.0)):
        raise ValueError("the target must be positive and given at each matching period")
    if not time_step > 0.0:
        raise ValueError(f"the time step must be positive, got {time_step!r}")
    if periods[0] < 4.0 * time_step:
        raise ValueError(
            f"the shortest matching period {periods[0]:g} s is below 4 time steps "
            f"({4 * time_step:g} s): the record cannot carry it"
        )
    if not peak_acceleration > 0.0:
        raise ValueError(f"the target PGA must be positive, got {peak_acceleration!r}")


def _shape_stationary_process(periods, target, times, shape, rng, settings) -> np.ndarray:
    """Steps 1–2: enveloped random-phase process, Fourier amplitudes corrected as in SIMQKE.

    The starting amplitudes follow |A(f)| ∝ Se(f)/√f, the shape that Vanmarcke's relation between
    a power spectral density and a response spectrum gives for narrow-band oscillators.
    """
    n_fft = fft.next_fast_len(2 * times.size)
    frequencies = fft.rfftfreq(n_fft, times[1] - times[0])
    phases = np.exp(2j * np.pi * rng.random(frequencies.size))
    band = _compute_band_taper(frequencies, 1.0 / periods[-1], 1.0 / periods[0])
    safe = np.maximum(frequencies, frequencies[1])
    amplitudes = band * _interpolate_on_frequencies(periods, target, safe) / np.sqrt(safe)
    for _ in range(settings.frequency_iterations):
        acceleration = shape * fft.irfft(amplitudes * phases, n_fft)[: times.size]
        psa = compute_psa(acceleration, times[1] - times[0], periods, settings.damping)
        amplitudes *= _interpolate_on_frequencies(periods, target / psa, safe)
    return shape * fft.irfft(amplitudes * phases, n_fft)[: times.size]


def _compute_band_taper(frequencies, low, high) -> np.ndarray:
    """1 on [low, high], cosine tapers down to 0 at low/2 and at 1.5·high [-]."""
    taper = np.ones_like(frequencies)
    below = frequencies < low
    taper[below] = 0.5 * (1.0 - np.cos(np.pi * np.clip(2.0 * frequencies[below] / low - 1.0, 0, 1)))
    above = frequencies > high
    taper[above] = 0.5 * (
        1.0 + np.cos(np.pi * np.clip(frequencies[above] / high - 1.0, 0, 0.5) * 2)
    )
    return taper


def _interpolate_on_frequencies(periods, values, frequencies) -> np.ndarray:
    """Values given at periods, interpolated on log frequency, held constant outside [-]."""
    return np.interp(np.log(frequencies), np.log(1.0 / periods[::-1]), values[::-1])


@dataclass(frozen=True)
class MatchProblem:
    """What stays fixed while one record is matched (SI units): by the generator, or for a seed
    (`seeds.match_seed`), with its own baseline correction and the Arias times to keep."""

    periods: np.ndarray
    target: np.ndarray
    pga: float
    time_step: float
    shape: np.ndarray
    taper: np.ndarray
    counted: np.ndarray
    settings: MatchSettings
    baseline: BaselineCorrection
    arias: AriasGoal | None = None

    @classmethod
    def of(
        cls, periods, target, pga, time_step, shape, taper, settings, band, baseline=None,
        arias=None,
    ) -> MatchProblem:  # fmt: skip
        """The checked problem: ``band`` (default: all the periods) says which periods count in
        the misfit compared with the tolerance; ``baseline`` (default: the least-displacement
        correction over the whole record, `correction_terms`) follows every step."""
        periods = np.asarray(periods, dtype=float)
        target = np.asarray(target, dtype=float)
        _check_matching_inputs(periods, target, pga, time_step)
        low, high = (periods[0], periods[-1]) if band is None else band
        counted = (periods >= low * (1.0 - 1e-9)) & (periods <= high * (1.0 + 1e-9))
        if not counted.any():
            raise ValueError(f"no matching period lies in the band {band!r}")
        if baseline is None:
            duration = (shape.size - 1) * time_step
            terms = correction_terms(duration, high, settings.baseline_reach)
            baseline = BaselineCorrection.of(shape, time_step, terms)
        return cls(periods, target, pga, time_step, shape, taper, counted, settings, baseline,
                   arias)  # fmt: skip

    @property
    def omegas(self) -> np.ndarray:
        return 2.0 * np.pi / self.periods

    def finish(self, acceleration: np.ndarray) -> np.ndarray:
        """Baseline correction, then exact scaling to the target PGA (both linear)."""
        corrected = self.baseline(acceleration)
        return corrected * (self.pga / np.max(np.abs(corrected)))

    def measure(self, acceleration: np.ndarray):
        """The crests of every oscillator and the score: the worst and RMS misfits, and by how
        much a seed's durations changed (`wavelets.AriasGoal.duration_change`; 0 for others)."""
        crests = find_peak_responses(
            acceleration,
            self.time_step,
            self.periods,
            self.settings.damping,
            self.settings.crests,
        )
        ratios = self.omegas**2 * np.abs(crests[0][:, 0]) / self.target
        worst = float(np.max(np.abs(ratios[self.counted] - 1.0)))
        rms = float(np.sqrt(np.mean(np.log(ratios) ** 2)))
        if self.arias is None:
            return crests, (worst, rms, 0.0)
        return crests, (worst, rms, self.arias.duration_change(acceleration, self.time_step))

    def rank(self, score: tuple[float, float, float]) -> tuple[bool, float]:
        """How a score compares with others, lower first: a worst misfit outside the tolerance,
        then the larger of the worst misfit and a seed's change of durations, each over its
        tolerance (both within them: 1 or less)."""
        worst, _, change = score
        settings = self.settings
        excess = max(worst / settings.tolerance, change / settings.duration_tolerance)
        return worst > settings.tolerance, excess


def match_in_time_domain(problem: MatchProblem, acceleration: np.ndarray):
    """Step 3: wavelet corrections, each step halved until it lowers the RMS misfit.

    Every iterate is baseline-corrected and scaled to the target PGA, so its misfit is final;
    the worst misfit counts only the periods in the band, the RMS one all of them. The best
    iterate ranks first (`MatchProblem.rank`): the least worst misfit or, for a seed, the
    least excess over the tolerances of the worst misfit and of its change of durations,
    among the iterates within the spectral tolerance if any is.

    Returns
    -------
    tuple
        the best record [m/s²], the iterations run and the best worst-misfit [-].
    """
    settings = problem.settings
    delay = find_wavelet_delay(settings.wavelet_width, settings.damping)
    acceleration = problem.finish(acceleration)
    crests, score = problem.measure(acceleration)
    best = (problem.rank(score), score[0], acceleration)
    iteration = improved = 0
    while (
        best[0] > (False, 1.0)
        and iteration < settings.max_iterations
        and iteration - improved < settings.patience
    ):
        iteration += 1
        weight = max(
            settings.regularisation, settings.initial_regularisation / 2 ** (iteration - 1)
        )
        change = _compute_correction(problem, acceleration, crests, delay, weight)
        step = 1.0
        for _ in range(settings.halvings + 1):
            trial = problem.finish(acceleration + step * change)
            trial_crests, trial_score = problem.measure(trial)
            if trial_score[1] < score[1]:
                break
            step *= 0.5
        acceleration, crests, score = trial, trial_crests, trial_score
        if problem.rank(score) < best[0]:
            best, improved = (problem.rank(score), score[0], acceleration), iteration
    return best[2], iteration, best[1]


def _compute_correction(problem: MatchProblem, acceleration, crests, delay, weight) -> np.ndarray:
    """The acceleration change that moves the selected crests and peaks to target, to first order.

    Unknowns: the amplitude of one wavelet per selected crest and of one local-peak pattern per
    sample near the PGA. Equations: each selected crest ω²·u(t) becomes sign·target; each such
    sample stays at min(|a|, pga) with its sign. The baseline correction that follows each step
    is linear, so it is folded into the system (each pattern enters with its own correction)
    and the step is exact to first order for the corrected record. A seed's Arias times
    (`wavelets.AriasGoal`) add one equation each. Neighbouring oscillators that peak together
    give nearly equal rows, hence the Tikhonov weight ``weight``.
    """
    settings, time_step, pga = problem.settings, problem.time_step, problem.pga
    rows, row_times, current = select_crests(crests, problem.omegas, problem.target)
    omegas = problem.omegas[rows]
    samples = find_peak_samples(acceleration, pga)
    half_width = max(1, int(round(0.5 * problem.periods[0] / time_step)))
    patterns = stack_patterns(
        build_wavelets(
            problem.taper,
            time_step,
            omegas,
            settings.damping,
            row_times,
            settings.wavelet_width,
            delay,
        ),
        build_peak_patterns(acceleration, samples, half_width),
    )
    basis = build_baseline_basis(problem.baseline.functions)
    arguments = (row_times, omegas, settings.damping, time_step)
    influence = compute_influence(*arguments, *patterns.arrays, samples)
    weights = problem.baseline.weights
    coupling = problem.baseline.coefficients(compute_pattern_motion(*patterns.arrays, weights))
    influence -= compute_influence(*arguments, *basis.arrays, samples) @ coupling
    signed_psa = omegas**2 * current
    held = np.minimum(np.abs(acceleration[samples]), pga)
    wanted = np.concatenate(
        [
            np.sign(signed_psa) * problem.target[rows] - signed_psa,
            np.sign(acceleration[samples]) * held - acceleration[samples],
        ]
    )
    if problem.arias is not None:
        gradient, shifts = problem.arias.rows(acceleration, time_step)
        importance = settings.duration_weight * float(np.mean(problem.target))
        times = compute_pattern_motion(*patterns.arrays, gradient)
        times -= compute_pattern_motion(*basis.arrays, gradient) @ coupling
        influence = np.vstack([influence, importance * times])
        wanted = np.concatenate([wanted, importance * shifts])
    scale = weight * np.mean(np.max(np.abs(influence), axis=0))
    amplitudes = solve_regularised(influence, wanted, scale)
    change = superpose(patterns, amplitudes, acceleration.size)
    return change - (coupling @ amplitudes) @ basis.values
