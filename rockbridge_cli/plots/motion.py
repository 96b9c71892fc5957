"""Ground motions in time: acceleration, velocity and displacement of each record, the velocity
and displacement integrated exactly from rest (`baseline.integrate_motion`), with EN 1998-1's
design ground displacement d_g marked when the records are a generated set."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..core.quantities import STANDARD_GRAVITY
from ..motions.baseline import integrate_motion
from .common import FAILURE_LINE, check_format, legend_columns, panel_label, plain, save, style
from .spectra import NAMED_RECORDS, load_records


def plot_record_motion(
    paths: list[str | Path],
    output: str | Path,
    units: str | None = None,
    time_step: float | None = None,
) -> Path:
    """Draw each record's acceleration [g], velocity [cm/s] and displacement [cm].

    Parameters
    ----------
    paths
        record files and/or folders of generated sets.
    output
        figure file, .png, .pdf or .svg.
    units
        ``"g"``, ``"m/s2"`` or ``"cm/s2"`` for plain files that do not state their units.
    time_step
        time step of one-column files [s].

    Returns
    -------
    pathlib.Path
        the figure file.
    """
    output = check_format(output)
    records, target, _, _ = load_records(paths, units, time_step)
    figure = Figure(figsize=(8.0, 7.5), layout="constrained")
    panels = figure.subplots(3, 1, sharex=True)
    named = len(records) <= NAMED_RECORDS
    for index, record in enumerate(records):
        velocity, displacement = integrate_motion(record.acceleration, record.time_step)
        time = np.arange(record.acceleration.size) * record.time_step
        look = {k: v for k, v in style(index).items() if "marker" not in k} if named else {
            "color": "0.6", "linestyle": "-"}  # fmt: skip
        label = plain(record.name) if named else None
        shown = (record.acceleration / STANDARD_GRAVITY, 100.0 * velocity, 100.0 * displacement)
        for axes, values in zip(panels, shown, strict=True):
            axes.plot(time, values, linewidth=0.7, label=label, **look)
    if not named:
        panels[0].plot([], [], color="0.6", label=f"{len(records)} records")
    if target is not None:
        dg = 100.0 * target.ground_displacement
        for sign in (1.0, -1.0):
            panels[2].axhline(sign * dg, **FAILURE_LINE,
                              label=rf"$\pm d_g$ = {dg:.1f} cm (EN 1998-1 §3.2.2.4)" if sign > 0
                              else None)  # fmt: skip
    for axes, label, letter in zip(panels, (r"$\ddot{u}_g$ [g]", r"$\dot{u}_g$ [cm/s]",
                                            r"$u_g$ [cm]"), "ABC", strict=True):  # fmt: skip
        axes.set_ylabel(label)
        axes.grid(True, color="0.9", linewidth=0.5)
        panel_label(axes, letter)
    panels[-1].set_xlabel("time t [s]")
    labelled = {  # each record is drawn in every panel: one entry each
        label: handle
        for axes in panels
        for handle, label in zip(*axes.get_legend_handles_labels(), strict=True)
    }
    figure.legend(labelled.values(), labelled.keys(), loc="outside upper center",
                  ncols=legend_columns(len(labelled)), frameon=False,
                  fontsize="small")  # fmt: skip
    return save(figure, output)
