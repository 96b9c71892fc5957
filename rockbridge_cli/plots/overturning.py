"""The overturning spectrum of a spectrum study, in the field's convention (Makris & Roussos 2000;
Zhang & Makris 2001): ω_p/p across, a_p/(g·tan α) (or a_p over the onset acceleration) up; the
map of what each analysis reached — the two modes of overturning, with and without an impact, the
safe region between them, and for a bridge the joints closing and the abutment failing — and the
bisected boundary of each limit state (`assessment.spectrum`)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.artist import Artist
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.figure import Figure
from matplotlib.patches import Patch, Rectangle

from ..assessment.spectrum import NOT_RUN, REGIONS, read_spectrum
from ..core.quantities import STANDARD_GRAVITY
from .common import FAILURE_LINE, GAP_LINE, check_format, plain, save

REGION_SHADES = {
    "not run": "white",
    "no_rocking": "white",
    "rocking": "0.86",
    "gap_closure": "0.74",
    "abutment_failure": "0.6",
    "overturning_after_impact": "0.42",
    "overturning_without_impact": "0.22",
}
"""Each region's grey (code −1 first), lighter to darker as the response grows, so that the map
prints as the other figures do; cells that did not run are white under `NOT_RUN_HATCH`."""

NOT_RUN_HATCH = "////"
"""The hatching of the cells whose analysis did not run (white like "no rocking" otherwise)."""

REGION_LABELS = {
    "not run": "not run",
    "no_rocking": "no rocking",
    "rocking": "rocks, survives",
    "gap_closure": "gaps close, survives",
    "abutment_failure": "abutment fails",
    "overturning_after_impact": "overturns after an impact",
    "overturning_without_impact": "overturns without an impact",
}
"""Legend labels of the regions."""

REFERENCE_LABELS = {
    "g_tan_alpha": r"$a_p\,/\,(g\,\tan\alpha)$",
    "onset": r"$a_p\,/\,\ddot{u}_{g,min}$",
}
"""The vertical axis, by the spectrum's reference acceleration."""

BOUNDARY_LINES = {
    "overturning": {"color": "black", "linestyle": "-", "linewidth": 1.4},
    "gap_closure": GAP_LINE,
    "abutment_failure": FAILURE_LINE,
}
"""How each limit state's boundary is drawn (a backfill state: dash-dot)."""


def plot_overturning(results: str | Path, output: str | Path) -> Path:
    """Draw the overturning spectrum of a results file of a spectrum study.

    Raises
    ------
    InputError
        The file is not a spectrum study's, or the figure cannot be written there.

    Returns
    -------
    pathlib.Path
        The figure file.
    """
    output = check_format(output)
    spectrum = read_spectrum(results)
    x, y = spectrum.frequency_ratios, spectrum.amplitude_ratios
    figure = Figure(figsize=(6.4, 4.8), layout="constrained")
    axes = figure.subplots()
    colours = ListedColormap(list(REGION_SHADES.values()))
    norm = BoundaryNorm(np.arange(NOT_RUN - 0.5, len(REGIONS)), colours.N)
    logarithmic = x.size > 2 and np.allclose(np.diff(np.log(x)), np.log(x[1] / x[0]))
    edges_x, edges_y = _edges(x, logarithmic), _edges(y)
    axes.pcolormesh(edges_x, edges_y, spectrum.regions.T, cmap=colours, norm=norm)
    for i, j in zip(*np.nonzero(spectrum.regions == NOT_RUN), strict=True):
        axes.add_patch(Rectangle((edges_x[i], edges_y[j]), edges_x[i + 1] - edges_x[i],
                                 edges_y[j + 1] - edges_y[j], facecolor="none",
                                 edgecolor="0.5", linewidth=0.0, hatch=NOT_RUN_HATCH))  # fmt: skip
    present = set(np.unique(spectrum.regions).tolist())
    handles: list[Artist] = [
        Patch(
            facecolor=shade,
            edgecolor="0.5",
            linewidth=0.5,
            label=REGION_LABELS[name],
            hatch=NOT_RUN_HATCH if code == NOT_RUN else None,
        )  # fmt: skip
        for code, (name, shade) in enumerate(REGION_SHADES.items(), start=NOT_RUN)
        if code in present
    ]
    for state, values in spectrum.boundaries.items():
        look = BOUNDARY_LINES.get(state, {"color": "black", "linestyle": "-.", "linewidth": 1.0})
        reached = "" if np.isfinite(values).any() else f": none up to {y.max():g}"
        label = f"lowest {state.replace('_', ' ')}{reached}"
        handles += axes.plot(x, values, **look, label=label)
    axes.set_xscale("log" if logarithmic else "linear")
    axes.set_xlim(edges_x[0], edges_x[-1])
    axes.set_ylim(edges_y[0], edges_y[-1])
    axes.set_xlabel(r"$\omega_p\,/\,p$")
    axes.set_ylabel(REFERENCE_LABELS[spectrum.reference])
    pulse = plain(str(spectrum.pulse["shape"]).replace("_", " "))
    axes.set_title(
        f"{plain(spectrum.bridge)} under {pulse}\n$p$ = "
        f"{spectrum.frequency_parameter:.3g} rad/s, $a_{{ref}}$ = "
        f"{spectrum.reference_acceleration / STANDARD_GRAVITY:.3g} g",
        fontsize="medium",
    )
    figure.legend(handles=handles, loc="outside right center", frameon=False, fontsize="small")
    return save(figure, output)


def _edges(centres: np.ndarray, logarithmic: bool = False) -> np.ndarray:
    """Cell edges around the axis values: midway between neighbours (in the logarithms on a
    logarithmic axis), and as far outside the ends."""
    if logarithmic:
        return np.exp(_edges(np.log(centres)))
    middle = 0.5 * (centres[1:] + centres[:-1])
    return np.concatenate([[2 * centres[0] - middle[0]], middle, [2 * centres[-1] - middle[-1]]])
