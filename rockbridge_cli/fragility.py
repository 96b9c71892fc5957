"""Fragility functions from a multiple-stripe study: for each bridge and limit state, the
lognormal probability of reaching the state against the intensity measure.

The fit is Baker's (2015, Earthquake Spectra 31(1)): at each intensity level x_j, z_j of the n_j
records reach the state; the median θ and the log-standard deviation β maximise the binomial
likelihood Π_j Φ((ln x_j − ln θ)/β)^z_j · (1 − Φ(…))^(n_j − z_j). Its uncertainty is a bootstrap
over the records (the same record at every level is one draw). This module reads a results file
and computes; it never changes the file.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.optimize import minimize
from scipy.stats import norm

from .errors import InputError
from .results.reading import open_results, peak_columns

LIMIT_STATES: dict[str, Callable[[dict[str, np.ndarray]], np.ndarray]] = {
    "gap_closure": lambda c: c["dcr_backfill"] > 0.0,
    "backfill_50": lambda c: c["dcr_backfill"] >= 0.5,
    "abutment_failure": lambda c: c["failure_mode"] == "abutment",
    "overturning": lambda c: np.char.startswith(c["failure_mode"].astype(str), "overturning"),
}
"""Limit states: the end joint closes (the backfill is loaded), the backfill reaches half its
capacity, the abutment–backfill fails, a pier overturns (docs/model.md §7–8)."""

BOOTSTRAP = 100
"""Resamplings of the records for the interval of the median."""


@dataclass(frozen=True)
class Fragility:
    """The fragility of one bridge for one limit state.

    Attributes
    ----------
    bridge, limit_state, measure : what it is of (measure: ``pga_g``, ``sa_g`` or ``scale``)
    median : θ, the intensity at which half the records reach the state; None if no record
        reaches it within the levels, or every record already at the lowest
    beta : β, the log-standard deviation [-]; None with ``median``, or where the levels do not
        resolve it (every record changes state between the same two levels)
    median_90 : 5 % and 95 % bootstrap percentiles of θ over the records (None without a fit)
    levels : the intensity levels
    fractions : share of the records that reach the state at each level
    capacities : per record, the lowest level at which it reaches the state, or None
    """

    bridge: str
    limit_state: str
    measure: str
    median: float | None
    beta: float | None
    median_90: tuple[float, float] | None
    levels: list[float]
    fractions: list[float]
    capacities: dict[str, float | None]

    def row(self) -> dict[str, object]:
        """As JSON-ready data."""
        return {
            "bridge": self.bridge, "limit_state": self.limit_state, "measure": self.measure,
            "median": self.median, "beta": self.beta,
            "median_90": list(self.median_90) if self.median_90 else None,
            "levels": self.levels, "fractions": self.fractions, "capacities": self.capacities,
        }  # fmt: skip


def fit_lognormal(levels: np.ndarray, reached: np.ndarray, tried: np.ndarray):
    """Maximum-likelihood lognormal fragility (Baker 2015).

    Parameters
    ----------
    levels
        Intensity levels x_j (> 0).
    reached, tried
        Records that reach the state at each level, and records analysed there.

    Returns
    -------
    (median θ, β), or None when the data cannot fix them (no record reaches the state, or every
    record at every level does). When every record changes between two adjacent levels (no level
    with some records below and some above), the likelihood does not fix β: the median is then
    the geometric mean of those two levels and β is None.
    """
    levels, reached, tried = (np.asarray(a, dtype=float) for a in (levels, reached, tried))
    if reached.sum() == 0 or np.all(reached == tried):
        return None
    fractions = reached / np.maximum(tried, 1.0)
    if np.all((fractions == 0.0) | (fractions == 1.0)) and np.all(np.diff(fractions) >= 0.0):
        above = int(np.argmax(fractions == 1.0))
        return math.sqrt(levels[above - 1] * levels[above]), None
    logs = np.log(levels)

    def negative_log_likelihood(parameters: np.ndarray) -> tuple[float, np.ndarray]:
        """−ln L and its gradient in (ln θ, ln β)."""
        log_median, log_beta = parameters
        beta = math.exp(log_beta)
        u = (logs - log_median) / beta
        p = np.clip(norm.cdf(u), 1e-300, 1.0 - 1e-16)
        value = -float(np.sum(reached * np.log(p) + (tried - reached) * np.log1p(-p)))
        slope = -norm.pdf(u) * (reached / p - (tried - reached) / (1.0 - p))  # ∂(−ln L)/∂u
        return value, np.array([-np.sum(slope) / beta, -np.sum(slope * u)])

    start = np.array([np.average(logs, weights=tried), math.log(0.4)])
    bounds = [(logs.min() - 5.0, logs.max() + 5.0), (math.log(1e-3), math.log(5.0))]
    fit = minimize(negative_log_likelihood, start, jac=True, method="L-BFGS-B", bounds=bounds,
                   options={"ftol": 1e-11, "gtol": 1e-7})  # fmt: skip
    return math.exp(fit.x[0]), math.exp(fit.x[1])


def fragilities(path: str | Path, bootstrap: int = BOOTSTRAP, seed: int = 0) -> list[Fragility]:
    """Every bridge's fragility for every limit state, from a multiple-stripe results file.

    Analyses that did not end ok are left out of the counts.

    Raises
    ------
    InputError
        The file's study has no intensity section (no stripes to fit).
    """
    with open_results(path) as file:
        intensity = json.loads(file.attrs.get("intensity", "null"))
        columns = peak_columns(file)
    if intensity is None:
        raise InputError(path, [("", "the study has no intensity section: nothing to fit")])
    ok = columns["status"] == "ok"
    columns = {name: values[ok] for name, values in columns.items()}
    levels = np.array(sorted(set(columns["intensity"].tolist())))
    rng = np.random.default_rng(seed)
    found = []
    for bridge in dict.fromkeys(columns["bridge"]):
        mine = {name: values[columns["bridge"] == bridge] for name, values in columns.items()}
        records = list(dict.fromkeys(mine["base_record"]))
        for state, test in LIMIT_STATES.items():
            table = _reached(mine, test(mine), records, levels)  # records × levels, NaN: missing
            fit = fit_lognormal(levels, *_counts(table))
            interval = None
            if fit is not None and fit[1] is not None and bootstrap:
                draws = [
                    fit_lognormal(levels, *_counts(table[rng.integers(0, len(records),
                                                                       len(records))]))
                    for _ in range(bootstrap)
                ]  # fmt: skip
                medians = [d[0] for d in draws if d is not None and d[1] is not None]
                if medians:
                    low, high = np.percentile(medians, [5.0, 95.0])
                    interval = (float(low), float(high))
            reached_at = {
                record: next((float(x) for x, r in zip(levels, row, strict=True) if r == 1), None)
                for record, row in zip(records, table, strict=True)
            }
            counts = _counts(table)
            found.append(Fragility(
                bridge, state, intensity["measure"], fit[0] if fit else None,
                fit[1] if fit else None, interval, levels.tolist(),
                (counts[0] / np.maximum(counts[1], 1)).tolist(), reached_at,
            ))  # fmt: skip
    return found


def _reached(mine: dict, reached: np.ndarray, records: list[str], levels: np.ndarray):
    """1 where a record reaches the state at a level, 0 where not, NaN where it was not analysed."""
    table = np.full((len(records), levels.size), np.nan)
    row = {record: i for i, record in enumerate(records)}
    column = {level: j for j, level in enumerate(levels.tolist())}
    for record, level, hit in zip(mine["base_record"], mine["intensity"], reached, strict=True):
        table[row[record], column[float(level)]] = float(hit)
    return table


def _counts(table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Records reaching the state, and records analysed, at each level."""
    return np.nansum(table, axis=0), np.sum(~np.isnan(table), axis=0)
