"""What every executor offers a run (`Workers`: ``run`` for the cells, ``call`` for the rest) and
what they share: what collects a call, the journalling of a batch's results, the line said when a
stopping signal stops a run, and how many times a batch is sent again."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import CancelledError
from concurrent.futures.process import BrokenProcessPool
from typing import Any, NamedTuple

from ...interrupts import held, stopped_by
from ...results.packing import Packed
from ..grid import Cell
from ..journal import Journal
from ..work import Finished

RESENDS = 8
"""Times a run sends batches again after a worker died before it gives up: a local pool is
started anew (its batches in flight run again), a Dask cluster gets the grid again."""

Run = Callable[[Sequence[Cell]], Iterator[list[Finished]]]
"""Runs cells of the grid and yields their outcomes, a batch at a time, as the batches finish and
are journalled."""

Call = Callable[..., Callable[..., Any]]
"""``call(function, *args)``: computes ``function(*args)`` on a worker and returns what collects
the result (`collector`); it is computed in this process instead when no worker runs it (none
started, or the run was stopped first)."""


Notice = Callable[[str], None]
"""Called with a line to show while a run goes on (`kernels.COMPILING`, once)."""


class Workers(NamedTuple):
    """What an executor offers a run: ``run`` (`Run`) for the cells, ``call`` (`Call`) for the
    rest."""

    run: Run
    call: Call


def collector(function: Callable, args: tuple, futures: list[Any]) -> Callable[..., Any]:
    """What collects ``function(*args)``: the result of the first of ``futures`` (there is at
    most one), else computed here (none was submitted, it was cancelled, or its worker died).
    Called with ``wait=False`` (a stopped run, which neither waits nor computes), it gives the
    result only if a worker has computed it already, else None."""

    def collect(wait: bool = True) -> Any:
        if futures and (wait or futures[0].done()):
            try:
                return futures[0].result()
            except (CancelledError, BrokenProcessPool):
                pass
        if not wait:
            return None
        with held():  # compiled kernels, in this process
            return function(*args)

    return collect


def saving(exc: BaseException, journal: Journal, notice: Notice | None) -> None:
    """Say at once, when a stopping signal stops a run, what happens before it ends."""
    if isinstance(exc, KeyboardInterrupt) and notice is not None:
        notice(f"{stopped_by(exc)}: saving the analyses finished so far to {journal.output} "
               "(those running finish first)")  # fmt: skip


def journalled(journal: Journal, analyzed: list[tuple[Finished, Packed]]) -> list[Finished]:
    """Commit a batch's results to the journal; its outcomes."""
    journal.add(analyzed)
    return [finished for finished, _ in analyzed]
