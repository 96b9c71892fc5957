"""The plan of a study: the rounds in which it runs, and what it has run.

A plain study is one round: every cell without a verdict yet (`OneRound`). An incremental dynamic
analysis runs the IDA rule (`assessment.ida`) on every curve at once — each round the levels the
verdicts so far call for — and, on resuming, replays the rule from the stored verdicts without
re-running anything (`Plan`). The workers hold the records as read; each analysis scales its
record itself (`grid.Cell`).

An overturning spectrum (`config.spectrum`) is such an IDA that also maps: its first round runs
every scan level of every curve (the map), and its bisections then start from the map's verdicts.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping, Sequence
from typing import overload

import numpy as np

from ..assessment.ida import Rule, Walk
from ..assessment.limit_states import Verdict
from ..config.study import Study
from ..motions.intensity import measure_value
from .grid import Cell, Grid


def plan_of(study: Study, grid: Grid, cells: list[Cell]) -> OneRound | Plan:
    """The plan of a study's ``cells`` (all of its grid's, or a shard's): an IDA's, or one
    round."""
    intensity = study.intensity_section
    if intensity is not None and intensity.ida is not None:
        return Plan(study, grid, cells)
    return OneRound(grid, cells)


class OneRound:
    """A study whose analyses are all known from the start: one round, the cells without a
    verdict; its results file is complete when it holds them all (``sized``)."""

    sized = True

    def __init__(self, grid: Grid, cells: list[Cell]):
        self.grid, self.cells = grid, cells

    def round(self, verdicts: Mapping[tuple[str, str], Verdict]) -> list[Cell]:
        """The cells without a verdict: all that are left at first, none once they have run."""
        return [cell for cell in self.cells if self.grid.ids(cell) not in verdicts]

    def ran(self, verdicts: Mapping[tuple[str, str], Verdict]) -> list[Cell]:
        """The study's cells, whichever have run."""
        return self.cells


class Plan:
    """The IDA of a study, or of some of its curves: its rounds, and what it has run. Its
    results file is complete only once its rule calls for no more levels (not ``sized``: how
    many analyses it needs is found as it runs).

    Parameters
    ----------
    study
        A study whose intensity section has ``ida``; its records are the records as read.
    grid
        The study's grid (`Grid.of`): one cell per curve, bridge × record as read.
    curves
        The curves to follow (a shard's); default every cell of ``grid``.
    """

    sized = False

    def __init__(self, study: Study, grid: Grid, curves: Iterable[Cell] | None = None):
        intensity = study.intensity_section
        assert intensity is not None and intensity.ida is not None
        self.grid = grid
        self.rule = Rule.of(intensity)
        self.lattice = self.rule.lattice
        self.curves = list(grid.cells if curves is None else curves)
        self.natives = [
            measure_value(intensity.measure, r.record.acceleration, r.record.time_step,
                          *intensity.spectral) if r.record is not None else 1.0
            for r in study.records
        ]  # fmt: skip
        self.mapped = study.spectrum is not None
        scans = range(0, self.lattice.count, self.lattice.stride) if self.mapped else range(0)
        self.scans = {n: self.rule.record("", n) for n in scans}
        """A spectrum's map: each scan level's lattice index, with what its level adds to a
        record's id (`assessment.ida.Rule.record`)."""

    def round(self, verdicts: Mapping[tuple[str, str], Verdict]) -> Cells:
        """The analyses to run next, on every curve at once; empty when the IDA is done."""
        return self._cells(verdicts, "wanted")

    def ran(self, verdicts: Mapping[tuple[str, str], Verdict]) -> list[Cell]:
        """The analyses the rule has used so far, in the order of the results (bridge, record,
        level)."""
        return self._cells(verdicts, "visited").in_order()[:]

    def walk(self, curve: Cell, verdicts: Mapping[tuple[str, str], Verdict]) -> Walk:
        """Where one curve stands, given the verdicts so far (`assessment.ida.Rule.replay`)."""
        bridge = self.grid.bridges[curve.bridge_index].id
        base = self.grid.records[curve.record_index].id
        return self.rule.replay(base, lambda record: verdicts.get((bridge, record)))

    def cells(self, curve: Cell, indices: Iterable[int]) -> Cells:
        """The analyses of a curve at lattice ``indices``, in their order; a cell's index orders
        the results by bridge, record and level. Its level is `Lattice.level`'s, the same
        operations on whole arrays (a spectrum's map has a million)."""
        n = np.fromiter(indices, dtype=np.int64)
        lattice = self.lattice
        levels = lattice.start + lattice.step * n / lattice.stride
        return Cells(
            curve.index * lattice.count + n, np.full(n.size, curve.bridge_index),
            np.full(n.size, curve.record_index), levels,
            levels / self.natives[curve.record_index],
        )  # fmt: skip

    def _cells(self, verdicts: Mapping[tuple[str, str], Verdict], which: str) -> Cells:
        return Cells.joined([
            self.cells(curve, sorted(self._indices(curve, verdicts, which)))
            for curve in self.curves
        ])  # fmt: skip

    def _indices(
        self, curve: Cell, verdicts: Mapping[tuple[str, str], Verdict], which: str
    ) -> set[int]:
        """The lattice indices of a curve the rule wants or has visited, with, for a spectrum,
        the scan levels of the map it has not run yet or has run."""
        indices = set(getattr(self.walk(curve, verdicts), which))
        if self.scans:  # the map's ids formatted once a level, not once a point (1e6 of them)
            bridge = self.grid.bridges[curve.bridge_index].id
            base = self.grid.records[curve.record_index].id
            ran = set()  # none before the first verdict: no id formatted
            if verdicts:
                ran = {n for n, tag in self.scans.items() if (bridge, base + tag) in verdicts}
            indices |= self.scans.keys() - ran if which == "wanted" else ran
        return indices


class Cells(Sequence[Cell]):
    """Cells held as columns (`grid.Cell`'s fields, one array each), each cell built only when
    it is taken: a batch at a time, as the executors take them (a spectrum's first round has a
    million, which as objects took seconds and hundreds of MB before the first analysis ran).
    A cell taken is the one a list of them would hold, its fields Python numbers."""

    def __init__(self, *columns: np.ndarray):
        self.columns = columns

    @classmethod
    def joined(cls, parts: Sequence[Cells]) -> Cells:
        """The cells of ``parts``, one after the other."""
        if not parts:
            return cls(*(np.empty(0, dtype) for dtype in (np.int64,) * 3 + (np.float64,) * 2))
        return cls(
            *(np.concatenate(column) for column in zip(*(p.columns for p in parts), strict=True))
        )

    def in_order(self) -> Cells:
        """The same cells in the order of their index (the results')."""
        order = np.argsort(self.columns[0], kind="stable")
        return Cells(*(column[order] for column in self.columns))

    def __len__(self) -> int:
        return len(self.columns[0])

    @overload
    def __getitem__(self, which: int) -> Cell: ...

    @overload
    def __getitem__(self, which: slice) -> list[Cell]: ...

    def __getitem__(self, which: int | slice) -> Cell | list[Cell]:
        if isinstance(which, slice):
            return list(map(Cell, *(column[which].tolist() for column in self.columns)))
        return Cell(*(column[which].item() for column in self.columns))

    def __iter__(self) -> Iterator[Cell]:
        for start in range(0, len(self), TAKEN_AT_ONCE):
            yield from self[start : start + TAKEN_AT_ONCE]


TAKEN_AT_ONCE = 4096
"""Cells built at a time when `Cells` are iterated."""
