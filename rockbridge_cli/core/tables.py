"""Tabulated kinematics: everything the integrator asks of the linkage, as piecewise cubics.

One degree of freedom means one-dimensional coefficients: per rocking mode, each quantity the
equation of motion and the event functions need (the table's named slots, `kinematics.SLOT_MASS`
… `SLOT_THETA_DECK`: M, M', ∂V/∂φ, Σm·∂x/∂φ, u_deck, ∂u_deck/∂φ, then the displacements and
rotations) is a function of θ1 alone. `tabulated` samples them once per bridge on a uniform grid
of s·θ1 from a little below rest (the linkage is smooth through it) to a little beyond the first
failure the bridge can reach, with the exact kinematics, and fits a not-a-knot cubic spline through
each. An evaluation is then an index and a Horner cubic per quantity instead of the ~20
transcendental calls of the exact linkage; outside the grid the kernels fall back to the exact
path, never extrapolate. The error against the exact path is measured by `tests/test_tables.py`
(relative 1e-12 or better at 2048 intervals).
"""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy.interpolate import CubicSpline

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
        spline = CubicSpline(x, values, axis=0, bc_type="not-a-knot")
        table[mode] = np.moveaxis(spline.c, 0, -1)  # (intervals, quantity, power 3…0)
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
