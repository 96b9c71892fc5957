"""Constants of one bridge: dimensions, masses, inertias and the derived ratios of the paper.

The bridge is the four-bar linkage of Thomaidis, Camara & Kappos (2022), Fig. 1: a tall pier
(2B × 2H1) at x = 0, a short pier (2B × 2H2) at x = L2 standing on ground raised to 2H1 − 2H2, and a
deck of depth 2h on both. All values are SI (m, kg, s, rad, N).

`Model` is a plain named tuple of floats so that the compiled kernels can read it directly.
The two reductions the paper builds on are the same tuple with some terms switched off:

* a **frame** (Dimitrakopoulos & Giouvanidis 2015; Makris & Vassiliou 2013) has no abutments:
  ``has_abutments = 0``;
* a **single block** (Housner 1963) is pier 1 alone: the twin pier and the deck are massless, so
  every term they contribute to the equation of motion and to the impact vanishes.
"""

from __future__ import annotations

import math
from typing import NamedTuple


class Model(NamedTuple):
    """Everything the numerical core needs to know about one bridge, in SI units.

    Attributes
    ----------
    B : half width of both piers [m]
    H1, H2 : half heights of the tall and the short pier, H1 ≥ H2 [m]
    L1, L2 : side and central span [m]
    h : half depth of the deck [m]
    m1, m2, md : masses of the tall pier, the short pier and the deck [kg]
    I1, I2, Id : their moments of inertia about their own centres of gravity [kg·m²]
    g : acceleration of gravity [m/s²]
    has_abutments : 1.0 when the deck meets abutments at its ends, else 0.0 [-]
    u_jo : end-joint gap [m]
    k : abutment–backfill stiffness [N/m]
    c : abutment–backfill dashpot [N·s/m]
    u_ab : ultimate abutment–backfill displacement beyond the gap [m]
    e : coefficient of restitution of the deck–backwall pounding [-]
    m_abut : backfill mass that takes part in the pounding (Eq. 19) [kg]
    """

    B: float
    H1: float
    H2: float
    L1: float
    L2: float
    h: float
    m1: float
    m2: float
    md: float
    I1: float
    I2: float
    Id: float
    g: float
    has_abutments: float
    u_jo: float
    k: float
    c: float
    u_ab: float
    e: float
    m_abut: float

    @property
    def R1(self) -> float:
        """Semi-diagonal of the tall pier [m]."""
        return math.hypot(self.H1, self.B)

    @property
    def R2(self) -> float:
        """Semi-diagonal of the short pier [m]."""
        return math.hypot(self.H2, self.B)

    @property
    def alpha1(self) -> float:
        """Slenderness angle of the tall pier, atan(B/H1) [rad]."""
        return math.atan2(self.B, self.H1)

    @property
    def alpha2(self) -> float:
        """Slenderness angle of the short pier, atan(B/H2) [rad]."""
        return math.atan2(self.B, self.H2)


def pier_mass(density: float, B: float, H: float) -> float:
    """Mass of a square pier 2B × 2B × 2H, m = 8ρB²H [kg]."""
    return 8.0 * density * B * B * H


def pier_inertia(mass: float, B: float, H: float) -> float:
    """Moment of inertia of a rectangular pier about its centre of gravity, m·R²/3 [kg·m²]."""
    return mass * (H * H + B * B) / 3.0


def deck_inertia(mass: float, length: float, depth: float) -> float:
    """Moment of inertia of a slender rectangular deck about its centre, m·(L² + d²)/12 [kg·m²].

    docs/model.md §2: the paper gives no I_CG for the studied bridges; Fig. 7's 360·10⁷ kg·m²
    agrees with m·L²/12, and the depth term adds less than 0.02 %.
    """
    return mass * (length * length + depth * depth) / 12.0


def backfill_mass(soil_density: float, length: float, width: float, height: float) -> float:
    """Backfill mass resisting the deck's pounding, m_abut = ρ_s·L_cr·B_abut·h_bw (Eq. 19) [kg]."""
    return soil_density * length * width * height


def single_block(B: float, H: float, density: float, g: float) -> Model:
    """Housner's block 2B × 2H, as a frame whose twin pier and deck are massless.

    The twin pier is pier 1's mirror image one width away, so its geometry stays regular; with zero
    mass it adds nothing to the equation of motion or to the impact.
    """
    m = pier_mass(density, B, H)
    return Model(
        B=B, H1=H, H2=H, L1=0.0, L2=4.0 * B, h=0.0,
        m1=m, m2=0.0, md=0.0, I1=pier_inertia(m, B, H), I2=0.0, Id=0.0, g=g,
        has_abutments=0.0, u_jo=math.inf, k=0.0, c=0.0, u_ab=math.inf, e=1.0, m_abut=0.0,
    )  # fmt: skip


def kind(model: Model) -> str:
    """Name of the model a bridge reduces to.

    Returns
    -------
    One of ``single-block``, ``symmetric-frame``, ``asymmetric-frame``, ``symmetric-bridge``,
    ``asymmetric-bridge``.
    """
    if model.md == 0.0 and model.m2 == 0.0:
        return "single-block"
    shape = "symmetric" if model.H1 == model.H2 else "asymmetric"
    return f"{shape}-{'bridge' if model.has_abutments else 'frame'}"


def ratios(model: Model) -> dict[str, float]:
    """The paper's dimensionless ratios and the abutment parameter q.

    Returns
    -------
    dict with ``h_bar`` = H1/H2, ``b_bar`` = B/L2, ``L_bar`` = L1/L2, ``gamma`` = m_deck/(m1 + m2)
    [-], and ``q`` = 4R1/(g·[m1 + m2 + 3m_deck]) [m/N] (docs/model.md §2: the parentheses the
    printed form drops).
    """
    piers = model.m1 + model.m2
    return {
        "h_bar": model.H1 / model.H2,
        "b_bar": model.B / model.L2,
        "L_bar": model.L1 / model.L2,
        "gamma": model.md / piers,
        "q": 4.0 * model.R1 / (model.g * (piers + 3.0 * model.md)),
    }


def pounding_ratio(model: Model) -> float:
    """Ratio of the rocking velocity after and before a deck–backwall pounding (Eq. 20) [-].

    φ̇_II/φ̇_I = 1 − (1 + e)·m_abut/(m_abut + m_deck). docs/model.md §7 reads Eq. 19 as the velocity
    relation it is.
    """
    if not model.has_abutments:
        return 1.0
    return 1.0 - (1.0 + model.e) * model.m_abut / (model.m_abut + model.md)


def with_short_pier(model: Model, h_bar: float) -> Model:
    """The bridge with the short pier's height set by h̄ = H1/H2, same section and material (the
    variable the paper's Figs. 3, 4 and 7 vary)."""
    H2 = model.H1 / h_bar
    density = model.m1 / pier_mass(1.0, model.B, model.H1)
    m2 = pier_mass(density, model.B, H2)
    return model._replace(H2=H2, m2=m2, I2=pier_inertia(m2, model.B, H2))
