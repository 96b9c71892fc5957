"""Fig. 9 of Thomaidis, Camara & Kappos (2022): peak responses per record, one marker per bridge.

(A) u_deck, with the end-joint gap u_jo (dotted) and the abutment–backfill failure u_jo + u_ab
(dashed); (B) v_deck; (C) θ_deck; (D) θ1 (tall pier); (E) θ2 (short pier); (F) the paper's
demand/capacity ratio, the backfill's (|u_deck| − u_jo)/u_ab (docs/model.md §8), with failure at
100 %.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..results.reading import bridge_attributes, open_results, peak_columns
from .common import check_format, panel_label, save, style

PANELS = (
    ("u_deck_max", 1e3, r"$u_{deck}^{CG}$ [mm]"),
    ("v_deck_max", 1e3, r"$v_{deck}^{CG}$ [mm]"),
    ("theta_deck_max", 1e3, r"$\theta_{deck}$ [mrad]"),
    ("theta1_max", 1e3, r"$\theta_1$ (tall pier) [mrad]"),
    ("theta2_max", 1e3, r"$\theta_2$ (short pier) [mrad]"),
    ("dcr_backfill", 100.0, r"backfill demand/capacity [%]"),
)
"""Column of the peak table, scale from SI to the axis unit, axis label."""


def plot_peaks(results: str | Path, output: str | Path) -> Path:
    """Draw Fig. 9 from a results file.

    Parameters
    ----------
    results
        The HDF5 results file (`rockbridge_cli.results`).
    output
        The figure file: .png, .pdf or .svg.

    Returns
    -------
    pathlib.Path
        The figure file.
    """
    output = check_format(output)
    with open_results(results) as file:
        peaks, bridges = peak_columns(file), bridge_attributes(file)
    records = list(dict.fromkeys(peaks["record"]))
    figure = Figure(figsize=(10.0, 9.6), layout="constrained")
    grid = figure.subplots(3, 2, sharex=True)
    width = 0.5 / max(len(bridges), 1)
    positions = {record: index for index, record in enumerate(records)}
    for (column, scale, label), axes, letter in zip(PANELS, grid.flat, "ABCDEF", strict=True):
        for index, (bridge, attributes) in enumerate(bridges.items()):
            mine = peaks["bridge"] == bridge
            offset = (index - (len(bridges) - 1) / 2) * width
            x = np.array([positions[record] for record in peaks["record"][mine]]) + offset
            axes.plot(
                x, peaks[column][mine] * scale, linestyle="none", markersize=6,
                label=attributes["name"],
                **{k: v for k, v in style(index).items() if k != "linestyle"},
            )  # fmt: skip
        axes.set_ylabel(label)
        axes.grid(True, axis="y", color="0.9", linewidth=0.5)
        axes.set_xticks(np.arange(len(records)), records, rotation=45 if len(records) > 12 else 0)
        axes.tick_params(labelbottom=True)
        panel_label(axes, letter)
    _limits(grid[0, 0], bridges)
    grid[-1, -1].axhline(100.0, color="black", linestyle="--", linewidth=1.0)  # backfill failure
    for axes in grid.flat:  # from zero, with the markers and limit lines clear of the top frame
        axes.set_ylim(0.0, 1.08 * axes.get_ylim()[1])
    for axes in grid[-1]:
        axes.set_xlabel("record")
    handles, labels = grid[0, 0].get_legend_handles_labels()
    figure.legend(handles, labels, loc="outside upper center", ncols=3, frameon=False)
    return save(figure, output)


def _limits(axes, bridges: dict) -> None:
    """Horizontal lines of the end-joint gap and of abutment failure (bridges with abutments)."""
    seen = set()
    for bridge in bridges.values():
        gap, ultimate = bridge["model_u_jo"], bridge["model_u_ab"]
        if not math.isfinite(gap) or (gap, ultimate) in seen:
            continue
        seen.add((gap, ultimate))
        lines = (
            (gap, ":", f"contact, $u_{{jo}}$ = {gap * 1e3:.0f} mm"),
            (
                gap + ultimate,
                "--",
                f"failure, $u_{{jo}} + u_{{ab}}$ = {(gap + ultimate) * 1e3:.0f} mm",
            ),
        )
        for value, line, label in lines:
            axes.axhline(value * 1e3, color="black", linestyle=line, linewidth=1.0, label=label)
