"""How a peak table's analyses form summaries: per bridge in a study without an intensity section,
per bridge and intensity level in a multiple-stripe study. A summary over the records (a median,
a largest value, a count of failures) is one of records at one intensity: taken over every level
of a stripe study at once it mixes 0.1 g with 4 g. An IDA's levels differ by record (each curve
bisects to its own capacities and ends at its own first failure), so its peaks are summarised by
its capacities (`assessment.fragility`, ``rockbridge fragility``, ``rockbridge plot ida``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..results.sections import IntensitySection

IDA_POINTER = (
    "an IDA's levels differ by record (each curve ends at its own failure): its summary is the "
    "capacity of each limit state (rockbridge fragility RESULTS; rockbridge plot ida RESULTS)"
)
"""What a command that summarises peaks per intensity level says of an IDA."""


@dataclass(frozen=True)
class Group:
    """Analyses that a summary takes together.

    Attributes
    ----------
    bridge : the bridge's id
    level : the intensity level [the measure's unit]; None without an intensity section
    rows : booleans over the peak table's rows
    """

    bridge: str
    level: float | None
    rows: np.ndarray


def summary_groups(
    columns: dict[str, np.ndarray], intensity: IntensitySection | None
) -> list[Group]:
    """The groups of a peak table's rows that a summary over the records takes: per bridge, and
    per intensity level in a multiple-stripe study (levels in increasing order).

    Raises
    ------
    ValueError
        The study is an IDA (`IDA_POINTER` says why, and what to use instead).
    """
    if intensity is not None and intensity.ida is not None:
        raise ValueError(IDA_POINTER)
    groups = []
    for bridge in dict.fromkeys(columns["bridge"].tolist()):
        mine = columns["bridge"] == bridge
        if intensity is None:
            groups.append(Group(bridge, None, mine))
            continue
        for level in sorted(set(columns["intensity"][mine].tolist())):
            groups.append(Group(bridge, level, mine & (columns["intensity"] == level)))
    return groups


def record_count(columns: dict[str, np.ndarray]) -> int:
    """The records a peak table's analyses are of: scaled copies of a record (``AR01+0.5g``)
    count as their base record."""
    return len(set(columns.get("base_record", columns["record"]).tolist()))


def levels_of(columns: dict[str, np.ndarray]) -> list[float]:
    """The intensity levels of a multiple-stripe study's peak table, in increasing order (empty
    without an intensity section)."""
    return sorted(set(columns["intensity"].tolist())) if "intensity" in columns else []


def rows_at_level(
    columns: dict[str, np.ndarray], intensity: IntensitySection, level: float | None, unit: str
) -> tuple[np.ndarray, float]:
    """The rows of a multiple-stripe study at one of its levels, and that level as stored.

    Raises
    ------
    ValueError
        The study is an IDA (`IDA_POINTER`), or ``level`` is not one of the stripes' (the message
        lists them).
    """
    if intensity.ida is not None:
        raise ValueError(IDA_POINTER)
    levels = levels_of(columns)
    near = [x for x in levels if level is not None and math.isclose(x, level, rel_tol=1e-9)]
    if not near:
        listed = ", ".join(f"{x:g}" for x in levels)
        said = "" if level is None else f"{level:g} is not one; "
        raise ValueError(f"a summary over the records (a median, a mean) is taken at one "
                         f"intensity level: {said}choose one with --level ({listed} "
                         f"{unit})")  # fmt: skip
    return columns["intensity"] == near[0], near[0]
