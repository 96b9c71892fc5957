"""Fragility curves of a study with an intensity section: per limit state, the share of records
that reach it at each intensity level (markers; from an IDA, at or below each capacity) and the
fitted lognormal (lines), one style per bridge."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from scipy.stats import norm

from ..assessment.fragility import Fragility, fragilities
from ..motions.intensity import MEASURES
from .common import PLAIN, check_format, panel_label, save, style


def plot_fragility(
    results: str | Path, output: str | Path, found: list[Fragility] | None = None
) -> Path:
    """Draw one panel per limit state from a results file with an intensity section.

    Parameters
    ----------
    found
        The file's fits (`fragility.fragilities`), when the caller has them already.

    Returns
    -------
    pathlib.Path
        The figure file.
    """
    output = check_format(output)
    found = fragilities(results) if found is None else found
    bridges = list(dict.fromkeys(item.bridge for item in found))
    states = list(dict.fromkeys(item.limit_state for item in found))
    rows = max(1, -(-len(states) // 2))
    figure = Figure(figsize=(9.0, 3.5 * rows), layout="constrained")
    grid = figure.subplots(rows, 2, sharex=True, sharey=True, squeeze=False)
    for axes in grid.flat[len(states) :]:
        axes.set_visible(False)
    for axes, state, letter in zip(grid.flat, states, "ABCDEFGHIJKL", strict=False):
        for index, bridge in enumerate(bridges):
            item = next(f for f in found if f.bridge == bridge and f.limit_state == state)
            look = style(index)
            axes.plot(item.levels, item.fractions, linestyle="none", color=look["color"],
                      marker=look["marker"], markerfacecolor=look["markerfacecolor"],
                      markeredgecolor=look["markeredgecolor"], label=bridge)  # fmt: skip
            if item.median is not None and item.beta is not None:
                x = np.geomspace(min(item.levels) / 2, max(item.levels) * 1.5, 200)
                axes.plot(x, norm.cdf(np.log(x / item.median) / item.beta),
                          color=look["color"], linestyle=look["linestyle"])  # fmt: skip
        axes.set_title(state.replace("_", " "))
        mine = [f for f in found if f.limit_state == state]
        if all(c is None for f in mine for c in f.capacities.values()):
            unreachable = all(len(f.unreachable) == len(f.capacities) for f in mine)
            why = ("unreachable: a failure ends\nevery curve first" if unreachable else
                   "reached by no record\nat the levels run")  # fmt: skip
            axes.text(0.5, 0.5, why, ha="center", va="center", transform=axes.transAxes,
                      color="0.4")  # fmt: skip
        axes.set_xscale("log")
        axes.xaxis.set_major_formatter(PLAIN)  # 0.1, 1 rather than 10⁻¹, 10⁰
        axes.set_ylim(-0.03, 1.03)
        axes.grid(True, color="0.9", linewidth=0.5)
        panel_label(axes, letter)
    for axes in grid[-1]:
        axes.set_xlabel(MEASURES[found[0].measure].label if found else "")
    for axes in grid[:, 0]:
        axes.set_ylabel("share of records reaching it [-]")
    handles, labels = grid[0, 0].get_legend_handles_labels()
    figure.legend(handles, labels, loc="outside upper center", ncols=min(len(labels), 3),
                  frameon=False)  # fmt: skip
    return save(figure, output)
