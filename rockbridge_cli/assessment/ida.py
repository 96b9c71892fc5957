"""The rule of incremental dynamic analysis (Vamvatsikos & Cornell 2002): for each bridge × record
(a curve) and each limit state, the lowest intensity at which the state is reached.

The rule (docs/batch.md): scan upward from ``start`` by ``step`` until every limit state has been
reached or the next level would pass ``max``; then, for each state, bisect between the last scan
level that did not reach it and the first that did, until the two are within ``tolerance`` of the
upper one, which is the capacity. Rocking IDA curves need not be monotonic: a level above the
capacity may again not reach the state; the rule is the definition, and every level run is kept.

Every level an IDA can run lies on a lattice, ``start + step · n / 2^depth`` (bisection halves
the step), so a level has one exact value and one id however it was reached, and the position of
an analysis in the results is its lattice index. The rule is a function of the verdicts found so
far: a study runs it in rounds (`study.plan`), and the fragility fits replay it from the stored
verdicts (`assessment.fragility`) without running anything.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Lattice:
    """The levels an IDA may run: ``start + step · n / 2^depth`` for n = 0 … count − 1.

    ``depth`` is the fewest halvings of ``step`` that bring it within ``tolerance · start``, so
    that bisection can reach the tolerance anywhere above ``start``.
    """

    start: float
    step: float
    depth: int
    count: int

    @classmethod
    def of(cls, ida: Mapping[str, Any]) -> Lattice:
        """The lattice of an ``intensity.ida`` section."""
        start, step = float(ida["start"]), float(ida["step"])
        depth = max(0, math.ceil(math.log2(step / (ida["tolerance"] * start))))
        scans = math.floor((ida["max"] - start) / step + 1e-9)  # 1e-9: 4.0 − 0.1 by 0.1 is 39
        return cls(start, step, depth, scans * 2**depth + 1)

    @property
    def stride(self) -> int:
        """Lattice points between two scan levels."""
        return 2**self.depth

    def level(self, n: int) -> float:
        """The level at lattice index ``n``."""
        return self.start + self.step * n / self.stride


@dataclass(frozen=True)
class Walk:
    """Where one curve stands.

    Attributes
    ----------
    wanted : lattice indices to run next (empty when the curve is done)
    visited : lattice indices run so far that the rule uses
    capacities : limit state → lattice indices (below, level) of the capacity so far; level
        None if not reached, below −1 if reached at ``start``
    """

    wanted: frozenset[int]
    visited: frozenset[int]
    capacities: dict[str, tuple[int, int | None]]


def walk(
    lattice: Lattice,
    tolerance: float,
    states: tuple[str, ...],
    reaches: Callable[[int], frozenset[str] | None],
) -> Walk:
    """Follow the rule along one curve.

    Parameters
    ----------
    reaches
        For a lattice index, the limit states its analysis reached, or None if it has not run.
    """
    wanted: set[int] = set()
    visited: set[int] = set()
    reached_so_far: set[str] = set()
    scanned = []
    for n in range(0, lattice.count, lattice.stride):
        found = reaches(n)
        if found is None:
            wanted.add(n)
            break
        visited.add(n)
        scanned.append((n, found))
        reached_so_far |= found
        if reached_so_far.issuperset(states):
            break
    capacities: dict[str, tuple[int, int | None]] = {}
    for state in states:
        first = next((n for n, found in scanned if state in found), None)
        if first is None:
            capacities[state] = (-1, None)
            continue
        below, level = first - lattice.stride, first
        while (
            below >= 0
            and level - below > 1
            and (lattice.level(level) - lattice.level(below) > tolerance * lattice.level(level))
        ):
            middle = (below + level) // 2
            found = reaches(middle)
            if found is None:
                wanted.add(middle)
                break
            visited.add(middle)
            below, level = (below, middle) if state in found else (middle, level)
        capacities[state] = (max(below, -1), level)
    return Walk(frozenset(wanted), frozenset(visited), capacities)
