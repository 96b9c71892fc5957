"""The ``devices`` section of a bridge config: post-tensioned tendons and viscous dampers on the
piers (docs/model.md §13), validated, and built into the core's devices (`core.devices`).

Each device names its pier by its place in ``piers.heights`` (1 the first, left to right) and its
offset from the pier's axis, positive to the right, in the user's drawing; `core_devices` turns
them into the core's frame (tall pier first, mirrored where the tall pier stands on the right).
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import Discriminator, Field, NonNegativeFloat, PositiveFloat, Tag

from ..core.devices import Damper, Device, Tendon
from .loading import StrictModel


class TendonConfig(StrictModel):
    """An unbonded post-tensioned tendon, anchored in the foundation and in the deck (through the
    pier's duct; a single block's top)."""

    kind: Literal["tendon"] = Field(description="The kind of device")
    pier: int = Field(ge=1, le=2, description="Its pier, counted in piers.heights (1 the first)")
    offset: float = Field(
        0.0, description="Distance of its duct from the pier's axis, positive to the right [m]"
    )
    prestress: NonNegativeFloat = Field(description="Initial force P0 [N]")
    area: PositiveFloat = Field(description="Cross-section area of its steel [m²]")
    elastic_modulus: PositiveFloat = Field(195e9, description="Young's modulus of its steel [Pa]")
    free_length: PositiveFloat | None = Field(
        None, description="Unbonded length that stretches; default the pier's height 2H [m]"
    )
    yield_force: PositiveFloat | None = Field(
        None,
        description="Force at which its steel yields, above the prestress; the limit state "
        "tendon_yield (the tendon stays elastic past it: post-yield is not modelled) [N]",
    )
    rupture_strain: PositiveFloat | None = Field(
        None,
        description="Strain at which it ruptures, above the strain at prestress P0/(E·A); the "
        "limit state tendon_rupture (the tendon stays elastic past it) [-]",
    )

    def stiffness(self, height: float) -> float:
        """Axial stiffness E·A/L_free of the tendon on a pier ``height`` (2H) tall [N/m]."""
        return self.elastic_modulus * self.area / (self.free_length or height)

    def initial_strain(self) -> float:
        """The steel's strain at prestress, ε0 = P0/(E·A) (at rest the interfaces are closed and
        the tendon has its prestress alone) [-]."""
        return self.prestress / (self.elastic_modulus * self.area)


class DamperConfig(StrictModel):
    """A linear viscous damper across a pier's rocking interface(s)."""

    kind: Literal["damper"] = Field(description="The kind of device")
    pier: int = Field(ge=1, le=2, description="Its pier, counted in piers.heights (1 the first)")
    offset: float = Field(
        0.0, description="Distance from the pier's axis, positive to the right [m]"
    )
    coefficient: PositiveFloat = Field(description="Dashpot coefficient c [N·s/m]")
    interface: Literal["base", "top", "both"] = Field(
        "base",
        description="The rocking interface(s) it crosses: the pier's base, its top (the "
        "deck's underside) or both",
    )


def _kind(value: Any) -> str | None:
    """The ``kind`` of a device's mapping (or of its model, when written), or None."""
    return value.get("kind") if isinstance(value, dict) else getattr(value, "kind", None)


DeviceConfig = Annotated[
    Annotated[TendonConfig, Tag("tendon")] | Annotated[DamperConfig, Tag("damper")],
    Discriminator(
        _kind, custom_error_type="device",
        custom_error_message="expected a mapping whose kind is tendon or damper",
    ),
]  # fmt: skip
"""A device, by its ``kind`` key."""


def check_devices(devices: list[TendonConfig | DamperConfig], width: float, piers: int) -> None:
    """Refuse devices the bridge cannot carry: on a pier it does not have, outside the section,
    at the top of a single block; a tendon whose prestress already reaches its yield force or
    its rupture strain.

    Parameters
    ----------
    width
        The piers' width 2B [m].
    piers
        How many heights ``piers.heights`` lists [-].

    Raises
    ------
    ValueError
        Naming the device (``devices.<i>.<field>``) and the reason.
    """
    for index, device in enumerate(devices):
        where = f"devices.{index}"
        if device.pier > piers:
            raise ValueError(
                f"{where}.pier: {device.pier}, but piers.heights lists {piers} pier"
                f"{'s' if piers > 1 else ''}"
            )
        if not abs(device.offset) < 0.5 * width:
            raise ValueError(
                f"{where}.offset: {device.offset:g} m lies outside the section (|offset| < B = "
                f"{0.5 * width:g} m)"
            )
        if piers == 1 and isinstance(device, DamperConfig) and device.interface != "base":
            raise ValueError(
                f"{where}.interface: a single block rocks on its base only, it has no "
                f"{device.interface!r} interface"
            )
        if isinstance(device, TendonConfig):
            _check_tendon_limits(device, where)


def _check_tendon_limits(tendon: TendonConfig, where: str) -> None:
    """Refuse a tendon's yield force at or below its prestress, its rupture strain at or below
    its strain at prestress (`TendonConfig.initial_strain`)."""
    if tendon.yield_force is not None and not tendon.yield_force > tendon.prestress:
        raise ValueError(
            f"{where}.yield_force: {tendon.yield_force:g} N does not exceed the prestress "
            f"{tendon.prestress:g} N (the tendon would yield at rest)"
        )
    strain = tendon.initial_strain()
    if tendon.rupture_strain is not None and not tendon.rupture_strain > strain:
        raise ValueError(
            f"{where}.rupture_strain: {tendon.rupture_strain:g} does not exceed the strain at "
            f"prestress P0/(E·A) = {strain:.4g} (the tendon would rupture at rest)"
        )


def core_devices(
    devices: list[TendonConfig | DamperConfig], heights: list[float], mirrored: bool
) -> tuple[Device, ...]:
    """The devices in the core's frame: pier 0 the tall one, offsets mirrored with the bridge.

    Parameters
    ----------
    heights
        ``piers.heights`` as the user lists them [m].
    mirrored
        Whether the tall pier stands on the right (`BridgeConfig.mirrored`).
    """
    sign = -1.0 if mirrored else 1.0
    bridge = len(heights) == 2
    built: list[Device] = []
    for device in devices:
        pier = device.pier - 1
        core_pier = 1 - pier if mirrored else pier
        offset = sign * device.offset
        if isinstance(device, TendonConfig):
            built.append(Tendon(
                core_pier, offset, device.prestress, device.stiffness(heights[pier]), top=bridge,
                yield_force=device.yield_force or math.inf,
                rupture_strain=device.rupture_strain or math.inf,
                rigidity=device.elastic_modulus * device.area,
            ))  # fmt: skip
        else:
            base, top = device.interface != "top", device.interface != "base"
            built.append(Damper(core_pier, offset, device.coefficient, base=base, top=top))
    return tuple(built)
