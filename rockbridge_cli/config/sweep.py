"""Parameter sweeps: a study's bridges with some fields varied over lists or ranges.

A field is named by its dotted path in the bridge config, list positions as numbers:
``abutments.gap``, ``abutments.stiffness``, ``piers.heights.1`` (the second pier), ``spans.side``,
``devices.0.prestress`` (the first device's). A ``*`` in place of a list position names the field
in every item that has it, changed together: ``devices.*.prestress`` is the prestress of every
tendon (in an id, ``*`` is written ``all``).
One at a time (the default), each field runs over its values with the others as in the bridge
file; as a grid, every combination runs. Each variant is a bridge of its own, validated as a
bridge file would be, with a readable id: ``<bridge>+<field>_<value>`` (one field) or the fields
one after the other (a grid).
"""

from __future__ import annotations

import itertools
import math
import re
import typing
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
        The value; NaN for a number the bridge leaves unset (its default applies), and for a
        ``*`` whose items differ in the bridge file (no one value).
    """
    values = {_number(config, concrete) for concrete in concrete_paths(config, path)}
    return values.pop() if len(values) == 1 else math.nan


def concrete_paths(config: BridgeConfig, path: str) -> list[str]:
    """The dotted paths ``path`` names in ``config``: itself, or with each ``*`` replaced by the
    list positions whose item has the rest of the path (``devices.*.prestress`` → every tendon's).

    Raises
    ------
    ValueError
        A ``*`` names no item (no list there, or no item with the field).
    """
    if "*" not in path.split("."):
        return [path]
    head, _, rest = path.partition(".*")
    node: Any = config.model_dump()
    for part in head.split("."):
        node = _child(node, part, path)
    if not isinstance(node, list):
        raise ValueError(f"{path}: {head} is not a list")
    tail = rest.removeprefix(".")
    found = [
        f"{head}.{index}" + (f".{tail}" if tail else "")
        for index, item in enumerate(node)
        if _has(item, tail.split(".")[0] if tail else "")
    ]
    if not found:
        raise ValueError(f"{path}: no item of {head} has {tail or 'a value'}")
    return [p for concrete in found for p in concrete_paths(config, concrete)]


def _has(item: Any, key: str) -> bool:
    """Whether a list's item has ``key`` (a mapping's field, a list's position; '' any item)."""
    if not key:
        return True
    if isinstance(item, dict):
        return key in item
    return isinstance(item, list) and (key == "*" or (key.isdigit() and int(key) < len(item)))


def _number(config: BridgeConfig, path: str) -> float:
    """The number at a dotted path without ``*`` (`field_value`)."""
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
    info = _field_info(path)
    return info is not None and str(info.annotation) == "float | None"


def _field_info(path: str) -> Any:
    """The pydantic field a dotted path names, list positions (numbers, ``*``) passed over and
    a list of several models (``devices``) searched for the first that has the field; None if
    no model has it."""
    models: list[Any] = [BridgeConfig]
    info = None
    for part in path.split("."):
        if part.isdigit() or part == "*":
            continue
        owners = [m for m in models if part in m.model_fields]
        if not owners:
            return None
        info = owners[0].model_fields[part]
        models = _models(info.annotation)
    return info


def _models(annotation: Any) -> list[Any]:
    """The config models inside a field's annotation (through lists, unions, ``Annotated``)."""
    if isinstance(annotation, type) and issubclass(annotation, StrictModel):
        return [annotation]
    return [m for arg in typing.get_args(annotation) for m in _models(arg)]


def varied(config: BridgeConfig, changes: dict[str, float]) -> BridgeConfig:
    """The bridge with ``changes`` (path → value) applied, validated like a bridge file.

    Raises
    ------
    ValueError
        A path does not name a number of this bridge, or the changed bridge is invalid.
    """
    data = config.model_dump(exclude_none=False)
    for named, value in changes.items():
        for path in concrete_paths(config, named):
            _number(config, path)  # the path names a number
            *parents, last = path.split(".")
            node = data
            for part in parents:
                node = _child(node, part, path)
            node[int(last) if isinstance(node, list) else last] = value
    try:
        return BridgeConfig.model_validate(data)
    except ValidationError as exc:
        error = exc.errors()[0]
        loc = ".".join(str(p) for p in error["loc"])
        where = f"{loc}: " if loc else ""  # a check of the whole bridge names its field itself
        raise ValueError(f"gives an invalid bridge: {where}"
                         f"{error['msg'].removeprefix('Value error, ')}") from None  # fmt: skip


def variant_id(bridge: str, changes: dict[str, float]) -> str:
    """``<bridge>+<path>_<value>`` for each change (a ``*`` of the path written ``all``)."""
    return bridge + "".join(
        f"+{path.replace('*', 'all')}_{value:.6g}" for path, value in changes.items()
    )


def _child(node: Any, part: str, path: str) -> Any:
    if isinstance(node, dict) and part in node:
        return node[part]
    if isinstance(node, list) and part.isdigit() and int(part) < len(node):
        return node[int(part)]
    raise ValueError(f"{path} is not a field of this bridge")


def field_unit(path: str) -> str:
    """The unit of a bridge field at a dotted path, from its description (``-`` if it has none)."""
    info = _field_info(path)
    description = (info.description if info is not None else None) or ""
    found = re.search(r"\[([^\]]+)\]\s*$", description)
    return found.group(1) if found else "-"
