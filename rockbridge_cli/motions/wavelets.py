"""The time-domain corrections of spectral matching (`matching`, step 3): tapered-cosine
wavelets placed at the crests of oscillator responses, patterns that hold the record's peaks and
baseline, the exact response of an oscillator to each (for a piecewise-linear record), and the
regularised solve of the linear system that links their amplitudes to the crests."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core._jit import jit
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
