"""What the figures share: file formats, a print-friendly style per series, saving.

Each series differs by marker, line style and shade of grey, as in the paper's figures, so that
the figures read in print: 3 shades, 8 markers and 6 line styles tell 24 series apart. Dotted and
dashed black lines are kept for limits (gap, failure).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter

from ..errors import InputError
from ..paths import checked_output, maker_metadata

FORMATS = (".png", ".pdf", ".svg")

_MARKERS = ("o", "s", "^", "D", "v", "P", "X", "*")
_LINES = ("-", "--", "-.", (0, (5, 1, 1, 1)), (0, (1, 3)), (0, (8, 2)))
_SHADES = ("black", "0.45", "0.7")


GAP_LINE: dict[str, Any] = {"color": "black", "linestyle": ":", "linewidth": 1.0}
"""A limit that is reached without harm: the end-joint gap closing."""

FAILURE_LINE: dict[str, Any] = {"color": "black", "linestyle": "--", "linewidth": 1.0}
"""A failure: its limit (abutment–backfill, 100 % of a capacity) or its time."""


PLAIN = FuncFormatter(lambda value, _: f"{value:g}")
"""Tick labels as plain numbers (0.1, 1, 10), also on logarithmic axes."""


def check_format(output: str | Path) -> Path:
    """The figure path, if its extension is a known format and it can be written.

    Raises
    ------
    InputError
        The extension is not .png, .pdf or .svg, the folder cannot be written, or a file that is
        not a figure rockbridge wrote is there (`paths.checked_output`).
    """
    output = Path(output)
    if output.suffix.lower() not in FORMATS:
        raise InputError(
            output, [("", f"unknown figure format {output.suffix!r}: use {', '.join(FORMATS)}")]
        )
    return checked_output(output, what="a figure rockbridge wrote")


def style(index: int, filled: bool = True) -> dict:
    """Matplotlib keywords of series ``index``: colour, marker, line style and marker fill."""
    colour = _SHADES[index % len(_SHADES)]
    return {
        "color": colour,
        "marker": _MARKERS[index % len(_MARKERS)],
        "linestyle": _LINES[index % len(_LINES)],
        "markerfacecolor": colour if filled and index % 2 == 0 else "white",
        "markeredgecolor": colour,
    }


def plain(text: str) -> str:
    """A user's text (a bridge's name, a record's) as Matplotlib shows it literally: a ``$``
    would start mathematics, which a stray one breaks (the figure fails to draw)."""
    return text.replace("$", r"\$")


def series_labels(bridges: dict[str, dict]) -> dict[str, str]:
    """Each bridge's legend label: its name (as `plain` text), or its id where names repeat (a
    sweep's variants share their base bridge's name)."""
    names = [attributes["name"] for attributes in bridges.values()]
    return {
        bridge: plain(attributes["name"]) if names.count(attributes["name"]) == 1 else bridge
        for bridge, attributes in bridges.items()
    }


def legend_columns(entries: int) -> int:
    """Columns of a figure legend above the panels, so that it stays within the figure."""
    return 1 if entries <= 2 else (2 if entries <= 6 else 3)


def panel_label(axes, letter: str) -> None:
    """The panel's letter (A, B, …) above its top-left corner, as the paper labels its figures."""
    axes.set_title(f"({letter})", loc="left", fontweight="bold")


def save(figure: Figure, output: Path) -> Path:
    """Write the figure (format from the extension), marked as rockbridge's, and return its
    path."""
    output.parent.mkdir(parents=True, exist_ok=True)
    FigureCanvasAgg(figure)
    figure.savefig(output, dpi=200, metadata=maker_metadata(output.suffix))
    return output
