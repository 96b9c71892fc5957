"""Fig. 10 of Thomaidis, Camara & Kappos (2022): response histories of several bridges under one
record, with the ground motion and the events that shape them.

(A) the ground acceleration, with each bridge's onset of rocking marked on it; then u_deck with
the end-joint gap ±u_jo (dotted) and each pounding marked, v_deck, θ_deck, θ1 (tall pier) and θ2
(short pier); one line style per bridge, and a dashed line where an analysis ends in failure.
A bridge with devices (tendons, dampers, dissipators) adds a last panel: each device's force,
in its bridge's colour, one line style per device. A panel that no drawn model has (a single
block has no deck and no short pier) is left out, and so is one whose history the study did not
keep (``output.histories``): the title says which.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Collection, Sequence
from pathlib import Path

import numpy as np
from matplotlib.colors import to_rgb
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ..core.quantities import FAILURE_EVENTS, SHOWN, STANDARD_GRAVITY, is_device_history
from ..errors import InputError, nearest
from ..results.reading import (
    bridge_attributes,
    event_arrays,
    ground_motion,
    history_arrays,
    open_results,
)
from .common import (
    FAILURE_LINE,
    GAP_LINE,
    check_format,
    panel_label,
    plain,
    save,
    series_labels,
    style,
)

PANELS = tuple((name, shown.factor, f"{shown.tex} [{shown.unit}]") for name, shown in SHOWN.items())
"""Response panels: history, scale from SI to the axis unit, axis label."""

DEVICE_LINES = ("-", "--", ":", "-.")
"""Line styles of a bridge's devices in the device panel, in their order."""

DEVICE_LIGHTENING = 0.22
"""How much lighter each next device of a bridge is drawn than the one before, towards white
(with its line style: four dissipators in one colour could not be told apart) [-]."""


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
        An unknown bridge or record, or an analysis without any of the histories drawn.
    """
    output = check_format(output)
    with open_results(results) as file:
        table = bridge_attributes(file)
        chosen = list(bridges) or list(table)
        unknown = [b for b in chosen if b not in table]
        if unknown:
            why = f"no bridge {unknown[0]}; {nearest(unknown[0], table, 'bridges')}"
            raise InputError(results, [("", why)])
        histories = {b: history_arrays(file, results, b, record) for b in chosen}
        events = {b: event_arrays(file, results, b, record) for b in chosen}
        time_step, ground = ground_motion(file, results, chosen[0], record)
    for bridge, arrays in histories.items():
        if not any(name in arrays for name, _, _ in PANELS):
            names = ", ".join(name for name, _, _ in PANELS)
            reason = f"none of the histories drawn ({names}) was kept (output.histories)"
            raise InputError(results, [(f"analyses/{bridge}/{record}", reason)])
    panels = [
        p for p in PANELS
        if any(p[0] in h and np.isfinite(h[p[0]]).any() for h in histories.values())
    ]  # fmt: skip
    absent = left_out(set.intersection(*(set(h) for h in histories.values())))
    forces = {b: device_forces(h) for b, h in histories.items()}
    count = len(panels) + 1 + any(forces.values())
    figure = Figure(figsize=(8.0, 1.2 + 1.95 * count), layout="constrained")
    axes_list = figure.subplots(count, 1, sharex=True, squeeze=False)[:, 0]
    letters = iter("ABCDEFG")
    labels = series_labels({b: table[b] for b in chosen})

    _ground_panel(axes_list[0], time_step, ground, events)
    _grid(axes_list[0], next(letters))
    gaps = sorted({table[b]["model_u_jo"] for b in chosen} - {math.inf})
    limits = sorted({table[b]["model_u_jo"] + table[b]["model_u_ab"] for b in chosen} - {math.inf})
    if any(forces.values()):
        _device_panel(axes_list[-1], histories, forces)
        _grid(axes_list[-1], "ABCDEFG"[count - 1])
    for (name, scale, label), axes in zip(panels, axes_list[1:], strict=False):
        for index, (bridge, arrays) in enumerate(histories.items()):
            if name not in arrays:
                continue
            look = {k: v for k, v in style(index).items() if "marker" not in k}
            axes.plot(arrays["time"], arrays[name] * scale, linewidth=1.0, label=labels[bridge],
                      **look)  # fmt: skip
            if name == "u_deck":
                times = events[bridge]["time"][events[bridge]["kind"] == "pounding"]
                at = np.interp(times, arrays["time"], arrays[name]) * scale
                axes.plot(times, at, linestyle="none", marker="x", ms=4, color=look["color"])
        axes.set_ylabel(label)
        _grid(axes, next(letters))
        for gap in gaps if name == "u_deck" else ():
            for sign in (1.0, -1.0):
                axes.axhline(sign * gap * SHOWN["u_deck"].factor, **GAP_LINE)
        for limit in limits if name == "u_deck" else ():  # abutment failure, as Fig. 9A
            for sign in (1.0, -1.0):
                axes.axhline(sign * limit * SHOWN["u_deck"].factor, **FAILURE_LINE)
    failures = [t for t in map(_failure_time, events.values()) if t is not None]
    for when in failures:
        for axes in axes_list:
            axes.axvline(when, **FAILURE_LINE)
    handles, names = axes_list[min(1, len(panels))].get_legend_handles_labels()
    keys = _legend_keys(any(name == "u_deck" for name, _, _ in panels) and bool(gaps),
                        bool(failures))  # fmt: skip
    figure.legend(handles + [key for key, _ in keys], names + [name for _, name in keys],
                  loc="outside upper center", ncols=2, frameon=False)  # fmt: skip
    for axes in axes_list:  # times under every panel, not under the last only
        axes.tick_params(labelbottom=True)
    axes_list[0].set_title(f"record {record}" + (f"; not kept: {', '.join(absent)}" * bool(absent)))
    axes_list[-1].set_xlabel("time t [s]")
    return save(figure, output)


def left_out(kept: Collection[str]) -> list[str]:
    """The responses of the figure (`PANELS`) whose histories are not among ``kept`` (a results
    file's ``histories`` attribute, or the histories of an analysis), as tables name them."""
    return [SHOWN[name].text for name, _, _ in PANELS if name not in kept]


def _ground_panel(axes, time_step: float, ground: np.ndarray, events: dict) -> None:
    """Panel (A): the ground acceleration [g], with each bridge's first onset of rocking on it."""
    ground_time = np.arange(ground.size) * time_step
    axes.plot(ground_time, ground / STANDARD_GRAVITY, color="0.35", linewidth=0.6)
    axes.set_ylabel(r"$\ddot{u}_g$ [g]")
    for index, found in enumerate(events.values()):
        onsets = found["time"][found["kind"] == "onset"]
        if onsets.size:  # the first onset, on the ground motion that caused it
            look = style(index)
            axes.plot(onsets[0], np.interp(onsets[0], ground_time, ground) / STANDARD_GRAVITY,
                      linestyle="none", marker=look["marker"], color=look["color"],
                      markerfacecolor=look["markerfacecolor"], markersize=7, zorder=3)  # fmt: skip


def device_forces(arrays: dict[str, np.ndarray]) -> list[str]:
    """The device force histories among an analysis's ``arrays`` (``tendon1_force``, …)."""
    return [name for name in arrays if name.endswith("_force") and is_device_history(name)]


def _device_panel(axes, histories: dict, forces: dict[str, list[str]]) -> None:
    """The last panel: each device's force [MN], positive in tension, its bridge's colour and
    one line style per device, named in the panel's own legend."""
    for index, (bridge, names) in enumerate(forces.items()):
        arrays, colour = histories[bridge], np.array(to_rgb(style(index)["color"]))
        for k, (name, line) in enumerate(zip(names, itertools.cycle(DEVICE_LINES))):
            label = name.removesuffix("_force") + (f" ({bridge})" if len(histories) > 1 else "")
            shade = colour + (1.0 - colour) * DEVICE_LIGHTENING * (k % len(DEVICE_LINES))
            axes.plot(arrays["time"], arrays[name] * 1e-6, linewidth=0.9, linestyle=line,
                      color=shade, label=plain(label))  # fmt: skip
    axes.set_ylabel("device force [MN]")
    axes.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.0, 1.0), frameon=False)


def _legend_keys(deck: bool, failed: bool) -> list[tuple[Line2D, str]]:
    """The legend's entries beside the bridges': onset; poundings and gap; failure."""
    keys = [(Line2D([], [], linestyle="none", marker="o", color="0.35"),
             "onset of rocking (on $\\ddot{u}_g$)")]  # fmt: skip
    if deck:
        keys += [(Line2D([], [], linestyle="none", marker="x", color="0.35"),
                  "pounding on the backwall"),
                 (Line2D([], [], **GAP_LINE), r"end-joint gap $\pm u_{jo}$")]  # fmt: skip
    if deck or failed:  # one style for a failure: its level (Fig. 9A's) and its time
        level = r": abutment at $\pm(u_{jo} + u_{ab})$" if deck else ""
        keys.append((Line2D([], [], **FAILURE_LINE),
                     f"failure{level}{', its time' * (failed and deck)}"))  # fmt: skip
    return keys


def _grid(axes, letter: str) -> None:
    axes.grid(True, color="0.9", linewidth=0.5)
    panel_label(axes, letter)


def _failure_time(events: dict[str, np.ndarray]) -> float | None:
    """When the analysis failed, or None (the failure is its last event)."""
    kinds = events["kind"]
    return float(events["time"][-1]) if kinds.size and kinds[-1] in FAILURE_EVENTS else None
