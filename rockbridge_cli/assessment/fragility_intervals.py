"""How sure a fragility is, and how many records settle it: the bootstrap intervals of the median
θ and of β, the band of fragility curves they span, and the width of both intervals against the
number of records.

A fragility fitted to n records (`assessment.fragility`) is itself uncertain, and with the tens of
records a study affords the uncertainty is not small (Bradley 2010, Earthquake Spectra 26(1)).
The fit's bootstrap resamples the records with replacement and refits each resampling
(`Fragility.draws`, a (θ, β) each); the 90 % interval of θ and of β are the 5 % and 95 %
percentiles of the same draws, the band of the fragility curve the pointwise 5 % and 95 %
percentiles of the draws' curves Φ(ln(x/θ_k)/β_k), and `assessment.risk` integrates each draw
with the hazard: one set of resamplings for all.

For a lognormal fit without censoring, ln θ̂ is the mean of n log-capacities and β̂ their standard
deviation, so their standard errors are β/√n and, asymptotically, β/√(2n) (the normal sample's
mean and standard deviation); a 90 % interval spans ±1.645 of them. The intervals therefore
shrink as 1/√n, and ln θ's half-width is √2·β times β's relative one: below β = 0.7, β settles
more slowly than the median (its relative standard error 1/√(2n), whatever β, is 10 % only from
50 records on).

**Records needed.** The study's records are subsampled: for each count n below the study's N,
`SUBSETS` subsets of n records drawn without replacement, each a study of n records with its
own bootstrap interval (`BOOTSTRAP` resamplings, as the fit's); at n = N the study's own
interval. The resamplings are fitted many at once: in closed form where their capacities are
all known, else by the fit's Newton's method vectorized over them (`_newton_many`; the same
maximum of a concave likelihood), and one by one only where that finds none. The width at n is
the median over the subsets of

* the median's half-width ln(θ95/θ05)/2 [-] (about the relative half-width of its interval), and
* β's relative half-width (β95 − β05)/(2·β̂) [-].

The rule that calls a fragility settled is on its median: the half-width of the median's 90 %
interval at most `SETTLED` = 1.645 × 0.10, i.e. a standard error of ln θ of at most 0.10 — the
precision Shome et al. (1998, Earthquake Spectra 14(3)) asked of a median response when they
found that about ten records suffice at a dispersion of 0.3 (n = (β/0.1)²). With the 1/√n law,
the count that meets it is about N·(w_N/`SETTLED`)² from the study's own width w_N.

The percentile bootstrap under-covers with few records. From a lognormal, the interval of θ holds
the true median in about P(|t_{n−1}| ≤ 1.645·√((n−1)/n)) of the studies (85 % at n = 10, 89 %
at 44; 84 % and 87.5 % measured with 100 resamplings), β's interval the true β in 65 % at
n = 10, 76 % at 22, 83 % at 44 and 87 % at 200 (β̂ is the 1/n estimate, biased low, its bootstrap
spread too narrow, and the 5 % and 95 % percentiles of 100 resamplings rest on five draws each:
88 % at 200 with 1000); tests/test_fragility_intervals.py measures them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from scipy.special import log_ndtr, ndtr

BOOTSTRAP = 100
"""Resamplings of each subset's records for its intervals (the fit's count,
`fragility.BOOTSTRAP`)."""

SUBSETS = 40
"""Subsets of n records drawn without replacement at each count n below the study's."""

SETTLED = 1.645 * 0.10
"""The largest half-width ln(θ95/θ05)/2 of the median's 90 % interval that calls a fragility
settled: a standard error of ln θ of 0.10 (Shome et al. 1998) [-]."""

MIN_RECORDS = 5
"""The fewest records whose widths are computed: n records have C(2n − 1, n) distinct
resamplings, 35 of 4 records (of 2, three, all with the same θ and β or none), too few for an
interval."""

LADDER = (5, 7, 10, 15, 22, 33, 44, 66, 100, 150, 220, 330, 440, 660, 1000)
"""Record counts tried below a study's own (steps of about √2, from FEMA P695's 22 and 44)."""

_LOG_ROOT_2PI = 0.5 * math.log(2.0 * math.pi)

Fit = tuple[float, float | None] | None
"""(θ, β) of a fit, β None where the data do not fix it; None without a fit."""


class Fitted(Protocol):
    """What the records needed read of a fit (`fragility.Fragility` has it; this module does not
    import `fragility`, which imports it)."""

    @property
    def bridge(self) -> str: ...
    @property
    def limit_state(self) -> str: ...
    @property
    def measure(self) -> str: ...
    @property
    def median(self) -> float | None: ...
    @property
    def beta(self) -> float | None: ...
    @property
    def draws(self) -> tuple[tuple[float, float], ...]: ...
    @property
    def resampling(self) -> Resampling | None: ...


@dataclass(frozen=True)
class Resampling:
    """What the bootstrap resamples for one fragility: one row per record and the fit of rows.

    Attributes
    ----------
    rows : per record, its data: an IDA's (capacity code, first level, last level), a stripe
        study's 1/0/NaN per level (reached, not, not analyzed)
    refit : the fit of a selection of rows (`fragility.fit_capacities`, `fit_lognormal`)
    log_capacities : an IDA's log-capacities [ln of the measure's unit], NaN where censored;
        None for stripes. A selection of records whose capacities are all known is fitted in
        closed form (their mean and standard deviation, as `fit_capacities` does), many
        selections at once, the others by Newton's method at once (`_censored_fits`)
    levels : a stripe study's levels [the measure's unit] (many selections at once by Newton's
        method, `_stripe_fits`); None for an IDA
    """

    rows: np.ndarray
    refit: Callable[[np.ndarray], Fit]
    log_capacities: np.ndarray | None = None
    levels: np.ndarray | None = None

    @classmethod
    def of_capacities(cls, rows: np.ndarray, refit: Callable[[np.ndarray], Fit]) -> Resampling:
        """An IDA's rows (capacity, first level, last level; a censored capacity coded 0 or
        +inf)."""
        known = np.isfinite(rows[:, 0]) & (rows[:, 0] > 0.0)
        return cls(rows, refit, np.log(np.where(known, rows[:, 0], np.nan)))

    @property
    def count(self) -> int:
        """The number of records."""
        return int(self.rows.shape[0])

    def subset(self, chosen: np.ndarray) -> Resampling:
        """The resampling of some of the records (indices)."""
        logs = None if self.log_capacities is None else self.log_capacities[chosen]
        return Resampling(self.rows[chosen], self.refit, logs, self.levels)


def bootstrap(resampling: Resampling, rng: np.random.Generator, count: int) -> np.ndarray:
    """(θ, β) of each of ``count`` resamplings of the records with replacement whose fit fixes
    both, as `fragility`'s bootstrap draws them (one ``rng.integers`` per resampling, in order).

    Returns
    -------
    An array (draws, 2): θ [the measure's unit] and β [-].
    """
    n = resampling.count
    picks = np.array([rng.integers(0, n, n) for _ in range(count)], dtype=int).reshape(count, n)
    draws = np.full((count, 2), np.nan)
    closed = np.zeros(count, dtype=bool)
    if resampling.log_capacities is not None:
        logs = resampling.log_capacities[picks]
        closed = ~np.isnan(logs).any(axis=1)
        beta = logs[closed].std(axis=1)
        draws[closed] = np.column_stack([np.exp(logs[closed].mean(axis=1)),
                                         np.where(beta > 0.0, beta, np.nan)])  # fmt: skip
        rest = np.flatnonzero(~closed)
        fits, solved = _censored_fits(resampling.rows, picks[rest])
        draws[rest[solved]] = fits[solved]
        closed[rest[solved]] = True
    elif resampling.levels is not None and count:
        fits, closed = _stripe_fits(resampling.rows, resampling.levels, picks)
        draws[closed] = fits[closed]
    for index in np.flatnonzero(~closed):
        fit = resampling.refit(resampling.rows[picks[index]])
        if fit is not None and fit[1] is not None:
            draws[index] = fit
    return draws[~np.isnan(draws).any(axis=1)]


def _censored_fits(rows: np.ndarray, picks: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """`fragility.fit_capacities` of many resamplings of an IDA's rows at once: Newton's method
    on the censored likelihood of `lognormal.Sample`, each record weighted by how often a
    resampling holds it, from `fit_capacities`' start. The likelihood is concave, so where the
    step converges inside the fit's region (`lognormal.fit`) it is the same maximum; elsewhere
    (no known capacity, no convergence, the maximum on the region's boundary) the resampling is
    left to the plain fit.

    Parameters
    ----------
    rows
        Per record: the capacity (0: at most the first level; +inf: above the last), the first
        and the last level [the measure's unit].
    picks
        Record indices of each resampling (resamplings × records).

    Returns
    -------
    (θ, β) of each resampling [the measure's unit, -], and where they were found.
    """
    count, total = picks.shape[0], rows.shape[0]
    weights = np.zeros((count, total))
    np.add.at(weights, (np.repeat(np.arange(count), picks.shape[1]), picks.ravel()), 1.0)
    code = rows[:, 0]
    known = np.isfinite(code) & (code > 0.0)
    logs = np.log(np.where(known, code, 1.0))
    censored = ~known
    below = code[censored] == 0.0
    bounds = np.log(np.where(below, rows[censored, 1], rows[censored, 2]))
    counts = weights[:, censored]
    held = weights[:, known]
    n = held.sum(axis=1)
    sum_y, sum_yy = held @ logs[known], held @ logs[known] ** 2
    mean = sum_y / np.maximum(n, 1.0)
    spread = np.sqrt(np.maximum(sum_yy / np.maximum(n, 1.0) - mean**2, 0.0))
    beta = np.maximum(np.where(n > 1, spread, 0.3), 0.05)
    present = weights > 0.0
    low = np.log(np.where(present, rows[:, 1], np.inf).min(axis=1))
    high = np.log(np.where(present, rows[:, 2], -np.inf).max(axis=1))
    known_sums = (n, sum_y, sum_yy)
    fits, solved = _newton_many(bounds, np.where(below, 1.0, -1.0), counts, known_sums,
                                (mean, beta), (low, high))  # fmt: skip
    return fits, solved & (n > 0)


def _stripe_fits(
    table: np.ndarray, levels: np.ndarray, picks: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """`fragility.fit_lognormal` of many resamplings of a stripe study's records at once: Baker's
    binomial likelihood with each record weighted by how often a resampling holds it, by
    `_newton_many`. A resampling whose levels leave no fit or separate the records (β open) is
    left to the plain fit, which says so without Newton's method.

    Parameters
    ----------
    table
        Records × levels: 1 where the record reaches the state, 0 where not, NaN where it was
        not analyzed.
    levels
        The intensity levels [the measure's unit].
    picks
        Record indices of each resampling (resamplings × records).

    Returns
    -------
    (θ, β) of each resampling [the measure's unit, -], and where they were found.
    """
    count = picks.shape[0]
    weights = np.zeros((count, table.shape[0]))
    np.add.at(weights, (np.repeat(np.arange(count), picks.shape[1]), picks.ravel()), 1.0)
    reached = weights @ np.nan_to_num(table)
    tried = weights @ (~np.isnan(table)).astype(float)
    logs = np.log(levels)
    analyzed = tried > 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        fractions = np.where(analyzed, reached / tried, np.nan)
    mixed = (fractions > 0.0) & (fractions < 1.0)
    running = np.fmax.accumulate(fractions, axis=1)
    rising = np.where(analyzed, fractions >= running, True).all(axis=1)
    empty = (reached.sum(axis=1) == 0.0) | (reached == tried).all(axis=1)
    separated = (mixed.sum(axis=1) <= 1) & rising  # `fit_lognormal` leaves β open
    crossing = logs[np.argmax(np.nan_to_num(running) >= 0.5, axis=1)]  # about where half reach
    zero = np.zeros(count)
    fits, solved = _newton_many(
        np.concatenate([logs, logs]), np.repeat([1.0, -1.0], logs.size),
        np.hstack([reached, tried - reached]), (zero, zero, zero), (crossing, np.full(count, 0.3)),
        (np.full(count, logs.min()), np.full(count, logs.max())),
    )  # fmt: skip
    return fits, solved & ~empty & ~separated


def _newton_many(
    bounds: np.ndarray,
    sign: np.ndarray,
    counts: np.ndarray,
    known_sums: tuple[np.ndarray, np.ndarray, np.ndarray],
    start: tuple[np.ndarray, np.ndarray],
    span: tuple[np.ndarray, np.ndarray],
) -> tuple[np.ndarray, np.ndarray]:
    """The maximum-likelihood (θ, β) of many samples at once, by `lognormal.fit`'s Newton's
    method (its steps, line search and stopping rule), vectorized over the samples.

    Parameters
    ----------
    bounds, sign
        Log-levels bounding capacities [ln of the measure's unit], and +1 where the capacities
        lie at or below a bound, −1 above.
    counts
        Per sample (rows), the capacities each bound holds.
    known_sums
        Per sample, the count of known log-capacities, their sum and the sum of their squares.
    start, span
        Per sample, (μ, β) to start from, and the lowest and highest log-level.

    Returns
    -------
    (θ, β) per sample [the measure's unit, -], and where Newton's method converged inside the
    fit's region (elsewhere the plain fit decides).
    """
    from . import lognormal

    n, sum_y, sum_yy = known_sums
    low, high = span
    count = counts.shape[0]

    def likelihood(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, ...]:
        """ln L, its gradient and Hessian in (a, b) per resampling (−inf where a ≤ 0)."""
        u = sign * (a[:, None] * bounds + b[:, None])
        log_cdf = log_ndtr(u)
        mills = np.exp(-0.5 * u * u - _LOG_ROOT_2PI - log_cdf)
        first = counts * sign * mills
        second = -counts * mills * (u + mills)
        with np.errstate(divide="ignore", invalid="ignore"):
            value = (counts * log_cdf).sum(axis=1) + n * np.log(a) - 0.5 * (
                a * a * sum_yy + 2.0 * a * b * sum_y + b * b * n)  # fmt: skip
        value = np.where(a > 0.0, value, -np.inf)
        ga = first @ bounds + n / a - (a * sum_yy + b * sum_y)
        gb = first.sum(axis=1) - (a * sum_y + b * n)
        haa = second @ bounds**2 - n / a**2 - sum_yy
        hab = second @ bounds - sum_y
        hbb = second.sum(axis=1) - n
        return value, ga, gb, haa, hab, hbb

    a, b = 1.0 / start[1], -start[0] / start[1]
    value, ga, gb, haa, hab, hbb = likelihood(a, b)
    done = np.zeros(count, dtype=bool)
    for _ in range(lognormal.STEPS):
        determinant = haa * hbb - hab * hab
        newton = (haa < 0.0) & (determinant > 1e-300)
        with np.errstate(divide="ignore", invalid="ignore"):
            step_a = np.where(newton, -(hbb * ga - hab * gb) / determinant, ga)
            step_b = np.where(newton, -(haa * gb - hab * ga) / determinant, gb)
        slope = ga * step_a + gb * step_b
        length = np.ones(count)
        pending = ~done
        found = [value, ga, gb, haa, hab, hbb]
        new_a, new_b = a, b
        while pending.any():
            trial = likelihood(a + length * step_a, b + length * step_b)
            accepted = pending & (trial[0] >= value + 1e-4 * length * slope
                                  - lognormal.ROUND_OFF * np.abs(value))  # fmt: skip
            found = [np.where(accepted, t, f) for t, f in zip(trial, found, strict=True)]
            new_a = np.where(accepted, a + length * step_a, new_a)
            new_b = np.where(accepted, b + length * step_b, new_b)
            pending &= ~accepted
            length = np.where(pending, 0.5 * length, length)
            stuck = pending & (length < 1e-12)  # no ascent left at this precision: the maximum
            done |= stuck
            pending &= ~stuck
            if not pending.any():
                break
        small = (np.abs(length * step_a) <= 1e-12 * (1.0 + np.abs(a))) & (
            np.abs(length * step_b) <= 1e-12 * (1.0 + np.abs(b)))  # fmt: skip
        moved = ~done
        a, b = np.where(moved, new_a, a), np.where(moved, new_b, b)
        value, ga, gb, haa, hab, hbb = (np.where(moved, f, g) for f, g in zip(
            found, (value, ga, gb, haa, hab, hbb), strict=True))  # fmt: skip
        done |= moved & small
        if done.all():
            break
    with np.errstate(divide="ignore", invalid="ignore"):
        median = -b / a
        steep, flat = 1.0 / lognormal.BETA_RANGE[0], 1.0 / lognormal.BETA_RANGE[1]
        inside = ((a >= flat) & (a <= steep) & (median >= low - lognormal.MARGIN)
                  & (median <= high + lognormal.MARGIN))  # fmt: skip
        fits = np.column_stack([np.exp(median), 1.0 / a])
    return fits, done & inside & np.isfinite(fits).all(axis=1)


def percentile_interval(values: np.ndarray | Sequence[float]) -> tuple[float, float] | None:
    """The 5 % and 95 % percentiles of bootstrap values; None without values."""
    values = np.asarray(values, dtype=float)
    if values.size == 0:
        return None
    low, high = np.percentile(values, [5.0, 95.0])
    return float(low), float(high)


def beta_interval(draws: Sequence[tuple[float, float]]) -> tuple[float, float] | None:
    """The 90 % bootstrap interval of β: the 5 % and 95 % percentiles of the draws' β [-]."""
    return percentile_interval([beta for _, beta in draws])


def band(
    draws: Sequence[tuple[float, float]] | np.ndarray, intensities: np.ndarray
) -> tuple[np.ndarray, np.ndarray] | None:
    """The 90 % band of a fragility curve: at each intensity, the 5 % and 95 % percentiles of
    P(LS | x) = Φ(ln(x/θ_k)/β_k) over the bootstrap draws.

    Parameters
    ----------
    draws
        (θ_k [the measure's unit], β_k [-]) of each resampling.
    intensities
        x [the measure's unit], > 0.

    Returns
    -------
    The lower and the upper probability at each intensity [-]; None without draws.
    """
    draws = np.asarray(draws, dtype=float).reshape(-1, 2)
    if not draws.size:
        return None
    medians, betas = draws[:, :1], draws[:, 1:]
    curves = ndtr(np.log(np.asarray(intensities, dtype=float)[None, :] / medians) / betas)
    low, high = np.percentile(curves, [5.0, 95.0], axis=0)
    return low, high


def half_widths(fit: Fit, draws: np.ndarray) -> tuple[float, float] | None:
    """The half-widths of the two 90 % intervals of a fit from its draws: the median's
    ln(θ95/θ05)/2 and β's (β95 − β05)/(2·β̂) [-]; None without a fit that fixes β, or with fewer
    than two draws."""
    if fit is None or fit[1] is None or len(draws) < 2:
        return None
    median = percentile_interval(draws[:, 0])
    beta = percentile_interval(draws[:, 1])
    assert median is not None and beta is not None  # draws exist
    return 0.5 * math.log(median[1] / median[0]), 0.5 * (beta[1] - beta[0]) / fit[1]


def record_counts(total: int) -> list[int]:
    """The record counts n tried for a study of ``total`` records (at least `MIN_RECORDS`):
    `LADDER`'s below it, and it."""
    return [n for n in LADDER if n < total] + [total]


@dataclass(frozen=True)
class Width:
    """The widths of the 90 % intervals of a fragility fitted to n of a study's records.

    Attributes
    ----------
    records : n
    subsets : subsets of n records drawn (1 at the study's count: the study itself)
    fitted : of those, the ones whose fit fixes θ and β
    median : the median's half-width ln(θ95/θ05)/2, the median over the fitted subsets [-];
        None without one
    beta : β's relative half-width (β95 − β05)/(2·β̂), likewise [-]
    kept : the share of the resamplings whose fit fixes β, the mean over the fitted subsets
        [-]: the others are left out of the intervals, and they are the extreme ones (stripes
        whose levels separate a few records), so the intervals are too narrow where it is small
    """

    records: int
    subsets: int
    fitted: int
    median: float | None
    beta: float | None
    kept: float | None = 1.0

    @property
    def settled(self) -> bool:
        """Whether the median's half-width meets the rule (`SETTLED`)."""
        return self.median is not None and self.median <= SETTLED


@dataclass(frozen=True)
class RecordsNeeded:
    """How the intervals of one fragility narrow with the number of records.

    Attributes
    ----------
    bridge, limit_state, measure : what it is of
    records : the study's record count N
    widths : one per record count tried (`record_counts`), the last the study's
    """

    bridge: str
    limit_state: str
    measure: str
    records: int
    widths: tuple[Width, ...]

    @property
    def settled_at(self) -> int | None:
        """The smallest count tried from which on every count meets the rule; None if the
        study's own does not."""
        found = None
        for width in reversed(self.widths):
            if not width.settled:
                break
            found = width.records
        return found

    @property
    def estimate(self) -> float | None:
        """The count that meets the rule by the 1/√n law from the study's own width,
        N·(w_N/`SETTLED`)²; None without one."""
        own = self.widths[-1].median if self.widths else None
        return None if own is None else self.records * (own / SETTLED) ** 2

    def row(self) -> dict[str, object]:
        """As JSON-ready data."""
        return {
            "bridge": self.bridge, "limit_state": self.limit_state, "measure": self.measure,
            "records": self.records, "settled_at": self.settled_at, "estimate": self.estimate,
            "rule": {"median_half_width_at_most": SETTLED},
            "widths": [
                {"records": w.records, "subsets": w.subsets, "fitted": w.fitted,
                 "median_half_width": w.median, "beta_half_width": w.beta,
                 "resamplings_kept": w.kept, "settled": w.settled}
                for w in self.widths
            ],
        }  # fmt: skip


def records_needed(
    item: Fitted,
    counts: Sequence[int] | None = None,
    subsets: int = SUBSETS,
    resamplings: int = BOOTSTRAP,
    seed: int = 0,
) -> RecordsNeeded | None:
    """The widths of a fragility's intervals against the number of records (the module's
    docstring gives the method).

    Parameters
    ----------
    item
        A fragility whose fit fixes θ and β, with its bootstrap (`fragility.fragilities`).
    counts
        Record counts n to try, each at most the study's; default `record_counts`.
    subsets, resamplings
        Subsets drawn at each n below the study's count, and bootstrap resamplings of each.
    seed
        Of the subsets and their resamplings: the same for every fragility, so that bridges and
        limit states are compared on the same subsets.

    Returns
    -------
    None for a fragility without a fit that fixes both, without its records' rows, or of fewer
    than `MIN_RECORDS` records.
    """
    resampling = item.resampling
    if item.median is None or item.beta is None or resampling is None or not item.draws:
        return None
    total = resampling.count
    if total < MIN_RECORDS:
        return None
    rng = np.random.default_rng(seed)
    widths = []
    for n in sorted(set(record_counts(total) if counts is None else counts)):
        if not MIN_RECORDS <= n <= total:
            raise ValueError(f"a record count must lie within {MIN_RECORDS}–{total}, not {n}")
        if n == total:
            own = half_widths((item.median, item.beta), np.array(item.draws))
            share = len(item.draws) / BOOTSTRAP  # the fit's resamplings, `fragility.BOOTSTRAP`
            median, beta = own or (None, None)
            widths.append(Width(n, 1, int(own is not None), median, beta, share))
            continue
        found, shares = [], []
        for _ in range(subsets):
            part = resampling.subset(np.sort(rng.choice(total, n, replace=False)))
            draws = bootstrap(part, rng, resamplings)
            found.append(half_widths(_fit(part), draws))
            if found[-1] is not None:
                shares.append(len(draws) / resamplings)
        kept = np.array([f for f in found if f is not None], dtype=float).reshape(-1, 2)
        if len(kept):
            middle = np.median(kept, axis=0)
            widths.append(Width(n, subsets, len(kept), float(middle[0]), float(middle[1]),
                                float(np.mean(shares))))  # fmt: skip
        else:
            widths.append(Width(n, subsets, 0, None, None, None))
    return RecordsNeeded(item.bridge, item.limit_state, item.measure, total, tuple(widths))


def _fit(resampling: Resampling) -> Fit:
    """The fit of all of a resampling's records."""
    logs = resampling.log_capacities
    if logs is not None and not np.isnan(logs).any():
        beta = float(np.std(logs))
        return math.exp(float(np.mean(logs))), beta if beta > 0.0 else None
    return resampling.refit(resampling.rows)


def all_records_needed(
    found: Sequence[Fitted], subsets: int = SUBSETS, seed: int = 0
) -> list[RecordsNeeded]:
    """`records_needed` of every fragility that has a fit fixing θ and β."""
    needed = (records_needed(item, subsets=subsets, seed=seed) for item in found)
    return [item for item in needed if item is not None]
