"""The ground's velocity and displacement under a record, and the correction that zeroes them at
its end: both integrated exactly for a piecewise-linear acceleration; the baseline correction
(Boore 2001), with the least ground displacement, or the least away from a reference record's;
and the record's build-up of Arias intensity: significant durations (D5–95, D5–75) and Arias
times."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.polynomial import legendre


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


@dataclass(frozen=True)
class BaselineCorrection:
    """The baseline correction of records of one envelope and length: the enveloped slow trend
    whose removal zeroes the final velocity and displacement and, of all such trends, leaves the
    least ground displacement.

    The trends are I(t)·Σ c_k·P_k(τ), I the envelope, P_k the Legendre polynomials of
    τ = 2t/t_end − 1 for k < ``terms``. Two terms give Boore's (2001) enveloped linear trend,
    which the two final conditions fix alone; it can leave the ground a metre away from rest in
    mid-record. More terms leave freedom that the correction spends on the least squares of the
    displacement over the samples, which removes that long-period wander; its functions only
    reach periods of about 2·t_end/(terms − 1), longer than the matched band
    (`correction_terms`). All of it is linear in the acceleration. Where the envelope is strong
    in a part of the record only, τ can span that part alone (``span``; held at ±1 outside it):
    over a 90 s record whose shaking lasts 20 s, 31 polynomials over the whole record are
    numerically dependent inside those 20 s, and their coefficients reach 1e4.

    `anchored` gives the correction that leaves the least displacement away from a reference
    record's instead: a ↦ r + B(a − r), B this correction, which keeps the reference's own slow
    motion (a recorded seed's ground displacement) and bounds only what the matching adds.

    Attributes
    ----------
    functions
        the trend's functions at the samples, shape (terms, n) [-].
    weights
        rows whose products with an acceleration are all the coefficients depend on: what its
        displacement gives each coefficient, then its final velocity and displacement, shape
        (terms + 2, n).
    gain
        coefficients = ``gain @ (weights @ acceleration)``, shape (terms, terms + 2).
    anchor
        the trend of the reference (`anchored`), added back to every corrected record [m/s²];
        None: no reference.
    """

    functions: np.ndarray
    weights: np.ndarray
    gain: np.ndarray
    anchor: np.ndarray | None = None

    @classmethod
    def of(
        cls,
        shape: np.ndarray,
        time_step: float,
        terms: int = 2,
        span: tuple[int, int] | None = None,
    ) -> BaselineCorrection:
        """The correction for records of envelope ``shape`` [-] at ``time_step`` [s], its
        polynomials over the samples ``span`` (first, last; default: all)."""
        if terms < 2:
            raise ValueError(f"the two final conditions need two terms or more, got {terms}")
        if span is None:
            tau = np.linspace(-1.0, 1.0, shape.size)
        else:
            first, last = span
            tau = np.clip(2.0 * (np.arange(shape.size) - first) / (last - first) - 1.0, -1.0, 1.0)
        functions = shape * legendre.legvander(tau, terms - 1).T
        shapes = np.stack([integrate_motion(row, time_step)[1] for row in functions])
        scale = np.sqrt(np.mean(shapes**2, axis=1))  # balance the system: unit RMS displacements
        functions, shapes = functions / scale[:, None], shapes / scale[:, None]
        # c = P·f + Z·z: P meets the final conditions f, Z (their null space) is free; z is the
        # least-squares fit of the rest of the displacement (SVDs: no squared condition number)
        final = final_motion_weights(shape.size, time_step)
        ends = final @ functions.T
        particular = np.linalg.pinv(ends)
        free = np.linalg.svd(ends)[2][2:].T
        spread = free @ np.linalg.pinv(shapes.T @ free)  # displacement → coefficients
        gain = np.hstack([np.eye(terms), particular - spread @ (shapes.T @ particular)])
        projections = np.stack([displacement_gradient(row, time_step) for row in spread])
        return cls(functions, np.vstack([projections, final]), gain)

    def coefficients(self, measures: np.ndarray) -> np.ndarray:
        """The trend's coefficients from ``weights @ acceleration`` (a column per record)."""
        return self.gain @ measures

    def trend(self, acceleration: np.ndarray) -> np.ndarray:
        """The trend that the correction removes from ``acceleration`` [m/s²]."""
        return self.coefficients(self.weights @ acceleration) @ self.functions

    def anchored(self, reference: np.ndarray) -> BaselineCorrection:
        """The correction a ↦ r + self(a − r) for the reference r [m/s²], whose final velocity
        and displacement must be zero (they are the corrected records')."""
        return replace(self, anchor=self.trend(reference))

    def __call__(self, acceleration: np.ndarray) -> np.ndarray:
        """The corrected acceleration [m/s²]."""
        corrected = acceleration - self.trend(acceleration)
        return corrected if self.anchor is None else corrected + self.anchor


def correction_terms(duration: float, longest_period: float, reach: float) -> int:
    """Terms of a `BaselineCorrection` whose functions stay at periods above ``reach`` times the
    longest matched period: a polynomial of degree k swings k times over ``duration`` [-]."""
    return 1 + max(1, math.ceil(2.0 * duration / (reach * longest_period)))


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
    """Significant duration D5–95 (D5–75 with ``end=0.75``): the time between 5 % and 95 % of
    the Arias intensity (Trifunac & Brady 1975), ∫a²dt by trapezoids, its crossings
    interpolated linearly between samples.

    Parameters
    ----------
    acceleration
        ground acceleration [m/s²].
    time_step
        time step [s].
    start, end
        fractions of the total intensity that bound the duration [-].
    """
    times = compute_arias_times(acceleration, time_step, np.array([start, end]))
    return float(times[1] - times[0])


def compute_arias_times(
    acceleration: np.ndarray, time_step: float, fractions: np.ndarray
) -> np.ndarray:
    """When the record has built up each fraction of its Arias intensity [s] (from its first
    sample; 0.5: the Arias time, the centre of its shaking).

    Parameters
    ----------
    acceleration
        ground acceleration [m/s²].
    time_step
        time step [s].
    fractions
        fractions of the total intensity, in [0, 1] [-].
    """
    build_up = arias_build_up(acceleration)
    times = np.arange(build_up.size) * time_step
    return np.interp(fractions, build_up, times)


def arias_build_up(acceleration: np.ndarray) -> np.ndarray:
    """The share of the Arias intensity ∫a²dt reached at each sample (trapezoidal) [-].

    Raises
    ------
    ValueError
        A record of zeros, which builds up nothing.
    """
    squared = np.asarray(acceleration, dtype=float) ** 2
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (squared[1:] + squared[:-1]))])
    if cumulative[-1] <= 0.0:
        raise ValueError("a record of zeros has no significant duration")
    return cumulative / cumulative[-1]


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


def final_motion_weights(n: int, time_step: float) -> np.ndarray:
    """Rows w_v, w_d with v_end = w_v·a and d_end = w_d·a (see `final_motion_vector`)."""
    velocity = np.full(n, time_step)
    velocity[[0, -1]] *= 0.5
    return np.stack([velocity, time_step**2 * displacement_weights(n)])


def displacement_gradient(factors: np.ndarray, time_step: float) -> np.ndarray:
    """g with Σ_k factors_k·d_k = g·a for the displacement d of `integrate_motion` (its adjoint:
    the same recurrences run backwards)."""
    h = time_step
    later = np.cumsum(factors[::-1])[::-1][1:]  # Σ of the factors after each step
    gradient = np.zeros(factors.size)
    gradient[:-1] += h * h * later / 3.0
    gradient[1:] += h * h * later / 6.0
    through_velocity = np.cumsum(later[::-1])[::-1] - later  # Σ over the later steps' h·v terms
    gradient[:-1] += 0.5 * h * h * through_velocity
    gradient[1:] += 0.5 * h * h * through_velocity
    return gradient
