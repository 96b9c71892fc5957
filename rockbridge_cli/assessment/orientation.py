"""What orientation does to a study's demand: for a study that swept each pair of horizontal
components over angles (`config.orientation`), each quantity's median over the angles (the
response counterpart of RotD50), its worst (RotD100's) and the critical angle, per bridge, pair
and intensity level (`orientation_summary`), and those over the pairs against the first
component alone (`across_pairs`), from the results file alone; each row's pair and angle beside
the peak table's columns (`with_angles`).

The angle and pair of each analysed record are its group's ``angle_deg`` and ``pair``
(``/records/<id>``); a record analysed as given has neither and is left out.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..motions.orientation import summarize_angles
from ..results.reading import open_results, read_peaks

if TYPE_CHECKING:
    import h5py
    import pandas as pd

QUANTITIES = ("theta1_max", "u_deck_max", "dcr_backfill")
"""The quantities summarised unless others are named: the tall pier's peak rotation [rad], the
deck's peak displacement [m] and the backfill's demand-to-capacity ratio [-]."""


ANGLE_UNITS = {"pair": "-", "angle_deg": "deg"}
"""The units of the two columns `with_angles` adds."""


def angles_in(file: h5py.File) -> dict[str, tuple[str, float]]:
    """Each analysed projection's pair and angle [deg], by record id, from an open results file
    (empty for a study without an orientation section)."""
    return {
        name: (str(node.attrs["pair"]), float(node.attrs["angle_deg"]))
        for name, node in file["records"].items()
        if "angle_deg" in node.attrs
    }


def record_angles(path: str | Path) -> dict[str, tuple[str, float]]:
    """`angles_in` of a results file."""
    with open_results(path) as file:
        return angles_in(file)


def angle_keys(columns: Any, angles: dict[str, tuple[str, float]]) -> list[str]:
    """Each row's key in ``angles``: its record, or its base record where an IDA stores its
    records unscaled (``/records/<base>``); the record where neither is in ``angles``."""
    records = [str(r) for r in columns["record"]]
    if "base_record" not in columns:
        return records
    bases = [str(b) for b in columns["base_record"]]
    return [r if r in angles or b not in angles else b for r, b in zip(records, bases, strict=True)]


def with_angles(columns: dict[str, Any], angles: dict[str, tuple[str, float]]) -> dict[str, Any]:
    """The peak table's columns with each row's ``pair`` and ``angle_deg`` [deg] right after
    ``record`` ("" and NaN for a record analysed as given); the columns themselves, unchanged,
    when no record was analysed along an angle.

    Parameters
    ----------
    columns
        name → values, one per row, ``record`` among them (`results.reading.peak_columns`).
    angles
        record id → (pair, angle [deg]) (`angles_in`).
    """
    if not angles:
        return columns
    found = [angles.get(key, ("", math.nan)) for key in angle_keys(columns, angles)]
    added = {
        "pair": np.array([pair for pair, _ in found], dtype=object),
        "angle_deg": np.array([angle for _, angle in found], dtype=float),
    }
    out: dict[str, Any] = {}
    for name, values in columns.items():
        out[name] = values
        if name == "record":
            out.update(added)
    return out


def orientation_summary(
    peaks: pd.DataFrame,
    angles: dict[str, tuple[str, float]],
    quantities: Sequence[str] = QUANTITIES,
) -> pd.DataFrame:
    """Per bridge, pair and level (NaN without an intensity section), and per quantity: its
    value along the pair's first component (0°), its median over the angles, its worst and the
    angle of the worst (`summarize_angles`).

    Parameters
    ----------
    peaks
        a peak table (`results.reading.read_peaks`).
    angles
        record id → (pair, angle [deg]) (`record_angles`).
    quantities
        peak-table columns to summarise (their units).

    Returns
    -------
    pandas.DataFrame
        columns bridge, pair, intensity, quantity, first (at 0°; NaN if 0° was not analysed or
        did not finish), median, worst, critical_angle_deg, angles (how many angles finished, of
        those analysed).
    """
    import pandas as pd

    keys = pd.Series(angle_keys(peaks, angles), index=peaks.index)
    kept = peaks[keys.isin(angles)]
    level = kept["intensity"] if "intensity" in kept else pd.Series(math.nan, index=kept.index)
    pairs = keys[kept.index].map(lambda r: angles[r][0])
    degrees = keys[kept.index].map(lambda r: angles[r][1])
    rows = []
    keys = pd.DataFrame({"bridge": kept["bridge"], "pair": pairs, "intensity": level})
    for (bridge, pair, intensity), group in keys.groupby(
        ["bridge", "pair", "intensity"], sort=False, dropna=False
    ):
        for name in quantities:
            values = kept.loc[group.index, name].to_numpy(dtype=float)
            along = degrees[group.index].to_numpy(dtype=float)
            first = float(values[along == 0.0][0]) if (along == 0.0).any() else math.nan
            summary = summarize_angles(along, values)
            finished = int((~pd.isna(values)).sum())
            rows.append(
                (bridge, pair, intensity, name, first, *summary, f"{finished}/{values.size}")
            )
    columns = ["bridge", "pair", "intensity", "quantity", "first", "median", "worst",
               "critical_angle_deg", "angles"]  # fmt: skip
    return pd.DataFrame(rows, columns=columns)


def summary_of(path: str | Path, quantities: Sequence[str] = QUANTITIES) -> pd.DataFrame:
    """`orientation_summary` of a results file."""
    return orientation_summary(read_peaks(path), record_angles(path), quantities)


def across_pairs(summary: pd.DataFrame) -> pd.DataFrame:
    """What orientation does over a suite: per bridge, level and quantity, the median over the
    pairs of their value along the first component alone, of their median over the angles and
    of their worst, and how much the worst raises a pair's first component (median and largest
    of worst/first over the pairs with a nonzero first).

    Parameters
    ----------
    summary
        `orientation_summary`'s rows.

    Returns
    -------
    pandas.DataFrame
        columns bridge, intensity, quantity, pairs, first, median, worst (each the median over
        the pairs, NaN left out; the quantity's unit), worst_over_first_median,
        worst_over_first_max [-].
    """
    import pandas as pd

    rows = []
    for (bridge, intensity, name), group in summary.groupby(
        ["bridge", "intensity", "quantity"], sort=False, dropna=False
    ):
        first = group["first"].to_numpy(dtype=float)
        worst = group["worst"].to_numpy(dtype=float)
        usable = np.isfinite(first) & np.isfinite(worst) & (first != 0.0)
        ratio = worst[usable] / first[usable]
        medians = [_median(group[key].to_numpy(dtype=float)) for key in ("first", "median")]
        rows.append((bridge, intensity, name, len(group), *medians, _median(worst),
                     _median(ratio), float(ratio.max()) if ratio.size else math.nan))  # fmt: skip
    columns = ["bridge", "intensity", "quantity", "pairs", "first", "median", "worst",
               "worst_over_first_median", "worst_over_first_max"]  # fmt: skip
    return pd.DataFrame(rows, columns=columns)


def _median(values: np.ndarray) -> float:
    """The median of the finite values, NaN if none."""
    finite = values[np.isfinite(values)]
    return float(np.median(finite)) if finite.size else math.nan


COMBINES = ("median", "worst")
"""How a fragility takes a pair's angles as one record (`pairs_reached`, `pair_capacities`): the
state is reached when the quantity's median over the angles reaches it (at least half of the
angles do: RotD50's counterpart) or its worst does (any angle: RotD100's)."""

COMBINED = {"median": "the median over its angles", "worst": "its worst angle"}
"""What reaches a state for a pair taken as one record, by `COMBINES`, as a sentence says it."""


def pairs_of(columns: dict[str, Any], angles: dict[str, tuple[str, float]]) -> dict[str, str]:
    """The pair of each base record (``base_record``, the record before an intensity section
    scaled it) analysed along an angle, from a peak table's columns and `angles_in` (keyed by
    record, or by base record where an IDA stores its records unscaled)."""
    found = {}
    for key, base in zip(angle_keys(columns, angles), columns["base_record"], strict=True):
        if key in angles:
            found[str(base)] = angles[key][0]
    return found


def groups_of(names: Sequence[str], pairs: dict[str, str]) -> dict[str, list[int]]:
    """The indices in ``names`` (base records) of each pair's angles, pairs in order of first
    appearance; a name without a pair is a group of its own."""
    groups: dict[str, list[int]] = {}
    for index, name in enumerate(names):
        groups.setdefault(pairs.get(name, name), []).append(index)
    return groups


def pairs_reached(table: np.ndarray, groups: dict[str, list[int]], combine: str) -> np.ndarray:
    """Stripes' outcomes of each angle (records × levels: 1 reached, 0 not, NaN not analysed)
    as one row per pair: 1 where the pair's median over its analysed angles reaches the state
    (at least half of them reach it) or its worst does (``combine`` "worst": any angle), NaN
    where no angle was analysed."""
    out = np.full((len(groups), table.shape[1]), np.nan)
    for row, indices in enumerate(groups.values()):
        part = table[indices]
        analysed, hits = np.sum(~np.isnan(part), axis=0), np.nansum(part, axis=0)
        needed = analysed / 2.0 if combine == "median" else np.ones_like(hits)
        out[row] = np.where(analysed > 0, (hits >= needed) & (hits > 0), np.nan)
    return out


def pair_capacities(
    data: np.ndarray, groups: dict[str, list[int]], combine: str
) -> tuple[np.ndarray, list[int]]:
    """An IDA's capacities of each angle as one per pair: the worst angle's (the smallest, so the
    largest demand over the angles first reaches the state there) or the median over the angles
    (the ⌈n/2⌉-th smallest of n, where at least half of the angles have reached it).

    Parameters
    ----------
    data
        rows (capacity, start, top) per angle, as `assessment.fragility.fit_capacities` takes
        them: 0 where the state is reached at ``start`` already, +inf where not up to ``top``.
    groups
        each pair's rows (`groups_of`).
    combine
        "median" or "worst".

    Returns
    -------
    (rows, sources)
        one row per pair, as ``data``'s; and the row of ``data`` whose bound or capacity is the
        pair's. A pair whose order statistic lies between one angle's capacity and another's
        censoring bound (a curve a failure ended below another angle's capacity) is censored
        at the lower bound: known to exceed it.
    """
    rows, sources = [], []
    for indices in groups.values():
        part = data[indices]
        capacity, start, top = part[:, 0], part[:, 1], part[:, 2]
        lower = np.where(capacity == 0.0, 0.0, np.where(np.isinf(capacity), top, capacity))
        upper = np.where(capacity == 0.0, start, capacity)
        k = 0 if combine == "worst" else math.ceil(len(indices) / 2) - 1
        order = np.argsort(lower, kind="stable")
        low, high = float(lower[order[k]]), float(np.sort(upper)[k])
        sources.append(indices[int(order[k])])
        if low == 0.0:  # at least k + 1 angles reach the state at their first level
            rows.append((0.0, high, float(top.max())))
        elif low == high:
            rows.append((low, float(start.min()), float(top.max())))
        else:  # not reached up to low by at least n − k angles
            rows.append((math.inf, float(start.min()), low))
    return np.array(rows, dtype=float).reshape(-1, 3), sources
