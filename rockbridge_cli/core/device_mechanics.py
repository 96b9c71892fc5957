"""The mechanics of the piers' devices (`devices`), compiled: each one's elongation and force,
their generalised force on θ1 (`restrained`, which `dynamics.acceleration` calls), the moment of
the tendons' prestress at the onset of rocking, the energy the devices store, and the devices'
peaks along a response (docs/model.md §13). The yielding devices' events (yield, unloading,
rupture or fracture) are `device_events`'s.

Each function that the integrator calls is compiled for the type of its ``devices``: a table
(`devices.table`), or None, for which it does nothing (`restrained` returns the force it is
given), so that a bridge without devices runs the free-standing model's code.
"""

from __future__ import annotations

import numpy as np
from numba.extending import overload

from ._jit import absent, jit
from .devices import (
    BASE,
    BRANCH,
    BROKEN,
    DAMPER,
    DAMPING,
    ELASTIC,
    HARDENING,
    KIND,
    LOADING,
    OFFSET,
    PIER,
    PLASTIC,
    PRESTRESS,
    STIFFNESS,
    TENDON,
    TOP,
    YIELD,
)
from .geometry import Model
from .kinematics import (
    EXACT,
    SLOT_THETA2,
    SLOT_THETA_DECK,
    Kinematics,
    cubic,
    linkage,
    slope,
    table_piece,
)


@jit
def turns(model: Model, s: float, theta1: float, kin: Kinematics):
    """How the four rocking interfaces turn in mode s at θ1 [rad], shared by all the devices of a
    bridge: for the base and the top of each pier (base 1, top 1, base 2, top 2), the sine and
    cosine of half its turn (θ_i, and θ_i − θ_deck at a top) and the turn's φ-derivative (1, ψ';
    less θ' at a top) [-, -, -]. θ2, ψ', θ_deck and θ' come from ``kin``'s tables where it has
    them and θ1 lies inside (their cubics and slopes; the tables are in s·θ1), else from the
    exact linkage (docs/model.md §3)."""
    piece, dx, mode = table_piece(kin, s, theta1)
    if piece >= 0:
        t = kin.table
        theta2, dpsi = (
            cubic(t, mode, piece, SLOT_THETA2, dx),
            s * slope(t, mode, piece, SLOT_THETA2, dx),
        )
        deck, dtheta = (
            cubic(t, mode, piece, SLOT_THETA_DECK, dx),
            s * slope(t, mode, piece, SLOT_THETA_DECK, dx),
        )
    else:
        _, psi, deck, dpsi, dtheta, _, _ = linkage(model, s, theta1, EXACT)
        theta2 = psi - (0.5 * np.pi - s * np.arctan2(model.B, model.H2))
    return (
        _half(theta1, 1.0), _half(theta1 - deck, 1.0 - dtheta),
        _half(theta2, dpsi), _half(theta2 - deck, dpsi - dtheta),
    )  # fmt: skip


@jit
def _half(turn: float, rate: float):
    """sin(x/2), cos(x/2) and ∂x/∂φ of an interface that turned by x [-, -, -]."""
    return np.sin(0.5 * turn), np.cos(0.5 * turn), rate


@jit
def stretch(model: Model, row: np.ndarray, s: float, turned):
    """Elongation Δ of one device (a row of `table`) and ∂Δ/∂φ in mode s, the interfaces turned
    as `turns` says.

    Returns
    -------
    Δ [m], ∂Δ/∂φ [m/rad]
    """
    base_turn, top_turn = (turned[0], turned[1]) if row[PIER] == 0.0 else (turned[2], turned[3])
    base, top = model.B + s * row[OFFSET], model.B - s * row[OFFSET]
    # chords 2ℓ·|sin(x/2)|, with |…| = s·(…) while the interface opens in mode s
    length = 2.0 * s * (row[BASE] * base * base_turn[0] + row[TOP] * top * top_turn[0])
    rate = s * (
        row[BASE] * base * base_turn[1] * base_turn[2] + row[TOP] * top * top_turn[1] * top_turn[2]
    )
    return length, rate


@jit
def elongation(model: Model, row: np.ndarray, s: float, theta1: float):
    """`stretch` of one device, with the exact linkage solved for it [m, m/rad]."""
    return stretch(model, row, s, turns(model, s, theta1, EXACT))


@jit
def pull(row: np.ndarray, length: float, speed: float) -> float:
    """The force of one device (a row of `table`, in its state) at elongation Δ [m] and its rate
    Δ̇ [m/s], positive in tension [N]: the damper's c·Δ̇, else the yielding devices' law on their
    branch (`elastic_pull` on the elastic one, the yield line on a plastic one, 0 when broken)."""
    if row[KIND] == DAMPER:
        return row[DAMPING] * speed
    branch = row[BRANCH]
    if branch == ELASTIC:
        return elastic_pull(row, length)
    if branch == BROKEN:
        return 0.0
    return yield_line(row, length, branch)


@jit
def elastic_pull(row: np.ndarray, length: float) -> float:
    """The force of a tendon or dissipator on its elastic branch at elongation Δ [m] [N]: the
    tendon's max(0, P0 + k·(Δ − Δp)) (slack below zero), the dissipator's k1·(Δ − Δp)."""
    if row[KIND] == TENDON:
        return max(0.0, row[PRESTRESS] + row[STIFFNESS] * (length - row[PLASTIC]))
    return row[STIFFNESS] * (length - row[PLASTIC])


@jit
def yield_line(row: np.ndarray, length: float, side: float) -> float:
    """The yield line of a tendon or dissipator on the ``side`` `LOADING` (+1, tension) or
    `UNLOADING` (−1) at elongation Δ [m] [N]: the tendon's F_y (it has no lower line: it goes
    slack instead, −inf), the dissipator's k2·Δ ± (1 − k2/k1)·F_y."""
    if row[KIND] == TENDON:
        return row[YIELD] if side == LOADING else -np.inf
    k1, k2 = row[STIFFNESS], row[HARDENING]
    return k2 * length + side * (1.0 - k2 / k1) * row[YIELD]


def restrained(force: float, devices, model: Model, s: float, theta1: float, omega: float, kin):
    """The generalised force on θ1 [N·m] with that of the ``devices`` (a `table`, or None) added:
    ``force`` less Σ (T + F)·∂Δ/∂φ at (θ1, θ̇1) = (theta1, omega) [rad, rad/s] in mode s, the
    linkage as ``kin`` computes it (`turns`)."""
    if devices is None:
        return force
    return force - _device_moment(devices, model, s, theta1, omega, kin)


@overload(restrained)
def _compiled_restrained(force, devices, model, s, theta1, omega, kin):
    """`restrained` compiled for the type of ``devices``: without any, ``force`` itself."""
    if absent(devices):
        return lambda force, devices, model, s, theta1, omega, kin: force
    return lambda force, devices, model, s, theta1, omega, kin: (
        force - _device_moment(devices, model, s, theta1, omega, kin)
    )


@jit
def _device_moment(devices: np.ndarray, model: Model, s, theta1, omega, kin: Kinematics):
    """Σ (T + F)·∂Δ/∂φ of the devices [N·m]."""
    moment, turned = 0.0, turns(model, s, theta1, kin)
    for i in range(devices.shape[0]):
        length, lever = stretch(model, devices[i], s, turned)
        moment += pull(devices[i], length, lever * omega) * lever
    return moment


@jit
def strain_energy(devices: np.ndarray, model: Model, s: float, theta1: float) -> float:
    """Elastic energy the devices store in their state, above that of the prestress at rest [J]:
    Σ (T² − P0²)/(2k) of the tendons (P0·Δ + ½k·Δ² while elastic with Δp = 0; a slack or
    ruptured tendon's is −P0²/(2k)) and Σ F²/(2k1) of the dissipators (0 when fractured);
    dampers store none. What the yielding devices' work ∫F·dΔ leaves beyond its change is their
    plastic work (and the energy released at a rupture)."""
    energy, turned = 0.0, turns(model, s, theta1, EXACT)
    for i in range(devices.shape[0]):
        row = devices[i]
        if row[KIND] != DAMPER:
            force = pull(row, stretch(model, row, s, turned)[0], 0.0)
            energy += 0.5 * (force * force - row[PRESTRESS] ** 2) / row[STIFFNESS]
    return energy


def prestress_moment(model: Model, devices: np.ndarray, s: float) -> float:
    """Σ P0·∂Δ/∂φ of the tendons at rest in mode s: what their prestress adds to gravity's
    resistance to the onset of rocking (`impacts.onset_threshold`) [N·m]. For a tendon through a
    pier of a bridge, ∂Δ/∂φ ≈ ℓ_base + ℓ_top = 2B, wherever its duct lies."""
    return float(
        sum(
            row[PRESTRESS] * elongation(model, row, s, 0.0)[1]
            for row in devices
            if row[KIND] == TENDON
        )
    )


@jit
def settled(devices: np.ndarray) -> bool:
    """Whether every device is as it was built: none has a plastic elongation or is broken, so
    that its force at rest is its prestress (`prestress_moment` holds) [-]."""
    for i in range(devices.shape[0]):
        if devices[i, PLASTIC] != 0.0 or devices[i, BRANCH] == BROKEN:
            return False
    return True


@jit
def rest_moment(devices: np.ndarray, model: Model, s: float) -> float:
    """Σ F·∂Δ/∂φ of the devices at rest (Δ = 0, Δ̇ = 0) in their current state, in mode s [N·m]:
    after a yield, a tendon's P0 − k·Δp (or 0, slack or ruptured) and a dissipator's residual
    force instead of the prestress of `prestress_moment`."""
    moment = 0.0
    for i in range(devices.shape[0]):
        moment += pull(devices[i], 0.0, 0.0) * elongation(model, devices[i], s, 0.0)[1]
    return moment


PEAK_LENGTH, PEAK_LENGTH_TIME, PEAK_FORCE, PEAK_FORCE_TIME = range(4)
"""Columns of the devices' peaks (`peaks_of`, `tracked`): the largest elongation Δ [m] and its
time [s], the largest |force| [N] and its time [s]. When a device first yielded and broke is in
its state (`devices.YIELDED_AT`, `devices.BROKEN_AT`)."""

PEAK_COLUMNS = 4


def peaks_of(devices) -> np.ndarray:
    """The devices' peaks at the start, one row each (none without devices)."""
    return np.zeros((0 if devices is None else devices.shape[0], PEAK_COLUMNS))


@overload(peaks_of)
def _compiled_peaks_of(devices):
    if absent(devices):
        return lambda devices: np.zeros((0, PEAK_COLUMNS))
    return lambda devices: np.zeros((devices.shape[0], PEAK_COLUMNS))


def tracked(devices, peaks: np.ndarray, model: Model, s: float, theta1, omega, t, kin) -> None:
    """Raise the devices' ``peaks`` to their elongations and forces in mode s at (θ1, θ̇1) =
    (theta1, omega) [rad, rad/s] and time t [s], the linkage as ``kin`` computes it; nothing
    without devices."""
    if devices is not None:
        _tracked(devices, peaks, model, s, theta1, omega, t, kin)


@overload(tracked)
def _compiled_tracked(devices, peaks, model, s, theta1, omega, t, kin):
    if absent(devices):
        return lambda devices, peaks, model, s, theta1, omega, t, kin: None
    return lambda devices, peaks, model, s, theta1, omega, t, kin: _tracked(
        devices, peaks, model, s, theta1, omega, t, kin
    )


@jit
def _tracked(devices: np.ndarray, peaks: np.ndarray, model: Model, s, theta1, omega, t, kin):
    turned = turns(model, s, theta1, kin)
    for i in range(devices.shape[0]):
        length, lever = stretch(model, devices[i], s, turned)
        force = abs(pull(devices[i], length, lever * omega))
        if length > peaks[i, PEAK_LENGTH]:
            peaks[i, PEAK_LENGTH], peaks[i, PEAK_LENGTH_TIME] = length, t
        if force > peaks[i, PEAK_FORCE]:
            peaks[i, PEAK_FORCE], peaks[i, PEAK_FORCE_TIME] = force, t
