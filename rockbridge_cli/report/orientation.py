"""The report's section of a study whose records section has an orientation
(`config.orientation`): what the direction the bridge feels does to its demand, over the pairs
(`assessment.orientation.across_pairs`) and pair by pair (`orientation_summary`), each quantity
in the unit the peak table shows it in."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..core.quantities import display_unit
from .markup import MAX_ROWS, cell, escaped, table_html

if TYPE_CHECKING:
    import pandas as pd

INTRODUCTION = (
    "Each pair of horizontal components was analysed along several angles of the bridge's axis, "
    "θ from the pair's first component (0°) toward its second (90°). For each quantity: its "
    "value along the first component alone, its median over the angles (the response "
    "counterpart of RotD50), its worst (RotD100's) and the critical angle, the first at which "
    "the worst occurs. rockbridge peaks RESULTS --orientation [--json] prints the same."
)


def orientation_section(results: Path, units: dict[str, str]) -> str:
    """The section, or "" when no record of ``results`` was analysed along an angle.

    Parameters
    ----------
    results
        The HDF5 results file.
    units
        The peak table's units (`results.reading.peak_units`).
    """
    from ..assessment.orientation import across_pairs, summary_of

    summary = summary_of(results)
    if summary.empty:
        return ""
    suite = across_pairs(summary)
    levels = bool(summary["intensity"].notna().any())
    over = ["bridge", *(["level"] if levels else []), "quantity", "pairs", "0° (first)",
            "median", "worst", "worst/first, median", "worst/first, max"]  # fmt: skip
    each = ["bridge", "pair", *(["level"] if levels else []), "quantity", "0° (first)", "median",
            "worst", "critical [deg]", "angles"]  # fmt: skip
    more = f'<p class="note">{len(summary) - MAX_ROWS} more rows.</p>' if (
        len(summary) > MAX_ROWS) else ""  # fmt: skip
    suite_rows = _rows(suite, units, levels, pair=False)
    pair_rows = _rows(summary.head(MAX_ROWS), units, levels, pair=True)
    return (
        f"<h2>Orientation</h2>\n<p>{escaped(INTRODUCTION)}</p>\n"
        "<p>Over the pairs (medians; worst/first: how much the worst angle raises a pair's first "
        "component alone):</p>\n"
        f"{table_html(over, suite_rows, text_columns=(0, 1 + levels))}\n<p>Pair by pair:</p>\n"
        f"{table_html(each, pair_rows, text_columns=(0, 1, 2 + levels))}{more}"
    )


def _rows(table: pd.DataFrame, units: dict[str, str], levels: bool, pair: bool) -> list[list]:
    """The cells of `orientation_summary`'s rows (``pair``) or `across_pairs`' rows, each
    quantity with its shown unit after its name."""
    rows = []
    for row in table.itertuples(index=False):
        unit, scale = display_unit(units.get(row.quantity, "-"))
        name = row.quantity if unit in ("-", "") else f"{row.quantity} [{unit}]"
        values = [cell(getattr(row, key), scale) for key in ("first", "median", "worst")]
        level = [cell(row.intensity, 1.0)] if levels else []
        if pair:
            angle = [cell(row.critical_angle_deg, 1.0), row.angles]
            rows.append([row.bridge, row.pair, *level, name, *values, *angle])
        else:
            ratios = [cell(row.worst_over_first_median, 1.0), cell(row.worst_over_first_max, 1.0)]
            rows.append([row.bridge, *level, name, str(row.pairs), *values, *ratios])
    return rows
