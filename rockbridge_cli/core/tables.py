"""Tabulated kinematics: everything the integrator asks of the linkage, as piecewise cubics.

One degree of freedom means one-dimensional coefficients: per rocking mode, each quantity the
equation of motion and the event functions need (the table's named slots, `kinematics.SLOT_MASS`
… `SLOT_THETA_DECK`: M, M', ∂V/∂φ, Σm·∂x/∂φ, u_deck, ∂u_deck/∂φ, then the displacements and
rotations) is a function of θ1 alone. `tabulated` samples them once per bridge on a uniform grid
of s·θ1 from a little below rest (the linkage is smooth through it) to a little beyond the first
failure the bridge can reach, with the exact kinematics, and fits a not-a-knot cubic spline through
each (`not_a_knot`, in numpy: a worker that builds tables imports no scipy). An evaluation is
then an index and a Horner cubic per quantity instead of the ~20 transcendental calls of the
exact linkage; outside the grid the kernels fall back to the exact path, never extrapolate. The
error against the exact path is measured by `tests/test_tables.py`
(relative 1e-12 or better at 2048 intervals).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ._jit import jit
from .dynamics import coefficients
from .geometry import Model
from .impacts import failure_rotations
from .kinematics import (
    COEFFICIENTS,
    DISPLACEMENTS,
    EXACT,
    SLOT_MASS,
    SLOT_U_PIER1,
    SLOTS,
    Kinematics,
    displacements,
)

INTERVALS = 2048
"""Intervals of the tables over the reachable rotation of each mode."""

BELOW_REST = 0.25
"""The tables reach this fraction of the reachable rotation below rest (s·θ1 < 0), at the same
interval: the trial steps that overshoot an impact while it is located land there, and with most
analyses logging hundreds of impacts, computing them with the exact linkage took half of an
analysis's time."""

MARGIN = 1.1
"""The tables reach this far beyond the first failure's rotation, so that the steps that overshoot
it while the event is located stay inside them."""


@functools.lru_cache(maxsize=256)
def tabulated(model: Model, intervals: int = INTERVALS) -> Kinematics:
    """The tabulated kinematics of a bridge, built once per process and bridge (≈ 2 ms).

    Parameters
    ----------
    model
        The bridge (hashable: equal bridges share their tables).
    intervals
        Intervals of the uniform grid of s·θ1 from rest to the reach [-]; those below rest
        (`BELOW_REST`) come in addition.
    """
    limit = reach(model)
    start = -BELOW_REST * limit
    while True:  # shorten the grid to where the linkage closes, if it does not everywhere
        step = limit / intervals
        below = int(-start / step + 1e-9)
        x = step * np.arange(-below, intervals + 1)
        samples = [_sample(model, s, x) for s in (1.0, -1.0)]
        closes = np.all(np.isfinite(np.stack(samples)), axis=(0, 2))  # per grid point
        if closes.all():
            break
        if not closes[below]:  # not even at rest
            return EXACT
        opens_above = np.flatnonzero(~closes[below:])
        opens_below = np.flatnonzero(~closes[:below])
        if opens_above.size:
            limit = x[below + opens_above[0] - 1]
        if opens_below.size:
            start = x[opens_below[-1] + 1]
        if limit <= 0.0:
            return EXACT
    table = np.empty((2, x.size - 1, SLOTS, 4))
    for mode, values in enumerate(samples):
        table[mode] = not_a_knot(x, values)  # (intervals, quantity, power 3…0)
    return Kinematics(EXACT.fits, table, step, x[0], x[-1])


def reach(model: Model) -> float:
    """The largest s·θ1 an analysis visits in either mode: the rotation of the first failure the
    mode reaches, times `MARGIN`, or the largest the linkage closes at [rad]."""
    first = [
        min(abs(rotation[mode]) for rotation in failure_rotations(model).values())
        for mode in ("p", "n")
    ]
    finite = [value for value in first if math.isfinite(value)]
    return MARGIN * max(finite) if finite else 1.5 * model.alpha1


@jit
def _sample(model: Model, s: float, x: np.ndarray) -> np.ndarray:
    """The tabulated quantities at s·θ1 = x, exactly: shape (x.size, `SLOTS`)."""
    out = np.empty((x.size, SLOTS))
    for i in range(x.size):
        theta1 = s * x[i]
        c = coefficients(model, s, theta1, EXACT)
        d = displacements(model, s, theta1, EXACT)
        for q in range(COEFFICIENTS):
            out[i, SLOT_MASS + q] = c[q]
        for q in range(DISPLACEMENTS):
            out[i, SLOT_U_PIER1 + q] = d[q]
    return out


def not_a_knot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The not-a-knot cubic spline through points, as the coefficients of each interval's cubic.

    The spline is the piecewise cubic with continuous first and second derivatives through
    (x_i, y_i) whose third derivative is continuous at x_1 and x_(n−2) too (the first two and the
    last two intervals are one cubic each; de Boor 2001, *A Practical Guide to Splines*, ch. IV).
    Its slopes s_i at the points solve a tridiagonal system, row i (0 < i < n − 1)

        h_i·s_(i−1) + 2(h_(i−1) + h_i)·s_i + h_(i−1)·s_(i+1) = 3(h_i·m_(i−1) + h_(i−1)·m_i),

    with h_i = x_(i+1) − x_i and m_i = (y_(i+1) − y_i)/h_i, and the not-a-knot conditions as its
    first and last rows; it is solved by Gaussian elimination without pivoting (`_thomas`: the
    system is diagonally dominant but for those two rows, whose elimination is safe on grids
    without abrupt changes of interval, such as the tables' uniform ones). The cubic of interval
    i is then the Hermite cubic of y_i, y_(i+1), s_i, s_(i+1). The same equations as
    ``scipy.interpolate.CubicSpline(x, y, bc_type="not-a-knot")``, whose coefficients it
    reproduces to rounding (`tests/test_tables.py`), without its import.

    Parameters
    ----------
    x
        The points' abscissae, increasing, at least 4 [any unit].
    y
        The values at ``x``, shape (n, m): m quantities at once [any units].

    Returns
    -------
    Shape (n − 1, m, 4): for interval i and quantity q the coefficients of (x − x_i)³,
    (x − x_i)², (x − x_i) and 1.
    """
    if x.ndim != 1 or x.size < 4 or y.shape[:1] != x.shape or y.ndim != 2:
        raise ValueError(f"not_a_knot takes n ≥ 4 points and values of shape (n, m), got "
                         f"{x.shape} and {y.shape}")  # fmt: skip
    h = np.diff(x)
    m = np.diff(y, axis=0) / h[:, None]
    n = x.size
    lower, diagonal, upper = np.zeros(n), np.empty(n), np.zeros(n)
    lower[1:-1], diagonal[1:-1], upper[1:-1] = h[1:], 2.0 * (h[:-1] + h[1:]), h[:-1]
    right = np.empty_like(y, dtype=float)
    right[1:-1] = 3.0 * (h[1:, None] * m[:-1] + h[:-1, None] * m[1:])
    first, last = x[2] - x[0], x[-1] - x[-3]  # the not-a-knot rows
    diagonal[0], upper[0] = h[1], first
    right[0] = ((h[0] + 2.0 * first) * h[1] * m[0] + h[0] ** 2 * m[1]) / first
    lower[-1], diagonal[-1] = last, h[-2]
    right[-1] = (h[-1] ** 2 * m[-2] + (2.0 * last + h[-1]) * h[-2] * m[-1]) / last
    s = _thomas(lower, diagonal, upper, right)
    t = (s[:-1] + s[1:] - 2.0 * m) / h[:, None]
    return np.stack([t / h[:, None], (m - s[:-1]) / h[:, None] - t, s[:-1], y[:-1]], axis=-1)


def _thomas(
    lower: np.ndarray, diagonal: np.ndarray, upper: np.ndarray, right: np.ndarray
) -> np.ndarray:
    """The solution of a tridiagonal system for several right-hand sides, by Gaussian
    elimination without pivoting (the Thomas algorithm).

    Row i reads lower_i·z_(i−1) + diagonal_i·z_i + upper_i·z_(i+1) = right_i (``lower[0]`` and
    ``upper[-1]`` unused); ``right`` has shape (n, m), one column per system. The pivots depend
    on the matrix alone (`_eliminated`, row by row). The substitutions, forward and back, are
    first-order linear recurrences on the columns, each computed by recursive doubling
    (`_recurrence`, whose order of operations sets the tables' bits).
    """
    pivot, factors = _eliminated(lower, diagonal, upper)
    forward = _recurrence(-factors, right)  # z_i = r_i − f_i·z_(i−1)
    back = np.zeros(diagonal.size)  # s_i = z_i/p_i − (u_i/p_i)·s_(i+1), from the last row up
    back[1:] = (-upper[:-1] / pivot[:-1])[::-1]
    return _recurrence(back, (forward / pivot[:, None])[::-1])[::-1]


@jit
def _eliminated(lower: np.ndarray, diagonal: np.ndarray, upper: np.ndarray):
    """The pivots and the elimination factors of a tridiagonal matrix, row by row (arguments as
    in `_thomas`). Compiled: a loop of Python over the rows took 2.5 ms of each bridge's tables
    (2 × 2561 rows)."""
    pivots, factors = diagonal.copy(), np.zeros(diagonal.size)
    for i in range(1, diagonal.size):
        factors[i] = lower[i] / pivots[i - 1]
        pivots[i] -= factors[i] * upper[i - 1]
    return pivots, factors


@jit
def _recurrence(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """z_0 = b_0, z_i = b_i + a_i·z_(i−1) (``a[0]`` unused), by recursive doubling: after the
    step of stride k, z_i = b'_i + a'_i·z_(i−k) with a'_i the product of the k factors it
    skips, so that log2(n) steps reach the first row (Stone 1973, J. ACM 20(1) 27–38). Written
    for numpy's arrays, one array operation a step; now compiled (4 ms of each bridge's tables
    in numpy), with the same operations in the same order, which keep the tables' bits.

    Parameters
    ----------
    a
        The factors, shape (n,).
    b
        The terms, shape (n, m).
    """
    factor, z = a.copy(), b.copy()
    factor[0] = 0.0
    stride = 1
    while stride < factor.size:
        for i in range(factor.size - 1, stride - 1, -1):  # from the end: z[i − stride] is old
            for j in range(z.shape[1]):
                z[i, j] = z[i, j] + factor[i] * z[i - stride, j]
            factor[i] = factor[i] * factor[i - stride]
        stride *= 2
    return z
