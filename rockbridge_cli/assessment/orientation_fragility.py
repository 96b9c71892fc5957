"""What orientation does to a study's fragility: for a study with an intensity section whose
records section swept an orientation, each bridge's fragility (median θ, β) for each limit state
three ways, each angle a record of its own, each pair by the median over its angles and by its
worst angle (`fragility.fragilities`' ``orientation``), beside the one the run stores
(`fragility.study_orientation`)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..results.reading import open_results, read_intensity
from .fragility import fragilities, study_orientation

WAYS = {"angles": None, "median": "median", "worst": "worst"}
"""The three fits, by the name of their columns → `fragilities`' ``orientation``."""


def fragility_by_orientation(path: str | Path) -> list[dict[str, Any]]:
    """Per bridge and limit state, the fragility fitted each of the `WAYS` (no bootstrap: the
    fits alone), and which of them the run stored.

    Returns
    -------
    list of dict
        bridge, limit_state, measure, stored ("median" or "worst"), then for each way its
        ``<way>_median`` [the measure's unit] and ``<way>_beta`` [-] (None where it has no fit);
        empty for a study without an intensity section or without an orientation.
    """
    with open_results(path) as file:
        if read_intensity(file) is None:
            return []
        stored = study_orientation(file)
    if stored is None:
        return []
    fits = {
        way: {(f.bridge, f.limit_state): f for f in fragilities(path, bootstrap=0, orientation=o)}
        for way, o in WAYS.items()
    }
    rows = []
    for key, item in fits["angles"].items():
        row: dict[str, Any] = {"bridge": item.bridge, "limit_state": item.limit_state,
                               "measure": item.measure, "stored": stored}  # fmt: skip
        for way, found in fits.items():
            row[f"{way}_median"], row[f"{way}_beta"] = found[key].median, found[key].beta
        rows.append(row)
    return rows
