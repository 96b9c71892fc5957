"""The figure of a selected record set (`records.selection`): the EN 1998-1 target (and the
user's spectrum that replaced it over the range, if any), each scaled
record's spectrum, their mean, the 90 % line of §3.2.3.1.2(4)c and the period range, shaded
(matplotlib, Agg backend; readable in greyscale)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import NullFormatter

from ..core.quantities import STANDARD_GRAVITY
from ..motions.spectra import compute_psa
from ..records.set_files import read_manifest, read_record_set
from ..records.target import read_set_target
from .common import check_format, plain, save, style
from .spectra import PERIOD_TICKS

SHOWN = (0.02, 4.0)
"""Periods drawn, around the range [s]."""


def plot_selection(folder: str | Path, output: str | Path, points: int = 240) -> Path:
    """Draw a selected set's scaled spectra, their mean and the target.

    Parameters
    ----------
    folder
        the set, as `records.selection.select_record_set` wrote it.
    output
        figure file, .png, .pdf or .svg.
    points
        log-spaced periods drawn [-].

    Returns
    -------
    pathlib.Path
        the figure file.
    """
    output = check_format(output)
    records = read_record_set(folder)
    target = read_set_target(folder)
    manifest = read_manifest(folder)
    low, high = manifest["check"]["band_s"]
    user = manifest.get("user_spectrum")
    periods = np.geomspace(*SHOWN, points)
    values = np.array([compute_psa(r.acceleration, r.time_step, periods, target.damping)
                       for r in records]) / STANDARD_GRAVITY  # fmt: skip
    goal = target.evaluate(periods) / STANDARD_GRAVITY
    figure = Figure(figsize=(7.5, 5.0), layout="constrained")
    axes = figure.add_subplot()
    axes.axvspan(low, high, facecolor="0.93", edgecolor="none",
                 label=f"period range {low:g}-{high:g} s")  # fmt: skip
    for index, (record, row) in enumerate(zip(records, values, strict=True)):
        look = {k: v for k, v in style(index).items() if "marker" not in k}
        factor = record.metadata.get("scale_factor", float("nan"))
        axes.plot(periods, row, linewidth=0.8, alpha=0.8,
                  label=f"{plain(record.name)} x{factor:.3g}", **look)  # fmt: skip
    axes.plot(periods, values.mean(axis=0), color="0.1", linewidth=2.0, marker="o",
              markersize=3.5, markevery=16, label=f"mean of {len(records)}", zorder=4)  # fmt: skip
    axes.plot(periods, goal, color="black", linestyle="--", linewidth=1.4, zorder=5,
              label=f"EN 1998-1 type {target.spectrum_type}, ground "
              f"{target.ground_type}")  # fmt: skip
    if user is not None:  # the user's spectrum replaces Se over the range
        periods = np.geomspace(low, high, points)
        goal = np.exp(np.interp(np.log(periods), np.log(user["periods_s"]),
                                np.log(user["sa_m_s2"]))) / STANDARD_GRAVITY  # fmt: skip
        axes.plot(periods, goal, color="black", linestyle="-.", linewidth=1.4, zorder=5,
                  label=f"target: {plain(user['file'])}")  # fmt: skip
    axes.plot(periods, 0.9 * goal, color="black", linestyle=":", linewidth=1.0, zorder=5,
              label="90 % of target (EN 1998-1 §3.2.3.1.2(4)c)")  # fmt: skip
    axes.set_xscale("log")
    axes.set_xlim(*SHOWN)
    axes.set_xticks(list(PERIOD_TICKS[:-1]), [f"{t:g}" for t in PERIOD_TICKS[:-1]])
    axes.xaxis.set_minor_formatter(NullFormatter())
    axes.set_ylim(bottom=0.0)
    axes.set_xlabel("period T [s]")
    axes.set_ylabel(f"pseudo-spectral acceleration, {target.damping:.0%} damping [g]")
    axes.grid(True, which="both", color="0.9", linewidth=0.5)
    axes.legend(loc="upper right", frameon=True, framealpha=0.9, edgecolor="none",
                fontsize="x-small", ncols=2)  # fmt: skip
    return save(figure, output)
