"""Which intensity measure predicts a bridge's IDA capacities best (Luco & Cornell 2007; Tothong
& Luco 2007): an *efficient* one has a small dispersion β of the capacities, so fewer records fix
the median to a given confidence (its standard error is β/√n); a *sufficient* one leaves no trend
of the log-capacities with magnitude or distance, so the records' seismological provenance does
not bias the fragility. `compare` tabulates both, for the capacities converted to each measure
(`measures.Conversion`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np

from .fragility import fragilities

COMPARED = ("pga_g", "pgv", "pgd", "sa_g", "avgsa_g", "arias", "cav")
"""The measures `compare` tabulates by default. Not ``pga_tan_alpha``: within one bridge it is
PGA times a constant, so its β and trends are ``pga_g``'s (a test holds it)."""

SQUARED = ("arias",)
"""Measures that scale as the square of a record's factor: their β is twice that of a measure
proportional to it with the same predictive power, so `comparable_beta` halves it."""


def comparable_beta(measure: str, beta: float) -> float:
    """β as it compares across measures: half an energy measure's (`SQUARED`) [-]."""
    return beta / 2.0 if measure in SQUARED else beta


def best_measures(rows: list[MeasureRow]) -> dict[str, int]:
    """How many bridge × limit-state cases each measure has the smallest comparable β in, most
    first (a case without any fit counts for none)."""
    smallest: dict[tuple[str, str], tuple[float, str]] = {}
    for row in rows:
        if row.beta is not None:
            key, value = (row.bridge, row.limit_state), (comparable_beta(row.measure, row.beta),
                                                          row.measure)  # fmt: skip
            smallest[key] = min(smallest.get(key, value), value)
    counts: dict[str, int] = {}
    for _, measure in smallest.values():
        counts[measure] = counts.get(measure, 0) + 1
    return dict(sorted(counts.items(), key=lambda item: -item[1]))


@dataclass(frozen=True)
class MeasureRow:
    """How well one measure predicts one bridge's capacities for one limit state.

    Attributes
    ----------
    bridge, limit_state, measure : what it is of
    beta : dispersion of the capacities in the measure (censored fit) [-]; None without a fit
    records : records with a capacity within the levels
    magnitude_slope, magnitude_p : slope of the log-capacity residuals against magnitude and its
        p-value (None where the records carry no magnitude)
    distance_slope, distance_p : the same against ln of the rupture distance [km] (at least 1 km)
    """

    bridge: str
    limit_state: str
    measure: str
    beta: float | None
    records: int
    magnitude_slope: float | None
    magnitude_p: float | None
    distance_slope: float | None
    distance_p: float | None


def compare(
    path: str | Path,
    measures: tuple[str, ...] = COMPARED,
    period: float = 1.0,
    period_range: tuple[float, float] = (0.2, 3.0),
) -> list[MeasureRow]:
    """Efficiency and sufficiency of each measure, per bridge and limit state, from an IDA.

    Parameters
    ----------
    measures
        Names of `MEASURES`.
    period, period_range
        Sa's period and AvgSa's range [s].
    """
    from scipy.stats import linregress

    with h5py.File(path, "r") as file:
        provenance = {
            name: (node.attrs.get("magnitude"), node.attrs.get("distance_rrup_km"))
            for name, node in file["records"].items()
        }
    rows = []
    for measure in measures:
        for item in fragilities(path, 0, 0, measure, period, period_range):
            known = {r: c for r, c in item.capacities.items() if c is not None and c > 0.0}
            trends: list[float | None] = [None] * 4
            if len(known) > 2 and all(provenance[r][0] is not None for r in known):
                residuals = np.log(list(known.values()))
                residuals -= residuals.mean()
                magnitude = [float(provenance[r][0]) for r in known]
                distance = [math.log(max(float(provenance[r][1]), 1.0)) for r in known]
                for index, x in enumerate((magnitude, distance)):
                    if np.ptp(x) > 0.0:
                        fit = linregress(x, residuals)
                        trends[2 * index : 2 * index + 2] = [float(fit.slope), float(fit.pvalue)]
            rows.append(MeasureRow(item.bridge, item.limit_state, item.measure, item.beta,
                                   len(known), *trends))  # fmt: skip
    return rows
