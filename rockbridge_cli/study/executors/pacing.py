"""The pace of a run: how long its analyses have taken so far (`Pace`), which sizes its batches,
and the cells cut into batches of that size (`batched`)."""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence

from ..grid import Cell
from ..work import Finished

BATCH_SECONDS = 1.0
"""The work a batch holds, at most [s]: what the parent does per batch (send it, wake up three
threads, receive its outcomes: ≈ 0.7 ms of CPU when every core is busy) is then negligible, and
an interrupted run waits for at most about this long for the batches that are running."""

MAX_BATCH = 512
"""Most cells in a batch, however short the analyses."""

FIRST_BATCH = 8
"""Cells in a batch before any has come back to tell how long an analysis takes."""

BATCHES_PER_WORKER = 4
"""A batch holds at most this fraction of the cells left per worker: batches shrink as the run
nears its end (guided scheduling), so that the workers finish together."""


class Pace:
    """How long the analyses of a run have taken so far, which sizes its batches."""

    def __init__(self) -> None:
        self.seconds = 0.0
        self.analyses = 0

    def record(self, outcomes: list[Finished]) -> list[Finished]:
        """Count a batch's times in (`work.Finished.busy_s`); the outcomes, unchanged."""
        for finished in outcomes:
            if math.isfinite(finished.busy_s):
                self.seconds += finished.busy_s
                self.analyses += 1
        return outcomes

    def batch_size(self, cells: int, workers: int) -> int:
        """Cells in the next batch when ``cells`` are left for ``workers`` processes: about
        `BATCH_SECONDS` of work (`FIRST_BATCH` until an analysis has come back), at most
        `MAX_BATCH` and a `BATCHES_PER_WORKER`-th of what is left per worker."""
        if not self.analyses:
            timed = FIRST_BATCH
        elif self.seconds > 0.0:
            timed = int(BATCH_SECONDS * self.analyses / self.seconds)
        else:
            timed = MAX_BATCH
        guided = math.ceil(cells / (workers * BATCHES_PER_WORKER))
        return max(1, min(MAX_BATCH, timed, guided))


def batched(cells: Sequence[Cell], workers: int, pace: Pace) -> Iterator[list[Cell]]:
    """The cells in batches of `Pace.batch_size`, in order (each sized when it is taken)."""
    start = 0
    while start < len(cells):
        size = pace.batch_size(len(cells) - start, workers)
        yield list(cells[start : start + size])
        start += size
