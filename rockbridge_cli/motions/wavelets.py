"""The time-domain corrections of spectral matching (`matching`, step 3): tapered-cosine
wavelets placed at the crests of oscillator responses, patterns that hold the record's peaks and
baseline, the exact response of an oscillator to each (for a piecewise-linear record), the rows
that hold a seed's build-up of Arias intensity (`AriasGoal`), and the regularised solve of the
linear system that links their amplitudes to the crests."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core._jit import jit
from .baseline import arias_build_up, compute_arias_times
from .spectra import find_peak_responses

#: Local peaks of |a| within this fraction of the PGA are held in place while matching [-].
PEAK_MARGIN = 0.05


def build_baseline_basis(functions: np.ndarray) -> Patterns:
    """The functions of a `baseline.BaselineCorrection` as full-length patterns."""
    count, length = functions.shape
    return Patterns(np.zeros(count, np.int64), np.full(count, length, np.int64), functions)


@jit
def compute_pattern_motion(starts, lengths, values, weights):
    """``weights @ pattern`` for each pattern: what the baseline correction depends on
    (`baseline.BaselineCorrection.weights`; rows × patterns)."""
    motion = np.zeros((weights.shape[0], starts.size))
    for row in range(weights.shape[0]):
        for j in range(starts.size):
            for k in range(lengths[j]):
                motion[row, j] += weights[row, starts[j] + k] * values[j, k]
    return motion


ARIAS_SHARES = (0.05, 0.25, 0.5, 0.75, 0.95)
"""The shares of its Arias intensity whose times a matched seed keeps (`AriasGoal`) [-]."""


@dataclass(frozen=True)
class AriasGoal:
    """When a seed builds up `ARIAS_SHARES` of its Arias intensity: the times its matched record
    should keep, as equations linear in a correction.

    At the seed's sample k_q a record has built up the share F(k_q) = I(k_q)/I(N), I(k) the
    trapezoidal ∫a²dt; a change δa moves it by (δI(k_q) − F(k_q)·δI(N))/I(N), with
    δI(k) = 2h·Σ_i w_i(k)·a_i·δa_i (trapezoid weights w: 1 inside, 1/2 at 0 and k, 0 after k).
    Divided by the rate F' at which the record builds up there, a share is a time (Newton's
    step for the time at which the record reaches the seed's share); divided by the seed's
    D5–95 too, a time as a fraction of its duration [-].

    Attributes
    ----------
    samples
        the sample at which the seed reaches each share [-].
    shares
        the seed's share at each of them [-].
    durations
        the seed's D5–95 and D5–75 [s].
    reach
        F' is the mean rate over this many samples either side, ±2 % of D5–95 [-].
    """

    samples: np.ndarray
    shares: np.ndarray
    durations: tuple[float, float]
    reach: int

    @classmethod
    def of(cls, seed: np.ndarray, time_step: float) -> AriasGoal:
        """The goal of a seed [m/s²] at ``time_step`` [s]."""
        build_up = arias_build_up(seed)
        durations = _significant_durations(seed, time_step)
        samples = np.searchsorted(build_up, ARIAS_SHARES)
        reach = max(1, int(round(0.02 * durations[0] / time_step)))
        return cls(samples, build_up[samples], durations, reach)

    def duration_change(self, acceleration: np.ndarray, time_step: float) -> float:
        """The larger relative change of D5–95 and D5–75 from the seed's to a record's [-]."""
        durations = _significant_durations(acceleration, time_step)
        return max(abs(new / old - 1.0) for new, old in zip(durations, self.durations, strict=True))

    def rows(self, acceleration: np.ndarray, time_step: float) -> tuple[np.ndarray, np.ndarray]:
        """The equations for a record [m/s²] at ``time_step`` [s]: ``gradient @ δa`` is the
        first-order change of each share, ``wanted`` the change back to the seed's,
        both as times over the seed's D5–95 [-].

        Returns
        -------
        tuple of numpy.ndarray
            gradient, shape (shares, samples) [s²/m], and wanted, shape (shares,) [-].
        """
        build_up, scales, wanted = self._linearise(acceleration, time_step)
        squared = acceleration**2
        total = time_step * (squared.sum() - 0.5 * (squared[0] + squared[-1]))
        whole = np.ones(acceleration.size)
        whole[[0, -1]] = 0.5
        gradient = np.empty((self.samples.size, acceleration.size))
        for row, sample in enumerate(self.samples):
            partial = np.where(np.arange(acceleration.size) <= sample, whole, 0.0)
            partial[[0, sample]] = 0.5 if sample > 0 else 0.0
            gradient[row] = (partial - build_up[sample] * whole) * acceleration
        gradient *= (2.0 * time_step / total * scales)[:, None]
        return gradient, wanted

    def _linearise(self, acceleration, time_step):
        """The record's build-up, 1/(F'·D5–95) at the seed's samples, and how far it is from the
        seed's shares there, as times over D5–95 [-]."""
        build_up = arias_build_up(acceleration)
        before = np.maximum(self.samples - self.reach, 0)
        after = np.minimum(self.samples + self.reach, acceleration.size - 1)
        rates = (build_up[after] - build_up[before]) / ((after - before) * time_step)
        scales = 1.0 / (np.maximum(rates, 1e-12) * self.durations[0])
        return build_up, scales, (self.shares - build_up[self.samples]) * scales


def _significant_durations(acceleration: np.ndarray, time_step: float) -> tuple[float, float]:
    """D5–95 and D5–75 of a record [s]."""
    start, three_quarters, end = compute_arias_times(acceleration, time_step, DURATION_SHARES)
    return float(end - start), float(three_quarters - start)


DURATION_SHARES = np.array([0.05, 0.75, 0.95])
"""The shares that bound D5–95 and D5–75 [-]."""


def select_crests(crests, omegas, target):
    """The crests to constrain: each oscillator's peak, and its other crests above the target.

    Returns the oscillator index, time [s] and signed displacement [m] of each selected crest.
    """
    values, times = crests
    keep = omegas[:, None] ** 2 * np.abs(values) > target[:, None]
    keep[:, 0] = True
    rows, columns = np.nonzero(keep)
    return rows, times[rows, columns], values[rows, columns]


@dataclass(frozen=True)
class Patterns:
    """Sampled correction patterns: pattern j is values[j, :lengths[j]] from sample starts[j]."""

    starts: np.ndarray
    lengths: np.ndarray
    values: np.ndarray

    @property
    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return self.starts, self.lengths, self.values


def stack_patterns(first: Patterns, second: Patterns) -> Patterns:
    width = max(first.values.shape[1], second.values.shape[1])
    values = np.zeros((first.values.shape[0] + second.values.shape[0], width))
    values[: first.values.shape[0], : first.values.shape[1]] = first.values
    values[first.values.shape[0] :, : second.values.shape[1]] = second.values
    return Patterns(
        np.concatenate([first.starts, second.starts]),
        np.concatenate([first.lengths, second.lengths]),
        values,
    )


def superpose(patterns: Patterns, amplitudes: np.ndarray, n: int) -> np.ndarray:
    change = np.zeros(n)
    for j in range(amplitudes.size):
        start, length = patterns.starts[j], patterns.lengths[j]
        change[start : start + length] += amplitudes[j] * patterns.values[j, :length]
    return change


def build_wavelets(taper, time_step, omegas, damping, peak_times, width, delay) -> Patterns:
    """One tapered-cosine wavelet per crest, placed so that its oscillator's response peaks there.

    w_j(t) = cos(ω_d,j·(t − c_j))·exp(−((t − c_j)/γ_j)²) with γ_j = width·T_j; the centre
    c_j = t_j − δ·T_j puts the peak response of the oscillator to its own wavelet at the crest
    time t_j (δ = ``delay``, from `find_wavelet_delay`). A Gaussian-tapered cosine this wide is
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
    return Patterns(starts, lengths, values)


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


def build_peak_patterns(acceleration, samples, half_width) -> Patterns:
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
    return Patterns(starts.astype(np.int64), lengths.astype(np.int64), values)


def find_wavelet_delay(width: float, damping: float) -> float:
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


def find_peak_samples(
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
def compute_influence(peak_times, omegas, damping, time_step, starts, lengths, values, samples):
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
    """−ω²·u(t_i) for a unit sample at each of samples first..last (see `compute_influence`)."""
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
def solve_regularised(matrix, rhs, scale):
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
