"""Fig. 10 of Thomaidis, Camara & Kappos (2022): response histories of several bridges under one
record.

(A) u_deck, with the end-joint gap ±u_jo (dotted); (B) v_deck; (C) θ_deck; (D) θ1 (tall pier);
(E) θ2 (short pier); one line style per bridge.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

from matplotlib.figure import Figure

from ..errors import InputError
from ..results.reading import bridge_attributes, history_arrays, open_results
from .common import check_format, panel_label, save, style

PANELS = (
    ("u_deck", 1e3, r"$u_{deck}^{CG}$ [mm]"),
    ("v_deck", 1e3, r"$v_{deck}^{CG}$ [mm]"),
    ("theta_deck", 1e3, r"$\theta_{deck}$ [mrad]"),
    ("theta1", 1e3, r"$\theta_1$ [mrad]"),
    ("theta2", 1e3, r"$\theta_2$ [mrad]"),
)
"""History, scale from SI to the axis unit, axis label."""


def plot_history(
    results: str | Path, record: str, output: str | Path, bridges: Sequence[str] = ()
) -> Path:
    """Draw Fig. 10 for one record from a results file.

    Parameters
    ----------
    results
        The HDF5 results file (`rockbridge_cli.results`).
    record
        The record id.
    output
        The figure file: .png, .pdf or .svg.
    bridges
        Bridge ids to draw; default all of the file's.

    Raises
    ------
    InputError
        An unknown bridge or record, or an analysis without the histories the figure needs.
    """
    output = check_format(output)
    with open_results(results) as file:
        table = bridge_attributes(file)
        chosen = list(bridges) or list(table)
        unknown = [b for b in chosen if b not in table]
        if unknown:
            raise InputError(
                results,
                [("", f"no bridge {', '.join(unknown)}; the file has {', '.join(table)}")],
            )
        histories = {b: history_arrays(file, results, b, record) for b in chosen}
    for bridge, arrays in histories.items():
        missing = [name for name, _, _ in PANELS if name not in arrays]
        if missing:
            raise InputError(
                results, [(f"analyses/{bridge}/{record}", f"no {', '.join(missing)} history")]
            )
    figure = Figure(figsize=(8.0, 11.0), layout="constrained")
    axes_list = figure.subplots(len(PANELS), 1, sharex=True)
    for (name, scale, label), axes, letter in zip(PANELS, axes_list, "ABCDE", strict=True):
        for index, (bridge, arrays) in enumerate(histories.items()):
            axes.plot(arrays["time"], arrays[name] * scale, linewidth=1.0, marker="none",
                      label=table[bridge]["name"],
                      **{k: v for k, v in style(index).items() if "marker" not in k})  # fmt: skip
        axes.set_ylabel(label)
        axes.grid(True, color="0.9", linewidth=0.5)
        panel_label(axes, letter)
    gaps = {table[b]["model_u_jo"] for b in chosen} - {math.inf}
    for gap in sorted(gaps):
        for sign in (1.0, -1.0):
            axes_list[0].axhline(sign * gap * 1e3, color="black", linestyle=":", linewidth=0.8)
    handles, labels = axes_list[0].get_legend_handles_labels()
    figure.legend(handles, labels, loc="outside upper center", ncols=3, frameon=False)
    axes_list[0].set_title(f"record {record}" + (" (dotted: end-joint gap ±u_jo)" if gaps else ""))
    axes_list[-1].set_xlabel("time t [s]")
    return save(figure, output)
