"""The HTML pieces of the report: tables, cells and escaped text."""

from __future__ import annotations

import html
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from ..core.quantities import ROUND_OFF

MAX_ROWS = 500
"""Rows of the peak table shown at most; the page says how many more the file holds."""


def table_html(headers: Sequence[str], rows: Iterable[Sequence[Any]], text_columns=()) -> str:
    """A table that scrolls sideways on a narrow screen; ``text_columns`` are left-aligned."""

    def tagged(tag: str, index: int, value: Any) -> str:
        kind = ' class="text"' if index in text_columns else ""
        return f"<{tag}{kind}>{escaped(value)}</{tag}>"

    head = "".join(tagged("th", i, h) for i, h in enumerate(headers))
    body = "".join(
        "<tr>" + "".join(tagged("td", i, v) for i, v in enumerate(row)) + "</tr>" for row in rows
    )
    table = f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"
    return f'<div class="scroll">{table}</div>'


def cell(value: Any, scale: float) -> str:
    """A peak-table value as shown: a number times ``scale`` to 4 digits, "-" where missing."""
    if isinstance(value, (float, np.floating)):
        return "-" if not np.isfinite(value) else f"{rounded(float(value)) * scale:.4g}"
    if isinstance(value, (int, np.integer)):
        return "-" if value < 0 else str(int(value))
    return str(value)


def rounded(value: float) -> float:
    """0 for round-off (`core.quantities.ROUND_OFF`), else the value."""
    return 0.0 if abs(value) < ROUND_OFF else value


def number(value: float | None) -> str:
    """Three significant digits, "-" for None."""
    return "-" if value is None else f"{value:.3g}"


def escaped(value: Any) -> str:
    """The value as HTML text."""
    return html.escape(str(value))
