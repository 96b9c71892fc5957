"""Devices that restrain a rocking pier: unbonded post-tensioned tendons, linear viscous dampers
and hysteretic (bilinear) dissipators across its rocking interfaces (docs/model.md §13).

A device joins two points that coincide at rest, one on each side of a rocking interface, at a
distance ℓ from the pivot of the current mode. When the interface turns by x about that pivot,
the two points part by the chord 2ℓ·|sin(x/2)| (exact for a device that stays straight across the
opened interface), and

* a **tendon** runs from the foundation through a duct in the pier to the deck, so it crosses both
  interfaces of a pier of a bridge (the base turns by θ_i, the top by θ_i − θ_deck) and the base
  of a single block; it pulls with T = max(0, P0 + k·(Δ − Δp)) (prestress P0, axial stiffness
  k = E·A/L_free, plastic elongation Δp), T = F_y while it yields, and 0 once it has ruptured;
* a **damper** crosses one interface (or both) and pulls with F = c·Δ̇;
* a **dissipator** crosses one interface (or both) and pulls with a bilinear law of kinematic
  hardening: F = k1·(Δ − Δp) between the lines k2·Δ ± (1 − k2/k1)·F_y, on them while it yields,
  and 0 once it has fractured.

The yielding devices' state (branch, Δp) changes only at events, which the integrator locates
(`device_mechanics.watch`) and applies (`device_mechanics.settle`); it is held in the table's last
columns, which the integrator changes in its own copy.

At the base the pivot of mode s is the corner at −s·B, at the top the corner at +s·B (the core's
frame, docs/model.md §1), so a device at offset d from the pier's axis has ℓ = B + s·d at the base
and B − s·d at the top. Its generalised force on θ1 is −(T + F)·∂Δ/∂φ, through the linkage
(∂θ2/∂φ = ψ', ∂θ_deck/∂φ = θ'). The devices are massless and their forces finite, so they add no
impulse at an impact: the impact laws (Eqs. 21–30) stay those of the free-standing bridge.

This module holds what a device is, in plain floats (a bridge that carries devices loads no
compiled code); their mechanics, compiled, are `device_mechanics`'s. A bridge without devices runs
kernels compiled without them, so its results and speed are those of the free-standing model, bit
for bit.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

TENDON, DAMPER, DISSIPATOR = 0, 1, 2
"""Kinds of device, as the compiled table (`table`) codes them."""

KIND, PIER, OFFSET, BASE, TOP, PRESTRESS, STIFFNESS, DAMPING, YIELD, HARDENING, LIMIT = range(11)
"""Columns of the compiled table that describe a device: kind, pier (0 tall, 1 short), offset d
[m], whether it crosses the base and the top interface (1.0 or 0.0), prestress P0 [N], (initial)
stiffness k or k1 [N/m], dashpot c [N·s/m], yield force F_y [N] (inf: none), post-yield stiffness
k2 [N/m] (0 for a tendon), elongation Δ at which it ruptures or fractures [m] (inf: none)."""

BRANCH, PLASTIC, YIELDED_AT, BROKEN_AT = range(11, 15)
"""Columns of the compiled table that hold a device's state, which the integrator changes at the
events (`device_mechanics.settle`): its branch (`ELASTIC`, `LOADING` on the upper yield line,
`UNLOADING` on the lower one, `BROKEN`), its plastic elongation Δp on the elastic branch [m], and
the times it first yielded and broke (NaN: not yet) [s]."""

ELASTIC, LOADING, UNLOADING, BROKEN = 0.0, 1.0, -1.0, 2.0
"""Branches of a device's law (column `BRANCH`)."""

COLUMNS = 15


class Tendon(NamedTuple):
    """An unbonded post-tensioned tendon through a pier, in the core's frame.

    Attributes
    ----------
    pier : 0 for the tall pier, 1 for the short one [-]
    offset : distance of its duct from the pier's axis, positive to the right, |d| < B [m]
    prestress : initial force P0 [N]
    stiffness : axial stiffness E·A/L_free [N/m]
    top : whether it crosses the pier–deck interface too (a bridge's pier; not a single block)
    yield_force : force at which its steel yields, inf if not stated [N]
    rupture_strain : strain at which it ruptures, inf if not stated [-]
    rigidity : axial rigidity E·A, inf if not stated (no strain reported) [N]

    Past its yield force the tendon yields at a constant force F_y while it stretches (elastic–
    perfectly plastic steel) and unloads elastically, having lost prestress k·Δp; at its rupture
    strain its force drops to zero for good (the limit states ``tendon_yield``,
    ``tendon_rupture``). Its elongation at rupture is (ε_u·E·A − P0)/k (`rupture_elongation`).
    """

    pier: int
    offset: float
    prestress: float
    stiffness: float
    top: bool = True
    yield_force: float = math.inf
    rupture_strain: float = math.inf
    rigidity: float = math.inf

    def strain(self, force: float) -> float:
        """The steel's strain at tension ``force`` [N]: T/(E·A), which is ε0 + Δ/L_free for the
        elastic tendon (T = P0 + k·Δ, P0 = E·A·ε0, k = E·A/L_free) [-]; 0 without a rigidity."""
        return force / self.rigidity

    def rupture_elongation(self) -> float:
        """Elongation Δ at which the tendon ruptures: its strain ε0 + Δ/L_free reaches ε_u, with
        ε0 = P0/(E·A) and L_free = E·A/k, so Δ_u = (ε_u·E·A − P0)/k; inf without a limit [m]."""
        if math.isinf(self.rupture_strain) or math.isinf(self.rigidity):
            return math.inf
        return (self.rupture_strain * self.rigidity - self.prestress) / self.stiffness


class Damper(NamedTuple):
    """A linear viscous damper across a pier's rocking interface(s), in the core's frame.

    Attributes
    ----------
    pier, offset : as in `Tendon` [-, m]
    coefficient : dashpot c [N·s/m]
    base, top : which interfaces it crosses
    """

    pier: int
    offset: float
    coefficient: float
    base: bool = True
    top: bool = False


class Dissipator(NamedTuple):
    """A hysteretic dissipator (a yielding steel bar or fuse) across a pier's rocking
    interface(s), in the core's frame, with a bilinear law of kinematic hardening.

    Attributes
    ----------
    pier, offset : as in `Tendon` [-, m]
    stiffness : elastic stiffness k1 [N/m]
    yield_force : yield force F_y [N]
    hardening : post-yield stiffness k2, 0 ≤ k2 < k1 [N/m]
    fracture : elongation Δ at which it fractures (its force drops to zero for good), inf if
        not stated [m]
    length : its gauge length L_d, which turns Δ into a strain Δ/L_d [m]
    base, top : which interfaces it crosses
    """

    pier: int
    offset: float
    stiffness: float
    yield_force: float
    hardening: float = 0.0
    fracture: float = math.inf
    length: float = math.inf
    base: bool = True
    top: bool = False


Device = Tendon | Damper | Dissipator


def table(devices: tuple[Device, ...]) -> np.ndarray:
    """The devices as the compiled kernels take them: one row each, columns `KIND` … `LIMIT`,
    and their state at rest (`BRANCH` … `BROKEN_AT`: elastic, Δp = 0, not yielded nor broken)."""
    rows = np.zeros((len(devices), COLUMNS))
    rows[:, YIELD] = rows[:, LIMIT] = math.inf
    rows[:, YIELDED_AT] = rows[:, BROKEN_AT] = math.nan
    for row, device in zip(rows, devices, strict=True):
        row[PIER], row[OFFSET] = device.pier, device.offset
        if isinstance(device, Tendon):
            row[KIND], row[BASE], row[TOP] = TENDON, 1.0, float(device.top)
            row[PRESTRESS], row[STIFFNESS] = device.prestress, device.stiffness
            row[YIELD], row[LIMIT] = device.yield_force, device.rupture_elongation()
        elif isinstance(device, Dissipator):
            row[KIND], row[BASE], row[TOP] = DISSIPATOR, float(device.base), float(device.top)
            row[STIFFNESS], row[YIELD] = device.stiffness, device.yield_force
            row[HARDENING], row[LIMIT] = device.hardening, device.fracture
        else:
            row[KIND], row[BASE], row[TOP] = DAMPER, float(device.base), float(device.top)
            row[DAMPING] = device.coefficient
    return rows


def names(devices: tuple[Device, ...]) -> list[str]:
    """Each device's name: ``tendon1``, ``damper1``, ``dissipator1``, … numbered by kind in the
    given order (the bridge config's)."""
    found, counts = [], {Tendon: 0, Damper: 0, Dissipator: 0}
    for device in devices:
        counts[type(device)] += 1
        found.append(f"{type(device).__name__.lower()}{counts[type(device)]}")
    return found


def mirrored(devices: tuple[Device, ...]) -> tuple[Device, ...]:
    """The devices of the mirror image: offsets change sign (`bridge.Bridge.mirrored`)."""
    return tuple(device._replace(offset=-device.offset) for device in devices)
