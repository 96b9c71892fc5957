"""What runs in a worker process of a local pool (its start-up: `start_worker`; its batches:
`run_batch`) or of a Dask cluster (`prepared`): the kernels made ready first (`ready_kernels`)."""

from __future__ import annotations

import contextlib
import ctypes
import os
import signal
import sys
from collections.abc import Callable
from typing import Any

from .. import kernels
from ..grid import Cell, Grid
from ..journal import Journal
from ..work import Finished, run_cells
from .interface import journalled

_PR_SET_PDEATHSIG = 1
"""Linux prctl(2) option: the signal a process gets when its parent dies."""

STOP_PREPARING = signal.SIGUSR1
"""The signal a stopped run sends its local workers: those loading or compiling their kernels
(`ready_kernels`, no analysis in hand) end at once, instead of making the run wait for a compile
(85–133 s on a busy host, issue 39); the others ignore it and finish their batch."""

_grid: Grid | None = None
"""The grid of the study a worker process serves (set when it starts)."""

_journal: Journal | None = None
"""The journal a worker process commits to (opened when it starts)."""

_said: Any = None
"""Where a local worker process tells its parent that it compiles the kernels."""


def start_worker(setups: Any, said: Any, parent: int) -> None:
    """Worker start-up: leave Ctrl-C and SIGTERM to the parent, which stops the pool and saves
    the results (and `STOP_PREPARING`, but while the kernels load); die with the parent, however
    it dies; load the kernels if the cache holds them; then take the study (its grid, and the
    journal, a connection of its own) when the parent gives it."""
    global _grid, _journal, _said
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    signal.signal(STOP_PREPARING, signal.SIG_IGN)  # but while its kernels load (`ready_kernels`)
    if sys.platform.startswith("linux"):
        ctypes.CDLL(None).prctl(_PR_SET_PDEATHSIG, signal.SIGKILL)
    if os.getppid() != parent:  # the parent died before the request took effect
        os._exit(1)
    _said = said
    kernels.own_process()
    ready_kernels(compiling=False)
    setup = setups.get()
    if setup is not None:  # None: the pool ends unused (the run was refused or stopped)
        grid, output, config_hash = setup
        _grid = grid
        _journal = Journal(output, config_hash)


def run_batch(cells: list[Cell]) -> list[Finished]:
    assert _grid is not None and _journal is not None, "a worker runs cells after start_worker"
    ready_kernels(vertical=_grid.vertical, devices=_grid.devices)
    return journalled(_journal, run_cells(_grid, cells))


def ready_kernels(compiling: bool = True, vertical: bool = False, devices: bool = False) -> None:
    """`kernels.prepare` in a worker, which tells its parent (a local pool's) that it compiles
    them; a failure is left to each analysis to meet and record with its message. ``vertical``:
    those of an analysis with a vertical ground motion too; ``devices``: those of a bridge with
    tendons or dampers too. A local pool's worker dies at once
    of `STOP_PREPARING` meanwhile (a compile cannot be stopped from inside; the worker has no
    analysis in hand), and ignores it otherwise."""

    def announce() -> None:
        if _said is not None:
            _said.put(compiling_said(vertical, devices))

    local = _said is not None  # a Dask worker's signals are left alone
    if local:
        signal.signal(STOP_PREPARING, signal.SIG_DFL)  # the default action: end the process
    try:
        with contextlib.suppress(Exception):
            kernels.prepare(announce, compiling, vertical, devices)
    finally:
        if local:
            signal.signal(STOP_PREPARING, signal.SIG_IGN)


def compiling_said(vertical: bool, devices: bool) -> str:
    """What a local worker tells its parent when it compiles kernels: ``compiling``, with
    `` vertical`` and `` devices`` for those kernels (`LocalPool.listen` reads it back)."""
    return "compiling" + (" vertical" if vertical else "") + (" devices" if devices else "")


def prepared(function: Callable, *args: Any) -> Any:
    """``function(*args)`` on a worker, its kernels made ready first (`kernels.prepare`; those
    of a vertical ground motion where a grid among ``args`` has one)."""
    grids = [arg for arg in args if isinstance(arg, Grid)]
    ready_kernels(
        vertical=any(grid.vertical for grid in grids), devices=any(grid.devices for grid in grids)
    )
    return function(*args)
