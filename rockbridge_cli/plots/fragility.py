"""Fragility curves of a study with an intensity section: per limit state, the share of records
that reach it at each intensity level (markers; from an IDA, at or below each capacity), the
fitted lognormal (lines), one style per bridge, and the 90 % band of the bootstrap's curves
(grey, `fragility_intervals.band`); and how the intervals narrow with the number of records.
Of a study that swept an orientation, the records are its pairs, as the study takes them
(`fragility.study_orientation`), and the figure says so."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import NullFormatter
from scipy.special import ndtr

from ..assessment.fragility import STUDY, Fragility, fragilities
from ..assessment.fragility_intervals import SETTLED, RecordsNeeded, all_records_needed, band
from ..assessment.orientation import COMBINED
from ..motions.intensity import MEASURES
from .common import PLAIN, check_format, panel_label, save, style


def plot_fragility(
    results: str | Path, output: str | Path, found: list[Fragility] | None = None
) -> Path:
    """Draw one panel per limit state from a results file with an intensity section.

    Parameters
    ----------
    found
        The file's fits (`fragility.fragilities`), when the caller has them already; default:
        the study's (each pair one record, where it swept an orientation).

    Returns
    -------
    pathlib.Path
        The figure file.
    """
    output = check_format(output)
    found = fragilities(results, orientation=STUDY) if found is None else found
    bridges = list(dict.fromkeys(item.bridge for item in found))
    states = list(dict.fromkeys(item.limit_state for item in found))
    paired = found[0].orientation if found else None
    rows = max(1, -(-len(states) // 2))
    figure = Figure(figsize=(9.0, 3.5 * rows), layout="constrained")
    grid = figure.subplots(rows, 2, sharex=True, sharey=True, squeeze=False)
    for axes in grid.flat[len(states) :]:
        axes.set_visible(False)
    for axes, state, letter in zip(grid.flat, states, "ABCDEFGHIJKL", strict=False):
        banded = False  # one legend entry for the bands
        for index, bridge in enumerate(bridges):
            item = next(f for f in found if f.bridge == bridge and f.limit_state == state)
            look = style(index)
            axes.plot(item.levels, item.fractions, linestyle="none", color=look["color"],
                      marker=look["marker"], markerfacecolor=look["markerfacecolor"],
                      markeredgecolor=look["markeredgecolor"], label=bridge)  # fmt: skip
            if item.median is not None and item.beta is not None:
                x = np.geomspace(min(item.levels) / 2, max(item.levels) * 1.5, 200)
                spread = band(item.draws, x)
                if spread is not None:
                    label = None if banded else "90 % band (bootstrap)"
                    axes.fill_between(x, *spread, color="0.5", alpha=0.2, linewidth=0, zorder=1,
                                      label=label)  # fmt: skip
                    banded = True
                axes.plot(x, ndtr(np.log(x / item.median) / item.beta),
                          color=look["color"], linestyle=look["linestyle"], zorder=3)  # fmt: skip
        axes.set_title(state.replace("_", " "))
        mine = [f for f in found if f.limit_state == state]
        if all(c is None for f in mine for c in f.capacities.values()):
            unreachable = all(len(f.unreachable) == len(f.capacities) for f in mine)
            why = ("unreachable: a failure ends\nevery curve first" if unreachable else
                   f"reached by no {paired and 'pair' or 'record'}\nat the levels run")  # fmt: skip
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
        axes.set_ylabel(f"share of {'pairs' if paired else 'records'} reaching it [-]")
    handles, labels = grid[0, 0].get_legend_handles_labels()
    legend = figure.legend(handles, labels, loc="outside upper center",
                           ncols=min(len(labels), 3), frameon=False)  # fmt: skip
    if paired:
        legend.set_title(f"each pair of horizontal components: {COMBINED[paired]}")
    return save(figure, output)


def plot_records_needed(
    results: str | Path, output: str | Path, needed: list[RecordsNeeded] | None = None
) -> Path:
    """Draw, per limit state, the half-widths of the 90 % intervals of the median (filled
    markers, solid) and of β (open markers, dashed) against the number of records
    (`fragility_intervals.records_needed`), one style per bridge, and the rule's limit on the
    median's (dotted).

    Parameters
    ----------
    needed
        The widths, when the caller has them already.

    Returns
    -------
    pathlib.Path
        The figure file.
    """
    output = check_format(output)
    needed = (
        all_records_needed(fragilities(results, orientation=STUDY)) if needed is None else needed
    )
    bridges = list(dict.fromkeys(item.bridge for item in needed))
    states = list(dict.fromkeys(item.limit_state for item in needed)) or ["-"]
    counts_tried = sorted({w.records for item in needed for w in item.widths})
    rows = max(1, -(-len(states) // 2))
    figure = Figure(figsize=(9.0, 3.5 * rows), layout="constrained")
    grid = figure.subplots(rows, 2, sharex=True, sharey=True, squeeze=False)
    for axes in grid.flat[len(states) :]:
        axes.set_visible(False)
    for axes, state, letter in zip(grid.flat, states, "ABCDEFGHIJKL", strict=False):
        for index, bridge in enumerate(bridges):
            item = next((f for f in needed if f.bridge == bridge and f.limit_state == state), None)
            if item is None:
                continue
            look = style(index)
            counts = [w.records for w in item.widths]
            axes.plot(counts, [np.nan if w.median is None else w.median for w in item.widths],
                      color=look["color"], marker=look["marker"], linestyle="-",
                      label=f"{bridge}: median")  # fmt: skip
            axes.plot(counts, [np.nan if w.beta is None else w.beta for w in item.widths],
                      color=look["color"], marker=look["marker"], linestyle="--",
                      markerfacecolor="white", label=f"{bridge}: β")  # fmt: skip
        axes.axhline(SETTLED, color="black", linestyle=":", linewidth=1.0,
                     label=f"settled: median ± {SETTLED:.3f}")  # fmt: skip
        axes.set_title(state.replace("_", " "))
        axes.set_xscale("log")
        axes.set_xticks(counts_tried, [str(n) for n in counts_tried])
        axes.xaxis.set_minor_formatter(NullFormatter())
        axes.grid(True, color="0.9", linewidth=0.5)
        panel_label(axes, letter)
    widths = [v for f in needed for w in f.widths for v in (w.median, w.beta) if v is not None]
    grid[0, 0].set_ylim(0.0, 1.05 * max([SETTLED, *widths]))  # the panels share it
    for axes in grid.flat[: len(states)]:  # above an empty panel too, not the last row's only
        axes.tick_params(labelbottom=True)
        axes.set_xlabel("records n [-]")
    for axes in grid[:, 0]:
        axes.set_ylabel("half-width of the 90 % interval [-]")
    handles, labels = grid[0, 0].get_legend_handles_labels()
    figure.legend(handles, labels, loc="outside upper center", ncols=min(len(labels), 3),
                  frameon=False)  # fmt: skip
    return save(figure, output)
