"""Onset of rocking, impacts at the rocking interfaces, pounding and failure limits.

* Onset (Eq. 8, docs/model.md §5): mode s starts when s·ü_g exceeds the static threshold at rest.
* Impacts at the rocking interfaces (Eqs. 21–29, docs/model.md §6): the impulse–momentum balance
  of the three bodies with impulses at the new pivots, the abutment seats carrying L1/(L1 + L2) of
  the pier–deck impulses, solved as one linear system (the tests check it against the corrected
  closed form of Eq. 30).
* Pounding on the backwall (Eq. 20) is `geometry.pounding_ratio`.
* Failure (docs/model.md §7): the abutment–backfill fails at |u_deck| = u_jo + u_ab, a pier
  overturns at |u_pier| = B; `failure_rotations` finds the tall pier's rotation at which each is
  reached (by bisection, `_first_reached`: no scipy on a worker's start).
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numba.extending import overload

from ._jit import absent, jit
from .device_mechanics import prestress_moment, rest_moment, settled
from .dynamics import coefficients
from .geometry import Model
from .kinematics import EXACT, Displacements, centres, displacements
from .quantities import ABUTMENT, PIER1_OVERTURNING, PIER2_OVERTURNING


def onset_threshold(model: Model, s: float, devices: np.ndarray | None = None) -> float:
    """Ground acceleration at which rocking starts in mode s (Eq. 8) [m/s²].

    The virtual work of the ground's inertia forces equals that of gravity at rest:
    ü_g,min = g·Σ m_i·∂z_i/∂φ / (−Σ m_i·∂x_i/∂φ). Positive for mode p, negative for mode n;
    rocking in mode s starts when s·ü_g > s·ü_g,min. Tendons (``devices``, a
    `devices.table`) add the moment of their prestress to gravity's (`devices.prestress_moment`).
    """
    _, _, gravity, inertia, _, _ = coefficients(model, s, 0.0, EXACT)
    if devices is None:
        return gravity / -inertia
    return (gravity + prestress_moment(model, devices, s)) / -inertia


def onsets_at_rest(onset_p: float, onset_n: float, model: Model, devices) -> tuple[float, float]:
    """The onset thresholds (mode p, mode n) [m/s²] of a bridge at rest: ``onset_p`` and
    ``onset_n`` (`onset_threshold`'s, from the devices as built), unless its ``devices`` (a
    `devices.table` in its state, or None) have yielded or broken since: then Eq. 8 with the
    moment of their forces at rest (`device_mechanics.rest_moment`)."""
    if devices is None or settled(devices):
        return onset_p, onset_n
    return _onset_now(model, 1.0, devices), _onset_now(model, -1.0, devices)


@overload(onsets_at_rest)
def _compiled_onsets_at_rest(onset_p, onset_n, model, devices):
    """`onsets_at_rest` compiled for the type of ``devices``: without any, the thresholds given."""
    if absent(devices):
        return lambda onset_p, onset_n, model, devices: (onset_p, onset_n)
    return lambda onset_p, onset_n, model, devices: (
        (onset_p, onset_n)
        if settled(devices)
        else (_onset_now(model, 1.0, devices), _onset_now(model, -1.0, devices))
    )


@jit
def _onset_now(model: Model, s: float, devices: np.ndarray) -> float:
    """Eq. 8 in mode s with the devices' forces at rest in their current state [m/s²]."""
    _, _, gravity, inertia, _, _ = coefficients(model, s, 0.0, EXACT)
    return (gravity + rest_moment(devices, model, s)) / -inertia


def restitution(model: Model, s: float, abutment_seats: bool = True) -> float:
    """Coefficient of restitution η = φ̇_II/φ̇_I of an impact that ends mode s.

    Solves the impulse–momentum balance of the three bodies at rest (docs/model.md §6): unknown
    impulses at the new base pivots (A, C), at the new pier–deck pivots (B, D) and, for a bridge,
    vertical impulses at the abutment seats E, E' with Λ_E = L1/(L1 + L2)·Λ_B,z and
    Λ_E' = L1/(L1 + L2)·Λ_D,z (Eqs. 21–22); the bodies move in mode s before and in mode −s after.

    Parameters
    ----------
    model
        The bridge.
    s
        The mode before the impact: +1 for p→n, −1 for n→p [-].
    abutment_seats
        False drops the seat impulses: the asymmetric frame of Dimitrakopoulos & Giouvanidis (2015).

    Returns
    -------
    η [-]; the angular velocity keeps its sign across the impact (φ̇_II = η·φ̇_I).
    """
    before = _rest_jacobian(model, s)
    after = _rest_jacobian(model, -s)
    pos = centres(model, s, 0.0, EXACT)[0]
    cg = np.reshape(pos, (3, 2))
    # New pivots (those of mode −s): base of pier 1, base of pier 2, deck on pier 1, deck on pier 2.
    B, H1, H2, L2 = model.B, model.H1, model.H2, model.L2
    base1 = (s * B, 0.0)
    base2 = (L2 + s * B, 2.0 * (H1 - H2))
    top1 = (-s * B, 2.0 * H1)
    top2 = (L2 - s * B, 2.0 * H1)
    seats = (-model.L1, L2 + model.L1)
    share = model.L1 / (model.L1 + L2) if (abutment_seats and model.has_abutments) else 0.0

    # Unknowns: Λ_A (x, z), Λ_C (x, z), Λ_B (x, z), Λ_D (x, z), Λ_E, Λ_E', φ̇_II; φ̇_I = 1.
    # Λ_A, Λ_C act on the piers from the ground; Λ_B, Λ_D on the deck from the piers.
    matrix = np.zeros((11, 11))
    rhs = np.zeros(11)
    masses = (model.m1, model.m2, model.md)
    inertias = (model.I1, model.I2, model.Id)
    loads = (  # (body, unknown column of the x-impulse, point, sign)
        (0, 0, base1, 1.0), (0, 4, top1, -1.0),
        (1, 2, base2, 1.0), (1, 6, top2, -1.0),
        (2, 4, top1, 1.0), (2, 6, top2, 1.0),
    )  # fmt: skip
    for body, column, point, sign in loads:
        rx, rz = point[0] - cg[body, 0], point[1] - cg[body, 1]
        matrix[3 * body, column] += sign
        matrix[3 * body + 1, column + 1] += sign
        matrix[3 * body + 2, column] += -sign * rz
        matrix[3 * body + 2, column + 1] += sign * rx
    for column, x_seat in zip((8, 9), seats, strict=True):
        matrix[7, column] = 1.0
        matrix[8, column] = x_seat - cg[2, 0]
    for body in range(3):
        for axis in range(3):
            weight = inertias[body] if axis == 2 else masses[body]
            matrix[3 * body + axis, 10] = -weight * after[body, axis]
            rhs[3 * body + axis] = -weight * before[body, axis]
    matrix[9, 8], matrix[9, 5] = 1.0, -share
    matrix[10, 9], matrix[10, 7] = 1.0, -share
    return float(np.linalg.solve(matrix, rhs)[10])


def _rest_jacobian(model: Model, s: float) -> np.ndarray:
    """Velocities (ẋ, ż, ω) of pier 1, pier 2 and deck per unit φ̇ at rest in mode s, (3, 3)."""
    _, d1, _, ang = centres(model, s, 0.0, EXACT)
    return np.array(
        [[d1[0], d1[1], 1.0], [d1[2], d1[3], ang[0]], [d1[4], d1[5], ang[1]]], dtype=float
    )


def failure_rotations(model: Model) -> dict[str, dict[str, float]]:
    """Rotation of the tall pier at which each failure limit is reached, per mode.

    Computed once per bridge and process (the tables and the bridge's summary both ask); the
    caller gets its own copy.

    Returns
    -------
    ``{limit: {"p": θ1 [rad], "n": θ1 [rad]}}`` for ``abutment`` (|u_deck| = u_jo + u_ab; absent
    without abutments), ``overturning_pier1`` and ``overturning_pier2`` (|u_pier| = B). A limit the
    linkage cannot reach below 1.5·α1 is ``inf``.
    """
    return {name: dict(rotations) for name, rotations in _failure_rotations(model).items()}


@functools.lru_cache(maxsize=256)
def _failure_rotations(model: Model) -> dict[str, dict[str, float]]:
    limits = {  # failure mode: (the displacement that reaches it, the limit [m])
        ABUTMENT: ("u_deck", model.u_jo + model.u_ab),
        PIER1_OVERTURNING: ("u_pier1", model.B),
        PIER2_OVERTURNING: ("u_pier2", model.B),
    }
    if not model.has_abutments:
        del limits[ABUTMENT]
    if model.m2 == 0.0:
        del limits[PIER2_OVERTURNING]
    return {
        name: {mode: _rotation_at(model, s, field, limit) for mode, s in (("p", 1.0), ("n", -1.0))}
        for name, (field, limit) in limits.items()
    }


def governing_failure(model: Model, caps: dict[str, dict[str, float]] | None = None) -> str:
    """The failure limit reached at the smallest rotation of the tall pier, over both modes.

    ``caps`` are the model's `failure_rotations`, when already computed.
    """
    caps = caps if caps is not None else failure_rotations(model)
    return min(caps, key=lambda name: min(abs(v) for v in caps[name].values()))


def _rotation_at(model: Model, s: float, field: str, limit: float) -> float:
    """Smallest s·θ1 > 0 at which the `Displacements` ``field`` reaches ±limit, or ±inf if none
    below 1.5·α1: the first of 384 steps of θ1 where it is reached, then `_first_reached`."""
    grid = np.linspace(0.0, 1.5 * model.alpha1, 385)[1:]
    return s * _first_reached(model, s, Displacements._fields.index(field), limit, grid)


@jit
def _first_reached(model: Model, s: float, field: int, limit: float, grid: np.ndarray) -> float:
    """The smallest float t > 0 at which |``field`` of `Displacements`| at θ1 = s·t reaches
    ``limit``: the first point of ``grid`` where it does, then bisection to the last bit between
    it and the point before (the limit's rotation to within one unit in the last place; scipy's
    brentq, used before, stopped within 1e-15 + 1e-14·t); inf if no point reaches it before the
    linkage stops closing [rad]. Compiled: called from Python, its ~1300 evaluations took 10 ms
    of each new bridge's tables, which a sampled study builds for every bridge (issue 43)."""
    below = 0.0
    for above in grid:
        value = _excess(model, s, field, limit, above)
        if not math.isfinite(value):
            break
        if value >= 0.0:
            while True:
                middle = 0.5 * (below + above)
                if not below < middle < above:  # adjacent floats: nothing left to split
                    return above
                if _excess(model, s, field, limit, middle) >= 0.0:
                    above = middle
                else:
                    below = middle
        below = above
    return math.inf


@jit
def _excess(model: Model, s: float, field: int, limit: float, t: float) -> float:
    """How far |``field`` of `Displacements`| at θ1 = s·t is beyond ``limit`` [m]."""
    return abs(displacements(model, s, s * t, EXACT)[field]) - limit
