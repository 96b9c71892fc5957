"""The ground's velocity and displacement under a record, and the correction that zeroes them at
its end: both integrated exactly for a piecewise-linear acceleration; the baseline correction
(Boore 2001); and the significant duration D5–95."""

from __future__ import annotations

import numpy as np


def integrate_motion(acceleration: np.ndarray, time_step: float) -> tuple[np.ndarray, np.ndarray]:
    """Ground velocity and displacement at every sample, from rest, integrating the acceleration
    exactly as piecewise linear: v_k+1 = v_k + h·(a_k + a_k+1)/2 and
    d_k+1 = d_k + h·v_k + h²·(2a_k + a_k+1)/6.

    Parameters
    ----------
    acceleration
        ground acceleration [m/s²].
    time_step
        time step [s].

    Returns
    -------
    tuple of numpy.ndarray
        velocity [m/s] and displacement [m], the shape of ``acceleration``.
    """
    a = np.asarray(acceleration, dtype=float)
    h = float(time_step)
    velocity = np.concatenate([[0.0], np.cumsum(0.5 * h * (a[:-1] + a[1:]))])
    steps = h * velocity[:-1] + h * h * (2.0 * a[:-1] + a[1:]) / 6.0
    return velocity, np.concatenate([[0.0], np.cumsum(steps)])


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
    basis = baseline_values(shape)
    matrix = np.stack([final_motion_vector(row, time_step) for row in basis], axis=1)
    coefficients = np.linalg.solve(matrix, final_motion_vector(acceleration, time_step))
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
    velocity, displacement = final_motion_vector(np.asarray(acceleration, float), time_step)
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


def final_motion_vector(acceleration: np.ndarray, time_step: float) -> np.ndarray:
    """[v_end, d_end] as weighted sums of the samples (exact for linear segments, from rest)."""
    edges = 0.5 * (acceleration[0] + acceleration[-1])
    velocity = time_step * (acceleration.sum() - edges)
    displacement = time_step**2 * (acceleration @ displacement_weights(acceleration.size))
    return np.array([velocity, displacement])


def displacement_weights(n: int) -> np.ndarray:
    """w_i with d_end = h²·Σ w_i·a_i for N = n − 1 linear steps from rest.

    Summing d_k+1 = d_k + h·v_k + h²·(2a_k + a_k+1)/6 over the steps gives w_0 = N/2 − 1/6,
    w_i = N − i inside and w_N = 1/6 (for a ≡ 1 they add up to N²/2, i.e. d = t²/2).
    """
    last = n - 1
    weights = (last - np.arange(n)).astype(float)
    weights[0] = last / 2.0 - 1.0 / 6.0
    weights[-1] = 1.0 / 6.0
    return weights


def baseline_values(shape: np.ndarray) -> np.ndarray:
    """The baseline correction's functions I(t) and I(t)·t/t_end at the samples, shape (2, n)."""
    return np.stack([shape, shape * np.linspace(0.0, 1.0, shape.size)])


def final_motion_weights(n: int, time_step: float) -> np.ndarray:
    """Rows w_v, w_d with v_end = w_v·a and d_end = w_d·a (see `final_motion_vector`)."""
    velocity = np.full(n, time_step)
    velocity[[0, -1]] *= 0.5
    return np.stack([velocity, time_step**2 * displacement_weights(n)])
