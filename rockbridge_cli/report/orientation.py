"""The report's section of a study whose records section has an orientation
(`config.orientation`): what the direction the bridge feels does to its demand, over the pairs
(`assessment.orientation.across_pairs`) and pair by pair (`orientation_summary`), each quantity
in the unit the peak table shows it in; with an intensity section, to its fragility
(`assessment.orientation_fragility`)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..core.quantities import display_unit
from ..motions.intensity import MEASURES
from .markup import MAX_ROWS, cell, escaped, number, table_html

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
        f"{_fragility(results)}"
    )


def _fragility(results: Path) -> str:
    """The fragility's median and β each angle a record and on the pairs' median and worst
    (`fragility_by_orientation`), "" without an intensity section."""
    from ..assessment.orientation_fragility import WAYS, fragility_by_orientation

    rows = fragility_by_orientation(results)
    if not rows:
        return ""
    measure = rows[0]["measure"]
    text = (f"The fragility (median θ of {measure} [{MEASURES[measure].unit}], and β) fitted "
            "three ways: each angle a record of its own, each pair of components one record "
            "reaching a state where the median over its angles does, or where its worst angle "
            "does. The run stores, and the "
            f"Fragility section shows, the {rows[0]['stored']} (the study's "
            "intensity.orientation; rockbridge fragility --orientation chooses).")  # fmt: skip
    cells = [[row["bridge"], row["limit_state"],
              *(number(row[f"{way}_{part}"]) for way in WAYS for part in ("median", "beta"))]
             for row in rows]  # fmt: skip
    headers = ["bridge", "limit state", "each angle: θ", "β", "pairs' median: θ", "β",
               "pairs' worst: θ", "β"]  # fmt: skip
    return f"\n<p>{escaped(text)}</p>\n" + table_html(headers, cells, text_columns=(0, 1))


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
