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

from collections.abc import Iterable, Mapping
from itertools import repeat

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

    def round(self, verdicts: Mapping[tuple[str, str], Verdict]) -> list[Cell]:
        """The analyses to run next, on every curve at once; empty when the IDA is done."""
        return self._cells(verdicts, "wanted")

    def ran(self, verdicts: Mapping[tuple[str, str], Verdict]) -> list[Cell]:
        """The analyses the rule has used so far, in the order of the results (bridge, record,
        level)."""
        return sorted(self._cells(verdicts, "visited"))

    def walk(self, curve: Cell, verdicts: Mapping[tuple[str, str], Verdict]) -> Walk:
        """Where one curve stands, given the verdicts so far (`assessment.ida.Rule.replay`)."""
        bridge = self.grid.bridges[curve.bridge_index].id
        base = self.grid.records[curve.record_index].id
        return self.rule.replay(base, lambda record: verdicts.get((bridge, record)))

    def cells(self, curve: Cell, indices: Iterable[int]) -> list[Cell]:
        """The analyses of a curve at lattice ``indices``, in their order; a cell's index orders
        the results by bridge, record and level. Its level is `Lattice.level`'s, the same
        operations on whole arrays (a spectrum's map has a million)."""
        n = np.fromiter(indices, dtype=np.int64)
        lattice = self.lattice
        levels = lattice.start + lattice.step * n / lattice.stride
        scales = levels / self.natives[curve.record_index]
        return list(map(
            Cell, (curve.index * lattice.count + n).tolist(), repeat(curve.bridge_index, n.size),
            repeat(curve.record_index, n.size), levels.tolist(), scales.tolist(),
        ))  # fmt: skip

    def _cells(self, verdicts: Mapping[tuple[str, str], Verdict], which: str) -> list[Cell]:
        return [
            cell
            for curve in self.curves
            for cell in self.cells(curve, sorted(self._indices(curve, verdicts, which)))
        ]

    def _indices(
        self, curve: Cell, verdicts: Mapping[tuple[str, str], Verdict], which: str
    ) -> set[int]:
        """The lattice indices of a curve the rule wants or has visited, with, for a spectrum,
        the scan levels of the map it has not run yet or has run."""
        indices = set(getattr(self.walk(curve, verdicts), which))
        if self.scans:  # the map's ids formatted once a level, not once a point (1e6 of them)
            bridge = self.grid.bridges[curve.bridge_index].id
            base = self.grid.records[curve.record_index].id
            ran = {n for n, tag in self.scans.items() if (bridge, base + tag) in verdicts}
            indices |= self.scans.keys() - ran if which == "wanted" else ran
        return indices
