"""The ``devices`` section of a bridge config: post-tensioned tendons, viscous dampers and
hysteretic dissipators on the piers (docs/model.md §13), validated, and built into the core's
devices (`core.devices`).

Each device names its pier by its place in ``piers.heights`` (1 the first, left to right) and its
offset from the pier's axis, positive to the right, in the user's drawing; `core_devices` turns
them into the core's frame (tall pier first, mirrored where the tall pier stands on the right).
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import Discriminator, Field, NonNegativeFloat, PositiveFloat, Tag

from ..core.devices import Damper, Device, Dissipator, Tendon
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
        description="Force at which its steel yields, above the prestress: past it the tendon "
        "stretches at that force and unloads elastically with a loss of prestress; the limit "
        "state tendon_yield [N]",
    )
    rupture_strain: PositiveFloat | None = Field(
        None,
        description="Strain at which it ruptures (its force drops to zero for good), above the "
        "strain at prestress P0/(E·A); the limit state tendon_rupture [-]",
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


class DissipatorConfig(StrictModel):
    """A hysteretic dissipator (a yielding steel bar or fuse) across a pier's rocking
    interface(s): bilinear with kinematic hardening."""

    kind: Literal["dissipator"] = Field(description="The kind of device")
    pier: int = Field(ge=1, le=2, description="Its pier, counted in piers.heights (1 the first)")
    offset: float = Field(
        0.0, description="Distance from the pier's axis, positive to the right [m]"
    )
    stiffness: PositiveFloat = Field(description="Elastic stiffness k1 [N/m]")
    yield_force: PositiveFloat = Field(description="Yield force F_y [N]")
    post_yield_ratio: NonNegativeFloat = Field(
        0.0, description="Post-yield stiffness over the elastic one, k2/k1, below 1 [-]"
    )
    fracture_strain: PositiveFloat | None = Field(
        None,
        description="Strain (elongation over length) at which it fractures, its force dropping "
        "to zero for good; the limit state dissipator_fracture; needs length [-]",
    )
    length: PositiveFloat | None = Field(
        None, description="Gauge length that turns its elongation into a strain [m]"
    )
    interface: Literal["base", "top", "both"] = Field(
        "base",
        description="The rocking interface(s) it crosses: the pier's base, its top (the "
        "deck's underside) or both",
    )

    def fracture(self) -> float:
        """Elongation at which it fractures, fracture_strain·length; inf without [m]."""
        if self.fracture_strain is None or self.length is None:
            return math.inf
        return self.fracture_strain * self.length


def _kind(value: Any) -> str | None:
    """The ``kind`` of a device's mapping (or of its model, when written), or None."""
    return value.get("kind") if isinstance(value, dict) else getattr(value, "kind", None)


DeviceConfig = Annotated[
    Annotated[TendonConfig, Tag("tendon")] | Annotated[DamperConfig, Tag("damper")]
    | Annotated[DissipatorConfig, Tag("dissipator")],
    Discriminator(
        _kind, custom_error_type="device",
        custom_error_message="expected a mapping whose kind is tendon, damper or dissipator",
    ),
]  # fmt: skip

AnyDevice = TendonConfig | DamperConfig | DissipatorConfig
"""A device, by its ``kind`` key."""


def check_devices(devices: list[AnyDevice], width: float, piers: int) -> None:
    """Refuse devices the bridge cannot carry: on a pier it does not have, outside the section,
    at the top of a single block; a tendon whose prestress already reaches its yield force or
    its rupture strain; a dissipator that would not harden less than it stiffens, or would
    fracture before it yields.

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
        if piers == 1 and not isinstance(device, TendonConfig) and device.interface != "base":
            raise ValueError(
                f"{where}.interface: a single block rocks on its base only, it has no "
                f"{device.interface!r} interface"
            )
        if isinstance(device, TendonConfig):
            _check_tendon_limits(device, where)
        if isinstance(device, DissipatorConfig):
            _check_dissipator(device, where)


def _check_dissipator(dissipator: DissipatorConfig, where: str) -> None:
    """Refuse a post-yield ratio of 1 or more, a fracture strain without a length, and a
    fracture elongation at or below the yield elongation F_y/k1."""
    if not dissipator.post_yield_ratio < 1.0:
        raise ValueError(
            f"{where}.post_yield_ratio: {dissipator.post_yield_ratio:g} is not below 1 (the "
            f"post-yield stiffness k2 must be less than the elastic one k1)"
        )
    if dissipator.fracture_strain is not None and dissipator.length is None:
        raise ValueError(
            f"{where}.length: missing, and fracture_strain needs it to turn the strain into an "
            f"elongation"
        )
    yielding = dissipator.yield_force / dissipator.stiffness
    if not dissipator.fracture() > yielding:
        raise ValueError(
            f"{where}.fracture_strain: fractures at {dissipator.fracture():.4g} m, not beyond "
            f"its yield elongation F_y/k1 = {yielding:.4g} m (it would fracture before yielding)"
        )


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
    devices: list[AnyDevice], heights: list[float], mirrored: bool
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
        elif isinstance(device, DissipatorConfig):
            base, top = device.interface != "top", device.interface != "base"
            built.append(Dissipator(
                core_pier, offset, device.stiffness, device.yield_force,
                hardening=device.post_yield_ratio * device.stiffness, fracture=device.fracture(),
                length=device.length or math.inf, base=base, top=top,
            ))  # fmt: skip
        else:
            base, top = device.interface != "top", device.interface != "base"
            built.append(Damper(core_pier, offset, device.coefficient, base=base, top=top))
    return tuple(built)
