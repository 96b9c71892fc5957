"""Equation of motion of the rocking bridge in Lagrangian form (docs/model.md §4).

    M(φ)·φ̈ + ½·M'(φ)·φ̇² + ∂V/∂φ = Q

with the generalised mass M = Σ m_i·|∂p_i/∂φ|² + I1 + I2·ψ'² + I_deck·θ'², the potential
V = g·Σ m_i·z_i (+ ½k(|u_deck| − u_jo)² while the deck presses on an abutment) and the generalised
force Q = −ü_g·Σ m_i·∂x_i/∂φ (− c·(∂u_deck/∂φ)²·φ̇ while in contact). This is the paper's
Eq. (18) without its two misprints (docs/model.md §4); φ̇ = θ̇1 and φ̈ = θ̈1. A vertical ground
acceleration ü_v (positive up) adds the inertia force −m_i·ü_v to every body, so that g becomes
g + ü_v in the gravity term (docs/model.md §12): the term is multiplied by its ``lift``
(g + ü_v)/g, exactly 1 without one.
"""

from __future__ import annotations

import numpy as np

from ._jit import inlined, jit
from .device_mechanics import restrained
from .geometry import Model
from .kinematics import (
    SLOT_DMASS,
    SLOT_GRAVITY,
    SLOT_INERTIA,
    SLOT_MASS,
    SLOT_SPRING_DU,
    SLOT_SPRING_U,
    Kinematics,
    centres,
    cubic,
    table_piece,
)


@inlined
def coefficients(model: Model, s: float, theta1: float, kin: Kinematics):
    """Configuration-dependent coefficients of the equation of motion in mode s.

    Parameters
    ----------
    model
        The bridge.
    s
        Rocking mode, +1 or −1 [-].
    theta1
        Rotation of the tall pier [rad].
    kin
        How to compute the linkage (`kinematics.Kinematics`): from its tables where it has them
        and θ1 lies inside, else exactly (or with the paper's fits).

    Returns
    -------
    mass : generalised mass M [kg·m²]
    dmass : M' = dM/dφ [kg·m²/rad]
    gravity : ∂V_gravity/∂φ = g·Σ m_i·∂z_i/∂φ [N·m]
    inertia : Σ m_i·∂x_i/∂φ, the lever of the ground's inertia force [kg·m]
    u_deck : horizontal displacement of the deck's centre of gravity [m]
    du_deck : ∂u_deck/∂φ [m]
    """
    piece, dx, mode = table_piece(kin, s, theta1)
    if piece >= 0:
        t = kin.table
        return (
            cubic(t, mode, piece, SLOT_MASS, dx), cubic(t, mode, piece, SLOT_DMASS, dx),
            cubic(t, mode, piece, SLOT_GRAVITY, dx), cubic(t, mode, piece, SLOT_INERTIA, dx),
            cubic(t, mode, piece, SLOT_SPRING_U, dx), cubic(t, mode, piece, SLOT_SPRING_DU, dx),
        )  # fmt: skip
    return _linkage_coefficients(model, s, theta1, kin)


@jit
def _linkage_coefficients(model: Model, s: float, theta1: float, kin: Kinematics):
    """`coefficients` from the linkage itself (exact, or with the paper's fits): compiled once,
    not into every caller of `coefficients`."""
    pos, d1, d2, ang = centres(model, s, theta1, kin)
    dpsi, dtheta, d2psi, d2theta = ang[0], ang[1], ang[2], ang[3]
    m1, m2, md = model.m1, model.m2, model.md
    mass = (
        m1 * (d1[0] ** 2 + d1[1] ** 2)
        + m2 * (d1[2] ** 2 + d1[3] ** 2)
        + md * (d1[4] ** 2 + d1[5] ** 2)
        + model.I1
        + model.I2 * dpsi**2
        + model.Id * dtheta**2
    )
    dmass = 2.0 * (
        m1 * (d1[0] * d2[0] + d1[1] * d2[1])
        + m2 * (d1[2] * d2[2] + d1[3] * d2[3])
        + md * (d1[4] * d2[4] + d1[5] * d2[5])
        + model.I2 * dpsi * d2psi
        + model.Id * dtheta * d2theta
    )
    gravity = model.g * (m1 * d1[1] + m2 * d1[3] + md * d1[5])
    inertia = m1 * d1[0] + m2 * d1[2] + md * d1[4]
    return mass, dmass, gravity, inertia, pos[4] - 0.5 * model.L2, d1[4]


@inlined
def acceleration(
    model: Model,
    s: float,
    theta1: float,
    omega: float,
    ground: float,
    contact: bool,
    kin: Kinematics,
    lift: float = 1.0,
    devices: np.ndarray | None = None,
) -> float:
    """Angular acceleration θ̈1 of the tall pier.

    Parameters
    ----------
    model, s, theta1, kin
        As in `coefficients`.
    omega
        Angular velocity θ̇1 [rad/s].
    ground
        Ground acceleration ü_g, positive to the right [m/s²].
    contact
        Whether the deck presses on an abutment (|u_deck| ≥ u_jo); switches the spring–dashpot on.
    lift
        (g + ü_v)/g, the factor on gravity of a vertical ground acceleration ü_v, positive up;
        1 without one [-].
    devices
        The bridge's tendons and dampers (`devices.table`), or None without any: the kernels
        are then compiled without them.

    Returns
    -------
    θ̈1 [rad/s²]
    """
    mass, dmass, gravity, inertia, u, du = coefficients(model, s, theta1, kin)
    force = -ground * inertia - gravity * lift - 0.5 * dmass * omega * omega
    if contact:
        overlap = abs(u) - model.u_jo
        force -= model.k * overlap * np.sign(u) * du + model.c * du * du * omega
    return restrained(force, devices, model, s, theta1, omega, kin) / mass


@jit
def energy(model: Model, s: float, theta1: float, omega: float, contact: bool, kin: Kinematics):
    """Mechanical energy above rest: ½·M·θ̇1² + ΔV_gravity (+ the spring's) [J]."""
    mass = coefficients(model, s, theta1, kin)[0]
    pos = centres(model, s, theta1, kin)[0]
    potential = model.g * (
        model.m1 * (pos[1] - model.H1)
        + model.m2 * (pos[3] - 2.0 * model.H1 + model.H2)
        + model.md * (pos[5] - 2.0 * model.H1 - model.h)
    )
    if contact:
        overlap = abs(pos[4] - 0.5 * model.L2) - model.u_jo
        potential += 0.5 * model.k * overlap * overlap
    return 0.5 * mass * omega * omega + potential
