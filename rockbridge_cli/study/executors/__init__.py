"""Where the cells run: in this process, in a pool of worker processes on this machine, or on a Dask
distributed cluster.

Workers receive the study's `Grid` once, and then batches of cells. Local worker
processes commit their results to the journal themselves and send back only the outcomes
(`work.Finished`), so that what the parent does per analysis is small next to the analysis
itself; the workers of a Dask cluster, which may not reach the journal's disk, send the packed
results too, and the parent journals them. Workers also compute what else a run asks of the
compiled kernels (the bridges' summaries for the results file), so that the parent need not load
them. A worker loads its compiled kernels as soon as it starts, before its study is known, so
that a run can start its workers while it loads the study (`LocalPool`); on a cold cache its
first work compiles them, one process at a time (`kernels.prepare`). The number of batches in
flight is bounded, which keeps the parent's memory flat in the number of analyses. Every executor
yields the same outcomes, journalled; only their order and grouping differ, and the journal and
the results file put them back in the study's ord
The package's modules: what every executor offers and shares (`interface`), the batches and their
pace (`pacing`), the local pool (`local`), the Dask cluster (`dask`), what runs in a worker
process (`worker`), the notice of a stalled run (`stall`).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from ..grid import Grid
from ..journal import Journal
from .dask import dask_workers
from .interface import RESENDS, Call, Notice, Run, Workers
from .local import LISTEN_S, LocalPool, local_workers
from .pacing import BATCH_SECONDS, BATCHES_PER_WORKER, FIRST_BATCH, MAX_BATCH, Pace, batched
from .stall import STALL_S

__all__ = [
    "BATCHES_PER_WORKER", "BATCH_SECONDS", "FIRST_BATCH", "LISTEN_S", "MAX_BATCH", "RESENDS",
    "STALL_S", "Call", "LocalPool", "Notice", "Pace", "Run", "Workers", "batched",
    "dask_workers", "executor", "local_workers",
]  # fmt: skip


@contextmanager
def executor(
    grid: Grid,
    journal: Journal,
    workers: int,
    scheduler: str | None = None,
    notice: Notice | None = None,
    pool: LocalPool | None = None,
) -> Iterator[Workers]:
    """Workers for the cells of ``grid``, journalling into ``journal``, for as many calls as a
    run needs (an IDA's rounds): local worker processes (`local_workers`, in ``pool`` if it was
    started before) or a Dask cluster (`dask_workers`)."""
    with (
        local_workers(grid, journal, workers, notice, pool)
        if scheduler is None
        else dask_workers(grid, journal, scheduler, notice)
    ) as offered:
        yield offered
