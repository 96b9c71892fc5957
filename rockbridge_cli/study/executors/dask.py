"""The executor of a Dask distributed cluster (`dask_workers`)."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import CancelledError
from contextlib import contextmanager
from typing import Any

from ...errors import InputError
from ..grid import Cell, Grid
from ..journal import Journal
from ..work import Finished, run_cells
from .interface import RESENDS, Notice, Workers, collector, journalled, saving
from .pacing import Pace, batched
from .worker import prepared


def _parse(scheduler: str) -> None:
    """Raise ValueError unless ``scheduler`` parses as an address, by Dask's own parser, before
    any connection is tried: with a port that is not a number (``tcp://host:notaport``), the
    oldest `distributed` admitted sometimes failed inside its connection attempt with a bare
    AssertionError instead of its parser's ValueError."""
    from distributed.comm.addressing import parse_address, parse_host_port

    scheme, location = parse_address(scheduler)
    if scheme in ("tcp", "tls", "ws", "wss"):
        parse_host_port(location)


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
        _parse(scheduler)
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
        batches = batched(cells, threads, pace)
        running = as_completed()
        sent: dict[Any, list[Cell]] = {}

        def submit(batch: list[Cell]) -> None:
            future = client.submit(prepared, run_cells, shared, batch, pure=False)
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
                yield pace.record(journalled(journal, analyzed))
                for batch in itertools.islice(batches, 1):
                    submit(batch)
        finally:  # interrupted: nothing more is needed from the cluster
            client.cancel(list(running.futures))

    def call(function: Callable, *args: Any) -> Callable[[], Any]:
        future = client.submit(prepared, function, *args, pure=False)
        return collector(function, args, [future])

    with client:
        try:
            yield Workers(run, call)
        except KeyboardInterrupt as stop:
            saving(stop, journal, notice)
            raise
