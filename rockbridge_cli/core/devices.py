"""Devices that restrain a rocking pier: unbonded post-tensioned tendons and linear viscous
dampers across its rocking interfaces (docs/model.md §13).

A device joins two points that coincide at rest, one on each side of a rocking interface, at a
distance ℓ from the pivot of the current mode. When the interface turns by x about that pivot,
the two points part by the chord 2ℓ·|sin(x/2)| (exact for a device that stays straight across the
opened interface), and

* a **tendon** runs from the foundation through a duct in the pier to the deck, so it crosses both
  interfaces of a pier of a bridge (the base turns by θ_i, the top by θ_i − θ_deck) and the base
  of a single block; it pulls with T = P0 + k·Δ (prestress P0, axial stiffness k = E·A/L_free);
* a **damper** crosses one interface (or both) and pulls with F = c·Δ̇.

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

TENDON, DAMPER = 0, 1
"""Kinds of device, as the compiled table (`table`) codes them."""

KIND, PIER, OFFSET, BASE, TOP, PRESTRESS, STIFFNESS, DAMPING = range(8)
"""Columns of the compiled table: kind, pier (0 tall, 1 short), offset d [m], whether it crosses
the base and the top interface (1.0 or 0.0), prestress P0 [N], stiffness k [N/m], dashpot c
[N·s/m]."""

COLUMNS = 8


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

    The last three are limits the tendon is judged against (`strain`, the limit states
    ``tendon_yield`` and ``tendon_rupture``), not its behaviour: it stays elastic past them
    (post-yield behaviour is not modelled yet), and the compiled table (`table`) leaves them out.
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


Device = Tendon | Damper


def table(devices: tuple[Device, ...]) -> np.ndarray:
    """The devices as the compiled kernels take them: one row each, columns `KIND` … `DAMPING`."""
    rows = np.zeros((len(devices), COLUMNS))
    for row, device in zip(rows, devices, strict=True):
        row[PIER], row[OFFSET] = device.pier, device.offset
        if isinstance(device, Tendon):
            row[KIND], row[BASE], row[TOP] = TENDON, 1.0, float(device.top)
            row[PRESTRESS], row[STIFFNESS] = device.prestress, device.stiffness
        else:
            row[KIND], row[BASE], row[TOP] = DAMPER, float(device.base), float(device.top)
            row[DAMPING] = device.coefficient
    return rows


def names(devices: tuple[Device, ...]) -> list[str]:
    """Each device's name: ``tendon1``, ``damper1``, … numbered by kind in the given order (the
    bridge config's)."""
    found, counts = [], {Tendon: 0, Damper: 0}
    for device in devices:
        counts[type(device)] += 1
        found.append(f"{type(device).__name__.lower()}{counts[type(device)]}")
    return found


def mirrored(devices: tuple[Device, ...]) -> tuple[Device, ...]:
    """The devices of the mirror image: offsets change sign (`bridge.Bridge.mirrored`)."""
    return tuple(device._replace(offset=-device.offset) for device in devices)
