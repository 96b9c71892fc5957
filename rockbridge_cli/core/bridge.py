"""One bridge as the core analyses it: its `Model` (tall pier first), which way it faces, and the
restitution of its rocking interfaces.

Everything that analyses or describes a bridge takes this one object, so that no call can forget
the mirror image or an overridden restitution (`analysis.analyze`, `summary.summarize`). Loading
one does not load the compiled kernels (numba, scipy): a process that only reads configs and
hands the analyses to workers starts without them.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .devices import Device, table
from .geometry import Model, pounding_ratio

if TYPE_CHECKING:
    from .solver import Laws


@dataclass(frozen=True)
class Bridge:
    """A bridge, as analyzed.

    Attributes
    ----------
    model : the core model, tall pier first (docs/model.md §1)
    mirrored : True when the user's bridge has its tall pier on the right: the core runs the mirror
        image and its results are mirrored back, so that "p" is counter-clockwise rocking in the
        user's drawing
    restitution : η of the rocking interfaces in both directions, overriding the impact law
        (for example a measured value); None uses Eqs. 21–29 [-]
    devices : the piers' tendons and dampers (`devices.Tendon`, `devices.Damper`), in the
        core's frame; none for the paper's free-standing piers
    """

    model: Model
    mirrored: bool = False
    restitution: float | None = None
    devices: tuple[Device, ...] = ()

    def __post_init__(self) -> None:
        if not isinstance(self.model, Model):
            raise TypeError(f"Bridge needs a core Model, got {type(self.model).__name__}")

    @property
    def sign(self) -> float:
        """+1, or −1 when mirrored: multiplies user-frame quantities into the core frame [-]."""
        return -1.0 if self.mirrored else 1.0

    def user_modes(self) -> tuple[float, float]:
        """The core's modes behind the user's p and n (swapped when mirrored)."""
        return (self.sign, -self.sign)

    def device_table(self) -> np.ndarray | None:
        """The devices as the compiled kernels take them (`devices.table`), None without any."""
        return table(self.devices) if self.devices else None

    def eta(self, s: float) -> float:
        """Restitution of the impact that ends the core's mode s: the override, or the law [-]."""
        from . import impacts  # the compiled kernels, loaded when first needed

        return (
            self.restitution if self.restitution is not None else impacts.restitution(self.model, s)
        )

    def laws(self) -> Laws:
        """Onset thresholds, restitution coefficients and pounding ratio, in the core's frame
        (computed once per model and restitution: 0.3 ms, a tenth of an analysis).

        Raises
        ------
        ValueError
            When η ≤ 0 in either direction: the rocking would not reverse as the paper assumes.
        """
        return _laws(self)


@functools.lru_cache(maxsize=256)
def _laws(bridge: Bridge) -> Laws:
    from . import impacts
    from .solver import Laws

    eta_p, eta_n = bridge.eta(1.0), bridge.eta(-1.0)
    if min(eta_p, eta_n) <= 0.0:
        raise ValueError(
            f"the impact law gives η = {min(eta_p, eta_n):.4g} ≤ 0 for this bridge: the "
            "rocking would not reverse smoothly (the paper's assumption); set "
            "rocking_restitution in the bridge config"
        )
    devices = bridge.device_table()
    return Laws(
        onset_p=impacts.onset_threshold(bridge.model, 1.0, devices),
        onset_n=impacts.onset_threshold(bridge.model, -1.0, devices),
        eta_p=eta_p,
        eta_n=eta_n,
        pounding=pounding_ratio(bridge.model),
    )
