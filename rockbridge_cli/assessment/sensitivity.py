"""Which sampled bridge field drives a response: first- and total-order Sobol' indices from a
study whose bridges a saltelli design sampled (`config.uncertainty`), and how much of the
response's variance is record-to-record.

Each sampled bridge meets every record; its *output* is a statistic of a quantity over the records
(the mean by default): a peak-table column (``dcr_backfill``), or whether a limit state is reached
(``abutment_failure``, ``backfill_50``; its mean is the share of records that reach it). The
indices are those of `scipy.stats.sobol_indices` on the outputs of the A, B and A_B^(i) bridges:
first order by Saltelli et al. (2010), total order by Jansen (1999), with bootstrap confidence
intervals over the n base samples. The record share is, over every analysis of the A and B
bridges, E[Var(Q | θ)] / Var(Q): the variance left when the bridge is known, which no parameter
study removes (law of total variance; the rest, Var(E[Q | θ]) / Var(Q), is what the indices
split among the fields when the statistic is the mean).
"""

from __future__ import annotations

import inspect
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats

from ..core.quantities import LIMIT_STATES, check_limit_state
from ..errors import InputError
from ..results.layout import PEAK_COLUMNS, TEXT_COLUMNS
from ..results.reading import bridge_samples, open_results, peak_columns
from .limit_states import reached

STATISTICS = ("mean", "median")
"""How a sampled bridge's output is taken over its records."""

CONFIDENCE = 0.90
"""Confidence level of the indices' intervals [-]."""

RESAMPLES = 1000
"""Bootstrap resamples of the n base samples."""


@dataclass(frozen=True)
class FieldIndices:
    """One field's Sobol' indices of one output, with their bootstrap intervals [-]."""

    field: str
    first: float
    first_interval: tuple[float, float]
    total: float
    total_interval: tuple[float, float]


@dataclass(frozen=True)
class Sensitivity:
    """The sensitivity of one quantity of the samples of one bridge file.

    Attributes
    ----------
    bridge : the bridge file's id (its samples are ``<bridge>+A…``, ``+B…``, ``+AB<i>.…``)
    quantity, statistic : the output: ``statistic`` over the records of ``quantity``
    samples : n, the base samples of the design
    records : records each sample met
    mean, std : of the output over the A and B samples [the quantity's unit]
    records_share : E[Var(Q | θ)] / Var(Q) over every analysis of the A and B samples [-]; NaN
        where Q does not vary
    fields : the indices of each sampled field, in the design's order
    """

    bridge: str
    quantity: str
    statistic: str
    samples: int
    records: int
    mean: float
    std: float
    records_share: float
    fields: tuple[FieldIndices, ...]

    def rows(self) -> list[dict[str, Any]]:
        """One row per field: the indices, their intervals and the bridge's figures."""
        return [
            {
                "bridge": self.bridge, "quantity": self.quantity, "statistic": self.statistic,
                "field": item.field, "first_order": item.first,
                "first_order_low": item.first_interval[0],
                "first_order_high": item.first_interval[1],
                "total_order": item.total, "total_order_low": item.total_interval[0],
                "total_order_high": item.total_interval[1], "samples": self.samples,
                "records": self.records, "mean": self.mean, "std": self.std,
                "records_share": self.records_share,
            }
            for item in self.fields
        ]  # fmt: skip


def sobol(
    f_a: np.ndarray,
    f_b: np.ndarray,
    f_ab: np.ndarray,
    confidence: float = CONFIDENCE,
    resamples: int = RESAMPLES,
    seed: int = 0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """First- and total-order Sobol' indices of outputs already computed on a saltelli design.

    Parameters
    ----------
    f_a, f_b
        The outputs at the rows of A and of B, shape (n,), n a power of two.
    f_ab
        The outputs at the rows of each A_B^(i), shape (d, n).
    confidence, resamples, seed
        The bootstrap of the intervals: percentile intervals over ``resamples`` resamples of the
        n rows (`scipy.stats.bootstrap`); the same seed, the same bounds.

    Returns
    -------
    first, total : shape (d,)
    first_interval, total_interval : shape (2, d), low and high bounds
    """

    def indices(rows: np.ndarray) -> np.ndarray:
        result = stats.sobol_indices(
            func={"f_A": f_a[None, rows], "f_B": f_b[None, rows], "f_AB": f_ab[:, None, rows]},
            n=f_a.size,
        )
        return np.concatenate([np.ravel(result.first_order), np.ravel(result.total_order)])

    rows = np.arange(f_a.size)
    estimate = indices(rows)
    # scipy < 1.15 names the generator random_state, newer ones rng
    keyword = "rng" if "rng" in inspect.signature(stats.bootstrap).parameters else "random_state"
    with np.errstate(invalid="ignore", divide="ignore"):  # a resample that does not vary
        interval = stats.bootstrap(
            (rows,), indices, vectorized=False, n_resamples=resamples,
            confidence_level=confidence, method="percentile",
            **{keyword: np.random.default_rng(seed)},
        ).confidence_interval  # fmt: skip
    d = f_ab.shape[0]
    low, high = np.asarray(interval.low), np.asarray(interval.high)
    return (
        estimate[:d],
        estimate[d:],
        np.vstack([low[:d], high[:d]]),
        np.vstack([low[d:], high[d:]]),
    )


def design_outputs(
    samples: dict[str, dict[str, Any]], outputs: dict[str, float], fields: list[str], n: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The outputs of a saltelli design as `sobol` takes them.

    Parameters
    ----------
    samples
        Each sample's place in the design, by name (`config.uncertainty.Sample.described`:
        ``matrix``, ``index``, ``field``).
    outputs
        Each sample's output, by name.
    fields
        The sampled fields, in the design's order; n its base size.

    Returns
    -------
    f_a, f_b : shape (n,)
    f_ab : shape (d, n), row i that of A_B^(i)

    Raises
    ------
    ValueError
        A sample of the design has no output (or a NaN one): the message names its matrices.
    """
    found = {key: np.full(n, np.nan) for key in ["A", "B", *(f"AB{f}" for f in fields)]}
    for name, sample in samples.items():
        found[sample["matrix"] + sample.get("field", "")][sample["index"]] = outputs[name]
    missing = [key for key, out in found.items() if np.isnan(out).any()]
    if missing:
        raise ValueError(f"samples of {', '.join(missing)} have no output")
    return found["A"], found["B"], np.vstack([found[f"AB{f}"] for f in fields])


def check_quantity(name: str) -> str:
    """``name`` if it is a numeric peak-table column, a limit state or ``failure``.

    Raises
    ------
    ValueError
        It is none of them; the message lists what is.
    """
    numeric = [c for c in PEAK_COLUMNS if c not in TEXT_COLUMNS and not c.startswith("t_")]
    if name in numeric or name == "failure":
        return name
    try:
        return check_limit_state(name)
    except ValueError:
        raise ValueError(
            f"unknown quantity {name!r}: a peak column ({', '.join(numeric[:8])}, …), a limit "
            f"state ({', '.join(LIMIT_STATES)}) or failure"
        ) from None


def sensitivities(
    path: str | Path,
    quantity: str = "dcr_backfill",
    statistic: str = "mean",
    confidence: float = CONFIDENCE,
    resamples: int = RESAMPLES,
) -> list[Sensitivity]:
    """The sensitivity of ``quantity`` for each bridge file of a saltelli-sampled study.

    Parameters
    ----------
    path
        The results file (only its peak table and bridges' attributes are read).
    quantity
        A numeric peak-table column, a limit state, or ``failure`` (any failure mode).
    statistic
        ``mean`` or ``median`` of the quantity over each bridge's records (NaN rows, of analyses
        that did not run, left out).

    Raises
    ------
    InputError
        The file's study has no saltelli design, a sample has not run, or the quantity is unknown.
    """
    try:
        check_quantity(quantity)
    except ValueError as exc:
        raise InputError(path, [("--quantity", str(exc))]) from None
    with open_results(path) as file:
        config = json.loads(file.attrs["config"])
        design = config.get("uncertainty")
        if design is None or design.get("design") != "saltelli":
            why = "not a study with a saltelli design (uncertainty: {design: saltelli}): its "
            raise InputError(path, [("", why + "samples give no Sobol' indices")])
        samples = bridge_samples(file)
        columns = peak_columns(file)
    values = _values(columns, quantity)
    found = []
    for base in dict.fromkeys(name.rsplit("+", 1)[0] for name in samples):
        mine = {name: s for name, s in samples.items() if name.rsplit("+", 1)[0] == base}
        found.append(_of_bridge(path, base, mine, list(design["fields"]), design["size"],
                                columns["bridge"], values, quantity, statistic, confidence,
                                resamples))  # fmt: skip
    return found


def _values(columns: dict[str, np.ndarray], quantity: str) -> np.ndarray:
    """The quantity of every analysis: a column, or 1.0 where a limit state is reached (NaN where
    the analysis did not run)."""
    if quantity in PEAK_COLUMNS:
        return np.asarray(columns[quantity], dtype=float)
    ran = np.asarray(columns["status"]).astype(str) == "ok"
    if quantity == "failure":
        hit = ~np.isin(np.asarray(columns["failure_mode"]).astype(str), ["", "none"])
    else:
        hit = reached(quantity, columns)
    return np.where(ran, hit.astype(float), np.nan)


def _of_bridge(
    path: str | Path, base: str, samples: dict[str, dict[str, Any]], fields: list[str], n: int,
    bridges: np.ndarray, values: np.ndarray, quantity: str, statistic: str, confidence: float,
    resamples: int,
) -> Sensitivity:  # fmt: skip
    """One bridge file's indices (`sensitivities`)."""
    reduce = np.nanmean if statistic == "mean" else np.nanmedian
    rows: dict[str, np.ndarray] = {}
    order = np.argsort(bridges, kind="stable")
    ordered = bridges[order]
    for name in samples:
        start, stop = np.searchsorted(ordered, name), np.searchsorted(ordered, name, "right")
        rows[name] = values[order[start:stop]]
    reduced = {}
    for name, values in rows.items():
        ran = values[~np.isnan(values)]
        reduced[name] = reduce(ran) if ran.size else np.nan
    try:
        f_a, f_b, f_ab = design_outputs(samples, reduced, fields, n)
    except ValueError as exc:
        why = f"bridge {base}: {exc}: finish the study (rockbridge run) first"
        raise InputError(path, [("", why)]) from None
    if np.ptp(np.concatenate([f_a, f_b, f_ab.ravel()])) > 0.0:
        first, total, first_ci, total_ci = sobol(f_a, f_b, f_ab, confidence, resamples)
    else:  # the output does not vary: no share of its variance to give
        first = total = np.full(len(fields), np.nan)
        first_ci = total_ci = np.full((2, len(fields)), np.nan)
    both = [rows[name] for name, s in samples.items() if s["matrix"] in ("A", "B")]
    everything = np.concatenate(both)
    spread = np.nanvar(everything)
    within = np.mean([np.nanvar(r) if np.isfinite(r).any() else 0.0 for r in both])
    outer = np.concatenate([f_a, f_b])
    return Sensitivity(
        base, quantity, statistic, n, max(len(r) for r in rows.values()),
        float(np.mean(outer)), float(np.std(outer, ddof=1)),
        float(within / spread) if spread > 0.0 else float("nan"),
        tuple(
            FieldIndices(field, float(first[i]), (float(first_ci[0, i]), float(first_ci[1, i])),
                         float(total[i]), (float(total_ci[0, i]), float(total_ci[1, i])))
            for i, field in enumerate(fields)
        ),
    )  # fmt: skip
