"""The paper's parametric figures, computed for any two-pier bridge config.

* Fig. 3 — onset of rocking ü_g,min (Eq. 8) in both directions vs h̄ = H1/H2, varying the short
  pier's height (`plot_onset`);
* Fig. 4 — the abutment parameter q vs the short pier's mass, same variation (`plot_q`);
* Fig. 7 — the coefficient of restitution η of the bridge and of the same frame without abutment
  seats vs h̄, both directions (`plot_restitution`);
* Fig. 8 — η vs the side span L1 and vs the central span L2, deck mass and inertia constant as in
  the paper (`plot_spans`).

The short pier keeps the tall pier's section and material (its mass and inertia follow its height);
the deck does not change. Directions are the user's: for a bridge whose tall pier stands on the
right, the core's modes are swapped as in `core.summary.summarize`.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import NullLocator

from ..config.bridge import BridgeConfig, load_bridge
from ..core import impacts
from ..core.geometry import Model, ratios, with_short_pier
from ..errors import InputError
from .common import PLAIN, check_format, panel_label, plain, save, style

POINTS = 60
"""Points per curve [-]."""


def directions(config: BridgeConfig) -> tuple[float, float]:
    """The core's modes behind the user's p and n (swapped when the tall pier is on the right)."""
    return config.to_bridge().user_modes()


def h_bar_range(model: Model, h_max: float | None = None) -> np.ndarray:
    """h̄ from 1 to ``h_max``, by default the larger of 5 (Figs. 4, 7) and the bridge's own."""
    top = h_max if h_max is not None else max(5.0, model.H1 / model.H2)
    return np.linspace(1.0, top, POINTS)


def onset_curves(config: BridgeConfig, h_bars: np.ndarray) -> dict[str, np.ndarray]:
    """ü_g,min of modes p and n (magnitudes) at each h̄ [g] (Eq. 8; Fig. 3)."""
    model = config.to_bridge().model
    variants = [with_short_pier(model, h) for h in h_bars]
    return {
        mode: np.array([abs(impacts.onset_threshold(m, s)) / m.g for m in variants])
        for mode, s in zip(("p", "n"), directions(config), strict=True)
    }


def restitution_curves(
    config: BridgeConfig, variants: list[Model], frame: bool = True
) -> dict[str, np.ndarray]:
    """η of the bridge (and of the frame without seats), p→n and n→p, for each model [-]."""
    curves = {}
    for seats, kind in ((True, "bridge"), (False, "frame"))[: 2 if frame else 1]:
        for name, s in zip(("p→n", "n→p"), directions(config), strict=True):
            curves[f"{kind} {name}"] = np.array(
                [impacts.restitution(m, s, abutment_seats=seats) for m in variants]
            )
    return curves


def plot_onset(bridge: str | Path, output: str | Path, h_max: float | None = None) -> Path:
    """Draw Fig. 3 for a bridge config: ü_g,min in both directions vs h̄ [g]."""
    output = check_format(output)
    config, model = _two_piers(bridge)
    h_bars = h_bar_range(model, h_max)
    curves = onset_curves(config, h_bars)
    own = onset_curves(config, np.array([model.H1 / model.H2]))
    figure, axes = _figure()
    _short_pier_axis(axes, model, h_bars)
    for index, (mode, values) in enumerate(curves.items()):
        axes.plot(h_bars, values, markevery=6, label=f"mode {mode}", **style(index))
    _mark_own(axes, model.H1 / model.H2, [values[0] for values in own.values()])
    axes.set_xlabel(r"$\bar{h} = H_1/H_2$ [-]")
    axes.set_ylabel(r"$\ddot{u}_{g,min}$ [g]")
    axes.set_title(f"{plain(config.label(Path(bridge).stem))}\nonset of rocking (Eq. 8; Fig. 3)")
    axes.legend(frameon=False)
    return save(figure, output)


def plot_q(bridge: str | Path, output: str | Path, h_max: float | None = None) -> Path:
    """Draw Fig. 4 for a bridge config: q vs the short pier's mass."""
    output = check_format(output)
    config, model = _two_piers(bridge)
    variants = [with_short_pier(model, h) for h in h_bar_range(model, h_max)]
    mass = np.array([m.m2 for m in variants]) / 1e4
    q = np.array([ratios(m)["q"] for m in variants]) * 1e6
    figure, axes = _figure()
    axes.plot(mass, q, markevery=6, label="q", **style(0))
    _mark_own(axes, model.m2 / 1e4, [ratios(model)["q"] * 1e6])
    axes.set_xlabel(r"$m_{pier,2}$ [$10^4$ kg]")
    axes.set_ylabel(r"$q$ [$10^{-3}$ m/kN]")
    axes.set_title(f"{plain(config.label(Path(bridge).stem))}\nabutment parameter q (Fig. 4)")
    axes.legend(frameon=False)
    return save(figure, output)


def plot_restitution(bridge: str | Path, output: str | Path, h_max: float | None = None) -> Path:
    """Draw Fig. 7 for a bridge config: η of the bridge and of the frame vs h̄, both directions."""
    output = check_format(output)
    config, model = _two_piers(bridge)
    h_bars = h_bar_range(model, h_max)
    curves = restitution_curves(config, [with_short_pier(model, h) for h in h_bars])
    own = restitution_curves(config, [model])
    figure, axes = _figure()
    _short_pier_axis(axes, model, h_bars)
    for index, (name, values) in enumerate(curves.items()):
        axes.plot(h_bars, values, markevery=6, label=name, **style(index))
    _mark_own(axes, model.H1 / model.H2, [values[0] for values in own.values()])
    axes.set_xlabel(r"$\bar{h} = H_1/H_2$ [-]")
    axes.set_ylabel(r"$\eta$ [-]")
    axes.set_title(
        f"{plain(config.label(Path(bridge).stem))}\nrestitution at the rocking interfaces (Fig. 7)"
    )
    axes.legend(frameon=False)
    return save(figure, output)


def plot_spans(bridge: str | Path, output: str | Path) -> Path:
    """Draw Fig. 8 for a bridge config: η vs L1 (L2 fixed) and vs L2 (L1 fixed), both directions.

    Each span runs from a third to twice its value in the config (a zero side span: the central
    span's); the central span stays longer than the pier width. Deck mass and inertia are kept.
    """
    output = check_format(output)
    config, model = _two_piers(bridge)
    side = np.linspace(*_span_range(model.L1 or model.L2), POINTS)
    low, high = _span_range(model.L2)
    central = np.linspace(max(low, 1.05 * 2.0 * model.B), high, POINTS)
    figure = Figure(figsize=(10.0, 4.5), layout="constrained")
    panels = figure.subplots(1, 2, sharey=True)
    for axes, spans, field, label, letter in (
        (panels[0], side, "L1", r"side span $L_1$ [m]", "A"),
        (panels[1], central, "L2", r"central span $L_2$ [m]", "B"),
    ):
        variants = [model._replace(**{field: length}) for length in spans]
        curves = restitution_curves(config, variants, frame=False)
        for index, (name, values) in enumerate(curves.items()):
            axes.plot(spans, values, markevery=6, label=name, **style(index))
        own = restitution_curves(config, [model], frame=False)
        _mark_own(axes, getattr(model, field), [values[0] for values in own.values()])
        axes.set_xlabel(label)
        axes.grid(True, color="0.9", linewidth=0.5)
        panel_label(axes, letter)
    panels[0].set_ylabel(r"$\eta$ [-]")
    panels[0].legend(frameon=False)
    figure.suptitle(
        f"{plain(config.label(Path(bridge).stem))}: restitution vs span lengths (Fig. 8)"
    )
    return save(figure, output)


def _two_piers(bridge: str | Path) -> tuple[BridgeConfig, Model]:
    config = load_bridge(bridge)
    if len(config.piers.heights) != 2:
        raise InputError(bridge, [("piers.heights", "the figure varies a bridge with two piers")])
    return config, config.to_bridge().model


def _span_range(length: float) -> tuple[float, float]:
    return length / 3.0, 2.0 * length


def _mark_own(axes, x: float, values: list[float]) -> None:
    """The bridge's own point on each curve, with one legend entry."""
    axes.plot([x] * len(values), values, linestyle="none", marker="*", color="black",
              markersize=11, label="this bridge", zorder=4)  # fmt: skip


TOP_SPACING = 1.0 / 12.0
"""The top axis's labels are at least this share of the h̄ range apart."""


def short_pier_ticks(h1: float, low: float, high: float) -> list[float]:
    """Round short-pier heights 2H2 [m] to label over h̄ = H1/H2 in [low, high]: multiples of
    10ᵏ (the tallest's power of ten) first, then of 5·10ᵏ⁻¹, 2·10ᵏ⁻¹ and 10ᵏ⁻¹, each kept
    where it is at least `TOP_SPACING` of the range (in h̄) from every kept one. 2H2 = 2H1/h̄
    crowds evenly spaced heights toward high h̄, where matplotlib's own ticks overlapped (issue
    40)."""
    shortest, tallest = 2.0 * h1 / high, 2.0 * h1 / low
    gap = TOP_SPACING * (high - low)
    kept: list[float] = []
    power = 10.0 ** math.floor(math.log10(tallest))
    steps = [factor * power for factor in (1.0, 0.5, 0.2, 0.1)]
    for step in steps:
        first = math.ceil(shortest / step - 1e-9)
        for value in np.arange(first, math.floor(tallest / step + 1e-9) + 1) * step:
            h_bar = 2.0 * h1 / value
            if all(abs(h_bar - 2.0 * h1 / other) >= gap for other in kept):
                kept.append(round(float(value), 12))
    return sorted(kept)


def _short_pier_axis(axes, model: Model, h_bars: np.ndarray) -> None:
    """A top axis in the variable the paper varies, the short pier's height 2H2 = 2H1/h̄ [m],
    labelled at `short_pier_ticks`."""

    def swap(x):  # h̄ ↔ 2H2, its own inverse; matplotlib also asks at 0
        x = np.asarray(x, dtype=float)
        return np.divide(2.0 * model.H1, x, out=np.full_like(x, np.inf), where=x != 0.0)

    top = axes.secondary_xaxis("top", functions=(swap, swap))
    top.set_xticks(short_pier_ticks(model.H1, float(h_bars[0]), float(h_bars[-1])))
    top.xaxis.set_major_formatter(PLAIN)
    top.xaxis.set_minor_locator(NullLocator())
    top.set_xlabel(r"short pier height $2H_2$ [m]")


def _figure():
    figure = Figure(figsize=(6.5, 4.5), layout="constrained")
    axes = figure.add_subplot()
    axes.grid(True, color="0.9", linewidth=0.5)
    return figure, axes
