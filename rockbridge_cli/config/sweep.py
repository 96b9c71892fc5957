"""Parameter sweeps: a study's bridges with some fields varied over lists or ranges.

A field is named by its dotted path in the bridge config, list positions as numbers:
``abutments.gap``, ``abutments.stiffness``, ``piers.heights.1`` (the second pier), ``spans.side``.
One at a time (the default), each field runs over its values with the others as in the bridge
file; as a grid, every combination runs. Each variant is a bridge of its own, validated as a
bridge file would be, with a readable id: ``<bridge>+<field>_<value>`` (one field) or the fields
one after the other (a grid).
"""

from __future__ import annotations

import itertools
import math
import re
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import (
    Discriminator,
    Field,
    PositiveInt,
    Tag,
    ValidationError,
    field_validator,
    model_validator,
)

from .bridge import BridgeConfig
from .loading import StrictModel, kind_of

MAX_VARIANTS = 10_000
"""Most variants of each bridge a sweep makes (each is a bridge config held in memory)."""


class Range(StrictModel):
    """``count`` values from ``start`` to ``stop``, both included, evenly spaced or log-spaced."""

    start: float = Field(description="First value [the field's unit]")
    stop: float = Field(description="Last value [the field's unit]")
    count: PositiveInt = Field(ge=2, le=MAX_VARIANTS, description="Number of values [-]")
    spacing: Literal["linear", "log"] = Field("linear", description="linear or log")

    @model_validator(mode="after")
    def _positive_for_log(self) -> Range:
        if self.spacing == "log" and min(self.start, self.stop) <= 0.0:
            raise ValueError("log spacing needs positive start and stop")
        return self

    def values(self) -> list[float]:
        """The values, in order."""
        space = np.geomspace if self.spacing == "log" else np.linspace
        return [float(v) for v in space(self.start, self.stop, self.count)]


Values = Annotated[
    Annotated[list[float], Tag("=list")] | Annotated[Range, Tag("=mapping")],
    Discriminator(
        kind_of, custom_error_type="values",
        custom_error_message="expected a list of values or a range {start, stop, count}",
    ),
]  # fmt: skip
"""A swept field's values: a list, or a `Range`."""


class Sweep(StrictModel):
    """Bridge fields varied over lists or ranges (`config.sweep`)."""

    fields: dict[str, Values] = Field(
        min_length=1,
        description="Dotted path of a bridge field → its values, or a range [the field's unit]",
    )
    grid: bool = Field(False, description="Every combination, instead of one field at a time")

    @field_validator("fields")
    @classmethod
    def _distinct_values(cls, fields: dict[str, list[float] | Range]) -> dict:
        for path, values in fields.items():
            listed = values.values() if isinstance(values, Range) else values
            if not listed:
                raise ValueError(f"{path}: give at least one value")
            if len(set(listed)) != len(listed):
                raise ValueError(f"{path}: a value is listed twice")
        return fields

    @model_validator(mode="after")
    def _bounded(self) -> Sweep:
        counts = [v.count if isinstance(v, Range) else len(v) for v in self.fields.values()]
        variants = math.prod(counts) if self.grid else sum(counts)
        if variants > MAX_VARIANTS:
            raise ValueError(f"{variants:,} variants of each bridge, more than {MAX_VARIANTS:,}: "
                             "fewer values, or one field at a time (grid: false)")  # fmt: skip
        return self

    def variations(self) -> list[dict[str, float]]:
        """Each variant's changes, path → value, in the order of the results."""
        values = {
            path: v.values() if isinstance(v, Range) else [float(x) for x in v]
            for path, v in self.fields.items()
        }
        if self.grid:
            return [dict(zip(values, combination, strict=True))
                    for combination in itertools.product(*values.values())]  # fmt: skip
        return [{path: value} for path, listed in values.items() for value in listed]


def field_value(config: BridgeConfig, path: str) -> float:
    """The value of a bridge field at a dotted path.

    Raises
    ------
    ValueError
        The path does not name a number of this bridge.

    Returns
    -------
    float
        The value; NaN for a number the bridge leaves unset (its default applies).
    """
    node: Any = config.model_dump()
    for part in path.split("."):
        node = _child(node, part, path)
    if node is None and _optional_number(path):
        return math.nan  # unset: its default (``rocking_restitution``: from the impulse balance)
    if isinstance(node, bool) or not isinstance(node, (int, float)):
        raise ValueError(f"{path} is not a number of this bridge (it is {node!r})")
    return float(node)


def _optional_number(path: str) -> bool:
    """Whether the bridge field at ``path`` is a number that may be left unset."""
    model: Any = BridgeConfig
    info = None
    for part in path.split("."):
        if model is None or part not in model.model_fields:
            return False
        info = model.model_fields[part]
        inner = [a for a in getattr(info.annotation, "__args__", (info.annotation,))
                 if isinstance(a, type) and issubclass(a, StrictModel)]  # fmt: skip
        model = inner[0] if inner else None
    return info is not None and str(info.annotation) == "float | None"


def varied(config: BridgeConfig, changes: dict[str, float]) -> BridgeConfig:
    """The bridge with ``changes`` (path → value) applied, validated like a bridge file.

    Raises
    ------
    ValueError
        A path does not name a number of this bridge, or the changed bridge is invalid.
    """
    data = config.model_dump(exclude_none=False)
    for path, value in changes.items():
        field_value(config, path)  # the path names a number
        *parents, last = path.split(".")
        node = data
        for part in parents:
            node = _child(node, part, path)
        node[int(last) if isinstance(node, list) else last] = value
    try:
        return BridgeConfig.model_validate(data)
    except ValidationError as exc:
        error = exc.errors()[0]
        where = ".".join(str(p) for p in error["loc"])
        raise ValueError(f"gives an invalid bridge: {where}: "
                         f"{error['msg'].removeprefix('Value error, ')}") from None  # fmt: skip


def variant_id(bridge: str, changes: dict[str, float]) -> str:
    """``<bridge>+<path>_<value>`` for each change."""
    return bridge + "".join(f"+{path}_{value:.6g}" for path, value in changes.items())


def _child(node: Any, part: str, path: str) -> Any:
    if isinstance(node, dict) and part in node:
        return node[part]
    if isinstance(node, list) and part.isdigit() and int(part) < len(node):
        return node[int(part)]
    raise ValueError(f"{path} is not a field of this bridge")


def field_unit(path: str) -> str:
    """The unit of a bridge field at a dotted path, from its description (``-`` if it has none)."""
    model: Any = BridgeConfig
    description = ""
    for part in path.split("."):
        if part.isdigit():
            continue
        info = model.model_fields[part]
        description = info.description or ""
        inner = [a for a in getattr(info.annotation, "__args__", (info.annotation,))
                 if isinstance(a, type) and issubclass(a, StrictModel)]  # fmt: skip
        model = inner[0] if inner else None
    found = re.search(r"\[([^\]]+)\]\s*$", description)
    return found.group(1) if found else "-"
