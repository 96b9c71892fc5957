"""IDA curves: per bridge, each record's peak response against the intensity it was scaled to
(one thin line per record through every level run), the analyses that ended in a failure of the
bridge (crosses), and each record's capacity for each limit state (markers, one per state)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..assessment.fragility import fragilities_of
from ..core.quantities import NO_FAILURE, SHOWN, display_unit
from ..errors import InputError
from ..motions.intensity import MEASURES
from ..results.reading import (
    bridge_attributes,
    open_results,
    peak_columns,
    peak_units,
    read_intensity,
)
from .common import check_format, panel_label, save, series_labels, style

"""Units drawn in thousandths."""

PANEL_WIDTH, MIN_WIDTH = 4.0, 6.0
"""Width of a bridge's panel, and of the figure at least, so that one bridge's legend (two
entries a row) fits [in]."""


def plot_ida(results: str | Path, output: str | Path, quantity: str = "u_deck_max") -> Path:
    """Draw the IDA curves of a results file with an IDA (or stripes) section.

    Parameters
    ----------
    quantity
        The peak-table column on the horizontal axis.

    Raises
    ------
    InputError
        The study has no intensity section, or ``quantity`` is not a numeric peak column.

    Returns
    -------
    pathlib.Path
        The figure file.
    """
    output = check_format(output)
    with open_results(results) as file:
        intensity = read_intensity(file)
        columns, units = peak_columns(file), peak_units(file)
        names = series_labels(bridge_attributes(file))
    if intensity is None:
        raise InputError(results, [("", "the study has no intensity section: no IDA curves")])
    if quantity not in columns or columns[quantity].dtype.kind != "f" or quantity in (
        "intensity", "scale"
    ):  # fmt: skip
        choices = [n for n, v in columns.items() if v.dtype.kind == "f"]
        raise InputError(results, [("quantity", f"not a peak column: {quantity!r}; choose "
                                                f"from {', '.join(choices)}")])  # fmt: skip
    unit, factor = display_unit(units[quantity])
    ok = columns["status"] != "error"
    columns = {name: values[ok] for name, values in columns.items()}
    capacities = {(f.bridge, f.limit_state): f.capacities
                  for f in fragilities_of(columns, intensity, bootstrap=0)}  # fmt: skip
    states = list(dict.fromkeys(state for _, state in capacities))
    bridges = list(dict.fromkeys(columns["bridge"]))
    figure = Figure(figsize=(max(PANEL_WIDTH * len(bridges), MIN_WIDTH), 4.5), layout="constrained")
    panels = np.atleast_1d(figure.subplots(1, len(bridges), sharex=True, sharey=True))
    for axes, bridge, letter in zip(panels, bridges, "ABCDEFGHIJKLMNOPQRSTUVWXYZ", strict=False):
        mine = {name: values[columns["bridge"] == bridge] for name, values in columns.items()}
        response = mine[quantity] * factor
        for record in dict.fromkeys(mine["base_record"]):
            rows = np.flatnonzero(mine["base_record"] == record)
            rows = rows[np.argsort(mine["intensity"][rows])]
            axes.plot(response[rows], mine["intensity"][rows], color="0.6", linewidth=0.7)
            failed = rows[mine["failure_mode"][rows] != NO_FAILURE]
            axes.plot(response[failed], mine["intensity"][failed], linestyle="none",
                      marker="x", color="0.3", markersize=4)  # fmt: skip
            for index, state in enumerate(states):
                level = capacities[(bridge, state)].get(record)
                at = rows[mine["intensity"][rows] == level]
                if level is None or not at.size:
                    continue
                look = style(index)
                axes.plot(response[at[:1]], [level], linestyle="none", marker=look["marker"],
                          color=look["color"], markerfacecolor=look["markerfacecolor"],
                          markeredgecolor=look["markeredgecolor"],
                          label=state.replace("_", " "))  # fmt: skip
        axes.set_title(names.get(bridge, bridge))  # as Fig. 9 names them
        shown = SHOWN.get(quantity.removesuffix("_max"))
        axes.set_xlabel(f"peak {shown.tex} [{unit}]" if shown else f"{quantity} [{unit}]")
        axes.grid(True, color="0.9", linewidth=0.5)
        panel_label(axes, letter)
    panels[0].set_ylabel(MEASURES[intensity.measure].label)
    labelled = {
        label: handle
        for axes in panels
        for handle, label in zip(*axes.get_legend_handles_labels(), strict=True)
    }
    figure.legend(labelled.values(), labelled.keys(), loc="outside upper center",
                  ncols=min(len(labelled), 2 * len(bridges), 4), frameon=False,
                  title="capacity (first level reaching it); x: the bridge failed")  # fmt: skip
    return save(figure, output)
