"""Response spectra of records against their EN 1998-1 target (matplotlib, Agg backend).

Readable in greyscale: the records of a generated set are thin light lines (recorded motions, up
to `NAMED_RECORDS`, one named style each), their mean a dark line with markers, the target a black
dashed line over the set's per-record tolerance (shaded: rockbridge's check, not a code rule), and
the 90 % line of EN 1998-1 §3.2.3.1.2(4)c dotted. Periods are labelled in seconds.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import NullFormatter

from ..core.quantities import STANDARD_GRAVITY
from ..errors import InputError
from ..motions.spectra import compute_psa
from ..records.files import Record, read_record, read_stated_units
from ..records.set_files import MANIFEST, read_manifest, read_record_set
from ..records.target import TargetDefinition, read_set_target
from .common import check_format, plain, save, style

NAMED_RECORDS = 8
"""Records from files (not a generated set) up to this many are drawn and named one by one."""

PERIOD_TICKS = (0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 4.0, 10.0)
"""Labelled periods [s]."""


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
    records, target, band, tolerance = load_records(paths, units, time_step)
    gravity = STANDARD_GRAVITY  # spectra in the unit g
    periods = np.geomspace(band[0], band[1], 200)
    values = (
        np.array([compute_psa(r.acceleration, r.time_step, periods, damping) for r in records])
        / gravity
    )
    figure = Figure(figsize=(7.5, 5.0), layout="constrained")
    axes = figure.add_subplot()
    named = target is None and len(records) <= NAMED_RECORDS  # recorded motions, by name
    for index, (record, row) in enumerate(zip(records, values, strict=True)):
        if named:
            look = {k: v for k, v in style(index).items() if "marker" not in k}
            axes.plot(periods, row, linewidth=1.0, label=plain(record.name), **look)
        else:
            axes.plot(periods, row, color="0.78", linewidth=0.6, linestyle="-")
    if not named:
        axes.plot([], [], color="0.78", linewidth=0.6, label=f"records ({len(records)})")
    if len(records) > 1:
        axes.plot(periods, values.mean(axis=0), color="0.2", linewidth=1.6, marker="o",
                  markersize=3.5, markevery=12, label=f"mean of {len(records)} records",
                  zorder=4)  # fmt: skip
    if target is not None:
        goal = target.evaluate(periods) / gravity
        if tolerance is not None:
            label = f"±{tolerance:.0%}: tolerance per record (rockbridge)"
            axes.fill_between(periods, (1.0 - tolerance) * goal, (1.0 + tolerance) * goal,
                              facecolor="0.9", edgecolor="none", label=label)  # fmt: skip
        axes.plot(periods, goal, color="black", linestyle="--", linewidth=1.3, zorder=5,
                  label=f"target: EN 1998-1 type {target.spectrum_type}, ground "
                  f"{target.ground_type}")  # fmt: skip
        axes.plot(periods, 0.9 * goal, color="black", linestyle=":", linewidth=1.0,
                  label="90 % of target (EN 1998-1 §3.2.3.1.2)")  # fmt: skip
    axes.set_xscale("log")
    axes.set_xlim(*band)
    ticks = [t for t in PERIOD_TICKS if band[0] <= t <= band[1]]
    axes.set_xticks(ticks, [f"{t:g}" for t in ticks])
    axes.xaxis.set_minor_formatter(NullFormatter())
    axes.set_ylim(bottom=0.0)
    axes.set_xlabel("period T [s]")
    axes.set_ylabel(f"pseudo-spectral acceleration, {damping:.0%} damping [g]")
    axes.grid(True, which="both", color="0.9", linewidth=0.5)
    axes.legend(loc="upper right", frameon=True, framealpha=0.9, edgecolor="none", fontsize="small")
    return save(figure, output)


def load_records(
    paths, units, time_step
) -> tuple[list[Record], TargetDefinition | None, tuple[float, float], float | None]:
    """Records from files and set folders; the target, band [s] and per-record tolerance [-]
    when they all belong to one generated set."""
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
    target, tolerance = None, None
    band = (max(0.02, 5.0 * max(r.time_step for r in records)), 4.0)
    if len(sets) == 1 and (folder := next(iter(sets))).is_dir():
        target = read_set_target(folder)
        manifest = read_manifest(folder)
        low, high = manifest.get("check", {}).get("band_s", band)
        band = (float(low), float(high))
        tolerance = manifest.get("compliance", {}).get("tolerance")
    return records, target, band, tolerance


def _is_set_member(path: Path) -> bool:
    """Whether the record file ``path``, named on its own, is listed by a record set's manifest
    beside it; a manifest.json that is not a record set's (another program's) is no set."""
    manifest = path.parent / MANIFEST
    if not manifest.is_file():
        return False
    try:
        listed = read_manifest(path.parent)["records"]
    except InputError:
        return False
    return any(entry["file"] == path.name for entry in listed)
