"""Response spectra of records against their EN 1998-1 target (matplotlib, Agg backend).

Readable in greyscale: the records are thin light lines, the mean a thick grey line, the target
a black dashed line over a hatched ±10% band, and the 90% line of EN 1998-1 §3.2.3.1.2(4)c
dash-dotted.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..core.quantities import STANDARD_GRAVITY
from ..core.spectra import compute_psa
from ..records.files import (
    MANIFEST,
    Record,
    read_manifest,
    read_record,
    read_record_set,
    read_stated_units,
)
from ..records.sets import TargetDefinition, read_set_target
from .common import check_format, save


def plot_record_spectra(
    paths: list[str | Path],
    output: str | Path,
    units: str | None = None,
    time_step: float | None = None,
    damping: float = 0.05,
) -> Path:
    """Draw each record's pseudo-acceleration spectrum, their mean and, for a set, the target.

    Parameters
    ----------
    paths
        record files and/or folders of generated sets.
    output
        figure file, .png, .pdf or .svg.
    units
        ``"g"`` or ``"m/s2"`` for plain files that do not state their units.
    time_step
        time step of one-column files [s].
    damping
        oscillator damping ratio [-].

    Returns
    -------
    pathlib.Path
        the figure file.
    """
    output = check_format(output)
    records, target, band = _load(paths, units, time_step)
    gravity = STANDARD_GRAVITY  # spectra in the unit g
    periods = np.geomspace(band[0], band[1], 200)
    values = (
        np.array([compute_psa(r.acceleration, r.time_step, periods, damping) for r in records])
        / gravity
    )
    figure = Figure(figsize=(7.0, 4.5), layout="constrained")
    axes = figure.add_subplot()
    for row in values:
        axes.plot(periods, row, color="0.75", linewidth=0.7, linestyle="-")
    axes.plot([], [], color="0.75", linewidth=0.7, label=f"records ({len(records)})")
    axes.plot(periods, values.mean(axis=0), color="0.45", linewidth=2.6, label="mean")
    if target is not None:
        goal = target.evaluate(periods) / gravity
        axes.fill_between(
            periods,
            0.9 * goal,
            1.1 * goal,
            facecolor="0.92",
            edgecolor="0.6",
            hatch="....",
            linewidth=0.0,
            label="target ±10%",
        )
        axes.plot(
            periods,
            goal,
            color="black",
            linestyle="--",
            linewidth=1.3,
            zorder=3,
            label=f"EN 1998-1 type {target.spectrum_type}, ground {target.ground_type}",
        )
        axes.plot(
            periods,
            0.9 * goal,
            color="black",
            linestyle="-.",
            linewidth=0.9,
            label="90% of target (§3.2.3.1.2)",
        )
    axes.set_xscale("log")
    axes.set_xlim(*band)
    axes.set_ylim(bottom=0.0)
    axes.set_xlabel("period T [s]")
    axes.set_ylabel(f"pseudo-spectral acceleration ({damping:.0%} damping) [g]")
    axes.grid(True, which="both", color="0.9", linewidth=0.5)
    axes.legend(frameon=False, fontsize="small")
    return save(figure, output)


def _load(paths, units, time_step) -> tuple[list[Record], TargetDefinition | None, tuple]:
    """Records from files and set folders; the target when they all belong to one set."""
    records: list[Record] = []
    sets: set[Path] = set()
    for path in map(Path, paths):
        if path.is_dir():
            records += read_record_set(path)
            sets.add(path.resolve())
        else:
            stated = read_stated_units(path)  # --units only fills in for files without units
            records.append(read_record(path, units=None if stated else units, time_step=time_step))
            sets.add(path.parent.resolve() if _is_set_member(path) else path.resolve())
    target, band = None, (max(0.02, 5.0 * max(r.time_step for r in records)), 4.0)
    if len(sets) == 1 and (folder := next(iter(sets))).is_dir():
        target = read_set_target(folder)
        band = tuple(read_manifest(folder).get("check", {}).get("band_s", band))
    return records, target, band


def _is_set_member(path: Path) -> bool:
    manifest = path.parent / MANIFEST
    if not manifest.is_file():
        return False
    return any(entry["file"] == path.name for entry in read_manifest(path.parent)["records"])
