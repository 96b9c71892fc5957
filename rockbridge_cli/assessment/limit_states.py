"""Limit states: what an analysis's peaks say the bridge reached.

An analysis reaches

- ``gap_closure`` when an end joint closes and loads the backfill (``dcr_backfill`` > 0);
- ``backfill_<p>`` when the backfill deforms to p % of its capacity (``dcr_backfill`` ≥ p/100),
  for any whole p from 1 to 100 (``backfill_50``: half its capacity);
- ``abutment_failure`` when the abutment–backfill fails (``failure_mode`` ``abutment``);
- ``overturning`` when a pier overturns (``failure_mode`` ``overturning_*``);
- ``tendon_yield`` when a tendon yields, ``tendon_rupture`` when it ruptures,
  ``dissipator_fracture`` when a dissipator fractures (the solver's state; columns of those
  names, 1 reached, 0 not, NaN for a bridge whose devices state no such limit:
  `results.packing.device_states`; the behaviour past them: docs/model.md §13).

(docs/model.md §7–8, §13; their names are `core.quantities.LIMIT_STATES` and
`DEVICE_LIMIT_STATES`.) The tests take the columns of a peak table, or the scalars of one
analysis, and never fail on a missing value: an analysis that could not run reaches nothing.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from ..core.quantities import (
    ABUTMENT,
    DEVICE_LIMIT_STATES,
    PIER1_OVERTURNING,
    PIER2_OVERTURNING,
    check_limit_state,
)
from ..results.packing import device_states
from ..results.reading import device_tables
from .ida import Outcome

if TYPE_CHECKING:
    import h5py


def reached(name: str, columns: Mapping[str, Any]) -> np.ndarray:
    """Whether each analysis reaches the limit state ``name``.

    Parameters
    ----------
    columns
        ``dcr_backfill`` [-] and ``failure_mode``, as arrays (a peak table's columns) or scalars;
        for a tendon's limit state, the column of its name (none: not reached).

    Returns
    -------
    numpy.ndarray
        Booleans, the shape of the columns.
    """
    ratio = np.asarray(columns["dcr_backfill"], dtype=float)
    mode = np.asarray(columns["failure_mode"]).astype(str)
    if name in DEVICE_LIMIT_STATES:
        flags = columns.get(name)
        return np.zeros(ratio.shape, bool) if flags is None else np.asarray(flags, float) == 1.0
    if name == "gap_closure":
        return ratio > 0.0
    if name == "abutment_failure":
        return mode == ABUTMENT
    if name == "overturning":
        return (mode == PIER1_OVERTURNING) | (mode == PIER2_OVERTURNING)
    return ratio >= int(check_limit_state(name).removeprefix("backfill_")) / 100.0


class Verdict(NamedTuple):
    """What decides the limit states of one analysis: its status, the two peaks they test, and
    whether its tendons reached their limits (1.0, 0.0, NaN where none states one)."""

    status: str
    failure_mode: str
    dcr_backfill: float
    tendon_yield: float = float("nan")
    tendon_rupture: float = float("nan")
    dissipator_fracture: float = float("nan")

    def reaches(self, names: Iterable[str]) -> frozenset[str]:
        """The limit states among ``names`` this analysis reaches (none unless it ran)."""
        if self.status == "error":
            return frozenset()
        return frozenset(name for name in names if bool(reached(name, self._asdict())))

    def outcome(self, names: Iterable[str]) -> Outcome:
        """What the IDA rule needs: the states among ``names`` reached, and the failure limit
        state that ended the analysis, whether or not it is among ``names``."""
        ended_by = "" if self.status == "error" else ENDED_BY.get(self.failure_mode, "")
        return Outcome(self.reaches(names), ended_by)


ENDED_BY = {
    ABUTMENT: "abutment_failure", PIER1_OVERTURNING: "overturning",
    PIER2_OVERTURNING: "overturning",
}  # fmt: skip
"""The limit state of each failure mode, which ends an analysis."""


def stored_verdicts(file: h5py.File) -> dict[tuple[str, str], Verdict]:
    """The verdict of each analysis an open results file holds, by (bridge, record)."""
    group = file["peaks"]
    pairs = list(zip(group["bridge"].asstr()[()], group["record"].asstr()[()], strict=True))
    verdicts = zip(
        group["status"].asstr()[()], group["failure_mode"].asstr()[()],
        group["dcr_backfill"][()].tolist(), strict=True,
    )  # fmt: skip
    found = dict(zip(pairs, itertools.starmap(Verdict, verdicts), strict=True))
    for pair, rows in device_tables(file).items():  # the tendons' states, where some are
        found[pair] = Verdict(*found[pair][:3], *device_states(rows).values())
    return found
