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
the results file put them back in the study's order.
"""

from __future__ import annotations

import contextlib
import ctypes
import itertools
import math
import multiprocessing
import os
import signal
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, CancelledError, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from typing import Any, NamedTuple

from ..errors import InputError
from ..interrupts import held, stopped_by
from ..results.packing import Packed
from . import kernels
from .grid import Cell, Grid
from .journal import Journal
from .work import Finished, run_cells

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

_PR_SET_PDEATHSIG = 1
"""Linux prctl(2) option: the signal a process gets when its parent dies."""

STOP_PREPARING = signal.SIGUSR1
"""The signal a stopped run sends its local workers: those loading or compiling their kernels
(`_kernels`, no analysis in hand) end at once, instead of making the run wait for a compile
(85–133 s on a busy host, issue 39); the others ignore it and finish their batch."""

LISTEN_S = 0.2
"""How often the parent of a local pool looks for what its workers say while it waits for
batches [s]."""

_grid: Grid | None = None
"""The grid of the study a worker process serves (set when it starts)."""

_journal: Journal | None = None
"""The journal a worker process commits to (opened when it starts)."""

_said: Any = None
"""Where a local worker process tells its parent that it compiles the kernels."""


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


STALL_S = 300.0
"""How long a run on local workers waits with no batch finishing before it says so, naming the
workers that are stopped (SIGSTOP, a debugger: the run would otherwise wait for them without a
word, its progress line saying "about 1 s left") [s]."""

RESENDS = 8
"""Times a run sends batches again after a worker died before it gives up: a local pool is
started anew (its batches in flight run again), a Dask cluster gets the grid again."""

Run = Callable[[Sequence[Cell]], Iterator[list[Finished]]]
"""Runs cells of the grid and yields their outcomes, a batch at a time, as the batches finish and
are journalled."""

Call = Callable[..., Callable[[], Any]]
"""``call(function, *args)``: computes ``function(*args)`` on a worker and returns what collects
the result; it is computed in this process instead when no worker runs it (none started, or the
run was stopped first)."""


Notice = Callable[[str], None]
"""Called with a line to show while a run goes on (`kernels.COMPILING`, once)."""


class Workers(NamedTuple):
    """What an executor offers a run: ``run`` (`Run`) for the cells, ``call`` (`Call`) for the
    rest."""

    run: Run
    call: Call


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


def _collector(function: Callable, args: tuple, futures: list[Any]) -> Callable[[], Any]:
    """What collects ``function(*args)``: the result of the first of ``futures`` (there is at
    most one), else computed here (none was submitted, it was cancelled, or its worker died)."""

    def collect() -> Any:
        if futures:
            try:
                return futures[0].result()
            except (CancelledError, BrokenProcessPool):
                pass
        with held():  # compiled kernels, in this process
            return function(*args)

    return collect


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
        self.compiling: set[bool] = set()  # which kernels a worker has said it compiles (vertical)
        self.executor = ProcessPoolExecutor(
            size, mp_context=context, initializer=_start_worker,
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
            vertical = self._said.get() == "compiling vertical"
            if vertical not in self.compiling:
                self.compiling.add(vertical)
                said = kernels.compiling_message(vertical)
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
        _saving(exc, journal, notice)
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
            futures.append(self.pool.executor.submit(_prepared, function, *args))
        return _collector(function, args, futures)

    def run(self, cells: Sequence[Cell]) -> Iterator[list[Finished]]:
        if self.pool is None and self.started is None and (self.workers <= 1 or len(cells) <= 1):
            yield from _in_this_process(self.grid, self.journal, cells, self.pace, self.notice)
            return
        if self.pool is None:
            started = self.started
            self.count = started.size if started is not None else min(self.workers, len(cells))
            self.pool = self._start(self.count)
        batches = _batches(cells, self.count, self.pace)
        again: list[list[Cell]] = []  # the batches a dead worker took down with the pool
        in_flight: dict[Future, list[Cell]] = {}
        progressed, stalled = time.monotonic(), False
        try:
            while True:
                while len(in_flight) < 2 * self.count and (ready := _next(again, batches)):
                    in_flight[self.pool.executor.submit(_run_batch, ready)] = ready
                if not in_flight:
                    return
                done, _ = wait(in_flight, timeout=LISTEN_S, return_when=FIRST_COMPLETED)
                if (said := self.pool.listen()) and self.notice is not None:
                    self.notice(said)
                if done:
                    progressed, stalled = time.monotonic(), False
                elif not stalled and time.monotonic() - progressed > STALL_S:
                    stalled = True  # said once a stall
                    if self.notice is not None:
                        self.notice(_stall(self.pool, time.monotonic() - progressed))
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
                futures.append(begun.executor.submit(_prepared, function, *args))
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


def _stall(pool: LocalPool, waited: float) -> str:
    """What a run says when no batch has finished for `STALL_S`: which of its workers are
    stopped (their state ``T`` in ``/proc``, where there is one), and what to do."""
    processes = getattr(pool.executor, "_processes", None) or {}
    stopped = [pid for pid in sorted(processes) if _process_state(pid) in ("T", "t")]
    head = f"no analysis has finished for {waited:.0f} s"
    if stopped:
        pids = " ".join(map(str, stopped))
        return (f"{head}: worker process(es) {pids} stopped (SIGSTOP, a debugger?); kill -CONT "
                f"{pids} resumes them, Ctrl-C saves the analyses finished")  # fmt: skip
    return f"{head}: the analyses running are long, or stuck; Ctrl-C saves those finished"


def _process_state(pid: int) -> str:
    """A process's state letter from ``/proc/<pid>/stat`` (``T`` stopped), empty if unknown."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii", errors="replace") as stat:
            return stat.read().rpartition(")")[2].split()[0]
    except (OSError, IndexError):
        return ""


def _in_this_process(
    grid: Grid, journal: Journal, cells: Sequence[Cell], pace: Pace, notice: Notice | None
) -> Iterator[list[Finished]]:
    """Run the cells in this process, a batch at a time, its kernels made ready first (``notice``
    hears if they are compiled, in a child process that a stop ends at once:
    `kernels.prepare_stoppable`); a stopping signal stops the run once the batch is journalled
    (`interrupts.held`), as it stops a pool once the batches in flight are."""

    def announce() -> None:
        if notice is not None:
            notice(kernels.compiling_message(grid.vertical))

    with contextlib.suppress(Exception):  # a failure is left to each analysis to meet
        kernels.prepare_stoppable(announce, grid.vertical)
    for batch in _batches(cells, 1, pace):
        with held():
            outcomes = _journalled(journal, run_cells(grid, batch))
        yield pace.record(outcomes)


def _saving(exc: BaseException, journal: Journal, notice: Notice | None) -> None:
    """Say at once, when a stopping signal stops a run, what happens before it ends."""
    if isinstance(exc, KeyboardInterrupt) and notice is not None:
        notice(f"{stopped_by(exc)}: saving the analyses finished so far to {journal.output} "
               "(those running finish first)")  # fmt: skip


def _next(again: list[list[Cell]], batches: Iterator[list[Cell]]) -> list[Cell] | None:
    """The next batch to send: one to run again first, else the next new one; None when none is
    left."""
    return again.pop(0) if again else next(batches, None)


def _batches(cells: Sequence[Cell], workers: int, pace: Pace) -> Iterator[list[Cell]]:
    """The cells in batches of `Pace.batch_size`, in order (each sized when it is taken)."""
    start = 0
    while start < len(cells):
        size = pace.batch_size(len(cells) - start, workers)
        yield list(cells[start : start + size])
        start += size


def _journalled(journal: Journal, analyzed: list[tuple[Finished, Packed]]) -> list[Finished]:
    """Commit a batch's results to the journal; its outcomes."""
    journal.add(analyzed)
    return [finished for finished, _ in analyzed]


def _start_worker(setups: Any, said: Any, parent: int) -> None:
    """Worker start-up: leave Ctrl-C and SIGTERM to the parent, which stops the pool and saves
    the results (and `STOP_PREPARING`, but while the kernels load); die with the parent, however
    it dies; load the kernels if the cache holds them; then take the study (its grid, and the
    journal, a connection of its own) when the parent gives it."""
    global _grid, _journal, _said
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    signal.signal(STOP_PREPARING, signal.SIG_IGN)  # but while its kernels load (`_kernels`)
    if sys.platform.startswith("linux"):
        ctypes.CDLL(None).prctl(_PR_SET_PDEATHSIG, signal.SIGKILL)
    if os.getppid() != parent:  # the parent died before the request took effect
        os._exit(1)
    _said = said
    _kernels(compiling=False)
    setup = setups.get()
    if setup is not None:  # None: the pool ends unused (the run was refused or stopped)
        grid, output, config_hash = setup
        _grid = grid
        _journal = Journal(output, config_hash)


def _run_batch(cells: list[Cell]) -> list[Finished]:
    assert _grid is not None and _journal is not None, "a worker runs cells after _start_worker"
    _kernels(vertical=_grid.vertical)
    return _journalled(_journal, run_cells(_grid, cells))


def _kernels(compiling: bool = True, vertical: bool = False) -> None:
    """`kernels.prepare` in a worker, which tells its parent (a local pool's) that it compiles
    them; a failure is left to each analysis to meet and record with its message. ``vertical``:
    those of an analysis with a vertical ground motion too. A local pool's worker dies at once
    of `STOP_PREPARING` meanwhile (a compile cannot be stopped from inside; the worker has no
    analysis in hand), and ignores it otherwise."""

    def announce() -> None:
        if _said is not None:
            _said.put("compiling vertical" if vertical else "compiling")

    local = _said is not None  # a Dask worker's signals are left alone
    if local:
        signal.signal(STOP_PREPARING, signal.SIG_DFL)  # the default action: end the process
    try:
        with contextlib.suppress(Exception):
            kernels.prepare(announce, compiling, vertical)
    finally:
        if local:
            signal.signal(STOP_PREPARING, signal.SIG_IGN)


def _prepared(function: Callable, *args: Any) -> Any:
    """``function(*args)`` on a worker, its kernels made ready first (`kernels.prepare`; those
    of a vertical ground motion where a grid among ``args`` has one)."""
    _kernels(vertical=any(isinstance(arg, Grid) and arg.vertical for arg in args))
    return function(*args)


@contextmanager
def dask_workers(
    grid: Grid, journal: Journal, scheduler: str, notice: Notice | None = None
) -> Iterator[Workers]:
    """The workers of a Dask distributed cluster.

    The grid is sent to every worker once (``scatter``); batches are submitted as earlier ones
    come back with their packed results (which this process journals), at most two per worker
    thread in flight. Dask runs a batch again elsewhere if its worker dies, and a batch gives the
    same outcomes wherever it runs. A batch that Dask cancels because the grid died with a worker
    (the scattered data has no task to recompute it) is sent again with the grid, up to
    `RESENDS` times a run.

    Raises
    ------
    InputError
        The ``dask`` extra is not installed, or the scheduler cannot be reached.
    """
    try:
        from distributed import Client, as_completed
    except ImportError:
        reason = 'needs Dask: pip install "rockbridge[dask]"'
        raise InputError(scheduler, [("", reason)]) from None
    try:
        client = Client(scheduler, timeout="10s")
    except (ValueError, TypeError):  # not an address (Dask's words are its parser's)
        reason = "cannot reach the Dask scheduler: not an address like tcp://host:8786"
        raise InputError(scheduler, [("", reason)]) from None
    except (OSError, TimeoutError):  # unreachable
        reason = "cannot reach the Dask scheduler: nothing answered there within 10 s"
        raise InputError(scheduler, [("", reason)]) from None
    shared = None
    resends = 0
    pace = Pace()

    def run(cells: Sequence[Cell]) -> Iterator[list[Finished]]:
        nonlocal shared, resends
        if not cells:
            return
        if shared is None:
            shared = client.scatter(grid, broadcast=True, hash=False)
        threads = max(sum(client.nthreads().values()), 1)
        batches = _batches(cells, threads, pace)
        running = as_completed()
        sent: dict[Any, list[Cell]] = {}

        def submit(batch: list[Cell]) -> None:
            future = client.submit(_prepared, run_cells, shared, batch, pure=False)
            sent[future] = batch
            running.add(future)

        try:
            for batch in itertools.islice(batches, 2 * threads):
                submit(batch)
            for future in running:
                batch = sent.pop(future)
                try:
                    analyzed = future.result()
                except CancelledError:
                    if resends == RESENDS:
                        raise
                    resends += 1
                    shared = client.scatter(grid, broadcast=True, hash=False)
                    submit(batch)
                    continue
                yield pace.record(_journalled(journal, analyzed))
                for batch in itertools.islice(batches, 1):
                    submit(batch)
        finally:  # interrupted: nothing more is needed from the cluster
            client.cancel(list(running.futures))

    def call(function: Callable, *args: Any) -> Callable[[], Any]:
        future = client.submit(_prepared, function, *args, pure=False)
        return _collector(function, args, [future])

    with client:
        try:
            yield Workers(run, call)
        except KeyboardInterrupt as stop:
            _saving(stop, journal, notice)
            raise
