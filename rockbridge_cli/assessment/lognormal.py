"""Lognormal fits by maximum likelihood, of capacities known exactly or only bounded.

Both fragility fits (`assessment.fragility`) maximise one likelihood: log-capacities
y ~ N(μ, β²), some known (density φ((y − μ)/β)/β), the others known only to lie at or below a
level x (probability Φ((x − μ)/β)) or above it (1 − Φ((x − μ)/β)). Baker's (2015) binomial
likelihood of stripes is this one with, at each level, the records that reach the state below it
and the others above; an IDA's capacities are known, except those of the records that reach the
state at the first level already (below it) or never up to the last (above it).

In a = 1/β and b = −μ/β every term is a function of the linear predictor t = a·x + b (ln Φ(t),
ln Φ(−t), ln a − t²/2), each concave (Pratt 1981, J. Am. Stat. Assoc. 76(373); Olsen 1978,
Econometrica 46(5), for the censored normal), so the log-likelihood is concave in (a, b). Newton's
method with the exact gradient and Hessian and a backtracking line search finds its maximum from
any start in a handful of steps, without a general optimiser. The fit keeps β in `BETA_RANGE` and
μ within `MARGIN` of the levels: where the unconstrained maximum lies outside that region, or
does not exist (a step function fits the data), the maximum is on the region's boundary, found
edge by edge (on each, a concave function of one variable).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import log_ndtr

BETA_RANGE = (1e-3, 5.0)
"""The log-standard deviations a fit may return [-]."""

MARGIN = 5.0
"""How far beyond the lowest and the highest level a fitted ln θ may lie [-]."""

STEPS = 60
"""Newton steps before the maximum is sought on the boundary instead."""

ROUND_OFF = 1e-14
"""Relative change of the log-likelihood below its round-off: near the maximum a Newton step
changes it by less, and the line search takes it rather than halving it away [-]."""

_LOG_ROOT_2PI = 0.5 * math.log(2.0 * math.pi)


@dataclass(frozen=True)
class Sample:
    """Log-capacities [ln of the intensity measure's unit], known or bounded.

    Attributes
    ----------
    known : log-capacities known exactly
    bounds : log-levels that bound the other capacities
    counts : how many capacities each bound holds (a weight; need not be whole)
    below : per bound, True where its capacities lie at or below it, False above
    """

    known: np.ndarray
    bounds: np.ndarray
    counts: np.ndarray
    below: np.ndarray

    def log_likelihood(
        self, a: float, b: float
    ) -> tuple[float, np.ndarray | None, np.ndarray | None]:
        """ln L (up to a constant), its gradient and its Hessian in (a, b) = (1/β, −μ/β);
        −inf (and None) where a ≤ 0 and capacities are known."""
        if self.known.size and a <= 0.0:
            return -math.inf, None, None
        t = a * self.bounds + b
        u = np.where(self.below, t, -t)  # each bound's term is ln Φ(u)
        log_cdf = log_ndtr(u)
        mills = np.exp(-0.5 * u * u - _LOG_ROOT_2PI - log_cdf)  # φ(u)/Φ(u)
        first = self.counts * np.where(self.below, mills, -mills)  # ∂/∂t
        second = -self.counts * mills * (u + mills)  # ∂²/∂t²
        value = float(self.counts @ log_cdf)
        gradient = np.array([first @ self.bounds, first.sum()])
        hessian = np.array([[second @ self.bounds**2, second @ self.bounds],
                            [second @ self.bounds, second.sum()]])  # fmt: skip
        if self.known.size:
            n, y = self.known.size, self.known
            t = a * y + b
            value += n * math.log(a) - 0.5 * float(t @ t)
            gradient += [n / a - float(t @ y), -float(t.sum())]
            hessian += [[-n / a**2 - float(y @ y), -float(y.sum())], [-float(y.sum()), -n]]
        return value, gradient, hessian


def fit(
    sample: Sample, span: tuple[float, float], start: tuple[float, float]
) -> tuple[float, float]:
    """The maximum-likelihood (μ, β) of a sample.

    Parameters
    ----------
    sample
        The log-capacities.
    span
        The lowest and the highest log-level: μ stays within `MARGIN` of them.
    start
        (μ, β) to start from [-]; any start reaches the same maximum.

    Returns
    -------
    (μ, β): the log-median [ln of the measure's unit] and the log-standard deviation [-].
    """
    region = Region(1.0 / BETA_RANGE[1], 1.0 / BETA_RANGE[0], span[0] - MARGIN, span[1] + MARGIN)
    mean, beta = start
    point = _newton(sample, np.array([1.0 / beta, -mean / beta]))
    if point is None or not region.holds(point):
        point = max(
            (_on_segment(sample, *edge) for edge in region.edges()),
            key=lambda p: sample.log_likelihood(*p)[0],
        )
    a, b = float(point[0]), float(point[1])
    return -b / a, 1.0 / a


@dataclass(frozen=True)
class Region:
    """Where a fit may lie: a in [a_low, a_high], μ = −b/a in [mean_low, mean_high] (a convex
    quadrilateral in (a, b))."""

    a_low: float
    a_high: float
    mean_low: float
    mean_high: float

    def holds(self, point: np.ndarray) -> bool:
        a, b = point
        return bool(self.a_low <= a <= self.a_high and self.mean_low <= -b / a <= self.mean_high)

    def edges(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """Its four edges, each as its two corners."""
        corners = [
            np.array([a, -mean * a])
            for a, mean in ((self.a_low, self.mean_low), (self.a_high, self.mean_low),
                            (self.a_high, self.mean_high), (self.a_low, self.mean_high))
        ]  # fmt: skip
        return list(zip(corners, corners[1:] + corners[:1], strict=True))


def _newton(sample: Sample, point: np.ndarray) -> np.ndarray | None:
    """The unconstrained maximum by Newton's method with a backtracking (Armijo) line search;
    None if it has not converged within `STEPS` (no finite maximum: the data are separated)."""
    value, gradient, hessian = sample.log_likelihood(*point)
    for _ in range(STEPS):
        assert gradient is not None and hessian is not None  # value is finite at every point
        step = _ascent(gradient, hessian)
        slope = float(gradient @ step)
        length = 1.0
        while True:
            trial = point + length * step
            found = sample.log_likelihood(*trial)
            if found[0] >= value + 1e-4 * length * slope - ROUND_OFF * abs(value):
                break  # an ascent, or a step whose change is below the likelihood's round-off
            length *= 0.5
            if length < 1e-12:  # no ascent left at this precision: the maximum
                return point
        point, (value, gradient, hessian) = trial, found
        if np.all(np.abs(length * step) <= 1e-12 * (1.0 + np.abs(point))):
            return point
    return None


def _ascent(gradient: np.ndarray, hessian: np.ndarray) -> np.ndarray:
    """Newton's step −H⁻¹·g (a 2 × 2 system, by Cramer's rule); the gradient itself where the
    Hessian is not negative definite (the data do not fix both parameters)."""
    (haa, hab), (_, hbb) = hessian
    determinant = haa * hbb - hab * hab
    if not (haa < 0.0 and determinant > 1e-300):
        return gradient
    ga, gb = gradient
    return np.array([-(hbb * ga - hab * gb), -(haa * gb - hab * ga)]) / determinant


def _on_segment(sample: Sample, first: np.ndarray, last: np.ndarray) -> np.ndarray:
    """The maximum of the (concave) log-likelihood on the segment from ``first`` to ``last``:
    a corner, or where its derivative along the segment vanishes (Newton's method kept inside a
    bracket, bisection where a step would leave it)."""
    direction = last - first

    def derivatives(s: float) -> tuple[float, float]:
        _, gradient, hessian = sample.log_likelihood(*(first + s * direction))
        assert gradient is not None and hessian is not None  # a > 0 on the region
        return float(gradient @ direction), float(direction @ hessian @ direction)

    if derivatives(0.0)[0] <= 0.0:
        return first
    if derivatives(1.0)[0] >= 0.0:
        return last
    low, high, s = 0.0, 1.0, 0.5
    for _ in range(200):
        slope, curvature = derivatives(s)
        low, high = (s, high) if slope > 0.0 else (low, s)
        newton = s - slope / curvature if curvature < 0.0 else math.nan
        following = newton if low < newton < high else 0.5 * (low + high)
        if abs(following - s) <= 1e-15:
            break
        s = following
    return first + s * direction
