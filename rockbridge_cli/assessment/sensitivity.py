"""Which sampled bridge field drives a response: first- and total-order Sobol' indices from a
study whose bridges a saltelli design sampled (`config.uncertainty`), and how much of the
response's variance is record-to-record.

Each sampled bridge meets every record; its *output* is a statistic of a quantity over the records
(the mean by default): a peak-table column (``dcr_backfill``), or whether a limit state is reached
(``abutment_failure``, ``backfill_50``; its mean is the share of records that reach it); of an
IDA, a capacity (``capacity:abutment_failure``: the median of the sample's fragility). The
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
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats

from ..core.quantities import LIMIT_STATES, check_limit_state
from ..errors import InputError
from ..motions.intensity import MEASURES
from ..results.layout import PEAK_COLUMNS, TEXT_COLUMNS
from ..results.reading import (
    UNFINISHED,
    bridge_samples,
    open_results,
    partial,
    peak_columns,
    peak_units,
    read_intensity,
    swept_values,
)
from ..results.sections import IntensitySection
from .limit_states import reached

CAPACITY = "capacity:"
"""Prefix of a quantity that is an IDA's capacity for a limit state."""

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


@dataclass(frozen=True)
class Swing:
    """One field's swing in a tornado: the output with the field at its low and its high
    percentile, the others at their medians.

    Attributes
    ----------
    values : the field's low and high values [the field's unit]
    outputs : the output at each [the quantity's unit]
    """

    field: str
    values: tuple[float, float]
    outputs: tuple[float, float]

    @property
    def swing(self) -> float:
        """|high − low| of the output [the quantity's unit]."""
        return abs(self.outputs[1] - self.outputs[0])


@dataclass(frozen=True)
class Tornado:
    """The one-at-a-time swings of one quantity of one bridge file, largest first; ``median``
    the output of the bridge with every field at its median."""

    bridge: str
    quantity: str
    statistic: str
    median: float
    swings: tuple[Swing, ...]

    def rows(self) -> list[dict[str, Any]]:
        """One row per field."""
        return [
            {"bridge": self.bridge, "quantity": self.quantity, "statistic": self.statistic,
             "field": item.field, "low_value": item.values[0], "high_value": item.values[1],
             "output_low": item.outputs[0], "output_high": item.outputs[1],
             "output_median": self.median, "swing": item.swing}
            for item in self.swings
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

    d = f_ab.shape[0]
    # each field's indices depend on f_A, f_B and its own row of f_AB alone; scipy fails on a
    # single field (its indices are then scalars), so a lone row is given twice
    rows_ab = f_ab if d > 1 else np.vstack([f_ab, f_ab])

    def indices(rows: np.ndarray) -> np.ndarray:
        result = stats.sobol_indices(
            func={"f_A": f_a[None, rows], "f_B": f_b[None, rows], "f_AB": rows_ab[:, None, rows]},
            n=f_a.size,
        )
        first, total = np.ravel(result.first_order)[:d], np.ravel(result.total_order)[:d]
        return np.concatenate([first, total])

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
    missing = [key if key in ("A", "B") else f"A_B({key[2:]})" for key, out in found.items()
               if np.isnan(out).any()]  # fmt: skip
    if missing:
        raise ValueError(f"samples of {', '.join(missing)} have no output")
    return found["A"], found["B"], np.vstack([found[f"AB{f}"] for f in fields])


def check_quantity(name: str) -> str:
    """``name`` if it is a numeric peak-table column, a limit state, ``failure``, or
    ``capacity:<limit state>``.

    Raises
    ------
    ValueError
        It is none of them; the message lists what is.
    """
    numeric = [c for c in PEAK_COLUMNS if c not in TEXT_COLUMNS and not c.startswith("t_")]
    if name in numeric or name == "failure":
        return name
    try:
        if name.startswith(CAPACITY):
            return CAPACITY + check_limit_state(name.removeprefix(CAPACITY))
        return check_limit_state(name)
    except ValueError:
        raise ValueError(
            f"unknown quantity {name!r}: a peak column ({', '.join(numeric[:8])}, …), a limit "
            f"state ({', '.join(LIMIT_STATES)}), failure, or capacity:<limit state> of an IDA"
        ) from None


def sensitivities(
    path: str | Path,
    quantity: str = "dcr_backfill",
    statistic: str = "mean",
    confidence: float = CONFIDENCE,
    resamples: int = RESAMPLES,
) -> list[Sensitivity]:
    """The Sobol' indices of ``quantity`` for each bridge file of a saltelli-sampled study.

    Parameters
    ----------
    path
        The results file (only its peak table and bridges' attributes are read).
    quantity
        A numeric peak-table column, a limit state, ``failure`` (any failure mode), or, of an
        IDA, ``capacity:<limit state>``: each sample's median capacity (its fragility's θ, in
        the study's measure; `assessment.fragility`).
    statistic
        ``mean`` or ``median`` of a peak or a limit state over each bridge's records (NaN rows,
        of analyses that did not run, left out).

    Raises
    ------
    InputError
        The file's study has no saltelli design, a sample has not run or has no capacity, or the
        quantity is unknown or is a capacity of a study without an IDA.
    """
    design, samples, rows, outputs, statistic = _outputs(path, quantity, statistic, "saltelli")
    found = []
    for base, mine in _by_bridge_file(samples).items():
        try:
            f_a, f_b, f_ab = design_outputs(mine, outputs, list(design["fields"]), design["size"])
        except ValueError as exc:
            why = f"bridge {base}: {exc}: {UNFINISHED}"
            raise InputError(path, [("", why)]) from None
        both = [rows[name] for name, s in mine.items() if s["matrix"] in ("A", "B")]
        found.append(_indices(base, quantity, statistic, list(design["fields"]), f_a, f_b,
                              f_ab, both, confidence, resamples))  # fmt: skip
    return found


def tornadoes(
    path: str | Path, quantity: str = "dcr_backfill", statistic: str = "mean"
) -> list[Tornado]:
    """The one-at-a-time swings of ``quantity`` for each bridge file of a study with a tornado
    design (parameters and errors as for `sensitivities`)."""
    design, samples, _, outputs, statistic = _outputs(path, quantity, statistic, "tornado")
    with open_results(path) as file:
        drawn = swept_values(file)
    found = []
    for base, mine in _by_bridge_file(samples).items():
        named = {(s["matrix"], s.get("field", "")): name for name, s in mine.items()}
        if any(np.isnan(outputs[name]) for name in mine):
            why = f"bridge {base}: a bridge of the tornado has no output: finish the study first"
            raise InputError(path, [("", why)])
        swings = []
        for field in design["fields"]:
            ends = (named[("low", field)], named[("high", field)])
            values = (drawn[ends[0]][field], drawn[ends[1]][field])
            swings.append(Swing(field, values, (outputs[ends[0]], outputs[ends[1]])))
        swings.sort(key=lambda item: -item.swing)
        median = outputs[named[("mid", "")]]
        found.append(Tornado(base, quantity, statistic, median, tuple(swings)))
    return found


def output_unit(path: str | Path, quantity: str) -> str:
    """The unit of a sensitivity's output: a capacity's, the study's measure; a peak column's,
    its own; a limit state's or ``failure``'s, a share of the records (``-``)."""
    with open_results(path) as file:
        intensity = read_intensity(file)
        units = peak_units(file)
    if quantity.startswith(CAPACITY) and intensity is not None:
        return MEASURES[intensity.measure].unit
    return units.get(quantity, "-")


def design_of(path: str | Path) -> str:
    """The design of a sampled study's results file (``lhs``, …, ``saltelli``, ``tornado``);
    empty for a study without an uncertainty section."""
    with open_results(path) as file:
        design = json.loads(file.attrs["config"]).get("uncertainty") or {}
    return str(design.get("design", ""))


def _outputs(
    path: str | Path, quantity: str, statistic: str, kind: str
) -> tuple[dict, dict[str, dict], dict[str, np.ndarray], dict[str, float], str]:
    """The design, the samples, each sample's per-record values and its output, and the
    statistic's name, of a results file whose design is ``kind``."""
    try:
        quantity = check_quantity(quantity)
    except ValueError as exc:
        raise InputError(path, [("--quantity", str(exc))]) from None
    with open_results(path) as file:
        design = json.loads(file.attrs["config"]).get("uncertainty")
        intensity = read_intensity(file)
        if design is None or design.get("design") != kind:
            purpose = "Sobol' indices" if kind == "saltelli" else "one-at-a-time swings"
            why = (
                f"not a study with a {kind} design (uncertainty: {{design: {kind}}}): no {purpose}"
            )
            raise InputError(path, [("", why)])
        samples = bridge_samples(file)
        columns = peak_columns(file)
        if partial(file):
            why = "holds part of a sampled study, and its sensitivity needs all its analyses"
            raise InputError(path, [("", f"{why}: {UNFINISHED}")])
    if quantity.startswith(CAPACITY):
        if intensity is None or intensity.ida is None:
            why = f"{quantity}: capacities come from an IDA, and this study has none"
            raise InputError(path, [("--quantity", why)])
        rows, outputs = _capacities(columns, intensity, quantity.removeprefix(CAPACITY))
        return design, samples, rows, _every(outputs, samples), "median capacity"
    if intensity is not None and intensity.ida is not None:
        why = (f"{quantity}: an IDA's analyses stand at the levels each curve chose; ask for a "
               "capacity (capacity:abutment_failure, …)")  # fmt: skip
        raise InputError(path, [("--quantity", why)])
    rows = _per_bridge(columns["bridge"], _values(columns, quantity), samples)
    reduce = np.nanmean if statistic == "mean" else np.nanmedian
    outputs = {n: reduce(v[~np.isnan(v)]) if np.isfinite(v).any() else np.nan
               for n, v in rows.items()}  # fmt: skip
    return design, samples, rows, _every(outputs, samples), statistic


def _every(outputs: dict[str, float], samples: dict[str, dict]) -> dict[str, float]:
    """The outputs of every sample, NaN where one has none."""
    return {name: float(outputs.get(name, np.nan)) for name in samples}


def _by_bridge_file(samples: dict[str, dict]) -> dict[str, dict[str, dict]]:
    """The samples of each bridge file (``<bridge>+<label>``), in order."""
    found: dict[str, dict[str, dict]] = {}
    for name, sample in samples.items():
        found.setdefault(name.rsplit("+", 1)[0], {})[name] = sample
    return found


def _per_bridge(
    bridges: np.ndarray, values: np.ndarray, names: Iterable[str]
) -> dict[str, np.ndarray]:
    """The values of each bridge's analyses, for the bridges named."""
    order = np.argsort(bridges, kind="stable")
    ordered = bridges[order]
    return {
        name: values[
            order[np.searchsorted(ordered, name) : np.searchsorted(ordered, name, "right")]
        ]
        for name in names
    }


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


def _capacities(
    columns: dict[str, np.ndarray], intensity: IntensitySection, state: str
) -> tuple[dict[str, np.ndarray], dict[str, float]]:
    """Per bridge, its records' capacities for ``state`` (NaN where a record's is censored) and
    its fragility's median θ (NaN without a fit)."""
    from .fragility import fragilities_of

    rows, outputs = {}, {}
    for item in fragilities_of(columns, intensity, bootstrap=0):
        if item.limit_state == state:
            rows[item.bridge] = np.array([np.nan if c is None else c
                                          for c in item.capacities.values()])  # fmt: skip
            outputs[item.bridge] = np.nan if item.median is None else item.median
    return rows, outputs


def _indices(
    base: str, quantity: str, statistic: str, fields: list[str], f_a: np.ndarray,
    f_b: np.ndarray, f_ab: np.ndarray, rows: list[np.ndarray], confidence: float, resamples: int,
) -> Sensitivity:  # fmt: skip
    """One bridge file's `Sensitivity`, ``rows`` the per-record values of its A and B samples."""
    d = len(fields)
    if np.ptp(np.concatenate([f_a, f_b])) > 0.0:
        first, total, first_ci, total_ci = sobol(f_a, f_b, f_ab, confidence, resamples)
    else:  # the output does not vary over A and B, whose variance the indices share out
        first = total = np.full(d, np.nan)
        first_ci = total_ci = np.full((2, d), np.nan)
    spread = np.nanvar(np.concatenate(rows))
    within = np.mean([np.nanvar(r) if np.isfinite(r).sum() > 0 else 0.0 for r in rows])
    outer = np.concatenate([f_a, f_b])
    return Sensitivity(
        base, quantity, statistic, f_a.size, max(len(r) for r in rows),
        float(np.mean(outer)), float(np.std(outer, ddof=1)),
        float(within / spread) if spread > 0.0 else float("nan"),
        tuple(
            FieldIndices(field, float(first[i]), (float(first_ci[0, i]), float(first_ci[1, i])),
                         float(total[i]), (float(total_ci[0, i]), float(total_ci[1, i])))
            for i, field in enumerate(fields)
        ),
    )  # fmt: skip
