"""The executor of this machine: its worker processes (`LocalPool`), or this process alone with
one worker (`local_workers`)."""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from typing import Any

from ...interrupts import held
from .. import kernels
from ..grid import Cell, Grid
from ..journal import Journal
from ..work import Finished, run_cells
from . import stall
from .interface import RESENDS, Notice, Workers, collector, journalled, saving
from .pacing import Pace, batched
from .worker import STOP_PREPARING, prepared, run_batch, start_worker

LISTEN_S = 0.2
"""How often the parent of a local pool looks for what its workers say while it waits for
batches [s]."""


class LocalPool:
    """Worker processes on this machine, forked at once: each loads its kernels as soon as it
    starts if numba's cache holds them (`kernels.prepare`; else it compiles them when given its
    first work), then waits for the study it serves (`serve`), so that a run can start them
    while it loads its study. A context manager: `close` at its end.

    Parameters
    ----------
    size
        Worker processes.
    """

    def __init__(self, size: int):
        context = multiprocessing.get_context("fork" if hasattr(os, "fork") else None)
        self.size = size
        self._said: Any = context.SimpleQueue()  # what the workers say: that one compiles
        self._setups: Any = context.SimpleQueue()  # a study for each worker, None for none
        self._served = self._closed = False
        self.compiling: set[str] = (
            set()
        )  # what the workers have said they compile (`compiling_said`)
        self.executor = ProcessPoolExecutor(
            size, mp_context=context, initializer=start_worker,
            initargs=(self._setups, self._said, os.getpid()),
        )  # fmt: skip
        self.executor.submit(os.getpid)  # the first submission starts (forks) the workers

    def __enter__(self) -> LocalPool:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def serve(self, grid: Grid, journal: Journal) -> None:
        """Give every worker the study's grid and journal (once)."""
        if not self._served:
            for _ in range(self.size):
                self._setups.put((grid, journal.output, journal.config_hash))
            self._served = True

    def listen(self) -> str:
        """Read what the workers have said; what to show if one has just said that it compiles
        (`kernels.compiling_message`), else ""."""
        said = ""
        while not self._said.empty():
            told = self._said.get()
            if told not in self.compiling:
                self.compiling.add(told)
                said = kernels.compiling_message("vertical" in told, "devices" in told)
        return said

    def stop_preparing(self) -> None:
        """Send `STOP_PREPARING` to the workers: those loading or compiling their kernels end."""
        for pid in getattr(self.executor, "_processes", None) or {}:
            with contextlib.suppress(OSError):  # ended already
                os.kill(pid, STOP_PREPARING)

    def close(self) -> None:
        """Let the workers end once their batches are done (those not served: at once, or once
        their kernels have loaded). Closing it again does nothing."""
        if self._closed:
            return
        self._closed = True
        if not self._served:
            for _ in range(self.size):
                self._setups.put(None)
            self._served = True
        self.executor.shutdown(cancel_futures=True)


@contextmanager
def local_workers(
    grid: Grid,
    journal: Journal,
    workers: int,
    notice: Notice | None = None,
    started: LocalPool | None = None,
) -> Iterator[Workers]:
    """Worker processes on this machine, started when cells first come (or ``started`` before).

    With one worker (and none started) everything runs in this process, a batch at a time; a
    stopping signal stops the run once the batch is journalled (`interrupts.held`), as it stops
    a pool once the batches in flight are. With more, this process only sends batches and
    receives outcomes: each worker loads the compiled kernels itself (`kernels.prepare`) and
    journals its own batches, which keeps the parent's share of the work small. The pool has
    ``workers`` processes, or as many as the first cells if fewer. What is asked of ``call``
    goes to the pool, first, once it starts. A worker that dies (killed, out of memory) breaks
    the pool: a new one starts and runs the batches that were in flight again, as Dask would, up
    to `RESENDS` times a run. ``notice`` hears, once, that the kernels are being compiled.
    """
    local = _LocalWorkers(grid, journal, workers, notice, started)
    try:
        yield Workers(local.run, local.call)
    except BaseException as exc:
        saving(exc, journal, notice)
        if isinstance(exc, KeyboardInterrupt):  # no wait for a compile
            local.stop_preparing()
        raise
    finally:  # wait for the few batches in flight
        local.close()


class _LocalWorkers:
    """The pool of `local_workers` as it goes: started on the first cells, restarted where a
    worker died; ``calls`` are the functions asked of it, each with its futures."""

    def __init__(
        self, grid: Grid, journal: Journal, workers: int, notice: Notice | None,
        started: LocalPool | None,
    ):  # fmt: skip
        self.grid, self.journal, self.workers, self.notice = grid, journal, workers, notice
        self.started = started
        self.pool: LocalPool | None = None
        self.count = 1
        self.calls: list[tuple[Callable, tuple, list[Future]]] = []
        self.pace = Pace()
        self.restarts = 0

    def call(self, function: Callable, *args: Any) -> Callable[[], Any]:
        futures: list[Future] = []
        self.calls.append((function, args, futures))
        if self.pool is not None:
            futures.append(self.pool.executor.submit(prepared, function, *args))
        return collector(function, args, futures)

    def run(self, cells: Sequence[Cell]) -> Iterator[list[Finished]]:
        if self.pool is None and self.started is None and (self.workers <= 1 or len(cells) <= 1):
            yield from _in_this_process(self.grid, self.journal, cells, self.pace, self.notice)
            return
        if self.pool is None:
            started = self.started
            self.count = started.size if started is not None else min(self.workers, len(cells))
            self.pool = self._start(self.count)
        batches = batched(cells, self.count, self.pace)
        again: list[list[Cell]] = []  # the batches a dead worker took down with the pool
        in_flight: dict[Future, list[Cell]] = {}
        progressed, stalled = time.monotonic(), False
        try:
            while True:
                while len(in_flight) < 2 * self.count and (ready := _next(again, batches)):
                    in_flight[self.pool.executor.submit(run_batch, ready)] = ready
                if not in_flight:
                    return
                done, _ = wait(in_flight, timeout=LISTEN_S, return_when=FIRST_COMPLETED)
                if (said := self.pool.listen()) and self.notice is not None:
                    self.notice(said)
                if done:
                    progressed, stalled = time.monotonic(), False
                elif not stalled and time.monotonic() - progressed > stall.STALL_S:
                    stalled = True  # said once a stall
                    if self.notice is not None:
                        processes = getattr(self.pool.executor, "_processes", None) or {}
                        self.notice(stall.notice(processes, time.monotonic() - progressed))
                for future in done:
                    sent = in_flight.pop(future)
                    if isinstance(future.exception(), BrokenProcessPool):
                        again.append(sent)
                    else:
                        yield self.pace.record(future.result())
                if again:  # a worker died (killed, out of memory): a new pool runs them again
                    self._restart()
                    again += in_flight.values()
                    in_flight.clear()
        finally:  # interrupted: drop the batches not started
            for future in in_flight:
                future.cancel()

    def close(self) -> None:
        for unused in (self.pool, self.started):
            if unused is not None:
                unused.close()

    def stop_preparing(self) -> None:
        for pool in (self.pool, self.started):
            if pool is not None:
                pool.stop_preparing()

    def _start(self, size: int) -> LocalPool:
        if self.started is None:
            with self.journal.released():  # no SQLite connection may cross a fork
                self.started = LocalPool(size)
        begun, self.started = self.started, None
        begun.serve(self.grid, self.journal)
        for function, args, futures in self.calls:
            if not futures:  # asked before the first pool started (after, computed here)
                futures.append(begun.executor.submit(prepared, function, *args))
        return begun

    def _restart(self) -> None:
        """A new pool in place of one a worker's death broke, up to `RESENDS` times a run."""
        if self.restarts == RESENDS:
            raise RuntimeError(f"worker processes died {RESENDS + 1} times (out of memory?); "
                               "the finished analyses are saved")  # fmt: skip
        self.restarts += 1
        assert self.pool is not None
        self.pool.close()
        self.pool = self._start(self.count)


def _in_this_process(
    grid: Grid, journal: Journal, cells: Sequence[Cell], pace: Pace, notice: Notice | None
) -> Iterator[list[Finished]]:
    """Run the cells in this process, a batch at a time, its kernels made ready first (``notice``
    hears if they are compiled, in a child process that a stop ends at once:
    `kernels.prepare_stoppable`); a stopping signal stops the run once the batch is journalled
    (`interrupts.held`), as it stops a pool once the batches in flight are."""

    def announce() -> None:
        if notice is not None:
            notice(kernels.compiling_message(grid.vertical, grid.devices))

    with contextlib.suppress(Exception):  # a failure is left to each analysis to meet
        kernels.prepare_stoppable(announce, grid.vertical, grid.devices)
    for batch in batched(cells, 1, pace):
        with held():
            outcomes = journalled(journal, run_cells(grid, batch))
        yield pace.record(outcomes)


def _next(again: list[list[Cell]], batches: Iterator[list[Cell]]) -> list[Cell] | None:
    """The next batch to send: one to run again first, else the next new one; None when none is
    left."""
    return again.pop(0) if again else next(batches, None)
