"""The events of the yielding devices (tendons and dissipators, `devices`), compiled: the function
the integrator watches for them (`watch`) and the change of their state at an event (`settle`),
docs/model.md §13.

A yielding device's state (its branch and plastic elongation Δp, columns `devices.BRANCH` …) stays
fixed between events, as a segment's mode and gap do, so that the equation of motion stays smooth
inside a step. Its branch changes where

* on the elastic branch, its force reaches a yield line (the tendon's F_y; the dissipator's
  k2·Δ ± (1 − k2/k1)·F_y): it yields;
* on a yield line, its elongation rate Δ̇ turns against the line (a turning point of the pier):
  it unloads elastically from there, with Δp such that the elastic force equals the line's;
* its elongation reaches that at rupture (fracture): its force drops to zero for good.

Each function is compiled for the type of its ``devices``: a table (`devices.table`), or None,
for which `watch` is the constant −1 and `settle` does nothing (the free-standing model's code).
"""

from __future__ import annotations

import numpy as np
from numba.extending import overload

from ._jit import absent, jit
from .device_mechanics import stretch, turns, yield_line
from .devices import (
    BRANCH,
    BROKEN,
    BROKEN_AT,
    DAMPER,
    ELASTIC,
    KIND,
    LIMIT,
    LOADING,
    PLASTIC,
    PRESTRESS,
    STIFFNESS,
    UNLOADING,
    YIELD,
    YIELDED_AT,
)
from .geometry import Model

RATE_SCALE = 1.0
"""Time that turns k·Δ̇ [N/s] into a force in `watch`, so that the functions of all the devices
share a unit: the sign alone matters [s]."""


def watch(devices, model: Model, s: float, theta1: float, omega: float, kin) -> float:
    """The devices' event function at (θ1, θ̇1) = (theta1, omega) [rad, rad/s] in mode s, the
    linkage as ``kin`` computes it: the largest of each yielding device's distances to its next
    change of branch (`_distance`), which turns positive at the first of them; −1 when nothing
    can change (no devices, only dampers, or all broken) [N]."""
    if devices is None:
        return -1.0
    return _watch(devices, model, s, theta1, omega, kin)


@overload(watch)
def _compiled_watch(devices, model, s, theta1, omega, kin):
    if absent(devices):
        return lambda devices, model, s, theta1, omega, kin: -1.0
    return lambda devices, model, s, theta1, omega, kin: _watch(
        devices, model, s, theta1, omega, kin
    )


@jit
def _watch(devices: np.ndarray, model: Model, s: float, theta1, omega, kin) -> float:
    if not _changing(devices):  # the linkage is not even computed (dampers, elastic tendons)
        return -1.0
    g, turned = -np.inf, turns(model, s, theta1, kin)
    for i in range(devices.shape[0]):
        row = devices[i]
        if row[KIND] != DAMPER and row[BRANCH] != BROKEN:
            length, lever = stretch(model, row, s, turned)
            g = max(g, _distance(row, length, lever * omega))
    return g if g > -np.inf else -1.0


@jit
def _changing(devices: np.ndarray) -> bool:
    """Whether some device can still change branch: a tendon or dissipator, not broken, that
    states a yield force or a rupture elongation."""
    for i in range(devices.shape[0]):
        row = devices[i]
        if row[KIND] != DAMPER and row[BRANCH] != BROKEN:
            if row[YIELD] < np.inf or row[LIMIT] < np.inf:
                return True
    return False


@jit
def _spring(row: np.ndarray, length: float) -> float:
    """A yielding device's elastic force at elongation Δ [m], unclamped: P0 + k·(Δ − Δp) [N]."""
    return row[PRESTRESS] + row[STIFFNESS] * (length - row[PLASTIC])


@jit
def _distance(row: np.ndarray, length: float, speed: float) -> float:
    """How far past its next change of branch one yielding device is, at elongation Δ [m] and
    rate Δ̇ [m/s], positive once past [N]: k·(Δ − Δ_u) (rupture, fracture), and on the elastic
    branch its force less the upper yield line and the lower line less its force, on a yield
    line k·Δ̇·`RATE_SCALE` against the line."""
    g = row[STIFFNESS] * (length - row[LIMIT])
    branch = row[BRANCH]
    if branch == ELASTIC:
        force = _spring(row, length)
        return max(
            g, force - yield_line(row, length, LOADING), yield_line(row, length, UNLOADING) - force
        )
    return max(g, -branch * row[STIFFNESS] * speed * RATE_SCALE)


def settle(devices, model: Model, s: float, theta1: float, omega: float, t: float, kin) -> None:
    """Move each yielding device to the branch it is on at (θ1, θ̇1) = (theta1, omega) [rad,
    rad/s] in mode s at time t [s], just past an event (`_settled`), or, back at rest (s = 0),
    to the branch it leaves rest on (`_rested`); nothing without devices."""
    if devices is not None:
        _settle(devices, model, s, theta1, omega, t, kin)


@overload(settle)
def _compiled_settle(devices, model, s, theta1, omega, t, kin):
    if absent(devices):
        return lambda devices, model, s, theta1, omega, t, kin: None
    return lambda devices, model, s, theta1, omega, t, kin: _settle(
        devices, model, s, theta1, omega, t, kin
    )


@jit
def _settle(devices: np.ndarray, model: Model, s, theta1, omega, t, kin) -> None:
    if s != 0.0:
        _settled(devices, model, s, theta1, omega, t, kin)
    else:
        _rested(devices, t)


@jit
def _rested(devices: np.ndarray, t: float) -> None:
    """Back at rest at time t [s] (θ1 = 0, every Δ = 0): whichever way the bridge next lifts off,
    every device opens from Δ = 0 (Δ̇ ≥ 0), so each yielding device takes now the branch it
    leaves rest on (`shifted` at Δ = 0 with an opening rate, of which only the sign is read).
    One left on its lower line unloads, as it would at the first instant of the next rocking,
    where its event function would start at zero and turn positive at once: a step of length
    zero that changes nothing, again and again. Its force at rest, which the next onset counts
    (`impacts.onsets_at_rest`), is the same on either branch."""
    for i in range(devices.shape[0]):
        if devices[i, KIND] != DAMPER and devices[i, BRANCH] != BROKEN:
            shifted(devices[i], 0.0, 1.0, t)


@jit
def _settled(devices: np.ndarray, model: Model, s, theta1, omega, t, kin) -> None:
    """The state change of `settle`, device by device (`shifted`)."""
    turned = turns(model, s, theta1, kin)
    for i in range(devices.shape[0]):
        if devices[i, KIND] != DAMPER and devices[i, BRANCH] != BROKEN:
            length, lever = stretch(model, devices[i], s, turned)
            shifted(devices[i], length, lever * omega, t)


@jit
def shifted(row: np.ndarray, length: float, speed: float, t: float) -> None:
    """Move one yielding device (a row of `devices.table`, not broken) to the branch it is on at
    elongation Δ [m] and rate Δ̇ [m/s] at time t [s]: past its rupture elongation it breaks; on
    the elastic branch, with its force past a yield line (or on it, Δ̇ into it), it yields onto
    it (its first yield time noted); on a yield line (or just onto one), with Δ̇ against it, it
    unloads elastically (`_unloaded`).

    A device can be past a line and moving back at once where its crossing fell within the event
    tolerance of another event that reversed its rate (an impact): it yields and unloads in the
    same call, so that every device leaves an event on a branch it is not already past
    (`_distance` ≤ 0), without which the devices' event function would start positive and miss
    their next change."""
    if length >= row[LIMIT]:
        row[BRANCH], row[BROKEN_AT] = BROKEN, t
        return
    if row[BRANCH] == ELASTIC:
        force = _spring(row, length)
        for side in (LOADING, UNLOADING):
            past = side * (force - yield_line(row, length, side))
            if past > 0.0 or (past == 0.0 and side * speed > 0.0):
                row[BRANCH] = side
                if np.isnan(row[YIELDED_AT]):
                    row[YIELDED_AT] = t
    if row[BRANCH] != ELASTIC and -row[BRANCH] * speed > 0.0:
        _unloaded(row, length)


@jit
def _unloaded(row: np.ndarray, length: float) -> None:
    """Unload a device from its yield line at elongation Δ [m] onto the elastic branch, with the
    Δp that keeps its force, P0 + k·(Δ − Δp) = the line's; Δp is then moved by the last bits
    rounding left, until that force is not past the line, so that the device does not start its
    elastic branch already past the line it left."""
    side = row[BRANCH]
    line = yield_line(row, length, side)
    row[PLASTIC] = length - (line - row[PRESTRESS]) / row[STIFFNESS]
    while side * (_spring(row, length) - line) > 0.0:
        row[PLASTIC] = np.nextafter(row[PLASTIC], side * np.inf)
    row[BRANCH] = ELASTIC


def fresh(devices):
    """A copy of the devices' table whose state the integrator may change (None stays None)."""
    return None if devices is None else devices.copy()


@overload(fresh)
def _compiled_fresh(devices):
    if absent(devices):
        return lambda devices: None
    return lambda devices: devices.copy()
