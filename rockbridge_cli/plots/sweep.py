"""A peak or a capacity against a swept bridge field (`config.sweep`): per bridge, the median over
the records with the 16–84 % band of a peak (in a multiple-stripe study, at one intensity level),
or the median capacity of a limit state with its 90 % interval; one line per bridge file (and, in
a grid, per value of the other swept fields)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.colors import LinearSegmentedColormap, Normalize
from matplotlib.figure import Figure

from ..assessment.fragility import fragilities_of
from ..assessment.levels import rows_at_level
from ..core.quantities import check_limit_state, display_unit
from ..errors import InputError
from ..motions.intensity import MEASURES
from ..results.reading import (
    open_results,
    peak_columns,
    peak_units,
    read_intensity,
    swept_values,
)
from ..results.sections import IntensitySection
from .common import check_format, save, style

RAMP_LINES = 6
"""More lines than this along one other swept field are drawn in a grey ramp (`ramp_field`)."""

RAMP = LinearSegmentedColormap.from_list("rockbridge-greys", ["0.78", "0.0"])
"""Light grey (the other field's lowest value) to black (its highest), readable in print."""


def plot_sweep(
    results: str | Path,
    output: str | Path,
    field: str,
    quantity: str = "u_deck_max",
    level: float | None = None,
) -> Path:
    """Draw ``quantity`` against the swept ``field``.

    Parameters
    ----------
    field
        A swept field's dotted path (``abutments.gap``).
    quantity
        A numeric peak column (median over the records), or a limit state (median capacity, for
        a study with an intensity section).
    level
        The intensity level of a peak in a multiple-stripe study [the measure's unit]: the
        records' median is taken at one level, never over all at once.

    Raises
    ------
    InputError
        ``field`` is not swept, ``quantity`` is neither a peak column nor, with an intensity
        section, a limit state; or a peak is asked of an IDA, or of stripes without one of
        their levels.

    Returns
    -------
    pathlib.Path
        The figure file.
    """
    output = check_format(output)
    with open_results(results) as file:
        columns, units = peak_columns(file), peak_units(file)
        swept = swept_values(file)
        varies = {name: json.loads(node.attrs.get("varied", "[]"))
                  for name, node in file["bridges"].items()}  # fmt: skip
        intensity = read_intensity(file)
    fields = list(dict.fromkeys(path for values in swept.values() for path in values))
    if field not in fields:
        reason = f"{field!r} is not swept here; swept: {', '.join(fields) or 'nothing'}"
        raise InputError(results, [("field", reason)])
    capacity = intensity is not None and _is_limit_state(quantity)
    if not capacity and (quantity not in columns or columns[quantity].dtype.kind != "f"):
        also = " or a limit state" if intensity is not None else ""
        reason = f"not a peak column{also}: {quantity!r}"
        raise InputError(results, [("quantity", reason)])
    rows, level = _rows(results, columns, intensity, quantity, capacity, level)
    columns = {name: values[rows] for name, values in columns.items()}
    bridges = [b for b in dict.fromkeys(columns["bridge"]) if field in varies.get(b, ())]
    mine = {b: swept[b] for b in bridges}
    lines = _lines(columns, mine, field, quantity, intensity if capacity else None)
    factor, unit = (1.0, unit_of(intensity) if intensity is not None else "-")
    if not capacity:
        unit, factor = display_unit(units[quantity])
    sources = {source for source, _ in lines}
    one = len(sources) == 1  # the bridge named once, as the legend's title, not on each line
    ramp = ramp_field(lines)
    figure = Figure(figsize=(6.5 + 3.0 * (len(lines) > 1 and ramp is None), 4.5),
                    layout="constrained")  # fmt: skip
    axes = figure.subplots()
    _draw(figure, axes, lines, factor, ramp, units)
    what = f"capacity: {quantity.replace('_', ' ')}" if capacity else quantity
    band = "median, 90 % interval" if capacity else "median over the records, 16–84 %"
    if level is not None and intensity is not None:
        band += f", at {intensity.measure} = {level:g} {unit_of(intensity)}"
    axes.set_title(band, fontsize="medium")
    axes.set_xlabel(f"{field} [{units.get(field, '-')}]")
    axes.set_ylabel(f"{what} [{unit}]")
    axes.grid(True, color="0.9", linewidth=0.5)
    # beside the axes, not over the curves; and not loc="best", which matplotlib warns is slow
    # with many points (the warning reached the terminal on large sweeps)
    if ramp is None:
        figure.legend(loc="outside right upper", frameon=False, fontsize="small",
                      title=next(iter(sources)) if one and len(lines) > 1 else None,
                      title_fontsize="small")  # fmt: skip
    else:
        axes.set_title(f"{next(iter(sources))}: {band}", fontsize="medium")
    return save(figure, output)


def _draw(figure, axes, lines: dict[tuple, list], factor: float, ramp, units: dict) -> None:
    """The sweep's lines and bands: one style each, labelled by bridge file and the other swept
    fields' values; or, along a ramp field (`ramp_field`), greys by its value and a colour bar."""
    one = len({source for source, _ in lines}) == 1
    shades = Normalize(*ramp[1]) if ramp is not None else None
    for index, ((source, others), points) in enumerate(lines.items()):
        x, middles, lows, highs = (np.array(v) for v in zip(*sorted(points), strict=True))
        if shades is not None:  # one line style, a grey by the other field's value
            look = {"color": RAMP(shades(others[0][1])), "linestyle": "-", "marker": "."}
            label = None
        else:
            look = style(index)
            label = ", ".join([*([] if one and others else [source]),
                               *(f"{p} = {v:.4g}" for p, v in others)])  # fmt: skip
        axes.plot(x, middles * factor, label=label, **look)
        axes.fill_between(x, lows * factor, highs * factor, color=look["color"],
                          alpha=0.12 if shades is None else 0.05, linewidth=0)  # fmt: skip
    if ramp is not None and shades is not None:
        bar = figure.colorbar(ScalarMappable(shades, RAMP), ax=axes)
        bar.set_label(f"{ramp[0]} [{units.get(ramp[0], '-')}]")


def ramp_field(lines: dict[tuple, list]) -> tuple[str, tuple[float, float]] | None:
    """The other swept field and its range where the lines are those of one bridge file along
    one other field with more than `RAMP_LINES` values (a grid's second field): told apart by
    a grey ramp and a colour bar, not a legend entry each; None otherwise."""
    others = [other for _, other in lines]
    if len({source for source, _ in lines}) != 1 or len(others) <= RAMP_LINES:
        return None
    if any(len(other) != 1 for other in others) or len({o[0][0] for o in others}) != 1:
        return None
    values = [float(other[0][1]) for other in others]
    if not all(np.isfinite(values)):
        return None
    return others[0][0][0], (min(values), max(values))


def _rows(
    results: str | Path, columns: dict, intensity: IntensitySection | None, quantity: str,
    capacity: bool,
    level: float | None,
) -> tuple[np.ndarray, float | None]:  # fmt: skip
    """The rows drawn (analyses that ran; a peak's at one intensity level) and that level."""
    ok = columns["status"] != "error"
    if level is not None and (capacity or intensity is None):
        reason = "--level picks the stripe of a peak in a study with intensity levels"
        raise InputError(results, [("level", reason)])
    if capacity or intensity is None:
        return ok, level
    try:
        rows, level = rows_at_level(columns, intensity, level, unit_of(intensity))
    except ValueError as exc:
        where = "quantity" if intensity.ida is not None else "level"
        also = "; or a limit state's capacity" if intensity.ida is not None else ""
        reason = f"{quantity!r} per swept value: {exc}{also}"
        raise InputError(results, [(where, reason)]) from None
    return ok & rows, level


def _lines(
    columns: dict, swept: dict[str, dict[str, float]], field: str, quantity: str,
    capacity: IntensitySection | None,
) -> dict[tuple, list[tuple[float, float, float, float]]]:  # fmt: skip
    """Per line (bridge file, values of the other swept fields), the points (field value, median,
    low, high) of the bridges in ``swept`` (their swept values, by bridge id): of a peak, or of
    the capacity ``quantity`` names, given the study's intensity section as ``capacity``."""
    fits = {}
    if capacity is not None:
        mine = np.isin(columns["bridge"], list(swept))
        found = fragilities_of({k: v[mine] for k, v in columns.items()}, capacity)
        fits = {f.bridge: f for f in found if f.limit_state == quantity}
    lines: dict[tuple, list[tuple[float, float, float, float]]] = {}
    for bridge, values in swept.items():
        others = tuple((p, v) for p, v in values.items() if p != field)
        if capacity is not None:
            fit = fits.get(bridge)
            middle = np.nan if fit is None or fit.median is None else fit.median
            low, high = fit.median_90 if fit is not None and fit.median_90 else (middle, middle)
        else:
            peaks = columns[quantity][columns["bridge"] == bridge]
            middle, low, high = (float(v) for v in np.percentile(peaks, [50.0, 16.0, 84.0]))
        lines.setdefault((bridge.split("+", 1)[0], others), []).append(
            (values[field], middle, low, high)
        )
    return lines


def unit_of(intensity: IntensitySection) -> str:
    """The unit of a study's intensity measure."""
    return MEASURES[intensity.measure].unit


def _is_limit_state(name: str) -> bool:
    try:
        check_limit_state(name)
    except ValueError:
        return False
    return True
