"""Velocity pulses in recorded ground motions: whether a record holds a strong velocity pulse, its
period T_p and when it arrives, by the wavelet method of Baker (2007) in the form Shahi & Baker
(2014) gave it for one or two horizontal components.

The method, step by step (`identify_pulse`):

1. The velocity (the acceleration integrated from rest) is transformed with the continuous wavelet
   transform of the Daubechies wavelet of order 4 (db4) at 51 scales whose pseudo-periods run from
   0.25 to about 15 s, linearly in the scale (Shahi & Baker 2014).
2. With two orthogonal components the transform is linear, so the transform of the component at
   an angle θ from the first toward the second is cos θ·C1 + sin θ·C2: its magnitude is largest,
   √(C1² + C2²), at tan θ = C2/C1. The largest coefficient over scales, times and orientations is
   found without trying angles; the record is rotated to that θ (Shahi & Baker 2014). With one
   component, θ = 0.
3. The scale is refined to the sample between the grid's neighbours, at the times within the
   wavelet's support (Shahi & Baker refine at the coarse maximum's time only: `_refine` says
   why), and the pulse is extracted as the sum of the 10 largest wavelets of that scale within
   ±0.4 scale of the largest, each taken from what the previous ones left (matching pursuit;
   Baker 2007, with Shahi & Baker's window).
4. The residual's peak velocity and energy ∫v² dt over the record's give the PGV ratio and the
   energy ratio (Shahi & Baker sum the squares of the discrete wavelet transform's
   coefficients: the same energy by Parseval's theorem, but for the ends); their principal
   component PC = 0.63·(PGV ratio) + 0.777·(energy ratio) and the record's PGV [cm/s] give the
   pulse indicator
   PI = 9.384·(0.76 − PC − 0.0616·PGV)·(PC + 6.914·10⁻⁴·PGV − 1.072) − 6.179,
   positive for a pulse (Shahi & Baker 2014, their support-vector classifier).
5. A pulse is *late* when the record has 17 % of its energy before the pulse has 5 % of its own
   (Shahi & Baker 2014); a record holds a pulse when PI > 0 and the pulse is not late.
6. Up to five candidates are tried in turn, each away from the times of the ones before (±0.4 of
   their scale); the first that is a pulse is the record's (Shahi & Baker 2014).

T_p is the pseudo-period of the pulse's scale a, a·Δt/F_c, with F_c = 5/7 = 0.714 the centre
frequency of db4 as Baker (2007) and Shahi & Baker (2014) take it (MATLAB's ``centfrq``: the
largest term of the wavelet's Fourier series over its support of 7 units). The continuous Fourier
amplitude of db4 peaks 2 % lower, at 0.699: the published periods follow the former. T_p is the
pseudo-period of the db4 wavelet that matches the pulse best, not a parameter of the pulse's shape:
it is 1.03–1.15 times the period of a two-sided Mavroeidis & Papageorgiou (2003) pulse (γ = 2–3),
and about twice the duration of a one-sided velocity pulse (the velocity of Makris & Roussos'
one-sine acceleration pulse); ω_p/p (`frequency_ratio`) inherits the convention.

A study analyses one horizontal component: what it identifies is the pulse of that component
(`pulse_provenance`). The orientation-independent pulse of a recording needs both components.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. Bulletin
of the Seismological Society of America 53(2), 403–417.
Makris, N., Roussos, Y. S. (2000). Rocking response of rigid blocks under near-source ground
motions. Géotechnique 50(3), 243–262.
Mavroeidis, G. P., Papageorgiou, A. S. (2003). A mathematical representation of near-fault ground
motions. Bulletin of the Seismological Society of America 93(3), 1099–1131.
Baker, J. W. (2007). Quantitative classification of near-fault ground motions using wavelet
analysis. Bulletin of the Seismological Society of America 97(5), 1486–1501.
Shahi, S. K., Baker, J. W. (2014). An efficient algorithm to identify strong-velocity pulses in
multicomponent ground motions. Bulletin of the Seismological Society of America 104(5),
2456–2466.
Daubechies, I. (1992). Ten Lectures on Wavelets. SIAM, Table 6.1 (the filter of order 4).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ..core.quantities import STANDARD_GRAVITY
from .baseline import integrate_motion

DB4_FILTER = np.array([
    0.23037781330885523, 0.7148465705525415, 0.6308807679295904, -0.02798376941698385,
    -0.18703481171888114, 0.030841381835986965, 0.032883011666982945, -0.010597401784997278,
])  # fmt: skip
"""The scaling filter of the Daubechies wavelet with 4 vanishing moments (Daubechies 1992, Table
6.1, normalised to sum √2)."""

WAVELET_SUPPORT = 7.0
"""Length of db4's support, in units of its scale (2·4 − 1)."""

CASCADE_LEVELS = 10
"""Refinements of the cascade algorithm that samples db4: 2¹⁰ points per unit of scale."""

PERIOD_RANGE = (0.25, 15.0)
"""Pseudo-periods the transform searches [s] (Shahi & Baker 2014)."""

SCALE_STEPS = 50
"""Steps of the scale grid over `PERIOD_RANGE` (51 scales; Shahi & Baker 2014)."""

WAVELETS_PER_PULSE = 10
"""Wavelets summed into the pulse (Baker 2007; Shahi & Baker 2014)."""

SEARCH_WIDTH = 0.4
"""Half-width, in units of the scale, of the window the pulse's wavelets are taken from and of
the times a later candidate must avoid (Shahi & Baker 2014: 10/25)."""

REFINEMENT = 0.01
"""Relative step of the scales the search refines on, where integer scales are finer [-]."""

CANDIDATES = 5
"""Candidate pulses tried, strongest first (Shahi & Baker 2014)."""

LATE_RECORD_ENERGY = 0.17
LATE_PULSE_ENERGY = 0.05
"""A pulse is late when the record has `LATE_RECORD_ENERGY` of its energy before the pulse has
`LATE_PULSE_ENERGY` of its own (Shahi & Baker 2014)."""


@dataclass(frozen=True, eq=False)
class PulseIdentification:
    """What `identify_pulse` found: the record's pulse, or its strongest candidate if none is.

    Attributes
    ----------
    is_pulse : the record holds a pulse (indicator > 0, not late)
    period : pseudo-period T_p of the pulse's wavelet scale [s]
    indicator : Shahi & Baker's pulse indicator PI, > 0 for a pulse [-]
    pgv_ratio : peak velocity of the residual over the record's [-]
    energy_ratio : ∫v² dt of the residual over the record's [-]
    pgv : peak velocity of the record in the pulse's orientation [m/s]
    arrival_time : when the pulse has 5 % of its energy [s]
    late : the record has 17 % of its energy by then
    angle : orientation of the pulse, from the first component toward the second [deg]
    velocity : the record's velocity in that orientation [m/s]
    pulse : the extracted pulse [m/s]
    """

    is_pulse: bool
    period: float
    indicator: float
    pgv_ratio: float
    energy_ratio: float
    pgv: float
    arrival_time: float
    late: bool
    angle: float
    velocity: np.ndarray
    pulse: np.ndarray


def identify_pulse(acceleration: np.ndarray, time_step: float) -> PulseIdentification:
    """Whether a record holds a strong velocity pulse, and its period (the module's method).

    Parameters
    ----------
    acceleration
        one horizontal component, shape (n,), or two orthogonal ones, shape (2, n) [m/s²].
    time_step
        sample interval [s].

    Returns
    -------
    PulseIdentification
        the first candidate that is a pulse, else the strongest candidate (``is_pulse`` False);
        a record at rest gives a non-pulse with NaN period and indicator.
    """
    a = np.atleast_2d(np.asarray(acceleration, dtype=float))
    if a.ndim != 2 or a.shape[0] not in (1, 2) or a.shape[1] < 2:
        raise ValueError("give one component, shape (n,), or two, shape (2, n)")
    if not np.isfinite(a).all():  # NaN came back as "no pulse"
        raise ValueError("the accelerations must be finite numbers (a NaN or an infinity)")
    if not (math.isfinite(time_step) and time_step > 0.0):
        raise ValueError(f"the time step must be a positive number of seconds, not {time_step}")
    velocities = np.array([integrate_motion(row, time_step)[0] for row in a])
    unit = float(np.max(np.abs(velocities)))  # the search runs on velocities of peak 1
    duration = (a.shape[1] - 1) * time_step  # no pulse longer than the record is looked for
    if not (math.isfinite(unit) and unit > 0.0) or duration < PERIOD_RANGE[0]:
        rest = np.zeros(a.shape[1])
        return PulseIdentification(False, math.nan, math.nan, math.nan, math.nan, unit,
                                   math.nan, False, 0.0, rest, rest)  # fmt: skip
    velocities /= unit
    scales = search_scales(time_step, min(PERIOD_RANGE[1], duration))
    coefficients = wavelet_transform(velocities, scales)
    strength = np.sum(coefficients**2, axis=0)
    found: list[PulseIdentification] = []
    while len(found) < CANDIDATES and np.any(strength):
        row, column = (int(i) for i in np.unravel_index(np.argmax(strength), strength.shape))
        angle = _orientation(coefficients[:, row, column])
        direction = np.array([math.cos(angle), math.sin(angle)])[: velocities.shape[0]]
        found.append(_extract(direction @ velocities, unit, time_step, scales, row, column, angle))
        if found[-1].is_pulse:
            return found[-1]
        half = math.ceil(SEARCH_WIDTH * scales[row])
        strength[:, max(0, column - half) : column + half + 1] = 0.0
    return found[0]


def pulse_provenance(acceleration: np.ndarray, time_step: float) -> dict[str, float]:
    """The pulse of one component as a record's provenance (`records.files.PROVENANCE`):
    ``pulse_period_s`` [s], NaN when the record holds no pulse, and ``pulse_indicator`` [-]."""
    found = identify_pulse(acceleration, time_step)
    return {
        "pulse_period_s": found.period if found.is_pulse else math.nan,
        "pulse_indicator": found.indicator,
    }


def frequency_ratio(pulse_period: float, radius: float, gravity: float = STANDARD_GRAVITY) -> float:
    """ω_p/p, the pulse's circular frequency 2π/T_p over the frequency parameter
    p = √(3g/(4R)) of a rectangular block of half-diagonal R (Housner 1963): the abscissa of
    overturning spectra (Makris & Roussos 2000) [-].

    Parameters
    ----------
    pulse_period
        T_p [s].
    radius
        R, the block's half-diagonal (a bridge's tall pier: ``R1`` of `core.summary`) [m].
    gravity
        g [m/s²].
    """
    return 2.0 * math.pi / pulse_period / math.sqrt(3.0 * gravity / (4.0 * radius))


def search_scales(time_step: float, longest: float = PERIOD_RANGE[1]) -> np.ndarray:
    """The scales of the search [samples]: from the one of pseudo-period 0.25 s, `SCALE_STEPS`
    equal integer steps reaching 15 s (Shahi & Baker 2014), or ``longest`` [s], the record's
    duration, when it is shorter."""
    _, centre = db4_wavelet()
    low, high = (period * centre / time_step for period in (PERIOD_RANGE[0], longest))
    first = max(1, math.floor(low))
    step = max(1, math.ceil((high - first) / SCALE_STEPS))
    return first + step * np.arange(SCALE_STEPS + 1)


def pseudo_period(scale: float, time_step: float) -> float:
    """The period [s] of the db4 wavelet at a scale [samples]: scale·Δt/F_c (Baker 2007)."""
    return scale * time_step / db4_wavelet()[1]


@functools.cache
def db4_wavelet() -> tuple[np.ndarray, float]:
    """db4's wavelet function ψ on its support [0, 7], sampled every 2⁻¹⁰ by the cascade
    algorithm (Daubechies 1992, §6.5) and scaled to ∫ψ² = 1, and its centre frequency F_c, the
    frequency of the largest term of its Fourier series over the support [cycles per unit]."""
    filter_ = DB4_FILTER
    values = (-1.0) ** np.arange(filter_.size) * filter_[::-1]  # the wavelet filter
    for _ in range(CASCADE_LEVELS - 1):
        upsampled = np.zeros(2 * values.size - 1)
        upsampled[::2] = values
        values = math.sqrt(2.0) * np.convolve(upsampled, filter_)
    per_unit = 2**CASCADE_LEVELS
    values /= math.sqrt(np.sum(values**2) / per_unit)
    series = np.abs(np.fft.rfft(values, round(WAVELET_SUPPORT) * per_unit))
    centre = float(np.argmax(series)) / WAVELET_SUPPORT
    values.setflags(write=False)
    return values, centre


def wavelet_atom(scale: float) -> np.ndarray:
    """db4 at a scale [samples], centred on its middle sample and of unit energy on the samples:
    the atom whose dot product with a signal is its wavelet coefficient."""
    values, _ = db4_wavelet()
    half = math.floor(0.5 * WAVELET_SUPPORT * scale)
    where = np.arange(-half, half + 1) / scale + 0.5 * WAVELET_SUPPORT
    fine = np.arange(values.size) * 2.0**-CASCADE_LEVELS
    atom = np.interp(where, fine, values, left=0.0, right=0.0)
    return atom / math.sqrt(np.sum(atom**2))


def wavelet_transform(signals: np.ndarray, scales: np.ndarray) -> np.ndarray:
    """Continuous wavelet transform C[k, j, b] = Σ_n v_k[n]·w_j[n − b] of each signal v_k with
    the atom w_j of each scale (`wavelet_atom`), the signals zero outside their samples.

    Parameters
    ----------
    signals
        shape (k, n).
    scales
        [samples].

    Returns
    -------
    numpy.ndarray
        shape (k, scales, n).
    """
    count = signals.shape[-1]
    longest = 2 * math.floor(0.5 * WAVELET_SUPPORT * max(scales)) + 1
    size = _fast_length(count + longest - 1)
    spectra = np.fft.rfft(signals, size, axis=-1)
    result = np.empty((signals.shape[0], len(scales), count))
    for j, scale in enumerate(scales):
        atom = wavelet_atom(scale)
        middle = atom.size // 2
        product = np.fft.irfft(spectra * np.fft.rfft(atom[::-1], size), size, axis=-1)
        result[:, j] = product[:, middle : middle + count]
    return result


def _extract(
    velocity: np.ndarray,
    unit: float,
    time_step: float,
    scales: np.ndarray,
    row: int,
    column: int,
    angle: float,
) -> PulseIdentification:
    """Steps 3 to 5 of the method for the candidate at ``scales[row]`` and sample ``column``, in
    the orientation ``angle`` [rad], on a velocity in units of ``unit`` [m/s]."""
    scale, column = _refine(velocity, scales, row, column)
    atom = wavelet_atom(scale)
    middle = atom.size // 2
    window, coefficients = _local_transform(
        velocity, np.array([scale]), column, math.ceil(SEARCH_WIDTH * scale)
    )
    coefficients = coefficients[0]
    gram = _autocorrelation(atom)
    pulse = np.zeros(velocity.size)
    for _ in range(WAVELETS_PER_PULSE):
        k = int(np.argmax(np.abs(coefficients)))
        weight, at = coefficients[k], window[k]
        lo, hi = max(0, at - middle), min(velocity.size, at + middle + 1)
        pulse[lo:hi] += weight * atom[lo - at + middle : hi - at + middle]
        coefficients = coefficients - weight * gram[window - at + gram.size // 2]
    residual = velocity - pulse
    peak = float(np.max(np.abs(velocity)))
    pgv_ratio = float(np.max(np.abs(residual))) / peak
    energy_ratio = float(np.sum(residual**2) / np.sum(velocity**2))
    indicator = _pulse_indicator(pgv_ratio, energy_ratio, unit * peak)
    record_energy = np.cumsum(velocity**2) / np.sum(velocity**2)
    pulse_energy = np.cumsum(pulse**2) / np.sum(pulse**2)
    arrival = max(0, int(np.searchsorted(pulse_energy, LATE_PULSE_ENERGY, side="right")) - 1)
    late = bool(record_energy[arrival] >= LATE_RECORD_ENERGY)
    return PulseIdentification(
        indicator > 0.0 and not late, pseudo_period(scale, time_step), indicator, pgv_ratio,
        energy_ratio, unit * peak, arrival * time_step, late, math.degrees(angle),
        unit * velocity, unit * pulse,
    )  # fmt: skip


def _orientation(coefficients: np.ndarray) -> float:
    """The angle θ in (−π/2, π/2] [rad] at which cos θ·C1 + sin θ·C2 is largest in magnitude:
    tan θ = C2/C1 (0 for one component)."""
    if coefficients.size == 1:
        return 0.0
    angle = math.atan2(coefficients[1], coefficients[0])
    if angle > 0.5 * math.pi:
        return angle - math.pi
    return angle + math.pi if angle <= -0.5 * math.pi else angle


def _refine(velocity: np.ndarray, scales: np.ndarray, row: int, column: int) -> tuple[int, int]:
    """The scale [samples] and sample of the largest coefficient at the integer scales between
    the neighbours of ``scales[row]`` (no closer than `REFINEMENT` apart), at the samples within
    half the largest wavelet's support of ``column``. Shahi & Baker (2014) refine the scale at
    ``column`` only; searching the nearby times too finds Baker's (2007) maximum on the fine grid
    where neighbouring scales peak at different times (Rinaldi's pulse: 1.2 s and 1.5 s)."""
    low, high = scales[max(0, row - 1)], scales[min(scales.size - 1, row + 1)]
    count = min(high - low, math.ceil(math.log(high / low) / math.log1p(REFINEMENT))) + 1
    fine = np.unique(np.round(np.geomspace(low, high, count)).astype(int))
    reach = math.ceil(0.5 * WAVELET_SUPPORT * high)
    positions, transform = _local_transform(velocity, fine, column, reach)
    j, k = np.unravel_index(np.argmax(np.abs(transform)), transform.shape)
    return int(fine[j]), int(positions[k])


def _local_transform(
    signal: np.ndarray, scales: np.ndarray, centre: int, reach: int
) -> tuple[np.ndarray, np.ndarray]:
    """The samples within ``reach`` of ``centre`` and the transform there, shape (scales,
    samples): `wavelet_transform` of the stretch of the signal those coefficients need."""
    half = math.floor(0.5 * WAVELET_SUPPORT * max(scales))
    first = max(0, centre - reach - half)
    last = min(signal.size, centre + reach + half + 1)
    positions = np.arange(max(0, centre - reach), min(signal.size, centre + reach + 1))
    transform = wavelet_transform(signal[None, first:last], scales)[0]
    return positions, transform[:, positions - first]


def _autocorrelation(atom: np.ndarray) -> np.ndarray:
    """Σ_u w[u]·w[u + d] for d = −(m−1)…m−1 (m the atom's length), lag 0 in the middle: how a
    wavelet coefficient changes when an atom is taken away at another sample."""
    size = _fast_length(2 * atom.size - 1)
    spectrum = np.fft.rfft(atom, size)
    full = np.fft.irfft(spectrum * np.conj(spectrum), size)
    return np.concatenate([full[size - atom.size + 1 :], full[: atom.size]])


def _fast_length(size: int) -> int:
    """The smallest 2^i·3^j·5^k not below ``size``: a length numpy's FFT transforms fast."""
    best = 1 << (size - 1).bit_length()
    five = 1
    while five < best:
        odd = five
        while odd < best:
            best = min(best, odd << (-(-size // odd) - 1).bit_length())
            odd *= 3
        five *= 5
    return best


def _pulse_indicator(pgv_ratio: float, energy_ratio: float, pgv: float) -> float:
    """Shahi & Baker's (2014) pulse indicator, from the principal component of the two ratios and
    the record's PGV [m/s] (used in cm/s) [-]."""
    component = 0.63 * pgv_ratio + 0.777 * energy_ratio
    pgv_cm = 100.0 * pgv
    return (
        9.384 * (0.76 - component - 0.0616 * pgv_cm) * (component + 6.914e-4 * pgv_cm - 1.072)
        - 6.179
    )
