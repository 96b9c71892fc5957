"""What a worker does with a batch of cells: run each analysis and pack its result."""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

from ..core.analysis import analyze
from ..results.packing import AnalysisResult
from .grid import Cell, Grid


@dataclass(frozen=True)
class Finished:
    """One analysis done.

    Attributes
    ----------
    bridge, record : ids
    status : ``ok``, ``solver_error`` or ``error`` (`results.STATUSES`)
    message : why it stopped early or could not run; empty if ok
    solve_time_s : integration time, NaN if it could not run [s]
    """

    bridge: str
    record: str
    status: str
    message: str
    solve_time_s: float


class Outcome(NamedTuple):
    """A finished cell as it travels back from a worker: what it says, and its packed result."""

    cell: Cell
    finished: Finished
    packed: bytes


def run_cells(grid: Grid, cells: Sequence[Cell]) -> list[Outcome]:
    """Run the analyses of ``cells``; an exception fails only its own analysis."""
    outcomes = []
    for cell in cells:
        result = analyse(grid, cell)
        values = result.values
        finished = Finished(
            result.bridge, result.record, values["status"], values["message"],
            values["solve_time_s"],
        )  # fmt: skip
        outcomes.append(Outcome(cell, finished, result.pack()))
    return outcomes


def analyse(grid: Grid, cell: Cell) -> AnalysisResult:
    """Run one analysis; any exception becomes a result with status ``error`` and its message."""
    bridge, record = grid.bridges[cell.bridge], grid.records[cell.record]
    if record.acceleration is None:
        return AnalysisResult.failed(bridge.id, record.id, record.error)
    start = time.perf_counter()
    try:
        response = analyze(
            bridge.model, record.acceleration, record.time_step, grid.preset,
            mirrored=bridge.mirrored, restitution=bridge.restitution, **grid.overrides,
        )  # fmt: skip
    except Exception as exc:  # one failed analysis must not stop the others
        return AnalysisResult.failed(
            bridge.id, record.id, f"{type(exc).__name__}: {exc}", time.perf_counter() - start
        )
    return AnalysisResult.from_response(
        bridge.id, record.id, response, grid.keep, time.perf_counter() - start
    )
