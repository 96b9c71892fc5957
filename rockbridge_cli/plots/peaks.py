"""Fig. 9 of Thomaidis, Camara & Kappos (2022): peak responses per record, one marker per bridge.

(A) u_deck, with the end-joint gap u_jo (dotted) and the abutment–backfill failure u_jo + u_ab
(dashed); (B) v_deck; (C) θ_deck; (D) θ1 (tall pier); (E) θ2 (short pier).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..results import read_bridges, read_peaks
from .common import check_format, panel_label, save, style

PANELS = (
    ("u_deck_max", 1e3, r"$u_{deck}^{CG}$ [mm]"),
    ("v_deck_max", 1e3, r"$v_{deck}^{CG}$ [mm]"),
    ("theta_deck_max", 1e3, r"$\theta_{deck}$ [mrad]"),
    ("theta1_max", 1e3, r"$\theta_1$ (tall pier) [mrad]"),
    ("theta2_max", 1e3, r"$\theta_2$ (short pier) [mrad]"),
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
    peaks = read_peaks(results)
    bridges = read_bridges(results)
    records = list(dict.fromkeys(peaks["record"]))
    figure = Figure(figsize=(10.0, 9.0), layout="constrained")
    grid = figure.subplots(3, 2, sharex=True)
    width = 0.5 / max(len(bridges), 1)
    for (column, scale, label), axes, letter in zip(PANELS, grid.flat, "ABCDE", strict=False):
        for index, bridge in enumerate(bridges.index):
            rows = peaks[peaks["bridge"] == bridge].set_index("record").reindex(records)
            offset = (index - (len(bridges) - 1) / 2) * width
            axes.plot(
                np.arange(len(records)) + offset, rows[column].to_numpy(float) * scale,
                linestyle="none", markersize=6, label=bridges.loc[bridge, "name"],
                **{k: v for k, v in style(index).items() if k != "linestyle"},
            )  # fmt: skip
        axes.set_ylabel(label)
        axes.grid(True, axis="y", color="0.9", linewidth=0.5)
        axes.set_xticks(np.arange(len(records)), records, rotation=45 if len(records) > 12 else 0)
        axes.tick_params(labelbottom=True)
        panel_label(axes, letter)
    _limits(grid[0, 0], bridges)
    for axes in grid.flat[: len(PANELS)]:
        axes.set_ylim(bottom=0.0)
    grid[-1, 0].set_xlabel("record")
    legend = grid[-1, -1]
    legend.axis("off")
    handles, labels = grid[0, 0].get_legend_handles_labels()
    legend.legend(handles, labels, loc="center", frameon=False)
    return save(figure, output)


def _limits(axes, bridges) -> None:
    """Horizontal lines of the end-joint gap and of abutment failure (bridges with abutments)."""
    seen = set()
    for _, bridge in bridges.iterrows():
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
