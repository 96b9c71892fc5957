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
    found = [angles.get(str(record), ("", math.nan)) for record in columns["record"]]
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

    kept = peaks[peaks["record"].isin(angles)]
    level = kept["intensity"] if "intensity" in kept else pd.Series(math.nan, index=kept.index)
    pairs = kept["record"].map(lambda r: angles[r][0])
    degrees = kept["record"].map(lambda r: angles[r][1])
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
