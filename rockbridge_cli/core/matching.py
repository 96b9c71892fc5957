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
4. after each step, a baseline correction that zeroes the final velocity and displacement (a
   low-order correction in the spirit of Boore 2001) and an exact scaling to the target PGA, so
   that every iterate is a finished record; the best one is kept.

The wavelet system uses the exact response of the discrete (piecewise-linear) record, so it stays
accurate for periods of a few time steps. When the best misfit stays above the tolerance, a new
set of random phases is drawn from the same generator (a bounded number of attempts).

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

from ._jit import jit
from .spectra import compute_psa, find_peak_responses

#: Local peaks of |a| within this fraction of the PGA are held in place while matching [-].
PEAK_MARGIN = 0.05


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
    periods = np.asarray(periods, dtype=float)
    target = np.asarray(target, dtype=float)
    _check_matching_inputs(periods, target, peak_acceleration, time_step)
    low, high = (periods[0], periods[-1]) if band is None else band
    counted = (periods >= low * (1.0 - 1e-9)) & (periods <= high * (1.0 + 1e-9))
    if not counted.any():
        raise ValueError(f"no matching period lies in the band {band!r}")
    times = np.arange(int(round(envelope.duration / time_step)) + 1) * time_step
    shape = compute_envelope(times, envelope)
    taper = np.where(times < envelope.rise, shape, 1.0)
    problem = _Problem(
        periods, target, peak_acceleration, time_step, shape, taper, counted, settings
    )
    best = None
    for attempt in range(1, settings.max_attempts + 1):
        start = _shape_stationary_process(periods, target, times, shape, rng, settings)
        matched = _match_in_time_domain(problem, start)
        if best is None or matched[2] < best[2]:
            best = (*matched, attempt)
        if best[2] <= settings.tolerance:
            break
    acceleration, iterations, misfit, _ = best
    return MatchedRecord(acceleration, time_step, attempt, iterations, misfit)


def correct_baseline(acceleration: np.ndarray, time_step: float, shape: np.ndarray) -> np.ndarray:
    """Remove an enveloped linear trend so that the final velocity and displacement are zero.

    The correction is I(t)·(c0 + c1·t/t_end), I being the envelope, with c0 and c1 solving the two
    linear conditions v(t_end) = 0 and d(t_end) = 0, both integrated exactly for a piecewise-linear
    acceleration. It is the least-change member of Boore's (2001) polynomial corrections: it
    vanishes where the record does and only touches periods far longer than the record's band.

    Parameters
    ----------
    acceleration
        ground acceleration [m/s²].
    time_step
        time step [s].
    shape
        envelope at the samples [-].
    """
    basis = _baseline_values(shape)
    matrix = np.stack([_compute_final_motion(row, time_step) for row in basis], axis=1)
    coefficients = np.linalg.solve(matrix, _compute_final_motion(acceleration, time_step))
    return acceleration - coefficients @ basis


def compute_final_motion(acceleration: np.ndarray, time_step: float) -> tuple[float, float]:
    """Final ground velocity and displacement, integrating a piecewise-linear acceleration exactly.

    Parameters
    ----------
    acceleration
        ground acceleration, starting from rest [m/s²].
    time_step
        time step [s].

    Returns
    -------
    tuple of float
        velocity [m/s] and displacement [m] at the last sample.
    """
    velocity, displacement = _compute_final_motion(np.asarray(acceleration, float), time_step)
    return float(velocity), float(displacement)


def compute_significant_duration(
    acceleration: np.ndarray, time_step: float, start: float = 0.05, end: float = 0.95
) -> float:
    """Significant duration D5–95: time between 5% and 95% of the Arias intensity.

    The Arias intensity grows as ∫a²dt (trapezoidal here); the crossing times are interpolated
    linearly between samples (Trifunac & Brady 1975).

    Parameters
    ----------
    acceleration
        ground acceleration [m/s²].
    time_step
        time step [s].
    start, end
        fractions of the total intensity that bound the duration [-].
    """
    squared = np.asarray(acceleration, dtype=float) ** 2
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (squared[1:] + squared[:-1]))])
    if cumulative[-1] <= 0.0:
        raise ValueError("a record of zeros has no significant duration")
    fraction = cumulative / cumulative[-1]
    times = np.arange(fraction.size) * time_step
    return float(np.interp(end, fraction, times) - np.interp(start, fraction, times))


def _compute_final_motion(acceleration: np.ndarray, time_step: float) -> np.ndarray:
    """[v_end, d_end] as weighted sums of the samples (exact for linear segments, from rest)."""
    edges = 0.5 * (acceleration[0] + acceleration[-1])
    velocity = time_step * (acceleration.sum() - edges)
    displacement = time_step**2 * (acceleration @ _displacement_weights(acceleration.size))
    return np.array([velocity, displacement])


def _displacement_weights(n: int) -> np.ndarray:
    """w_i with d_end = h²·Σ w_i·a_i for N = n − 1 linear steps from rest.

    Summing d_k+1 = d_k + h·v_k + h²·(2a_k + a_k+1)/6 over the steps gives w_0 = N/2 − 1/6,
    w_i = N − i inside and w_N = 1/6 (for a ≡ 1 they add up to N²/2, i.e. d = t²/2).
    """
    last = n - 1
    weights = (last - np.arange(n)).astype(float)
    weights[0] = last / 2.0 - 1.0 / 6.0
    weights[-1] = 1.0 / 6.0
    return weights


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
class _Problem:
    """What stays fixed while one record is matched (SI units)."""

    periods: np.ndarray
    target: np.ndarray
    pga: float
    time_step: float
    shape: np.ndarray
    taper: np.ndarray
    counted: np.ndarray
    settings: MatchSettings

    @property
    def omegas(self) -> np.ndarray:
        return 2.0 * np.pi / self.periods

    def finish(self, acceleration: np.ndarray) -> np.ndarray:
        """Baseline correction, then exact scaling to the target PGA (both linear)."""
        corrected = correct_baseline(acceleration, self.time_step, self.shape)
        return corrected * (self.pga / np.max(np.abs(corrected)))

    def measure(self, acceleration: np.ndarray):
        """The crests of every oscillator and the (worst, RMS) misfit."""
        crests = find_peak_responses(
            acceleration,
            self.time_step,
            self.periods,
            self.settings.damping,
            self.settings.crests,
        )
        ratios = self.omegas**2 * np.abs(crests[0][:, 0]) / self.target
        worst = float(np.max(np.abs(ratios[self.counted] - 1.0)))
        return crests, (worst, float(np.sqrt(np.mean(np.log(ratios) ** 2))))


def _match_in_time_domain(problem: _Problem, acceleration: np.ndarray):
    """Step 3: wavelet corrections, each step halved until it lowers the RMS misfit.

    Every iterate is baseline-corrected and scaled to the target PGA, so its misfit is final;
    the worst misfit counts only the periods in the band, the RMS one all of them.

    Returns
    -------
    tuple
        the best record [m/s²], the iterations run and the best worst-misfit [-].
    """
    settings = problem.settings
    delay = _find_wavelet_delay(settings.wavelet_width, settings.damping)
    acceleration = problem.finish(acceleration)
    crests, score = problem.measure(acceleration)
    best = (score[0], acceleration)
    iteration = improved = 0
    while (
        best[0] > settings.tolerance
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
        if score[0] < best[0]:
            best, improved = (score[0], acceleration), iteration
    return best[1], iteration, best[0]


def _compute_correction(problem: _Problem, acceleration, crests, delay, weight) -> np.ndarray:
    """The acceleration change that moves the selected crests and peaks to target, to first order.

    Unknowns: the amplitude of one wavelet per selected crest and of one local-peak pattern per
    sample near the PGA. Equations: each selected crest ω²·u(t) becomes sign·target; each such
    sample stays at min(|a|, pga) with its sign. The baseline correction that follows each step
    is linear, so it is folded into the system (each pattern enters with its own correction)
    and the step is exact to first order for the corrected record. Neighbouring oscillators
    that peak together give nearly equal rows, hence the Tikhonov weight ``weight``.
    """
    settings, time_step, pga = problem.settings, problem.time_step, problem.pga
    rows, row_times, current = _select_crests(crests, problem.omegas, problem.target)
    omegas = problem.omegas[rows]
    samples = _find_peak_samples(acceleration, pga)
    half_width = max(1, int(round(0.5 * problem.periods[0] / time_step)))
    patterns = _stack_patterns(
        _build_wavelets(
            problem.taper,
            time_step,
            omegas,
            settings.damping,
            row_times,
            settings.wavelet_width,
            delay,
        ),
        _build_peak_patterns(acceleration, samples, half_width),
    )
    basis = _build_baseline_basis(problem.shape)
    arguments = (row_times, omegas, settings.damping, time_step)
    influence = _compute_influence(*arguments, *patterns.arrays, samples)
    weights = _final_motion_weights(acceleration.size, time_step)
    coupling = np.linalg.solve(
        _compute_pattern_motion(*basis.arrays, weights),
        _compute_pattern_motion(*patterns.arrays, weights),
    )
    influence -= _compute_influence(*arguments, *basis.arrays, samples) @ coupling
    signed_psa = omegas**2 * current
    held = np.minimum(np.abs(acceleration[samples]), pga)
    wanted = np.concatenate(
        [
            np.sign(signed_psa) * problem.target[rows] - signed_psa,
            np.sign(acceleration[samples]) * held - acceleration[samples],
        ]
    )
    scale = weight * np.mean(np.max(np.abs(influence), axis=0))
    amplitudes = _solve_regularised(influence, wanted, scale)
    change = _superpose(patterns, amplitudes, acceleration.size)
    return change - (coupling @ amplitudes) @ basis.values


def _build_baseline_basis(shape: np.ndarray) -> _Patterns:
    """The two functions of `correct_baseline` as full-length patterns."""
    return _Patterns(
        np.zeros(2, np.int64), np.full(2, shape.size, np.int64), _baseline_values(shape)
    )


def _baseline_values(shape: np.ndarray) -> np.ndarray:
    """The baseline correction's functions I(t) and I(t)·t/t_end at the samples, shape (2, n)."""
    return np.stack([shape, shape * np.linspace(0.0, 1.0, shape.size)])


def _final_motion_weights(n: int, time_step: float) -> np.ndarray:
    """Rows w_v, w_d with v_end = w_v·a and d_end = w_d·a (see `_compute_final_motion`)."""
    velocity = np.full(n, time_step)
    velocity[[0, -1]] *= 0.5
    return np.stack([velocity, time_step**2 * _displacement_weights(n)])


@jit
def _compute_pattern_motion(starts, lengths, values, weights):
    """Final velocity and displacement that each pattern adds (2 × patterns)."""
    motion = np.zeros((2, starts.size))
    for j in range(starts.size):
        for k in range(lengths[j]):
            motion[0, j] += weights[0, starts[j] + k] * values[j, k]
            motion[1, j] += weights[1, starts[j] + k] * values[j, k]
    return motion


def _select_crests(crests, omegas, target):
    """The crests to constrain: each oscillator's peak, and its other crests above the target.

    Returns the oscillator index, time [s] and signed displacement [m] of each selected crest.
    """
    values, times = crests
    keep = omegas[:, None] ** 2 * np.abs(values) > target[:, None]
    keep[:, 0] = True
    rows, columns = np.nonzero(keep)
    return rows, times[rows, columns], values[rows, columns]


@dataclass(frozen=True)
class _Patterns:
    """Sampled correction patterns: pattern j is values[j, :lengths[j]] from sample starts[j]."""

    starts: np.ndarray
    lengths: np.ndarray
    values: np.ndarray

    @property
    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return self.starts, self.lengths, self.values


def _stack_patterns(first: _Patterns, second: _Patterns) -> _Patterns:
    width = max(first.values.shape[1], second.values.shape[1])
    values = np.zeros((first.values.shape[0] + second.values.shape[0], width))
    values[: first.values.shape[0], : first.values.shape[1]] = first.values
    values[first.values.shape[0] :, : second.values.shape[1]] = second.values
    return _Patterns(
        np.concatenate([first.starts, second.starts]),
        np.concatenate([first.lengths, second.lengths]),
        values,
    )


def _superpose(patterns: _Patterns, amplitudes: np.ndarray, n: int) -> np.ndarray:
    change = np.zeros(n)
    for j in range(amplitudes.size):
        start, length = patterns.starts[j], patterns.lengths[j]
        change[start : start + length] += amplitudes[j] * patterns.values[j, :length]
    return change


def _build_wavelets(taper, time_step, omegas, damping, peak_times, width, delay) -> _Patterns:
    """One tapered-cosine wavelet per crest, placed so that its oscillator's response peaks there.

    w_j(t) = cos(ω_d,j·(t − c_j))·exp(−((t − c_j)/γ_j)²) with γ_j = width·T_j; the centre
    c_j = t_j − δ·T_j puts the peak response of the oscillator to its own wavelet at the crest
    time t_j (δ = ``delay``, from `_find_wavelet_delay`). A Gaussian-tapered cosine this wide is
    free of drift to within e^(−(πγ/T)²). ``taper`` (the envelope's build-up) keeps the record at
    rest at its start.
    """
    n = taper.size
    periods = 2.0 * np.pi / omegas
    widths = width * periods
    centres = peak_times - delay * periods
    starts = np.clip(np.floor((centres - 3.0 * widths) / time_step), 0, n - 1).astype(np.int64)
    stops = np.clip(np.ceil((centres + 3.0 * widths) / time_step) + 1, 1, n).astype(np.int64)
    lengths = np.maximum(stops - starts, 1)
    damped = omegas * math.sqrt(1.0 - damping**2)
    values = _sample_wavelets(taper, time_step, starts, lengths, centres, widths, damped)
    return _Patterns(starts, lengths, values)


@jit
def _sample_wavelets(taper, time_step, starts, lengths, centres, widths, damped):
    values = np.zeros((starts.size, lengths.max()))
    for j in range(starts.size):
        for k in range(lengths[j]):
            t = (starts[j] + k) * time_step - centres[j]
            values[j, k] = (
                math.cos(damped[j] * t) * math.exp(-((t / widths[j]) ** 2)) * taper[starts[j] + k]
            )
    return values


def _build_peak_patterns(acceleration, samples, half_width) -> _Patterns:
    """For each sample to bring to the target PGA, the record around it under a Hann window.

    Scaling such a pattern raises or lowers a whole local peak of the record with its shape, so
    its neighbouring samples do not become new peaks.
    """
    n = acceleration.size
    offsets = np.arange(-half_width, half_width + 1)
    window = np.cos(0.5 * np.pi * offsets / (half_width + 1)) ** 2
    starts = np.clip(samples - half_width, 0, n - 1)
    stops = np.clip(samples + half_width + 1, 1, n)
    lengths = stops - starts
    values = np.zeros((samples.size, offsets.size))
    for q, sample in enumerate(samples):
        index = np.arange(starts[q], stops[q])
        values[q, : lengths[q]] = acceleration[index] * window[index - sample + half_width]
    return _Patterns(starts.astype(np.int64), lengths.astype(np.int64), values)


def _find_wavelet_delay(width: float, damping: float) -> float:
    """Time from a wavelet's centre to its oscillator's peak response, in periods [-].

    The wavelet scales with the period, so one run of a unit-period oscillator (200 steps per
    period) gives the delay for all.
    """
    time_step = 1.0 / 200.0
    times = np.arange(-4.0 * width, 4.0 * width + 10.0, time_step)
    damped = 2.0 * np.pi * math.sqrt(1.0 - damping**2)
    wavelet = np.cos(damped * times) * np.exp(-((times / width) ** 2))
    _, peak_times = find_peak_responses(wavelet, time_step, np.array([1.0]), damping)
    return float(peak_times[0, 0] + times[0])


def _find_peak_samples(
    acceleration: np.ndarray, pga: float, margin: float = PEAK_MARGIN, limit: int = 8
) -> np.ndarray:
    """Sample indices of the (up to ``limit`` largest) local peaks of |a| above (1 − margin)·pga.

    Always includes the largest sample. These are held at min(|a|, pga): the record's PGA can
    then neither grow nor jump to another peak.
    """
    size = np.abs(acceleration)
    inner = size[1:-1]
    high = (inner >= size[:-2]) & (inner > size[2:]) & (inner > (1.0 - margin) * pga)
    local = np.union1d(np.flatnonzero(high) + 1, [int(np.argmax(size))])
    return np.sort(local[np.argsort(size[local])[::-1][:limit]])


@jit
def _compute_influence(peak_times, omegas, damping, time_step, starts, lengths, values, samples):
    """Matrix of first-order effects of the correction patterns on the piecewise-linear record.

    Rows: d(ω_i²·u_i(t_i)) for each oscillator, then d(a) at each of ``samples``. Columns: unit
    amplitude of each pattern. A unit sample (a hat of half-width h) excites the oscillator with
    u(s) = −R(s), R being the second difference of the ramp response H2 (see `_ramp_response`);
    for s >= h, R(s) = Re(K·e^(λs)) is a damped sinusoid, stepped by complex multiplication.
    """
    m = omegas.size
    columns = starts.size
    matrix = np.zeros((m + samples.size, columns))
    for i in range(m):
        omega = omegas[i]
        t_i = peak_times[i]
        last = int(math.floor(t_i / time_step)) + 1  # samples after t_i + h do not count
        # samples more than ln(10⁴)/(ξω) before t_i have decayed below 10⁻⁴ of their effect
        memory = 9.2 / (damping * omega) if damping > 0.0 else t_i + time_step
        earliest = max(0, int(math.floor((t_i - memory) / time_step)))
        kernel = _sample_hat_responses(t_i, omega, damping, time_step, earliest, last)
        for j in range(columns):
            first = max(starts[j], earliest)
            stop = min(starts[j] + lengths[j], last + 1)
            total = 0.0
            for k in range(first, stop):
                total += values[j, k - starts[j]] * kernel[k - earliest]
            matrix[i, j] = total
    for q in range(samples.size):
        for j in range(columns):
            offset = samples[q] - starts[j]
            if 0 <= offset < lengths[j]:
                matrix[m + q, j] = values[j, offset]
    return matrix


@jit
def _sample_hat_responses(t_i, omega, damping, time_step, first, last):
    """−ω²·u(t_i) for a unit sample at each of samples first..last (see `_compute_influence`)."""
    lam = complex(-damping * omega, omega * math.sqrt(1.0 - damping**2))
    back = np.exp(-lam * time_step)
    z = _hat_response_coefficient(omega, damping, time_step) * np.exp(
        lam * (t_i - first * time_step)
    )
    kernel = np.empty(max(last - first + 1, 0))
    for k in range(first, last + 1):
        s = t_i - k * time_step
        if s >= time_step:
            response = z.real
        else:
            response = _hat_response_near(s, omega, damping, time_step)
        kernel[k - first] = -omega * omega * response
        z *= back
    return kernel


@jit
def _solve_regularised(matrix, rhs, scale):
    """x minimising |A·x − b|² + scale²·|x|², by Cholesky on the normal equations.

    Written out (not LAPACK) so that the result does not depend on the BLAS threads.
    """
    n = matrix.shape[1]
    columns = np.ascontiguousarray(matrix.T)
    normal = np.zeros((n, n))
    x = np.zeros(n)
    for i in range(n):
        for j in range(i + 1):
            total = 0.0
            for k in range(columns.shape[1]):
                total += columns[i, k] * columns[j, k]
            normal[i, j] = total
        normal[i, i] += scale * scale
        total = 0.0
        for k in range(columns.shape[1]):
            total += columns[i, k] * rhs[k]
        x[i] = total
    for j in range(n):  # Cholesky, lower triangle in place
        pivot = normal[j, j]
        for k in range(j):
            pivot -= normal[j, k] * normal[j, k]
        pivot = math.sqrt(pivot)
        normal[j, j] = pivot
        for i in range(j + 1, n):
            value = normal[i, j]
            for k in range(j):
                value -= normal[i, k] * normal[j, k]
            normal[i, j] = value / pivot
    for i in range(n):  # forward: L·y = b
        for k in range(i):
            x[i] -= normal[i, k] * x[k]
        x[i] /= normal[i, i]
    for i in range(n - 1, -1, -1):  # backward: Lᵀ·x = y
        for k in range(i + 1, n):
            x[i] -= normal[k, i] * x[k]
        x[i] /= normal[i, i]
    return x


@jit
def _hat_response_coefficient(omega, damping, time_step):
    """K with R(s) = Re(K·e^(λs)) for s >= h: the free part of H2, second-differenced."""
    lam = complex(-damping * omega, omega * math.sqrt(1.0 - damping**2))
    omega_d = lam.imag
    u0 = 2.0 * damping / omega**3
    v0 = -1.0 / omega**2
    amplitude = complex(u0, -(v0 + damping * omega * u0) / omega_d)
    return amplitude * (np.exp(lam * time_step) + np.exp(-lam * time_step) - 2.0) / time_step


@jit
def _hat_response_near(s, omega, damping, time_step):
    """R(s) for −h < s < h, from the ramp response H2 (zero for negative arguments)."""
    return (
        _ramp_response(s + time_step, omega, damping)
        - 2.0 * _ramp_response(s, omega, damping)
        + _ramp_response(s - time_step, omega, damping)
    ) / time_step


@jit
def _ramp_response(x, omega, damping):
    """H2(x): response to a unit force ramp from rest, u'' + 2ξωu' + ω²u = x; 0 for x <= 0."""
    if x <= 0.0:
        return 0.0
    omega_d = omega * math.sqrt(1.0 - damping**2)
    u0 = 2.0 * damping / omega**3
    v0 = -1.0 / omega**2
    free = math.exp(-damping * omega * x) * (
        u0 * math.cos(omega_d * x) + (v0 + damping * omega * u0) / omega_d * math.sin(omega_d * x)
    )
    return x / omega**2 - u0 + free
