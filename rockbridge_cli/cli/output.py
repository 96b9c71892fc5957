"""Printing helpers shared by the commands: JSON with SI values, aligned key–value tables."""

from __future__ import annotations

import json
import math
from typing import Any

import click
import numpy as np


def to_jsonable(value: Any) -> Any:
    """Plain JSON types; non-finite floats become null (JSON has no infinity)."""
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, (np.floating, float)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.bool_):
        return bool(value)
    return value


def echo_json(value: Any) -> None:
    """Print one JSON object."""
    click.echo(json.dumps(to_jsonable(value), indent=2))


def echo_table(rows: list[tuple[str, str]]) -> None:
    """Print ``label  value`` rows with aligned values."""
    width = max(len(label) for label, _ in rows)
    for label, value in rows:
        click.echo(f"{label:<{width}}  {value}")
