"""The one-step schemes of the integrator (`solver`): the classical fixed-step Runge–Kutta of order
4 (the paper's) and the embedded Dormand–Prince 5(4) pair (Dormand & Prince 1980), on the state
(θ1, θ̇1) with θ̈1 from `dynamics.acceleration` and the ground acceleration linear between samples
(horizontal, and vertical where the record has one: `VerticalGround`).

A step is named by small tuples that the compiled kernels pass around: the `Segment` of the response
it belongs to (what stays fixed from one event to the next), the `Ground` motion, the `State` at
each of its ends, and the `Step` that joins them."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import types
from numba.extending import overload

from ._jit import absent, inlined, uncounted
from .dynamics import acceleration
from .geometry import Model
from .kinematics import Kinematics

RK4, DOPRI5 = 0, 1
"""Integration schemes."""


class Segment(NamedTuple):
    """The bridge along one smooth segment of the response, between two events (docs/model.md
    §11): what the equation of motion depends on besides the state, the kinematics and the
    ground motion. Those two hold arrays and travel beside it, as arguments of their own: inlined
    into the kernels of every step (`events.watched`), a segment holding them would count
    references to their arrays at each call, measured at 5–9 % of a `fast` analysis.

    Attributes
    ----------
    model : the bridge (core frame)
    s : rocking mode, +1 or −1 (0 at rest, where no step is taken) [-]
    contact : whether the end gap is closed (the abutment's spring–dashpot on)
    devices : the piers' tendons and dampers (`devices.table`), or None without any (the
        kernels are compiled for each, so that a free-standing bridge runs the paper's code)
    """

    model: Model
    s: float
    contact: bool
    devices: np.ndarray | None


class Ground(NamedTuple):
    """The ground motion, linear between its samples.

    Attributes
    ----------
    acc : ground acceleration at uniform samples, positive to the right [m/s²]
    dt : their interval [s]
    """

    acc: np.ndarray
    dt: float


class VerticalGround(NamedTuple):
    """A ground motion with a vertical component, linear between its samples.

    A type of its own, not a `Ground` with an empty vertical array: the kernels are compiled for
    each, so that an analysis without vertical motion runs the paper's code as it was, where an
    empty array tested at every stage cost 3–5 % of a `fast` analysis.

    Attributes
    ----------
    acc, dt : as in `Ground`
    vert : vertical ground acceleration at the same samples, positive up [m/s²]
    """

    acc: np.ndarray
    dt: float
    vert: np.ndarray


def ground_of(acc: np.ndarray, dt: float, vertical: np.ndarray | None = None):
    """The `Ground` of samples ``acc`` at ``dt`` [m/s², s], or with a ``vertical`` component
    [m/s²] its `VerticalGround`."""
    return Ground(acc, dt) if vertical is None else VerticalGround(acc, dt, vertical)


@overload(ground_of)
def _compiled_ground_of(acc, dt, vertical=None):
    """`ground_of` compiled for the type of ``vertical``: one type of ground or the other."""
    if vertical is None or absent(vertical):
        return lambda acc, dt, vertical=None: Ground(acc, dt)
    return lambda acc, dt, vertical=None: VerticalGround(acc, dt, vertical)


class State(NamedTuple):
    """The tall pier's rotation, angular velocity and angular acceleration at one instant.

    Attributes
    ----------
    theta : θ1 [rad]
    rate : θ̇1 [rad/s]
    accel : θ̈1 [rad/s²]; NaN where unknown (RK4 leaves it so at a step's end)
    """

    theta: float
    rate: float
    accel: float


class Step(NamedTuple):
    """One step of a scheme, never past the end of its sample interval.

    Attributes
    ----------
    k : the sample interval it lies in [-]
    t : time at its start [s]
    h : its length [s]
    start, end : the `State` at both ends
    """

    k: int
    t: float
    h: float
    start: State
    end: State


@inlined
def ground_at(acc: np.ndarray, dt: float, k: int, t: float) -> float:
    """Ground acceleration at time t inside sample interval k (linear between samples) [m/s²]."""
    return acc[k] + (acc[k + 1] - acc[k]) * (t / dt - k)


def lift_at(ground: Ground | VerticalGround, g: float, k: int, t: float) -> float:
    """(g + ü_v)/g at time t inside sample interval k: the factor by which the vertical ground
    acceleration ü_v changes the weight of every body (docs/model.md §12); 1 for a `Ground`
    without one, a constant the compiler folds away [-]. ``g``: gravity [m/s²]."""
    if not isinstance(ground, VerticalGround):
        return 1.0
    return 1.0 + ground_at(ground.vert, ground.dt, k, t) / g


@overload(lift_at)
def _compiled_lift_at(ground, g, k, t):
    """`lift_at` compiled for the type of ``ground``."""
    if isinstance(ground, types.NamedTuple) and ground.instance_class is VerticalGround:
        return lambda ground, g, k, t: 1.0 + ground_at(ground.vert, ground.dt, k, t) / g
    return lambda ground, g, k, t: 1.0


@inlined
def accel_at(segment: Segment, kin: Kinematics, ground, k: int, t: float, y, w) -> float:
    """θ̈1 at (θ1, θ̇1) = (y, w) and time t [s] in sample interval k (`dynamics.acceleration`)."""
    model, s, contact, devices = segment
    a_g = ground_at(ground.acc, ground.dt, k, t)
    lift = lift_at(ground, model.g, k, t)
    return acceleration(model, s, y, w, a_g, contact, kin, lift, devices)


@uncounted
def accel_called(segment: Segment, kin: Kinematics, ground, k: int, t: float, y, w) -> float:
    """`accel_at`, compiled once and called: for the evaluations of θ̈1 once a segment or an event
    (`solver._refreshed`, `solver._accelerated`), which, inlined, would each be typed and
    compiled again in their callers. The stages of a step (`take_step`) inline it: called there,
    a `fast` step took 10–15 % longer (2026-11-29)."""
    return accel_at(segment, kin, ground, k, t, y, w)


@uncounted
def take_step(segment: Segment, kin: Kinematics, ground: Ground, k, t, start: State, h, scheme):
    """One step of length h [s] of a segment from ``start`` at time t [s] in sample interval k of
    the ground motion, with `RK4` or `DOPRI5`; ``kin``: how to compute the linkage.

    Returns the `State` at its end (θ̈1 there is DOPRI5's last stage, which the next step reuses;
    NaN for RK4) and, for DOPRI5, the local error estimates of θ1 [rad] and θ̇1 [rad/s] (zero for
    RK4).
    """
    y, w, f0 = start
    if not np.isfinite(f0):
        f0 = accel_at(segment, kin, ground, k, t, y, w)
    if scheme == RK4:
        f1 = f0
        y2, w2 = y + 0.5 * h * w, w + 0.5 * h * f1
        f2 = accel_at(segment, kin, ground, k, t + 0.5 * h, y2, w2)
        y3, w3 = y + 0.5 * h * w2, w + 0.5 * h * f2
        f3 = accel_at(segment, kin, ground, k, t + 0.5 * h, y3, w3)
        y4, w4 = y + h * w3, w + h * f3
        f4 = accel_at(segment, kin, ground, k, t + h, y4, w4)
        end = State(
            y + h / 6.0 * (w + 2.0 * w2 + 2.0 * w3 + w4),
            w + h / 6.0 * (f1 + 2.0 * f2 + 2.0 * f3 + f4),
            np.nan,
        )
        return end, 0.0, 0.0
    # Dormand–Prince 5(4): the stages of θ1 are the θ̇1 values, those of θ̇1 the accelerations.
    a1 = f0
    v1 = w
    y2 = y + h * (v1 / 5.0)
    v2 = w + h * (a1 / 5.0)
    a2 = accel_at(segment, kin, ground, k, t + h / 5.0, y2, v2)
    y3 = y + h * (3.0 * v1 + 9.0 * v2) / 40.0
    v3 = w + h * (3.0 * a1 + 9.0 * a2) / 40.0
    a3 = accel_at(segment, kin, ground, k, t + 0.3 * h, y3, v3)
    y4 = y + h * (44.0 / 45.0 * v1 - 56.0 / 15.0 * v2 + 32.0 / 9.0 * v3)
    v4 = w + h * (44.0 / 45.0 * a1 - 56.0 / 15.0 * a2 + 32.0 / 9.0 * a3)
    a4 = accel_at(segment, kin, ground, k, t + 0.8 * h, y4, v4)
    y5 = y + h * (
        19372.0 / 6561.0 * v1 - 25360.0 / 2187.0 * v2 + 64448.0 / 6561.0 * v3 - 212.0 / 729.0 * v4
    )
    v5 = w + h * (
        19372.0 / 6561.0 * a1 - 25360.0 / 2187.0 * a2 + 64448.0 / 6561.0 * a3 - 212.0 / 729.0 * a4
    )
    a5 = accel_at(segment, kin, ground, k, t + 8.0 / 9.0 * h, y5, v5)
    y6 = y + h * (
        9017.0 / 3168.0 * v1 - 355.0 / 33.0 * v2 + 46732.0 / 5247.0 * v3
        + 49.0 / 176.0 * v4 - 5103.0 / 18656.0 * v5
    )  # fmt: skip
    v6 = w + h * (
        9017.0 / 3168.0 * a1 - 355.0 / 33.0 * a2 + 46732.0 / 5247.0 * a3
        + 49.0 / 176.0 * a4 - 5103.0 / 18656.0 * a5
    )  # fmt: skip
    a6 = accel_at(segment, kin, ground, k, t + h, y6, v6)
    y_new = y + h * (
        35.0 / 384.0 * v1 + 500.0 / 1113.0 * v3 + 125.0 / 192.0 * v4
        - 2187.0 / 6784.0 * v5 + 11.0 / 84.0 * v6
    )  # fmt: skip
    w_new = w + h * (
        35.0 / 384.0 * a1 + 500.0 / 1113.0 * a3 + 125.0 / 192.0 * a4
        - 2187.0 / 6784.0 * a5 + 11.0 / 84.0 * a6
    )  # fmt: skip
    a7 = accel_at(segment, kin, ground, k, t + h, y_new, w_new)
    # Difference of the 5th- and 4th-order solutions.
    e1, e3, e4 = 71.0 / 57600.0, -71.0 / 16695.0, 71.0 / 1920.0
    e5, e6, e7 = -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0
    err_y = h * (e1 * v1 + e3 * v3 + e4 * v4 + e5 * v5 + e6 * v6 + e7 * w_new)
    err_w = h * (e1 * a1 + e3 * a3 + e4 * a4 + e5 * a5 + e6 * a6 + e7 * a7)
    return State(y_new, w_new, a7), err_y, err_w
