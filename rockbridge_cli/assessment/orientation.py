"""What orientation does to a study's demand: for a study that swept each pair of horizontal
components over angles (`config.orientation`), each quantity's median over the angles (the
response counterpart of RotD50), its worst (RotD100's) and the critical angle, per bridge, pair
and intensity level (`orientation_summary`), from the results file alone.

The angle and pair of each analysed record are its group's ``angle_deg`` and ``pair``
(``/records/<id>``); a record analysed as given has neither and is left out.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from ..motions.orientation import summarize_angles
from ..results.reading import open_results, read_peaks

if TYPE_CHECKING:
    import pandas as pd

QUANTITIES = ("theta1_max", "u_deck_max", "dcr_backfill")
"""The quantities summarised unless others are named: the tall pier's peak rotation [rad], the
deck's peak displacement [m] and the backfill's demand-to-capacity ratio [-]."""


def record_angles(path: str | Path) -> dict[str, tuple[str, float]]:
    """Each analysed projection's pair and angle [deg], by record id, from a results file."""
    with open_results(path) as file:
        return {
            name: (str(node.attrs["pair"]), float(node.attrs["angle_deg"]))
            for name, node in file["records"].items()
            if "angle_deg" in node.attrs
        }


def orientation_summary(
    peaks: pd.DataFrame,
    angles: dict[str, tuple[str, float]],
    quantities: Sequence[str] = QUANTITIES,
) -> pd.DataFrame:
    """Per bridge, pair and level (NaN without an intensity section), and per quantity: its
    median over the angles, its worst and the angle of the worst (`summarize_angles`).

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
        columns bridge, pair, intensity, quantity, median, worst, critical_angle_deg, angles
        (how many angles finished, of those analysed).
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
            summary = summarize_angles(degrees[group.index].to_numpy(), values)
            finished = int((~pd.isna(values)).sum())
            rows.append((bridge, pair, intensity, name, *summary, f"{finished}/{values.size}"))
    columns = ["bridge", "pair", "intensity", "quantity", "median", "worst",
               "critical_angle_deg", "angles"]  # fmt: skip
    return pd.DataFrame(rows, columns=columns)


def summary_of(path: str | Path, quantities: Sequence[str] = QUANTITIES) -> pd.DataFrame:
    """`orientation_summary` of a results file."""
    return orientation_summary(read_peaks(path), record_angles(path), quantities)
