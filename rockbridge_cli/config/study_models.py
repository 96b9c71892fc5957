"""The study config as a YAML file describes it (`StudyConfig`), checked as a file: its keys,
types, and that the files and folders it names exist; its bridges (paths or inline bridges), its
fidelity (`FidelityConfig`) and its output (`Output`). `config.study` resolves it into a `Study`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import (
    BeforeValidator,
    Field,
    NonNegativeFloat,
    NonNegativeInt,
    PositiveFloat,
    PositiveInt,
    create_model,
    field_validator,
    model_validator,
)

from ..core.fidelity import KNOBS, PRESETS, Knob
from ..core.quantities import HISTORY_UNITS, is_device_history
from .bridge import BridgeConfig
from .intensity import Intensity
from .loading import ID_PATTERN, StrictModel
from .records import Records
from .spectrum import Spectrum
from .sweep import Sweep
from .uncertainty import Uncertainty


def _path_or_mapping(value: Any) -> Any:
    if not isinstance(value, (str, dict)):
        raise ValueError("expected the path of a bridge file or a bridge mapping with an id")
    return value


BridgeEntry = Annotated[str | dict[str, Any], BeforeValidator(_path_or_mapping)]


class InlineBridge(BridgeConfig):
    """A bridge written inside the study file, with the id that names it in the results."""

    id: str = Field(pattern=ID_PATTERN, description="Bridge id in the results [-]")


class _Preset(StrictModel):
    """A fidelity preset, and the checks of a ``fidelity`` section (`FidelityConfig`)."""

    preset: str = Field("default", description=f"One of {', '.join(PRESETS)}")

    @model_validator(mode="before")
    @classmethod
    def _shorthand(cls, data: Any) -> Any:
        if isinstance(data, str):
            return {"preset": data}
        if not isinstance(data, (dict, cls)):
            raise ValueError(f"expected a preset name ({', '.join(PRESETS)}) or a mapping")
        return data

    @field_validator("preset")
    @classmethod
    def _known(cls, preset: str) -> str:
        if preset not in PRESETS:
            raise ValueError(f"unknown preset {preset!r}: choose one of {', '.join(PRESETS)}")
        return preset

    def overrides(self) -> dict[str, Any]:
        """The knobs this config changes, in the core's terms."""
        return self.model_dump(exclude={"preset"}, exclude_none=True)


_NUMBERS: dict[tuple[type, bool], Any] = {
    (float, False): PositiveFloat, (float, True): NonNegativeFloat,
    (int, False): PositiveInt, (int, True): NonNegativeInt,
}  # fmt: skip
"""The type of a numeric knob's field, by its kind and whether 0 is a value of it."""


def _knob_field(knob: Knob) -> tuple[Any, Any]:
    """The field of a knob (`core.fidelity.KNOBS`) in a study's ``fidelity`` section: its type
    (one of its choices, a switch, or a number, positive where 0 is no value of it) and its
    description; None keeps the preset's. Its range is `core.fidelity.resolve`'s to check."""
    if knob.choices:
        kind: Any = Literal[knob.choices]  # type: ignore[valid-type]
    else:
        kind = bool if knob.kind is bool else _NUMBERS[knob.kind, knob.zero]
    description = f"{knob.meaning} [{knob.unit}]" if knob.unit else knob.meaning
    return kind | None, Field(None, description=description)


_KNOB_FIELDS: dict[str, Any] = {
    knob.name: _knob_field(knob) for knob in KNOBS if knob.name != "output_step"
}
"""The fields of a ``fidelity`` section's knobs: `core.fidelity.KNOBS`, but ``output_step``,
which is the ``output`` section's."""

FidelityConfig = create_model(
    "FidelityConfig",
    __base__=_Preset,
    __module__=__name__,
    __doc__="""A fidelity preset and any knobs to change (`rockbridge_cli.core.fidelity`); a plain
    preset name is short for ``{preset: <name>}``. Its knobs are `core.fidelity.KNOBS`, but
    ``output_step``, which is the ``output`` section's.""",
    **_KNOB_FIELDS,
)


class Output(StrictModel):
    """Where the results go and what they keep."""

    path: Path | None = Field(
        None, description="HDF5 file, relative to the study file; default results/<stem>.h5"
    )
    output_step: PositiveFloat | None = Field(
        None, description="Time step of the stored histories; default the preset's (0.01 s) [s]"
    )
    histories: str | list[str] = Field(
        "all",
        description=f"Histories to keep: all (with each device's), none, or a list of "
        f"{', '.join(HISTORY_UNITS)} or a device's (tendon1_force, dissipator1_plastic, …)",
    )

    @field_validator("histories", mode="before")
    @classmethod
    def _known(cls, names: Any) -> Any:
        choices = ", ".join(HISTORY_UNITS) + " or a device's (tendon1_force, damper2_elongation, …)"
        if names in ("all", "none"):
            return names
        if not isinstance(names, list) or not all(isinstance(name, str) for name in names):
            raise ValueError(f"give all, none or a list of history names ({choices})")
        unknown = [n for n in names if n not in HISTORY_UNITS and not is_device_history(n)]
        if unknown:
            raise ValueError(f"unknown histories {', '.join(unknown)}: choose from {choices}")
        if len(set(names)) != len(names):
            raise ValueError("a history is listed twice")
        return names

    def kept(self) -> tuple[str, ...]:
        """Names of the histories to store, in `HISTORY_UNITS` order, then the devices' a list
        names (``all`` names none: `core.quantities.kept_history` keeps every device's)."""
        if self.histories == "all":
            return tuple(HISTORY_UNITS)
        if self.histories == "none":
            return ()
        listed = [name for name in self.histories if is_device_history(name)]
        return (*(name for name in HISTORY_UNITS if name in self.histories), *listed)


class StudyConfig(StrictModel):
    """A study, as a YAML file describes it."""

    description: str | None = Field(None, description="Free text")
    bridges: list[BridgeEntry] = Field(
        min_length=1,
        description="Bridge files (relative to the study file; id = file stem) or inline bridges "
        "with an id",
    )
    records: Records | None = Field(None, description="The ground motions")
    intensity: Intensity | None = Field(
        None, description="Scale every record to levels of an intensity measure"
    )
    sweep: Sweep | None = Field(None, description="Vary bridge fields over lists or ranges")
    uncertainty: Uncertainty | None = Field(
        None, description="Draw bridge fields from distributions (config.uncertainty)"
    )
    spectrum: Spectrum | None = Field(
        None, description="Instead of records: the overturning spectrum of the one bridge under "
        "a pulse (config.spectrum)",
    )  # fmt: skip
    fidelity: FidelityConfig = Field(  # type: ignore[valid-type]
        default_factory=FidelityConfig, description="Numerical fidelity"
    )
    output: Output = Field(default_factory=Output, description="The results file")

    @model_validator(mode="after")
    def _records_or_spectrum(self) -> StudyConfig:
        if (self.records is None) == (self.spectrum is None):
            raise ValueError("give exactly one of records and spectrum")
        if self.sweep is not None and self.uncertainty is not None:
            raise ValueError(
                "give a sweep or an uncertainty section, not both: sample the swept field too, "
                "or write one study per swept value"
            )
        if self.spectrum is not None:
            others = [
                name for name in ("intensity", "sweep", "uncertainty")
                if getattr(self, name) is not None
            ]  # fmt: skip
            if others or len(self.bridges) != 1:
                raise ValueError(
                    "a spectrum is of one bridge, without intensity or sweep sections (it finds "
                    "its own levels): write one study per bridge"
                )
        return self
