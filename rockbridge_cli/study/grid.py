"""A study as its grid of cells: every analysis (bridge × record) in the order of the results,
with what a worker needs to run it as plain data, sent to each worker once; and the split of the
cells into the shards of an array job."""

from __future__ import annotations

import heapq
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from ..core.bridge import Bridge
from ..core.fidelity import Fidelity, resolve
from ..motions.intensity import scaled_id

if TYPE_CHECKING:
    from ..config.study import Study


class BridgeCase(NamedTuple):
    """A bridge of the study, by its id, as the core analyses it."""

    id: str
    bridge: Bridge


class RecordCase(NamedTuple):
    """A ground motion [m/s²] at ``time_step`` [s], or why it could not be read; with the
    record it was scaled from, the intensity level and the factor (`config.intensity.Intensity`),
    and its vertical component [m/s², positive up] where the study analyzes one (else None)."""

    id: str
    acceleration: np.ndarray | None
    time_step: float
    error: str
    base: str
    level: float
    scale: float
    vertical: np.ndarray | None = None


class Cell(NamedTuple):
    """One analysis: its position in the results, the indices of the bridge and the record it
    combines (in `Grid.bridges`, `Grid.records`), and the intensity level and factor the record
    is scaled by for this analysis alone (an IDA's; NaN and 1 when the record is analyzed as
    listed)."""

    index: int  # type: ignore[assignment]  # the cell's index, not tuple.index
    bridge_index: int
    record_index: int
    level: float = float("nan")
    scale: float = 1.0


RECHECK_KEEPS = ("tail", "output_step")
"""Knobs a recheck at ``reference`` keeps from the study (what is analyzed and stored, not how
precisely)."""


@dataclass(frozen=True)
class Grid:
    """Everything needed to run any cell of a study, and nothing else.

    Attributes
    ----------
    bridges, records : the study's, in its order
    fidelity : what every analysis runs at, settled with the study (`core.fidelity.resolve`)
    keep : names of the histories to store
    config_hash : the study's hash (`Study.config_hash`)
    recheck : the fidelity at which to run again what ends near or beyond a capacity
        (``reference``, keeping `RECHECK_KEEPS`), None where the study does not ask it
    measure : the intensity measure of the study, empty without
    listed : the cells, when not every bridge × record (a study whose sampled bridges each meet
        one record, `config.uncertainty`)
    """

    bridges: tuple[BridgeCase, ...]
    records: tuple[RecordCase, ...]
    fidelity: Fidelity
    keep: tuple[str, ...]
    config_hash: str
    recheck: Fidelity | None = None
    measure: str = ""
    listed: tuple[Cell, ...] | None = None

    @classmethod
    def of(cls, study: Study) -> Grid:
        """The grid of a resolved study: every bridge × record, or the pairs it lists."""
        bridges = tuple(BridgeCase(b.id, b.config.to_bridge()) for b in study.bridges)
        records = tuple(
            RecordCase(
                r.id, r.record.acceleration if r.record else None,
                r.record.time_step if r.record else float("nan"), r.error, r.base or r.id,
                r.level, r.scale, r.record.vertical if r.record else None,
            )
            for r in study.records
        )  # fmt: skip
        intensity = study.intensity_section
        measure = intensity.measure if intensity is not None else ""
        fidelity = study.fidelity
        recheck = None
        if fidelity.knobs["recheck"] and fidelity.preset != "reference":
            recheck = resolve("reference", **{k: fidelity.knobs[k] for k in RECHECK_KEEPS})
        cells = None
        if study.pairs is not None:
            cells = tuple(Cell(index, b, r) for index, (b, r) in enumerate(study.pairs))
        return cls(
            bridges, records, fidelity, study.histories, study.config_hash, recheck, measure,
            cells,
        )  # fmt: skip

    @property
    def vertical(self) -> bool:
        """Whether a record has a vertical component (its analyses need kernels of their own)."""
        return any(record.vertical is not None for record in self.records)

    @property
    def devices(self) -> bool:
        """Whether a bridge has tendons or dampers (its analyses need kernels of their own)."""
        return any(case.bridge.devices for case in self.bridges)

    @property
    def cells(self) -> list[Cell]:
        """Every analysis in the order of the results: those listed, or bridge by bridge,
        record by record."""
        if self.listed is not None:
            return list(self.listed)
        count = len(self.records)
        return [Cell(b * count + r, b, r) for b in range(len(self.bridges)) for r in range(count)]

    def ids(self, cell: Cell) -> tuple[str, str]:
        """(bridge id, record id) of a cell."""
        record = self.records[cell.record_index]
        if cell.level != cell.level:  # NaN: as listed
            return self.bridges[cell.bridge_index].id, record.id
        return self.bridges[cell.bridge_index].id, scaled_id(record.id, cell.level, self.measure)

    def record_of(self, cell: Cell) -> RecordCase:
        """The record a cell analyses, scaled as the cell says."""
        record = self.records[cell.record_index]
        if cell.level != cell.level:
            return record
        acceleration = None if record.acceleration is None else cell.scale * record.acceleration
        vertical = None if record.vertical is None else cell.scale * record.vertical
        return record._replace(
            id=self.ids(cell)[1], acceleration=acceleration, level=cell.level, scale=cell.scale,
            vertical=vertical,
        )  # fmt: skip

    def cost(self, cell: Cell) -> int:
        """The expected cost of a cell: the samples of its record (an analysis steps through
        each), and 0 for a record that could not be read."""
        record = self.records[cell.record_index]
        return 0 if record.acceleration is None else record.acceleration.size

    def shard(self, index: int, count: int) -> list[Cell]:
        """The cells of shard ``index`` of ``count`` (0-based), in the order of the results.

        The split depends on the grid alone, so every task of an array job computes the same one
        without talking to the others: the cells, costliest first (ties in the order of the
        results), each go to the shard with the least cost so far (ties to the lowest index);
        shards then differ in cost by at most one cell's. Shards beyond the number of cells are
        empty (their count costs no memory).

        Raises
        ------
        ValueError
            ``index`` is not in 0 … count − 1.
        """
        if not 0 <= index < count:
            raise ValueError(f"shard {index} of {count}: the index must be 0 … {count - 1}")
        # with more shards than cells, cell i (costliest first) fills shard i: the others are empty
        loads = [(0, shard) for shard in range(min(count, len(self.cells)))]
        mine = []
        for cell in sorted(self.cells, key=lambda c: (-self.cost(c), c.index)):
            load, shard = heapq.heappop(loads)
            if shard == index:
                mine.append(cell)
            heapq.heappush(loads, (load + self.cost(cell), shard))
        return sorted(mine)
