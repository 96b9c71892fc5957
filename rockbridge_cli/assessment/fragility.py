"""Fragility functions: for each bridge and limit state, the lognormal probability of reaching
the state against the intensity measure, from a study with an intensity section.

From multiple stripes, the fit is Baker's (2015, Earthquake Spectra 31(1)): at each intensity
level x_j, z_j of the n_j records reach the state; the median θ and the log-standard deviation β
maximise the binomial likelihood Π_j Φ((ln x_j − ln θ)/β)^z_j · (1 − Φ(…))^(n_j − z_j).

From an IDA, each record has a capacity (`assessment.ida`); ln θ and β are the mean and standard
deviation (1/n, the maximum-likelihood estimate) of the log-capacities. A curve the IDA has not
finished (an interrupted run, an analysis that could not run) is left out. Records that reach the
state at the first level already, or never up to the last, are censored there (their likelihood
is Φ or 1 − Φ at that level), not dropped: dropping them would bias θ. A record whose curve a
failure ended before it reached the state (*unreachable*: the abutment failed before any pier
overturned) is censored at the level where its curve ended, as a competing risk; a state no record
can reach has no fit. Both fits are one likelihood, maximised by Newton's method
(`assessment.lognormal`).

For a study whose records section sweeps an orientation, the fit may take each pair of
horizontal components as one record (``orientation``): it reaches a state where the median of its
angles' responses does (at least half of the angles) or the worst does (any angle), so an IDA's
pair capacity is the median or the smallest of its angles' (`assessment.orientation`). The
fragility the run stores, the report's and ``plot fragility``'s take the pairs so, by the study's
``intensity.orientation`` (the median without one, `study_orientation`).

The uncertainty of θ and β is a bootstrap over the records (the same record at every level is
one draw; a pair's angles are one draw; `fragility_intervals`). A run stores the fits in its
results file (`/fragility`, `store`); `fragilities` computes them from the peak table and never
changes the file.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import h5py
import numpy as np

from ..core.quantities import DEVICE_LIMIT_STATES, LIMIT_STATES
from ..errors import InputError
from ..motions.intensity import MEASURES
from ..results.reading import open_results, peak_columns, read_intensity, read_spectrum_section
from ..results.sections import IntensitySection
from . import limit_states, lognormal
from .fragility_intervals import Resampling, beta_interval
from .ida import Rule, Walk
from .limit_states import Verdict
from .orientation import (
    COMBINED,
    COMBINES,
    angles_in,
    groups_of,
    pair_capacities,
    pairs_of,
    pairs_reached,
)
from .spectrum import store as store_spectrum

if TYPE_CHECKING:
    from .measures import Conversion

BOOTSTRAP = 100
"""Resamplings of the records for the interval of the median."""

STUDY = "study"
"""The ``orientation`` of `fragilities` that follows the study's (`study_orientation`)."""


@dataclass(frozen=True)
class Fragility:
    """The fragility of one bridge for one limit state.

    Attributes
    ----------
    bridge, limit_state, measure : what it is of (measure: ``pga_g``, ``sa_g`` or ``scale``,
        or another of `motions.intensity.MEASURES`, whose unit every intensity below is in:
        g for ``pga_g`` and ``sa_g``, none for ``scale``)
    median : θ, the intensity at which half the records reach the state [the measure's unit];
        None if no record reaches it within the levels, or every record already at the lowest
    beta : β, the log-standard deviation [-]; None with ``median``, or where the levels do not
        resolve it (every record changes state between the same two levels)
    median_90 : 5 % and 95 % bootstrap percentiles of θ over the records [the measure's unit]
        (None without a fit)
    levels : the intensity levels [the measure's unit]
    fractions : share of the records that reach the state at each level
    capacities : per record, the lowest level at which it reaches the state, or None
    draws : (θ, β) of each bootstrap resampling of the records that fixes both (what
        `assessment.risk` propagates); empty without a fit
    unreachable : per record of an IDA on which the state cannot be observed, the failure limit
        state that ended its curve first and the level there (`assessment.ida`): its capacity
        is None, and the fit censors it at that level
    resampling : the records' rows the bootstrap resamples and their fit
        (`fragility_intervals`, which subsamples them for the records needed)
    orientation : "median" or "worst" where each record is a pair of horizontal components
        taken over its angles so (the records are the pairs), None where each is one record
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
    draws: tuple[tuple[float, float], ...] = ()
    unreachable: dict[str, tuple[str, float]] = field(default_factory=dict)
    resampling: Resampling | None = field(default=None, repr=False, compare=False)
    orientation: str | None = None

    @property
    def beta_90(self) -> tuple[float, float] | None:
        """5 % and 95 % percentiles of β over the bootstrap's draws, those of ``median_90``."""
        return beta_interval(self.draws)

    def row(self) -> dict[str, object]:
        """As JSON-ready data."""
        return {
            "bridge": self.bridge, "limit_state": self.limit_state, "measure": self.measure,
            "median": self.median, "beta": self.beta,
            "median_90": list(self.median_90) if self.median_90 else None,
            "beta_90": list(self.beta_90) if self.beta_90 else None,
            "levels": self.levels, "fractions": self.fractions, "capacities": self.capacities,
            "unreachable": {record: {"ended_by": by, "level": level}
                            for record, (by, level) in self.unreachable.items()},
            **({"orientation": self.orientation} if self.orientation else {}),
        }  # fmt: skip


def fit_lognormal(levels: np.ndarray, reached: np.ndarray, tried: np.ndarray):
    """Maximum-likelihood lognormal fragility (Baker 2015).

    Parameters
    ----------
    levels
        Intensity levels x_j (> 0).
    reached, tried
        Records that reach the state at each level, and records analyzed there.

    Returns
    -------
    (median θ, β), or None when the data cannot fix them (no record reaches the state, or every
    record at every level does). Where the levels separate the records — each level analyzed has
    all or none of its records reaching the state, the share growing with the level, except at
    most one level — the likelihood grows as β shrinks to 0 and does not fix β: β is None and the
    median is that one level, or without it the geometric mean of the last level that no record
    reaches and the first that all do.
    """
    levels, reached, tried = (np.asarray(a, dtype=float) for a in (levels, reached, tried))
    if reached.sum() == 0 or np.all(reached == tried):
        return None
    analyzed = tried > 0
    fractions = reached[analyzed] / tried[analyzed]
    mixed = (fractions > 0.0) & (fractions < 1.0)
    if np.count_nonzero(mixed) <= 1 and np.all(np.diff(fractions) >= 0.0):
        if mixed.any():
            return float(levels[analyzed][mixed][0]), None
        above = int(np.argmax(fractions == 1.0))
        return math.sqrt(levels[analyzed][above - 1] * levels[analyzed][above]), None
    logs = np.log(levels)
    sample = lognormal.Sample(
        known=np.empty(0), bounds=np.concatenate([logs, logs]),
        counts=np.concatenate([reached, tried - reached]),
        below=np.repeat([True, False], logs.size),
    )  # fmt: skip
    crossing = np.interp(0.5, np.maximum.accumulate(fractions), logs[analyzed])  # half reach it
    mean, beta = lognormal.fit(sample, (logs.min(), logs.max()), (crossing, 0.3))
    return math.exp(mean), beta


def fit_capacities(
    capacities: np.ndarray, start: float | np.ndarray, top: float | np.ndarray
) -> tuple[float, float | None] | None:
    """Lognormal fragility of IDA capacities, by maximum likelihood with censoring.

    Parameters
    ----------
    capacities
        Per record: the capacity; 0 where the state is reached at ``start`` already (capacity at
        most ``start``), +inf where it is not reached up to ``top`` (capacity above ``top``).
    start, top
        The first and the last scan level: one for every record, or per record (capacities
        converted to another measure, `assessment.measures`).

    Returns
    -------
    (median θ, β), or None when no record has a capacity between the two. Without censoring θ is
    the geometric mean and β the standard deviation (1/n) of the log-capacities; β is None when
    the data cannot fix it (a single capacity, or all equal).
    """
    capacities = np.asarray(capacities, dtype=float)
    known = np.log(capacities[np.isfinite(capacities) & (capacities > 0.0)])
    below, above = capacities == 0.0, np.isinf(capacities)
    if known.size == 0:
        return None
    if not below.any() and not above.any() or known.size == capacities.size:
        beta = float(np.std(known))
        return math.exp(float(np.mean(known))), beta if beta > 0.0 else None
    starts = np.broadcast_to(start, capacities.shape)
    tops = np.broadcast_to(top, capacities.shape)
    lows, highs = _censored(starts[below]), _censored(tops[above])  # (ln bound, records) pairs
    sample = lognormal.Sample(
        known=known, bounds=np.concatenate([lows[0], highs[0]]),
        counts=np.concatenate([lows[1], highs[1]]),
        below=np.repeat([True, False], [lows[0].size, highs[0].size]),
    )  # fmt: skip
    span = (math.log(float(starts.min())), math.log(float(tops.max())))
    spread = float(np.std(known)) if known.size > 1 else 0.3
    mean, beta = lognormal.fit(sample, span, (float(np.mean(known)), max(spread, 0.05)))
    return math.exp(mean), beta


def _censored(bounds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each censoring bound once, as its logarithm, and the number of records censored there."""
    values, counts = np.unique(bounds, return_counts=True)
    return np.log(values), counts.astype(float)


def fragilities(
    path: str | Path,
    bootstrap: int = BOOTSTRAP,
    seed: int = 0,
    measure: str | None = None,
    period: float | None = None,
    period_range: tuple[float, float] | None = None,
    orientation: str | None = None,
) -> list[Fragility]:
    """Every bridge's fragility for every limit state, from a results file with an intensity
    section (stripes or IDA). Analyses that could not run are left out.

    Parameters
    ----------
    measure, period, period_range
        Fit in another intensity measure than the study's (`motions.intensity.MEASURES`; Sa's
        period [s], AvgSa's range [s]): an IDA's capacities converted record by record
        (`assessment.measures`), without running anything.
    orientation
        "median" or "worst": each pair of horizontal components is one record, reaching a
        state where the median over its angles or the worst angle does (a study whose records
        section sweeps an orientation); None: each angle is a record; `STUDY`: as the study
        states (`study_orientation`; each record one where no record was analysed along an
        angle).

    Raises
    ------
    InputError
        The file's study has no intensity section (nothing to fit), another measure is asked
        of stripes or cannot be computed from the file, or an orientation is asked of a file
        without one.
    """
    with open_results(path) as file:
        intensity = read_intensity(file)
        columns = peak_columns(file)
        if intensity is None:
            raise InputError(path, [("", "the study has no intensity section: nothing to fit")])
        if read_spectrum_section(file) is not None:
            raise InputError(path, [("", "an overturning spectrum, not records of one hazard: "
                                     "rockbridge plot overturning draws it")])  # fmt: skip
        conversion = None
        if measure is not None and measure != intensity.measure:
            from .measures import Conversion

            conversion = Conversion.of(file, path, measure, period, period_range)
        if orientation == STUDY:
            orientation = study_orientation(file)
        pairs = None if orientation is None else _pairs(file, path, columns, orientation)
    return fragilities_of(columns, intensity, bootstrap, seed, conversion, pairs, orientation)


def _pairs(file: h5py.File, path: str | Path, columns: dict, orientation: str) -> dict[str, str]:
    """Each base record's pair, for a fit on the pairs' ``orientation`` (`fragilities`)."""
    if orientation not in COMBINES:
        raise ValueError(f"orientation must be one of {COMBINES}, not {orientation!r}")
    pairs = pairs_of(columns, angles_in(file))
    if not pairs:
        why = "no record was analysed along an angle: the study has no orientation section"
        raise InputError(path, [("records", why)])
    return pairs


def study_orientation(file: h5py.File) -> str | None:
    """How a study's own fragility takes each pair of a swept orientation, from its open
    results file: its intensity section's ``orientation``, "median" where it states none; None
    where no record was analysed along an angle (each record one)."""
    if not angles_in(file):
        return None
    intensity = read_intensity(file)
    return (intensity.orientation if intensity is not None else None) or "median"


def design_level(path: str | Path) -> tuple[str, float] | None:
    """(measure, level) of the design level a study's intensity section states, None without."""
    with open_results(path) as file:
        intensity = read_intensity(file)
    if intensity is None or intensity.design is None:
        return None
    return intensity.measure, intensity.design


def fragilities_of(
    columns: dict[str, np.ndarray],
    intensity: IntensitySection,
    bootstrap: int = BOOTSTRAP,
    seed: int = 0,
    conversion: Conversion | None = None,
    pairs: dict[str, str] | None = None,
    orientation: str | None = None,
) -> list[Fragility]:
    """`fragilities` of a peak table's columns and the study's intensity section, in the study's
    measure or converted to another (an IDA's); with ``pairs`` (base record → its pair) each
    pair one record, by its ``orientation`` ("median" or "worst" over its angles)."""
    by_pair = None if pairs is None else (pairs, orientation or "median")
    ok = columns["status"] != "error"
    columns = {name: values[ok] for name, values in columns.items()}
    rng = np.random.default_rng(seed)
    found = []
    order = np.argsort(columns["bridge"], kind="stable")  # each bridge's rows in their order,
    ordered = columns["bridge"][order]  # found once, not once per bridge (a sampled study's 576)
    for bridge in dict.fromkeys(columns["bridge"]):
        rows = order[np.searchsorted(ordered, bridge) : np.searchsorted(ordered, bridge, "right")]
        mine = {name: values[rows] for name, values in columns.items()}
        if intensity.ida is not None:
            found += _ida_fragility(bridge, mine, intensity, rng, bootstrap, conversion, by_pair)
        else:
            found += _stripe_fragility(bridge, mine, intensity, rng, bootstrap, by_pair)
    return found


def _stripe_fragility(bridge, mine, intensity, rng, bootstrap, by_pair) -> list[Fragility]:
    levels = np.array(sorted(set(mine["intensity"].tolist())))
    records = list(dict.fromkeys(mine["base_record"]))
    groups = None if by_pair is None else groups_of(records, by_pair[0])
    names = records if groups is None else list(groups)
    found = []
    for state in _applying((*LIMIT_STATES, *DEVICE_LIMIT_STATES), mine):
        table = _reached(mine, limit_states.reached(state, mine), records, levels)
        if groups is not None:  # each pair one row, its angles combined
            table = pairs_reached(table, groups, by_pair[1])
        counts = _counts(table)  # records × levels above, NaN where not analyzed
        fit = fit_lognormal(levels, *counts)
        draws = _bootstrap(fit, table, rng, bootstrap, lambda t: fit_lognormal(levels, *_counts(t)))
        reached_at = {
            record: next((float(x) for x, r in zip(levels, row, strict=True) if r == 1), None)
            for record, row in zip(names, table, strict=True)
        }
        median, beta = fit or (None, None)
        found.append(Fragility(
            bridge, state, intensity.measure, median, beta, _interval(draws),
            levels.tolist(), (counts[0] / np.maximum(counts[1], 1)).tolist(), reached_at, draws,
            resampling=Resampling(table, lambda t: fit_lognormal(levels, *_counts(t)),
                                  levels=levels),
            orientation=None if by_pair is None else by_pair[1],
        ))  # fmt: skip
    return found


def _ida_fragility(bridge, mine, intensity, rng, bootstrap, conversion, by_pair) -> list[Fragility]:
    rule = Rule.of(intensity)
    lattice, states = rule.lattice, rule.states
    nothing = np.full(len(mine["record"]), np.nan)  # a bridge without tendons' limits
    verdicts = {
        record: Verdict(status, mode, ratio, *flags)
        for record, status, mode, ratio, *flags in zip(
            mine["record"], mine["status"], mine["failure_mode"], mine["dcr_backfill"],
            *(mine.get(state, nothing) for state in DEVICE_LIMIT_STATES), strict=True,
        )
    }  # fmt: skip
    walks: dict[str, Walk] = {}
    for base in dict.fromkeys(mine["base_record"]):
        steps = rule.replay(base, verdicts.get)
        if not steps.wanted:  # a curve an interrupted run or a failed analysis left unfinished
            walks[base] = steps  # has no capacities yet

    def value(base: str, level: float) -> float:
        """A level of the study's measure in the measure fitted."""
        return level if conversion is None else conversion.value(bridge, base, level)

    top = lattice.level(lattice.count - 1)
    found = []
    for state in _applying(states, mine):
        indices = {base: steps.capacities[state] for base, steps in walks.items()}
        capacities = {
            base: None if n is None else value(base, lattice.level(n))
            for base, (_, n) in indices.items()
        }
        unreachable = {
            base: (steps.ended_by, value(base, lattice.level(steps.end)))
            for base, steps in walks.items()
            if steps.unreachable(state) and steps.end is not None
        }
        coded = np.array([
            np.inf if n is None else 0.0 if below < 0 else capacities[base]
            for base, (below, n) in indices.items()
        ]).reshape(-1, 1)  # fmt: skip
        bounds = np.array(
            [
                [
                    value(base, lattice.start),
                    unreachable[base][1] if base in unreachable else value(base, top),
                ]
                for base in walks
            ]
        ).reshape(-1, 2)  # a record never reaching the state is censored where its curve ends
        data = np.hstack([coded, bounds])  # a record's capacity with its bounds
        if by_pair is not None:
            data, capacities, unreachable = _by_pair(data, list(walks), unreachable, by_pair)
        fit = _fit_capacities(data)
        draws = _bootstrap(fit, data, rng, bootstrap, _fit_capacities)
        reached = np.array([c for c in capacities.values() if c is not None])
        levels = sorted(set(reached.tolist()))
        fractions = [float(np.sum(reached <= level)) / len(data) for level in levels]
        median, beta = fit or (None, None)
        found.append(Fragility(
            bridge, state, intensity.measure if conversion is None else conversion.measure,
            median, beta, _interval(draws), levels, fractions, capacities, draws, unreachable,
            Resampling.of_capacities(data, _fit_capacities),
            None if by_pair is None else by_pair[1],
        ))  # fmt: skip
    return found


def _by_pair(
    data: np.ndarray, bases: list[str], unreachable: dict, by_pair: tuple[dict[str, str], str]
) -> tuple[np.ndarray, dict[str, float | None], dict[str, tuple[str, float]]]:
    """An IDA's rows (capacity, start, top) per angle (``bases``) as rows per pair
    (`assessment.orientation.pair_capacities`), with each pair's capacity (None where censored
    above; its bound where reached at the first level) and, where a failure that ended an
    angle's curve bounds the pair, that failure and level."""
    groups = groups_of(bases, by_pair[0])
    rows, sources = pair_capacities(data, groups, by_pair[1])
    capacities: dict[str, float | None] = {}
    ended: dict[str, tuple[str, float]] = {}
    for pair, (capacity, start, top), source in zip(groups, rows, sources, strict=True):
        capacities[pair] = None if math.isinf(capacity) else start if capacity == 0.0 else capacity
        cause = unreachable.get(bases[source])
        if math.isinf(capacity) and cause is not None and cause[1] == top:
            ended[pair] = cause
    return rows, capacities, ended


FAILURE_PHRASES = {"abutment_failure": "the abutment fails", "overturning": "a pier overturns"}
"""How a failure limit state that ends an analysis reads in a sentence."""


def unreachable_note(item: Fragility) -> str:
    """Why a limit state of an IDA cannot be observed on some records, as one line ("" if it
    can on all): ``overturning: unreachable — the abutment fails first on 10/10 records``
    (``pairs`` where the records are a swept orientation's pairs)."""
    if not item.unreachable:
        return ""
    causes: dict[str, int] = {}
    for ended_by, _ in item.unreachable.values():
        causes[ended_by] = causes.get(ended_by, 0) + 1
    total, what = len(item.capacities), "pairs" if item.orientation else "records"
    which = "" if len(item.unreachable) == total else f" on some {what}"
    return f"{item.limit_state}: unreachable{which} — " + ", ".join(
        f"{FAILURE_PHRASES.get(by, by)} first on {n}/{total} {what}" for by, n in causes.items()
    )


def _fit_capacities(data: np.ndarray) -> tuple[float, float | None] | None:
    """`fit_capacities` of rows (capacity, start, top)."""
    return fit_capacities(data[:, 0], data[:, 1], data[:, 2])


def _bootstrap(
    fit, data: np.ndarray, rng, bootstrap: int, refit
) -> tuple[tuple[float, float], ...]:
    """(θ, β) of each of ``bootstrap`` resamplings of the records (rows of ``data``) whose refit
    fixes both; empty without a fit."""
    if fit is None or fit[1] is None or not bootstrap:
        return ()
    draws = [refit(data[rng.integers(0, len(data), len(data))]) for _ in range(bootstrap)]
    return tuple((d[0], d[1]) for d in draws if d is not None and d[1] is not None)


def _interval(draws: tuple[tuple[float, float], ...]) -> tuple[float, float] | None:
    """5 % and 95 % percentiles of the bootstrap's medians, None without draws."""
    if not draws:
        return None
    low, high = np.percentile([median for median, _ in draws], [5.0, 95.0])
    return float(low), float(high)


def _applying(states: Iterable[str], mine: dict) -> list[str]:
    """The limit states among ``states`` that a bridge's analyses (``mine``) can reach: a
    tendon's only where the bridge's tendons state its limit (its column is not all NaN)."""
    return [
        state for state in states
        if state not in DEVICE_LIMIT_STATES or not np.all(np.isnan(mine.get(state, [np.nan])))
    ]  # fmt: skip


def _reached(mine: dict, reached: np.ndarray, records: list[str], levels: np.ndarray):
    """1 where a record reaches the state at a level, 0 where not, NaN where it was not analyzed."""
    table = np.full((len(records), levels.size), np.nan)
    row = {record: i for i, record in enumerate(records)}
    column = {level: j for j, level in enumerate(levels.tolist())}
    for record, level, hit in zip(mine["base_record"], mine["intensity"], reached, strict=True):
        table[row[record], column[float(level)]] = float(hit)
    return table


def _counts(table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Records reaching the state, and records analyzed, at each level."""
    return np.nansum(table, axis=0), np.sum(~np.isnan(table), axis=0)


def store(file: h5py.File) -> None:
    """Write the fragilities of an open results file into it, as the table ``/fragility``: one
    row per bridge × limit state (median, beta, the 90 % interval of the median) and, per row,
    each record's capacity (``capacities``, rows × records, NaN where not reached). Of a study
    that swept an orientation, the records are its pairs, each taken over its angles as the
    study states (`study_orientation`, the ``orientation`` attribute). A spectrum study's file
    gets its spectrum instead (`spectrum.store`)."""
    intensity = read_intensity(file)
    if intensity is None:
        return
    if read_spectrum_section(file) is not None:  # its IDA finds a spectrum's boundaries
        store_spectrum(file)
        return
    peaks = peak_columns(file)
    orientation = study_orientation(file)
    pairs = None if orientation is None else pairs_of(peaks, angles_in(file))
    found = fragilities_of(peaks, intensity, pairs=pairs, orientation=orientation)
    records = list(dict.fromkeys(record for item in found for record in item.capacities))
    group = file.create_group("fragility")
    group.attrs["description"] = (
        "lognormal fragility per bridge and limit state (rockbridge_cli.assessment.fragility), "
        "as the run computed it; rockbridge fragility RESULTS.h5 prints the same"
    ) + ("" if orientation is None else f"; the records are the pairs of horizontal components, "
         f"each reaching a state where {COMBINED[orientation]} does")  # fmt: skip
    group.attrs["measure"] = intensity.measure
    if orientation is not None:
        group.attrs["orientation"] = orientation
    group.attrs["records"] = json.dumps(records)
    columns: dict[str, tuple[str, list[Any]]] = {
        "bridge": ("-", [item.bridge for item in found]),
        "limit_state": ("-", [item.limit_state for item in found]),
        "median": (MEASURES[intensity.measure].unit, [_number(item.median) for item in found]),
        "beta": ("-", [_number(item.beta) for item in found]),
        "median_05": (MEASURES[intensity.measure].unit,
                      [_number(item.median_90 and item.median_90[0]) for item in found]),
        "median_95": (MEASURES[intensity.measure].unit,
                      [_number(item.median_90 and item.median_90[1]) for item in found]),
    }  # fmt: skip
    for name, (unit, values) in columns.items():
        text = isinstance(values[0], str) if values else False
        dataset = group.create_dataset(
            name, data=np.array(values, dtype=object if text else float),
            dtype=h5py.string_dtype() if text else float,
        )  # fmt: skip
        dataset.attrs["units"] = unit
    capacities = np.array(
        [[_number(item.capacities.get(record)) for record in records] for item in found],
        dtype=float,
    ).reshape(len(found), len(records))
    dataset = group.create_dataset("capacities", data=capacities)
    dataset.attrs["units"] = MEASURES[intensity.measure].unit
    dataset.attrs["description"] = (
        "rows as the other columns, columns as the records attribute: the lowest level at which "
        "the record reaches the state (NaN: not within the levels run)"
    )


def _number(value: float | None) -> float:
    return float("nan") if value is None else float(value)
