"""Fig. 9 of Thomaidis, Camara & Kappos (2022): peak responses per record, one marker per bridge.

(A) u_deck, with the end-joint gap u_jo (dotted) and the abutment–backfill failure u_jo + u_ab
(dashed), one pair of lines per bridge where their gaps differ; (B) v_deck; (C) θ_deck; (D) θ1
(tall pier); (E) θ2 (short pier); (F) the paper's demand/capacity ratio, the backfill's
(|u_deck| − u_jo)/u_ab (docs/model.md §8), with failure at 100 %. Right of the records, each
bridge's mean over them.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..assessment.levels import rows_at_level
from ..core.quantities import SHOWN
from ..errors import InputError
from ..motions.intensity import MEASURES
from ..results.reading import (
    bridge_attributes,
    open_results,
    peak_columns,
    read_intensity,
    swept_values,
)
from .common import (
    FAILURE_LINE,
    GAP_LINE,
    check_format,
    legend_columns,
    panel_label,
    save,
    series_labels,
    style,
)

PANELS = (
    *(
        (f"{name}_max", shown.factor, f"{shown.tex} [{shown.unit}]")
        for name, shown in SHOWN.items()
    ),
    ("dcr_backfill", 100.0, r"backfill demand/capacity [%]"),
)
"""Column of the peak table, scale from SI to the axis unit, axis label."""

MAX_TICKS = 24
"""Records labelled on the x axis at most (every k-th beyond)."""

MAX_BRIDGES = 100
"""Bridges a figure of peaks draws at most (issue 40: 1000 took 55 s, a marker each)."""

MAX_NAMED = 12
"""Bridges named one by one in the legend at most; beyond, one entry says how many (a sweep's
variants read better against their field: ``rockbridge plot sweep``)."""

MAX_LIMITS = 4
"""Bridges with different gaps whose limit lines are drawn at most."""


def plot_peaks(results: str | Path, output: str | Path, level: float | None = None) -> Path:
    """Draw Fig. 9 from a results file.

    Parameters
    ----------
    results
        The HDF5 results file (`rockbridge_cli.results`).
    output
        The figure file: .png, .pdf or .svg.
    level
        In a multiple-stripe study, the intensity level drawn [the measure's unit]: the means
        are over the records at one level, never over all at once.

    Returns
    -------
    pathlib.Path
        The figure file.

    Raises
    ------
    InputError
        A study with stripes without one of its levels, or an IDA (whose levels differ by
        record: ``rockbridge plot ida``), or more than `MAX_BRIDGES` bridges (``rockbridge plot
        sweep``).
    """
    output = check_format(output)
    with open_results(results) as file:
        peaks, bridges = peak_columns(file), bridge_attributes(file)
        intensity = read_intensity(file)
        fields = list(dict.fromkeys(f for values in swept_values(file).values() for f in values))
    if intensity is not None:
        try:
            rows, _ = rows_at_level(peaks, intensity, level, MEASURES[intensity.measure].unit)
        except ValueError as exc:
            raise InputError(results, [("level", f"Fig. 9: {exc}")]) from None
        peaks = {name: values[rows] for name, values in peaks.items()}
    if len(bridges) > MAX_BRIDGES:  # 1000 bridges took 55 s to draw, one marker each, unreadable
        sweep = (f": their peaks against the swept field: rockbridge plot sweep {results} "
                 f"--field {fields[0]}") if fields else ""  # fmt: skip
        reason = (f"{len(bridges)} bridges are more than one figure of a marker per bridge and "
                  f"record draws readably ({MAX_BRIDGES} at most){sweep}")  # fmt: skip
        raise InputError(results, [("", reason)])
    records = list(dict.fromkeys(peaks["record"]))
    figure = Figure(figsize=(10.0, 9.6), layout="constrained")
    grid = figure.subplots(3, 2, sharex=True)
    width = 0.5 / max(len(bridges), 1)
    positions = {record: index for index, record in enumerate(records)}
    mean_at = len(records) + 0.5  # the means, apart from the records
    labels = series_labels(bridges)
    every = math.ceil(len(records) / MAX_TICKS)  # label at most MAX_TICKS records
    for (column, scale, label), axes, letter in zip(PANELS, grid.flat, "ABCDEF", strict=True):
        for index, bridge in enumerate(bridges):
            mine = peaks["bridge"] == bridge
            offset = (index - (len(bridges) - 1) / 2) * width
            x = np.array([positions[record] for record in peaks["record"][mine]]) + offset
            values = peaks[column][mine] * scale
            look = {k: v for k, v in style(index).items() if k != "linestyle"}
            named = labels[bridge] if len(bridges) <= MAX_NAMED else None
            axes.plot(x, values, linestyle="none", markersize=6, label=named, **look)
            if np.isfinite(values).any():
                axes.plot(mean_at + offset, np.nanmean(values), linestyle="none", markersize=8,
                          **look)  # fmt: skip
        axes.axvline(len(records) - 0.25, color="0.6", linewidth=0.6)
        axes.set_ylabel(label)
        axes.grid(True, axis="y", color="0.9", linewidth=0.5)
        ticks = [*range(0, len(records), every), mean_at]
        names = [*records[::every], "mean"]
        crowded = len(ticks) > 9
        axes.set_xticks(ticks, names, rotation=45 if crowded else 0,
                        ha="right" if crowded else "center", rotation_mode="anchor")  # fmt: skip
        axes.tick_params(labelbottom=True)
        panel_label(axes, letter)
    _limits(grid[0, 0], bridges)
    grid[-1, -1].axhline(100.0, **FAILURE_LINE)
    for axes in grid.flat:  # from just below zero, so that a marker at zero (a symmetric
        top = 1.08 * axes.get_ylim()[1]  # bridge's deck rotation) is not cut by the frame; the
        axes.set_ylim(-0.03 * top, top)  # markers and limit lines clear of the top frame
    for axes in grid[-1]:
        axes.set_xlabel("record")
    if len(bridges) > MAX_NAMED:
        grid[0, 0].plot([], [], linestyle="none", marker="o", color="0.45",
                        label=f"{len(bridges)} bridges, one marker style each (rockbridge plot "
                        "sweep draws a peak against a swept field)")  # fmt: skip
    handles, texts = grid[0, 0].get_legend_handles_labels()
    figure.legend(handles, texts, loc="outside upper center", ncols=legend_columns(len(texts)),
                  frameon=False, fontsize="small" if len(texts) > 6 else "medium")  # fmt: skip
    return save(figure, output)


def _limits(axes, bridges: dict) -> None:
    """Horizontal lines of the end-joint gap and of abutment failure (bridges with abutments):
    one black pair when the bridges share them, else one pair per bridge in its shade, each
    line ending at the right frame in the markers of the bridges it belongs to, so that it is
    told from the others in print, not by its shade alone (issue 40)."""
    shown = SHOWN["u_deck"]
    limits: dict[tuple[float, float], list[int]] = {}
    for index, attributes in enumerate(bridges.values()):
        if math.isfinite(attributes["model_u_jo"]):
            pair = (attributes["model_u_jo"], attributes["model_u_ab"])
            limits.setdefault(pair, []).append(index)
    if len(limits) == 1:
        ((gap, ultimate),) = limits
        contact, failure = gap * shown.factor, (gap + ultimate) * shown.factor
        label = f"contact, $u_{{jo}}$ = {contact:.0f} {shown.unit}"
        axes.axhline(contact, **GAP_LINE, label=label)
        label = f"failure, $u_{{jo}} + u_{{ab}}$ = {failure:.0f} {shown.unit}"
        axes.axhline(failure, **FAILURE_LINE, label=label)
        return
    if len(limits) > MAX_LIMITS:
        axes.plot([], [], linestyle="none", label=f"limit lines left out: {len(limits)} gaps")
        return
    for (gap, ultimate), indices in limits.items():
        shade = {"color": style(indices[0])["color"]}
        for level, line in ((gap, GAP_LINE), (gap + ultimate, FAILURE_LINE)):
            level *= shown.factor
            axes.axhline(level, **{**line, **shade})
            for place, index in enumerate(indices):  # the owners' markers, inside the frame
                look = {k: v for k, v in style(index).items() if k != "linestyle"}
                axes.plot(0.985 - 0.03 * place, level, transform=axes.get_yaxis_transform(),
                          linestyle="none", markersize=5, **look)  # fmt: skip
    if limits:  # one legend entry for each kind of line
        axes.plot([], [], **GAP_LINE, label=r"contact, $u_{jo}$ (each bridge's: its marker at "
                  "the right)")  # fmt: skip
        axes.plot([], [], **FAILURE_LINE, label=r"failure, $u_{jo} + u_{ab}$")
