"""Linear single-degree-of-freedom response spectra, exact for piecewise-linear ground motion.

The oscillator ü + 2ξωu̇ + ω²u = −a_g(t) is stepped with the closed-form recurrence of Nigam and
Jennings (1969): over a step the ground acceleration is linear, so the response is a particular
linear solution plus a damped free vibration, both known exactly. The recurrence is exact at the
samples whatever the ratio of the period to the time step; what the time step limits is how finely
the peak is seen. Two measures keep the peak accurate for short periods: steps are split into
sub-steps so that every period has at least `POINTS_PER_PERIOD` points (the input is still the same
piecewise-linear function), and the extreme within a step where the velocity changes sign is taken
from the cubic Hermite interpolant of the displacement and velocity at the step's ends.

The ground is taken to come to rest one time step after the last sample, and the first crest of
the free vibration that follows counts too: a long-period oscillator may peak after the record
ends (as it does in frequency-domain solutions with zero padding).

References
----------
Nigam, N. C. and Jennings, P. C. (1969). Calculation of response spectra from strong-motion
earthquake records. Bulletin of the Seismological Society of America 59(2), 909–922.
"""

from __future__ import annotations

import math

import numpy as np

from ..core._jit import jit

#: Minimum number of (sub-)steps per oscillator period [-].
POINTS_PER_PERIOD = 10


def compute_psa(
    acceleration: np.ndarray,
    time_step: float,
    periods: np.ndarray,
    damping: float = 0.05,
) -> np.ndarray:
    """Pseudo-spectral acceleration ω²·max|u| of a ground acceleration record.

    Parameters
    ----------
    acceleration
        ground acceleration at uniform time steps, linear between samples [m/s²].
    time_step
        time step of the record [s].
    periods
        oscillator periods; 0 gives the peak ground acceleration [s].
    damping
        oscillator damping ratio ξ, 0 <= ξ < 1 [-].

    Returns
    -------
    numpy.ndarray
        PSA at each period, shaped like ``periods`` [m/s²] (the unit of ``acceleration``).
    """
    shape = np.shape(periods)
    acceleration, periods = _check_inputs(acceleration, time_step, periods, damping)
    psa = np.empty(periods.size)
    zero = periods == 0.0
    psa[zero] = np.max(np.abs(acceleration))
    omegas = 2.0 * np.pi / periods[~zero]
    substeps = _count_substeps(time_step, periods[~zero])
    peaks = _find_crests(acceleration, time_step, omegas, damping, substeps, 1)[0][:, 0]
    psa[~zero] = omegas**2 * np.abs(peaks)
    return psa.reshape(shape)


def find_peak_responses(
    acceleration: np.ndarray,
    time_step: float,
    periods: np.ndarray,
    damping: float = 0.05,
    crests: int = 1,
) -> tuple[np.ndarray, np.ndarray]:
    """The largest crests (turning points) of each oscillator's displacement and their times.

    Parameters
    ----------
    acceleration
        ground acceleration at uniform time steps, linear between samples [m/s²].
    time_step
        time step of the record [s].
    periods
        oscillator periods, > 0 [s].
    damping
        oscillator damping ratio ξ, 0 <= ξ < 1 [-].
    crests
        how many of the largest crests to return per oscillator [-].

    Returns
    -------
    tuple of numpy.ndarray
        u at the crests, signed [m], and their times [s], both of shape (periods, crests): the
        first column is the peak max|u| wherever it occurs, then the other turning points by
        decreasing |u|; missing crests have u = 0.
    """
    acceleration, periods = _check_inputs(acceleration, time_step, periods, damping)
    if not np.all(periods > 0.0):
        raise ValueError("periods must be positive")
    if crests < 1:
        raise ValueError(f"crests must be at least 1, got {crests!r}")
    return _find_crests(
        acceleration,
        time_step,
        2.0 * np.pi / periods,
        damping,
        _count_substeps(time_step, periods),
        crests,
    )


def compute_oscillator_response(
    acceleration: np.ndarray, time_step: float, period: float, damping: float = 0.05
) -> np.ndarray:
    """Relative displacement history of one oscillator, starting at rest (Nigam & Jennings 1969).

    Parameters
    ----------
    acceleration
        ground acceleration at uniform time steps, linear between samples [m/s²].
    time_step
        time step of the record [s].
    period
        oscillator period, > 0 [s].
    damping
        oscillator damping ratio ξ, 0 <= ξ < 1 [-].

    Returns
    -------
    numpy.ndarray
        u at the samples of the record [m] (for ``acceleration`` in m/s²).
    """
    acceleration, periods = _check_inputs(acceleration, time_step, [period], damping)
    if not periods[0] > 0.0:
        raise ValueError(f"the period must be positive, got {period!r}")
    history = np.empty(acceleration.size)
    crests = np.zeros((2, 1))
    _integrate(acceleration, time_step, 2.0 * np.pi / periods[0], damping, 1, history, crests)
    return history


def _check_inputs(acceleration, time_step, periods, damping) -> tuple[np.ndarray, np.ndarray]:
    acceleration = np.ascontiguousarray(acceleration, dtype=float)
    periods = np.asarray(periods, dtype=float)
    if acceleration.ndim != 1 or acceleration.size < 2:
        raise ValueError("the acceleration must be a 1-D array of at least two samples")
    if not np.all(np.isfinite(acceleration)):
        raise ValueError("the acceleration holds NaN or infinite values")
    if not (math.isfinite(time_step) and time_step > 0.0):
        raise ValueError(f"the time step must be positive, got {time_step!r}")
    if np.any(~np.isfinite(periods)) or np.any(periods < 0.0):
        raise ValueError("periods must be finite and non-negative")
    if not 0.0 <= damping < 1.0:
        raise ValueError(f"the damping ratio must be in [0, 1), got {damping!r}")
    return acceleration, periods.ravel()


def _count_substeps(time_step: float, periods: np.ndarray) -> np.ndarray:
    """Sub-steps per record step so that each period spans `POINTS_PER_PERIOD` points [-]."""
    return np.maximum(1, np.ceil(POINTS_PER_PERIOD * time_step / periods - 1e-9)).astype(np.int64)


@jit
def _find_crests(acceleration, time_step, omegas, damping, substeps, count):
    values = np.zeros((omegas.size, count))
    times = np.zeros((omegas.size, count))
    no_history = np.empty(0)
    for j in range(omegas.size):
        crests = np.zeros((2, count + 1))  # one spare: the peak is usually a turning point too
        _integrate(acceleration, time_step, omegas[j], damping, substeps[j], no_history, crests)
        for k in range(count):  # element by element: numba takes 3 s longer to compile
            values[j, k] = crests[0, k]  # the assignment of a slice (2.4 s for the kernel)
            times[j, k] = crests[1, k]
    return values, times


@jit
def _integrate(acceleration, time_step, omega, damping, substeps, history, crests):
    """Step one oscillator through the record.

    The step map is that of Nigam & Jennings (1969): with slope s of the ground acceleration and
    value a at the start of a (sub-)step of length h, the particular solution is α + β·τ with
    β = −s/ω² and α = −a/ω² + 2ξs/ω³, and the free vibration is propagated by the exact
    transition matrix of the damped oscillator.

    Fills ``history`` with u at the samples when it is sized, and ``crests`` (2 × K: signed u,
    time) with the peak max|u| first, then the K − 1 largest other turning points, by |u|.
    """
    h = time_step / substeps
    root = math.sqrt(1.0 - damping * damping)
    omega_d = omega * root
    decay = math.exp(-damping * omega * h)
    sin_h = math.sin(omega_d * h)
    cos_h = math.cos(omega_d * h)
    a11 = decay * (cos_h + damping / root * sin_h)
    a12 = decay * sin_h / omega_d
    a21 = -decay * omega / root * sin_h
    a22 = decay * (cos_h - damping / root * sin_h)
    inverse = 1.0 / (omega * omega)
    lag = 2.0 * damping * inverse / omega
    u = 0.0
    v = 0.0
    peak = 0.0
    peak_time = 0.0
    keep = history.size > 0
    if keep:
        history[0] = 0.0
    last = acceleration.size - 1
    for i in range(last + 1):  # the last step brings the ground to rest: a = 0 at t_end + Δt
        following = acceleration[i + 1] if i < last else 0.0
        slope = (following - acceleration[i]) / time_step
        beta = -slope * inverse
        for k in range(substeps):
            alpha = lag * slope - (acceleration[i] + slope * (k * h)) * inverse
            free_u = u - alpha
            free_v = v - beta
            u_next = a11 * free_u + a12 * free_v + alpha + beta * h
            v_next = a21 * free_u + a22 * free_v + beta
            start = i * time_step + k * h
            if abs(u_next) > abs(peak):
                peak = u_next
                peak_time = start + h
            if v * v_next < 0.0:
                x, u_turn = _find_turning_point(u, v, u_next, v_next, h)
                if abs(u_turn) > abs(peak):
                    peak = u_turn
                    peak_time = start + x * h
                _insert_crest(crests, u_turn, start + x * h)
            u = u_next
            v = v_next
        if keep and i < last:
            history[i + 1] = u
    x, u_turn = _find_free_crest(u, v, omega, damping)
    if abs(u_turn) > abs(peak):
        peak = u_turn
        peak_time = (last + 1) * time_step + x
    _insert_crest(crests, u_turn, (last + 1) * time_step + x)
    _place_peak_first(crests, peak, peak_time)


@jit
def _find_free_crest(u, v, omega, damping):
    """First crest of the free vibration from (u, v), once the ground is at rest.

    u(τ) = e^(−ξωτ)·(u·cos ω_dτ + (v + ξωu)/ω_d·sin ω_dτ) turns where tan(ω_dτ) = v/K with
    K = (ξωv + ω²u)/ω_d; later crests are smaller.

    Returns
    -------
    tuple
        the time τ after the start of the free vibration [s] and u there [m].
    """
    omega_d = omega * math.sqrt(1.0 - damping * damping)
    k = (damping * omega * v + omega * omega * u) / omega_d
    if v == 0.0:
        return 0.0, u
    angle = math.atan2(v, k)  # tan = v/K; the first positive solution is this or π later
    if angle <= 0.0:
        angle += math.pi
    tau = angle / omega_d
    value = math.exp(-damping * omega * tau) * (
        u * math.cos(angle) + (v + damping * omega * u) / omega_d * math.sin(angle)
    )
    return tau, value


@jit
def _insert_crest(crests, value, time):
    """Keep crests[:, 1:] as the largest turning points by |u|, in decreasing order."""
    count = crests.shape[1]
    if count < 2 or abs(value) <= abs(crests[0, count - 1]):
        return
    slot = count - 1
    while slot > 1 and abs(value) > abs(crests[0, slot - 1]):
        crests[0, slot] = crests[0, slot - 1]
        crests[1, slot] = crests[1, slot - 1]
        slot -= 1
    crests[0, slot] = value
    crests[1, slot] = time


@jit
def _place_peak_first(crests, peak, peak_time):
    """Put the peak in column 0 and drop it from the turning points if it is one of them."""
    count = crests.shape[1]
    for slot in range(1, count):
        if crests[1, slot] == peak_time and crests[0, slot] == peak:
            for later in range(slot, count - 1):
                crests[0, later] = crests[0, later + 1]
                crests[1, later] = crests[1, later + 1]
            crests[0, count - 1] = 0.0
            crests[1, count - 1] = 0.0
            break
    crests[0, 0] = peak
    crests[1, 0] = peak_time


@jit
def _find_turning_point(u0, v0, u1, v1, h):
    """Turning point of the cubic Hermite interpolant of a step where the velocity changes sign.

    The interpolant is p(x) = u0 + h·v0·x + c2·x² + c3·x³ on x in [0, 1]; its error for a smooth
    response is O((h/T)⁴), so the peak between samples is not missed.

    Returns
    -------
    tuple
        the fraction x of the step [-] and p(x) [m].
    """
    c2 = 3.0 * (u1 - u0) - h * (2.0 * v0 + v1)
    c3 = 2.0 * (u0 - u1) + h * (v0 + v1)
    # p'(x) = h·v0 + 2·c2·x + 3·c3·x² changes sign on [0, 1]
    qa = 3.0 * c3
    qb = 2.0 * c2
    qc = h * v0
    if abs(qa) < 1e-12 * (abs(qb) + abs(qc)):
        x = -qc / qb
    else:
        disc = math.sqrt(max(qb * qb - 4.0 * qa * qc, 0.0))
        x = (-qb + disc) / (2.0 * qa)
        if x < 0.0 or x > 1.0:
            x = (-qb - disc) / (2.0 * qa)
    x = min(max(x, 0.0), 1.0)
    return x, u0 + x * (h * v0 + x * (c2 + x * c3))
