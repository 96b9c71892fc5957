"""Which sampled field matters, drawn (`assessment.sensitivity`): Sobol' indices of a study with a
saltelli design (per bridge file, each field's first-order index, filled, beside its total order,
open, with their bootstrap intervals), or a tornado's one-at-a-time swings."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..assessment.sensitivity import Sensitivity, sensitivities, tornadoes
from .common import check_format, panel_label, save


def plot_sensitivity(
    results: str | Path,
    output: str | Path,
    quantity: str = "dcr_backfill",
    statistic: str = "mean",
    found: list[Sensitivity] | None = None,
) -> Path:
    """Draw the indices of ``quantity`` (`assessment.sensitivity.sensitivities`).

    Returns
    -------
    pathlib.Path
        The figure file.
    """
    output = check_format(output)
    found = sensitivities(results, quantity, statistic) if found is None else found
    fields = len(found[0].fields) if found else 1
    figure = Figure(figsize=(8.0, (0.45 * fields + 1.4) * max(len(found), 1)),
                    layout="constrained")  # fmt: skip
    grid = figure.subplots(max(len(found), 1), 1, squeeze=False, sharex=True)
    for axes, item, letter in zip(grid[:, 0], found, "ABCDEFGHIJKL", strict=False):
        names = [f.field for f in item.fields]
        y = np.arange(len(names))
        for offset, which, face, label in ((-0.18, "first", "0.35", "first order"),
                                           (0.18, "total", "white", "total order")):  # fmt: skip
            values = np.array([getattr(f, which) for f in item.fields])
            bounds = np.array([getattr(f, f"{which}_interval") for f in item.fields]).T
            errors = np.abs(bounds - values)
            axes.barh(y + offset, values, height=0.34, color=face, edgecolor="black",
                      linewidth=0.7, label=label)  # fmt: skip
            axes.errorbar(values, y + offset, xerr=errors, fmt="none", ecolor="black",
                          elinewidth=0.7, capsize=2)  # fmt: skip
        axes.set_yticks(y, names)
        axes.invert_yaxis()
        axes.axvline(0.0, color="0.5", linewidth=0.6)
        axes.set_title(f"{item.bridge}: {item.statistic} of {item.quantity} over {item.records} "
                       f"records, n = {item.samples}\nrecord-to-record share of its variance "
                       f"{item.records_share:.2f}", fontsize=9, loc="left")  # fmt: skip
        axes.grid(True, axis="x", color="0.9", linewidth=0.5)
        if len(found) > 1:
            panel_label(axes, letter)
    grid[-1, 0].set_xlabel("Sobol' index [-]; whiskers: 90 % bootstrap interval")
    handles, labels = grid[0, 0].get_legend_handles_labels()
    figure.legend(handles, labels, loc="outside upper center", ncols=2, frameon=False)
    return save(figure, output)


def plot_tornado(
    results: str | Path, output: str | Path, quantity: str = "dcr_backfill", statistic: str = "mean"
) -> Path:
    """Draw the one-at-a-time swings of ``quantity`` of a study with a tornado design
    (`assessment.sensitivity.tornadoes`): per bridge file, a bar per field from the output at
    its low percentile (grey) to that at its high one (white), about the median bridge's."""
    output = check_format(output)
    found = tornadoes(results, quantity, statistic)
    fields = len(found[0].swings) if found else 1
    figure = Figure(figsize=(8.0, (0.4 * fields + 1.4) * max(len(found), 1)),
                    layout="constrained")  # fmt: skip
    grid = figure.subplots(max(len(found), 1), 1, squeeze=False)
    for axes, item, letter in zip(grid[:, 0], found, "ABCDEFGHIJKL", strict=False):
        y = np.arange(len(item.swings))
        for end, face, label in ((0, "0.55", "field at its low percentile"),
                                 (1, "white", "field at its high percentile")):  # fmt: skip
            widths = [s.outputs[end] - item.median for s in item.swings]
            axes.barh(y, widths, left=item.median, height=0.6, color=face, edgecolor="black",
                      linewidth=0.7, label=label)  # fmt: skip
        axes.axvline(item.median, color="black", linewidth=0.8)
        axes.set_yticks(y, [f"{s.field} ({s.values[0]:.3g}–{s.values[1]:.3g})"
                            for s in item.swings])  # fmt: skip
        axes.invert_yaxis()
        axes.set_title(item.bridge, fontsize=9, loc="left")
        axes.set_xlabel(f"{item.statistic} of {item.quantity} (line: every field at its median, "
                        f"{item.median:.3g})")  # fmt: skip
        axes.grid(True, axis="x", color="0.9", linewidth=0.5)
        if len(found) > 1:
            panel_label(axes, letter)
    handles, labels = grid[0, 0].get_legend_handles_labels()
    figure.legend(handles, labels, loc="outside upper center", ncols=2, frameon=False)
    return save(figure, output)
