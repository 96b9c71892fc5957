"""The bridge config: what a YAML file says about one bridge, validated, and turned into a `Model`.

Lengths are the full dimensions a designer draws (pier width 2B, heights 2H, deck depth 2h), in SI
units. Optional parts are optional: without ``abutments`` the bridge is a rocking frame; with a
single pier height and no deck it is Housner's block. Heights are listed left to right; a bridge
whose taller pier stands on the right is analyzed as the mirror image of one with the tall pier on
the left (docs/model.md §1), and `BridgeConfig.mirrored` says so.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from pydantic import (
    Field,
    PositiveFloat,
    SerializerFunctionWrapHandler,
    ValidationInfo,
    field_validator,
    model_serializer,
    model_validator,
)

from ..core import geometry
from ..core.bridge import Bridge
from ..core.geometry import Model
from ..errors import check_path_argument
from ..kinds import expecting
from . import loading
from .devices import DeviceConfig, check_devices, core_devices
from .loading import StrictModel

MAX_DASHPOT_RATE = 1e5
"""The largest backfill dashpot per deck mass, c / m_deck [1/s]: an explicit integrator's steps
shrink as its inverse while the end gap is closed (about c / (3 m_deck) steps per second of
contact: 1e15 N·s/m took minutes), and backfills have about 25 (48 MN·s/m on 2000 t)."""


MAX_SLENDERNESS = 1e6
"""Most a pier's height 2H may be over its width 2B [-]: built rocking piers lie between 1.5 and
40 (a warning says so beyond); near 1e15 the slope tan α = B/H reaches the floating-point
resolution and the geometry cannot be solved (``heights: [1e308, 13]`` ended in a raw
ValueError)."""


class Piers(StrictModel):
    """The rocking piers: square sections of one width, one or two heights."""

    width: PositiveFloat = Field(description="Pier width 2B (square section) [m]")
    heights: list[PositiveFloat] = Field(
        min_length=1,
        max_length=2,
        description="Pier heights 2H, left to right; one value makes a single block [m]",
    )

    @field_validator("heights")
    @classmethod
    def _slender(cls, heights: list[float], info: ValidationInfo) -> list[float]:
        width = info.data.get("width")
        for height in heights:
            if width is not None and width >= height:
                raise ValueError(
                    f"every height must exceed the width ({width} m), got {height} m: "
                    "a pier with B ≥ H does not rock on its corners in this model"
                )
            if width is not None and not height / width <= MAX_SLENDERNESS:
                raise ValueError(
                    f"a height of {height:g} m is more than {MAX_SLENDERNESS:g} times the width "
                    f"({width:g} m): its angle α (tan α = B/H) is lost in floating point"
                )
        return heights


class Deck(StrictModel):
    """The deck: a rigid beam on the piers (and on the abutment seats)."""

    depth: PositiveFloat = Field(description="Deck depth 2h [m]")
    area: PositiveFloat | None = Field(
        None, description="Cross-section area A_deck; mass = density·A·(2L1 + L2) [m²]"
    )
    mass: PositiveFloat | None = Field(None, description="Deck mass m_deck, instead of area [kg]")
    inertia: PositiveFloat | None = Field(
        None,
        description="Moment of inertia about its centre of gravity; default m·(L_tot² + (2h)²)/12 "
        "[kg·m²]",
    )

    @model_validator(mode="after")
    def _area_or_mass(self) -> Deck:
        if (self.area is None) == (self.mass is None):
            raise ValueError("give exactly one of 'area' and 'mass'")
        return self


class Spans(StrictModel):
    """Span lengths."""

    side: float = Field(0.0, ge=0.0, description="Side (end) span L1, pier to abutment [m]")
    central: PositiveFloat = Field(description="Central span L2, between the piers [m]")


class Pounding(StrictModel):
    """Deck–backwall pounding (Eqs. 19–20). Defaults: docs/model.md §2 (m_abut = 38 000 kg)."""

    restitution: float = Field(0.6, ge=0.0, le=1.0, description="Coefficient of restitution e [-]")
    mass: PositiveFloat | None = Field(
        None, description="Backfill mass m_abut; default ρ_s·L_cr·B_abut·h_bw [kg]"
    )
    soil_density: PositiveFloat = Field(2000.0, description="Backfill density ρ_s [kg/m³]")
    critical_length: PositiveFloat = Field(1.0, description="Backfill length L_cr [m]")
    backwall_width: PositiveFloat = Field(9.5, description="Backwall width B_abut [m]")
    backwall_height: PositiveFloat = Field(2.0, description="Backwall height h_bw [m]")

    @property
    def backfill_mass(self) -> float:
        """m_abut [kg]."""
        if self.mass is not None:
            return self.mass
        return geometry.backfill_mass(
            self.soil_density, self.critical_length, self.backwall_width, self.backwall_height
        )


class Abutments(StrictModel):
    """Seat-type abutments with an end-joint gap and a Kelvin–Voigt backfill (Eqs. 15–17)."""

    gap: float = Field(ge=0.0, description="End-joint gap u_jo [m]")
    stiffness: float = Field(ge=0.0, description="Backfill spring k [N/m]")
    damping: float = Field(ge=0.0, description="Backfill dashpot c [N·s/m]")
    ultimate_displacement: PositiveFloat = Field(
        description="Backfill displacement at failure beyond the gap, u_ab [m]"
    )
    pounding: Pounding = Field(default_factory=Pounding, description="Backwall pounding")


class BridgeConfig(StrictModel):
    """One bridge, as a YAML file describes it."""

    name: str | None = Field(None, description="Label used in tables and plots")
    description: str | None = Field(None, description="Free text")
    piers: Piers
    deck: Deck | None = Field(None, description="Absent only for a single block")
    spans: Spans | None = Field(None, description="Absent only for a single block")
    abutments: Abutments | None = Field(None, description="Absent: a rocking frame")
    density: PositiveFloat = Field(2500.0, description="Density of piers and deck ρ [kg/m³]")
    gravity: PositiveFloat = Field(9.81, description="Acceleration of gravity g [m/s²]")
    devices: list[DeviceConfig] = Field(
        default_factory=list,
        description="Post-tensioned tendons, viscous dampers and hysteretic dissipators on the "
        "piers (docs/model.md §13); "
        "none: the paper's free-standing piers",
    )
    rocking_restitution: float | None = Field(
        None,
        gt=0.0,
        le=1.0,
        description="Coefficient of restitution η of the rocking interfaces in both directions, "
        "for example a measured one; default: from the impulse balance (Eqs. 21–30) [-]",
    )

    @field_validator("deck", "spans", "abutments")
    @classmethod
    def _parts_fit(cls, part: StrictModel | None, info: ValidationInfo) -> StrictModel | None:
        piers = info.data.get("piers")
        if piers is None:
            return part
        if len(piers.heights) == 1 and part is not None:
            raise ValueError(
                "a single pier is a free-standing block: remove this or give two heights"
            )
        if len(piers.heights) == 2 and part is None and info.field_name != "abutments":
            raise ValueError("required for a bridge on two piers")
        if isinstance(part, Spans) and part.central <= piers.width:
            raise ValueError(
                f"the central span ({part.central} m) must exceed the pier width ({piers.width} m)"
            )
        return part

    @model_serializer(mode="wrap")
    def _without_no_devices(self, dump: SerializerFunctionWrapHandler) -> dict[str, Any]:
        """The config's fields, without ``devices`` when it lists none: a free-standing bridge's
        stored config (and the hash a results file resumes by) stays what it was before bridges
        had devices."""
        fields = dump(self)
        if not fields.get("devices"):
            fields.pop("devices", None)
        return fields

    @model_validator(mode="after")
    def _devices_fit(self) -> BridgeConfig:
        check_devices(self.devices, self.piers.width, len(self.piers.heights))
        return self

    @model_validator(mode="after")
    def _dashpot_within_reach(self) -> BridgeConfig:
        if self.abutments is None or self.deck is None or self.spans is None:
            return self
        rate = self.abutments.damping / self._deck_mass()
        if rate > MAX_DASHPOT_RATE:
            raise ValueError(
                f"abutments.damping: c / m_deck = {rate:.3g} 1/s is more than "
                f"{MAX_DASHPOT_RATE:g} 1/s (a backfill's is about 25): the integrator would need "
                "steps shorter than 10 µs while the gap is closed"
            )
        return self

    def _deck_mass(self) -> float:
        """m_deck [kg]: given, or density · area · (2 L1 + L2)."""
        assert self.deck is not None and self.spans is not None
        if self.deck.mass is not None:
            return self.deck.mass
        assert self.deck.area is not None  # the deck gives exactly one of the two
        return self.density * self.deck.area * (2.0 * self.spans.side + self.spans.central)

    @property
    def mirrored(self) -> bool:
        """True when the taller pier stands on the right (the model runs on the mirror image)."""
        heights = self.piers.heights
        return len(heights) == 2 and heights[1] > heights[0]

    def label(self, fallback: str = "bridge") -> str:
        """The bridge's name, or ``fallback``."""
        return self.name or fallback

    def to_bridge(self) -> Bridge:
        """The bridge as the core analyses it: the model (tall pier first, SI units), whether it
        is mirrored, the restitution override and the devices (in the core's frame)."""
        return Bridge(
            self._model(),
            mirrored=self.mirrored,
            restitution=self.rocking_restitution,
            devices=core_devices(self.devices, self.piers.heights, self.mirrored),
        )

    def _model(self) -> Model:
        B = 0.5 * self.piers.width
        heights = sorted(self.piers.heights, reverse=True)
        H1 = 0.5 * heights[0]
        if len(heights) == 1:
            return geometry.single_block(B, H1, self.density, self.gravity)
        assert self.deck is not None and self.spans is not None
        H2 = 0.5 * heights[1]
        L1, L2 = self.spans.side, self.spans.central
        length = 2.0 * L1 + L2
        md = self._deck_mass()
        inertia = self.deck.inertia or geometry.deck_inertia(md, length, self.deck.depth)
        m1 = geometry.pier_mass(self.density, B, H1)
        m2 = geometry.pier_mass(self.density, B, H2)
        abut = self.abutments
        return Model(
            B=B, H1=H1, H2=H2, L1=L1, L2=L2, h=0.5 * self.deck.depth,
            m1=m1, m2=m2, md=md,
            I1=geometry.pier_inertia(m1, B, H1), I2=geometry.pier_inertia(m2, B, H2), Id=inertia,
            g=self.gravity,
            has_abutments=1.0 if abut else 0.0,
            u_jo=abut.gap if abut else float("inf"),
            k=abut.stiffness if abut else 0.0,
            c=abut.damping if abut else 0.0,
            u_ab=abut.ultimate_displacement if abut else float("inf"),
            e=abut.pounding.restitution if abut else 1.0,
            m_abut=abut.pounding.backfill_mass if abut else 0.0,
        )  # fmt: skip


def load_bridge(path: str | Path) -> BridgeConfig:
    """Read and validate a bridge YAML file.

    Raises
    ------
    InputError
        Naming the file, the field path, the value and the reason for every problem; or naming
        the kind of file it is, where it is another (`kinds`).
    TypeError
        ``path`` is not a path (a mapping: `BridgeConfig.model_validate` it).
    """
    check_path_argument(path, "load_bridge", "a bridge YAML file (a mapping: "
                        "BridgeConfig.model_validate)")  # fmt: skip
    with expecting(path, "bridge"):
        return loading.load(BridgeConfig, path)
