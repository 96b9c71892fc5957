"""Kinematics of the rocking bridge: a four-bar linkage with one degree of freedom.

Ground A–C, tall pier A–B, deck B–D and short pier C–D (docs/model.md §1, §3). In rocking mode
s = +1 ("p", counter-clockwise) the base pivots are the piers' bottom-left corners and the deck
pivots their top-right corners; in mode s = −1 ("n") the mirror corners. The degree of freedom is
the tall pier's rotation θ1 = φ − φ1^s (Eq. 1), where φ is the angle of the pier's diagonal A→B
from +x and φ1^s = π/2 − s·α1 its value at rest. Working in θ1 rather than φ keeps full
precision near rest.

Positions follow from the loop closure 2R1·e(φ) + L2·e(θ) − 2R2·e(ψ) = C − A, with ψ (the paper's
φ_CD) the short pier's diagonal angle and θ the deck rotation (Eqs. 2–3), and their derivatives
with respect to φ from the linkage's velocity and acceleration analysis (exact). The paper's
"simplified procedure" replaces ψ', θ' by quadratic fits in θ1 (and ψ'', θ'' by the fits'
derivatives): `simplified` builds them. A third way, `tables.tabulated`, interpolates everything
the integrator needs from piecewise cubics built once per bridge. Every kernel takes the choice as
a `Kinematics`; `EXACT` selects the exact linkage.

All kernels take plain floats and return tuples of floats so that numba compiles them lean.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ._jit import inlined, jit
from .geometry import Model

COEFFICIENTS, DISPLACEMENTS = 6, 8
"""Quantities in the tables (`Kinematics.table`): the equation of motion's coefficients, then the
displacements and rotations."""

(
    SLOT_MASS, SLOT_DMASS, SLOT_GRAVITY, SLOT_INERTIA, SLOT_SPRING_U, SLOT_SPRING_DU,
) = range(COEFFICIENTS)  # fmt: skip
"""Slots of the tables that hold the equation of motion's coefficients, in the order
`dynamics.coefficients` returns them: M, M', ∂V/∂φ, Σm·∂x/∂φ, and u_deck and ∂u_deck/∂φ as the
abutment spring reads them."""

(
    SLOT_U_PIER1, SLOT_V_PIER1, SLOT_U_PIER2, SLOT_V_PIER2,
    SLOT_U_DECK, SLOT_V_DECK, SLOT_THETA2, SLOT_THETA_DECK,
) = range(COEFFICIENTS, COEFFICIENTS + DISPLACEMENTS)  # fmt: skip
"""Slots of the tables that hold the fields of `Displacements`, in their order."""

SLOTS = COEFFICIENTS + DISPLACEMENTS
"""Slots of the tables."""


class Kinematics(NamedTuple):
    """How the kernels compute the linkage.

    Attributes
    ----------
    fits : the paper's simplified fits (`simplified`), shape (2, 2, 3), or empty
    table : piecewise cubics per mode (p, n) over s·θ1, shape (2, intervals, `SLOTS`, 4): for each
        interval and quantity (slot `SLOT_MASS` … `SLOT_THETA_DECK`) the coefficients of
        (x − x_i)³, (x − x_i)², (x − x_i), 1; or empty
    step : width of the table's intervals [rad]
    start, limit : the table covers start ≤ s·θ1 < limit (start ≤ 0: a little below rest, where
        the trial steps that overshoot an impact land) [rad]; outside it the kernels compute
        exactly
    """

    fits: np.ndarray
    table: np.ndarray
    step: float
    start: float
    limit: float


EXACT = Kinematics(np.zeros((0, 2, 3)), np.zeros((0, 0, SLOTS, 4)), 1.0, 0.0, 0.0)
"""The exact kinematics (loop closure, velocity and acceleration analysis)."""


@jit
def rest_angle(model: Model, s: float) -> float:
    """Angle φ1^s of the tall pier's diagonal at rest in mode s, π/2 − s·α1 [rad]."""
    return 0.5 * np.pi - s * np.arctan2(model.B, model.H1)


@jit
def linkage(model: Model, s: float, theta1: float, kin: Kinematics):
    """Angles of the linkage and their derivatives with respect to φ.

    Parameters
    ----------
    model
        The bridge.
    s
        Rocking mode, +1 (p) or −1 (n) [-].
    theta1
        Rotation of the tall pier from rest, s·θ1 ≥ 0 while rocking [rad].
    kin
        `EXACT`, or `simplified` (its fits replace the derivatives; tables play no part here).

    Returns
    -------
    phi, psi, theta : diagonal angles of the piers and deck rotation [rad]
    dpsi, dtheta : ψ' and θ' [-]
    d2psi, d2theta : ψ'' and θ'' [1/rad]
    """
    R1 = np.hypot(model.H1, model.B)
    R2 = np.hypot(model.H2, model.B)
    L2 = model.L2
    phi = rest_angle(model, s) + theta1
    # Deck pivot B on the tall pier, and base pivot C of the short pier (Fig. 2).
    bx = -s * model.B + 2.0 * R1 * np.cos(phi)
    bz = 2.0 * R1 * np.sin(phi)
    cx = L2 - s * model.B
    cz = 2.0 * (model.H1 - model.H2)
    # D lies at 2R2 from C and L2 from B: intersect the two circles on the branch of the rest state.
    wx = bx - cx
    wz = bz - cz
    w = np.hypot(wx, wz)
    psi = np.arctan2(wz, wx) - np.arccos((w * w + 4.0 * R2 * R2 - L2 * L2) / (4.0 * R2 * w))
    theta = np.arctan2(cz + 2.0 * R2 * np.sin(psi) - bz, cx + 2.0 * R2 * np.cos(psi) - bx)
    if kin.fits.shape[0] == 0:
        dtheta = -2.0 * R1 * np.sin(psi - phi) / (L2 * np.sin(psi - theta))
        dpsi = R1 * np.sin(theta - phi) / (R2 * np.sin(theta - psi))
        # r = 2R1·e(φ) + L2·θ'²·e(θ) − 2R2·ψ'²·e(ψ)
        rx = (
            2.0 * R1 * np.cos(phi)
            + L2 * dtheta**2 * np.cos(theta)
            - 2.0 * R2 * dpsi**2 * np.cos(psi)
        )
        rz = (
            2.0 * R1 * np.sin(phi)
            + L2 * dtheta**2 * np.sin(theta)
            - 2.0 * R2 * dpsi**2 * np.sin(psi)
        )
        d2theta = (rx * np.cos(psi) + rz * np.sin(psi)) / (L2 * np.sin(psi - theta))
        d2psi = -(rx * np.cos(theta) + rz * np.sin(theta)) / (2.0 * R2 * np.sin(theta - psi))
    else:
        f = kin.fits[0 if s > 0 else 1]
        dpsi = f[0, 0] + theta1 * (f[0, 1] + theta1 * f[0, 2])
        dtheta = f[1, 0] + theta1 * (f[1, 1] + theta1 * f[1, 2])
        d2psi = f[0, 1] + 2.0 * theta1 * f[0, 2]
        d2theta = f[1, 1] + 2.0 * theta1 * f[1, 2]
    return phi, psi, theta, dpsi, dtheta, d2psi, d2theta


@jit
def deck_arm(model: Model, s: float):
    """Length r_BD^s and angle ψ_BD^s of the segment from the deck pivot B to the deck's CG.

    Returns
    -------
    r : √(h² + (L2/2 − s·B)²) [m]
    angle : atan(h/(L2/2 − s·B)) [rad]
    """
    dx = 0.5 * model.L2 - s * model.B
    return np.hypot(model.h, dx), np.arctan2(model.h, dx)


@jit
def centres(model: Model, s: float, theta1: float, kin: Kinematics):
    """Positions of the three centres of gravity and their first and second φ-derivatives.

    Pier 1 at A + R1·e(φ), pier 2 at C + R2·e(ψ), deck at A + 2R1·e(φ) + r_BD·e(θ + ψ_BD)
    (Eqs. 4–6). Parameters as in `linkage`.

    Returns
    -------
    pos : (x1, z1, x2, z2, xd, zd) [m]
    d1 : their first derivatives with respect to φ [m]
    d2 : their second derivatives [m]
    ang : (dpsi, dtheta, d2psi, d2theta, psi, theta) as returned by `linkage`
    """
    phi, psi, theta, dpsi, dtheta, d2psi, d2theta = linkage(model, s, theta1, kin)
    R1 = np.hypot(model.H1, model.B)
    R2 = np.hypot(model.H2, model.B)
    r, arm = deck_arm(model, s)
    ax = -s * model.B
    cx = model.L2 - s * model.B
    cz = 2.0 * (model.H1 - model.H2)
    c1, s1 = np.cos(phi), np.sin(phi)
    c2, s2 = np.cos(psi), np.sin(psi)
    cd, sd = np.cos(theta + arm), np.sin(theta + arm)
    pos = (
        ax + R1 * c1, R1 * s1,
        cx + R2 * c2, cz + R2 * s2,
        ax + 2.0 * R1 * c1 + r * cd, 2.0 * R1 * s1 + r * sd,
    )  # fmt: skip
    d1 = (
        -R1 * s1, R1 * c1,
        -R2 * dpsi * s2, R2 * dpsi * c2,
        -2.0 * R1 * s1 - r * dtheta * sd, 2.0 * R1 * c1 + r * dtheta * cd,
    )  # fmt: skip
    d2 = (
        -R1 * c1, -R1 * s1,
        -R2 * (d2psi * s2 + dpsi**2 * c2), R2 * (d2psi * c2 - dpsi**2 * s2),
        -2.0 * R1 * c1 - r * (d2theta * sd + dtheta**2 * cd),
        -2.0 * R1 * s1 + r * (d2theta * cd - dtheta**2 * sd),
    )  # fmt: skip
    return pos, d1, d2, (dpsi, dtheta, d2psi, d2theta, psi, theta)


class Displacements(NamedTuple):
    """Where a bridge is, relative to rest, at one rotation of its tall pier.

    Attributes
    ----------
    u_pier1, v_pier1 : horizontal and vertical displacement of the tall pier's centre of gravity [m]
    u_pier2, v_pier2 : the same for the short pier [m]
    u_deck, v_deck : the same for the deck [m]
    theta2, theta_deck : rotations of the short pier and of the deck from rest [rad]
    """

    u_pier1: float
    v_pier1: float
    u_pier2: float
    v_pier2: float
    u_deck: float
    v_deck: float
    theta2: float
    theta_deck: float


@inlined
def displacements(model: Model, s: float, theta1: float, kin: Kinematics):
    """Displacements of the centres of gravity from rest, and the rotations (Eqs. 1, 4–6).

    Parameters as in `linkage`; from the tables where ``kin`` has them and θ1 lies inside.

    Returns
    -------
    `Displacements`
    """
    piece, dx, mode = table_piece(kin, s, theta1)
    if piece >= 0:
        t = kin.table
        return Displacements(
            cubic(t, mode, piece, SLOT_U_PIER1, dx), cubic(t, mode, piece, SLOT_V_PIER1, dx),
            cubic(t, mode, piece, SLOT_U_PIER2, dx), cubic(t, mode, piece, SLOT_V_PIER2, dx),
            cubic(t, mode, piece, SLOT_U_DECK, dx), cubic(t, mode, piece, SLOT_V_DECK, dx),
            cubic(t, mode, piece, SLOT_THETA2, dx), cubic(t, mode, piece, SLOT_THETA_DECK, dx),
        )  # fmt: skip
    return _linkage_displacements(model, s, theta1, kin)


@jit
def _linkage_displacements(model: Model, s: float, theta1: float, kin: Kinematics):
    """`displacements` from the linkage itself (exact, or with the paper's fits)."""
    pos, _, _, ang = centres(model, s, theta1, kin)
    psi_rest = 0.5 * np.pi - s * np.arctan2(model.B, model.H2)
    return Displacements(
        pos[0], pos[1] - model.H1,
        pos[2] - model.L2, pos[3] - (2.0 * model.H1 - model.H2),
        pos[4] - 0.5 * model.L2, pos[5] - (2.0 * model.H1 + model.h),
        ang[4] - psi_rest, ang[5],
    )  # fmt: skip


@inlined
def table_piece(kin: Kinematics, s: float, theta1: float):
    """Where θ1 falls in the tables of mode s: (interval, offset into it [rad], mode index), or
    interval −1 where there are no tables or θ1 lies outside them."""
    x = s * theta1
    if kin.table.shape[0] == 0 or not kin.start <= x < kin.limit:
        return -1, 0.0, 0
    offset = x - kin.start
    piece = min(int(offset / kin.step), kin.table.shape[1] - 1)
    return piece, offset - piece * kin.step, 0 if s > 0 else 1


@inlined
def cubic(table: np.ndarray, mode: int, piece: int, slot: int, dx: float) -> float:
    """The piecewise cubic of the quantity in ``slot`` (`SLOT_MASS` …), ``dx`` into interval
    ``piece`` of ``mode`` (indexed in place: a view of the table would cost more than the cubic)."""
    return (
        (table[mode, piece, slot, 0] * dx + table[mode, piece, slot, 1]) * dx
        + table[mode, piece, slot, 2]
    ) * dx + table[mode, piece, slot, 3]


@inlined
def slope(table: np.ndarray, mode: int, piece: int, slot: int, dx: float) -> float:
    """The derivative of `cubic` with respect to s·θ1 [unit of the slot per rad]."""
    return (
        3.0 * table[mode, piece, slot, 0] * dx + 2.0 * table[mode, piece, slot, 1]
    ) * dx + table[mode, piece, slot, 2]


def simplified(model: Model) -> Kinematics:
    """The paper's simplified kinematics for a bridge (`simplified_fits`)."""
    return EXACT._replace(fits=simplified_fits(model))


def simplified_fits(model: Model, samples: int = 41) -> np.ndarray:
    """The paper's simplified kinematics: least-squares quadratics for ψ'(θ1) and θ'(θ1).

    Thomaidis et al. (2022) replace the exact derivatives of Eqs. (2)–(3) by linear and parabolic
    fits over φ (details in Thomaidis 2020, not published). Here each mode's ψ' and θ' are fitted
    by a quadratic in θ1 over the range from rest to the tall pier's overturning rotation α1, on
    Chebyshev nodes; ψ'' and θ'' are the fits' derivatives.

    Returns
    -------
    Array of shape (2, 2, 3): [mode p/n][ψ', θ'][coefficients of 1, θ1, θ1²].
    """
    alpha1 = model.alpha1
    nodes = 0.5 * alpha1 * (1.0 - np.cos(np.pi * (np.arange(samples) + 0.5) / samples))
    fits = np.empty((2, 2, 3))
    for index, s in enumerate((1.0, -1.0)):
        theta1 = s * nodes
        values = np.array([linkage(model, s, t, EXACT)[3:5] for t in theta1])
        valid = np.all(np.isfinite(values), axis=1)
        basis = np.vander(theta1[valid], 3, increasing=True)
        for quantity in range(2):
            fits[index, quantity] = np.linalg.lstsq(basis, values[valid, quantity], rcond=None)[0]
    return fits
