"""The rule of incremental dynamic analysis (Vamvatsikos & Cornell 2002): for each bridge × record
(a curve) and each limit state, the lowest intensity at which the state is reached.

The rule (docs/batch.md): scan upward from ``start`` by ``step`` until every limit state has been
reached, an analysis ended in a failure or the next level would pass ``max``; then, for each state,
bisect between the last scan level that did not reach it and the first that did, until the two are
within ``tolerance`` of the upper one, which is the capacity. A failure (the abutment's, or a
pier's overturning) ends an analysis, so the curve ends at the lowest level whose analysis failed:
a state not reached up to there is *unreachable* on that curve (its capacity is not above ``max``,
it cannot be observed). Rocking IDA curves need not be monotonic: a level above the capacity may
again not reach the state; the rule is the definition, and every level run is kept.

Every level an IDA can run lies on a lattice, ``start + step · n / 2^depth`` (bisection halves
the step), so a level has one exact value and one id however it was reached, and the position of
an analysis in the results is its lattice index. The rule is a function of the verdicts found so
far, replayed by one function (`Rule.replay`): a study runs it in rounds (`study.plan`), and the
fragility fits (`assessment.fragility`) and the overturning spectra (`assessment.spectrum`) replay
it from the stored verdicts without running anything.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import NamedTuple, Protocol

from ..motions.intensity import scaled_id
from ..results.sections import IdaSection, IntensitySection


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
    def of(cls, ida: IdaSection) -> Lattice:
        """The lattice of an intensity section's IDA."""
        start, step = ida.start, ida.step
        depth = max(0, math.ceil(math.log2(step / (ida.tolerance * start))))
        scans = math.floor((ida.max - start) / step + 1e-9)  # 1e-9: 4.0 − 0.1 by 0.1 is 39
        return cls(start, step, depth, scans * 2**depth + 1)

    @property
    def stride(self) -> int:
        """Lattice points between two scan levels."""
        return 2**self.depth

    def level(self, n: int) -> float:
        """The level at lattice index ``n``."""
        return self.start + self.step * n / self.stride


class Outcome(NamedTuple):
    """What the rule needs of one analysis.

    Attributes
    ----------
    reached : the limit states the analysis reached
    ended_by : the failure limit state that ended the analysis (``abutment_failure`` or
        ``overturning``), or "" if it ran to its end
    """

    reached: frozenset[str]
    ended_by: str = ""


class Judged(Protocol):
    """What an analysis's verdict tells the rule (`limit_states.Verdict`)."""

    def outcome(self, names: Iterable[str]) -> Outcome: ...


@dataclass(frozen=True)
class Rule:
    """The IDA of an intensity section: its lattice, the bisection's relative ``tolerance``, the
    limit states it finds the capacities of, and the measure its scaled records' ids name."""

    lattice: Lattice
    tolerance: float
    states: tuple[str, ...]
    measure: str

    @classmethod
    def of(cls, intensity: IntensitySection) -> Rule:
        """The rule of an intensity section with an IDA.

        Raises
        ------
        ValueError
            The section has no IDA (stripes).
        """
        if intensity.ida is None:
            raise ValueError("an intensity section of stripes has no IDA rule")
        ida = intensity.ida
        return cls(Lattice.of(ida), ida.tolerance, ida.limit_states, intensity.measure)

    def record(self, base: str, n: int) -> str:
        """The id of record ``base`` scaled to the level at lattice index ``n``
        (`motions.intensity.scaled_id`): ``base`` followed by ``record("", n)``, what the level
        adds (formatted once a level where a spectrum's map has a million ids)."""
        return scaled_id(base, self.lattice.level(n), self.measure)

    def replay(self, base: str, verdict: Callable[[str], Judged | None]) -> Walk:
        """Where the curve of record ``base`` stands: the rule followed on the verdicts so far,
        ``verdict`` giving that of a scaled record's analysis by its id (None: not run yet)."""

        def outcome(n: int) -> Outcome | None:
            found = verdict(self.record(base, n))
            return None if found is None else found.outcome(self.states)

        return walk(self.lattice, self.tolerance, self.states, outcome)


@dataclass(frozen=True)
class Walk:
    """Where one curve stands.

    Attributes
    ----------
    wanted : lattice indices to run next (empty when the curve is done)
    visited : lattice indices run so far that the rule uses
    capacities : limit state → lattice indices (below, level) of the capacity so far; level
        None if not reached, below −1 if reached at ``start``
    end : lattice index of the lowest analysis run that ended in a failure, where the curve
        ends; None if none did
    ended_by : the failure limit state that ended the curve ("" without ``end``)
    """

    wanted: frozenset[int]
    visited: frozenset[int]
    capacities: dict[str, tuple[int, int | None]]
    end: int | None = None
    ended_by: str = ""

    def unreachable(self, state: str) -> bool:
        """Whether ``state`` cannot be observed on this curve: a failure ended it first."""
        return self.end is not None and self.capacities[state][1] is None


def walk(
    lattice: Lattice,
    tolerance: float,
    states: tuple[str, ...],
    outcome: Callable[[int], Outcome | None],
) -> Walk:
    """Follow the rule along one curve.

    A failure (the abutment's, a pier's overturning) ends an analysis, so a state that its
    analysis did not reach cannot be observed at or above its level: the curve ends at the lowest
    level whose analysis ended in a failure, the scan stops at the first, and the states not
    reached up to it are unreachable. Should a bisection find a failure below the scan's that the
    capacities so far contradict (another failure, a state reached below it without a capacity),
    the rule is followed again on the curve that ends there.

    Parameters
    ----------
    outcome
        For a lattice index, what its analysis reached, or None if it has not run.
    """
    seen: dict[int, Outcome] = {}

    def look(n: int) -> Outcome | None:
        found = outcome(n)
        if found is not None:
            seen[n] = found
        return found

    scanned, wanted = _scan(lattice, states, look)
    last = max(scanned, default=None)
    end = last if last is not None and scanned[last].ended_by else None
    while True:
        capacities, asked = _bisect(lattice, tolerance, states, scanned, end, seen, look)
        lowest = min((n for n, found in seen.items() if found.ended_by), default=None)
        if lowest is None or lowest == end or _consistent(capacities, seen, lowest):
            break
        end = lowest  # a failure below the end that the capacities contradict: a shorter curve
    if lowest is not None:
        capacities = {
            state: (-1, None) if level is None or level > lowest else (below, level)
            for state, (below, level) in capacities.items()
        }  # a state not reached where the curve ends is unreachable
    wanted = {n for n in wanted | asked if lowest is None or n < lowest}
    ended_by = "" if lowest is None else seen[lowest].ended_by
    return Walk(frozenset(wanted), frozenset(seen), capacities, lowest, ended_by)


def _consistent(
    capacities: dict[str, tuple[int, int | None]], seen: dict[int, Outcome], end: int
) -> bool:
    """Whether the capacities agree with a curve that ends at ``end``: none lies above it, and
    every state reached at or below it has one."""
    for state, (_, level) in capacities.items():
        if level is None and any(n <= end and state in f.reached for n, f in seen.items()):
            return False
        if level is not None and level > end:
            return False
    return True


def _scan(
    lattice: Lattice, states: tuple[str, ...], look: Callable[[int], Outcome | None]
) -> tuple[dict[int, Outcome], set[int]]:
    """The scan levels run upward from ``start`` until every state is reached, an analysis
    ended in a failure or the next level would pass ``max``; and the level wanted next."""
    scanned: dict[int, Outcome] = {}
    reached: set[str] = set()
    for n in range(0, lattice.count, lattice.stride):
        found = look(n)
        if found is None:
            return scanned, {n}
        scanned[n] = found
        reached |= found.reached
        if found.ended_by or reached.issuperset(states):
            break
    return scanned, set()


def _bisect(
    lattice: Lattice,
    tolerance: float,
    states: tuple[str, ...],
    scanned: dict[int, Outcome],
    end: int | None,
    seen: dict[int, Outcome],
    look: Callable[[int], Outcome | None],
) -> tuple[dict[str, tuple[int, int | None]], set[int]]:
    """Each state's capacity on the curve up to ``end``: bisection between the last scan level
    below the first level that reaches it and that level; and the levels wanted next."""
    points = {n: found for n, found in scanned.items() if end is None or n < end}
    if end is not None:
        points[end] = seen[end]
    capacities: dict[str, tuple[int, int | None]] = {}
    wanted: set[int] = set()
    for state in states:
        first = min((n for n, found in points.items() if state in found.reached), default=None)
        if first is None:
            capacities[state] = (-1, None)
            continue
        below, level = (first - 1) // lattice.stride * lattice.stride, first
        while (
            below >= 0
            and level - below > 1
            and (lattice.level(level) - lattice.level(below) > tolerance * lattice.level(level))
        ):
            middle = (below + level) // 2
            found = look(middle)
            if found is None:
                wanted.add(middle)
                break
            below, level = (below, middle) if state in found.reached else (middle, level)
        capacities[state] = (max(below, -1), level)
    return capacities, wanted
