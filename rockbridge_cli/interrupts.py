"""The signals that stop a run — Ctrl-C (SIGINT), SIGTERM (``docker stop``, Kubernetes, SLURM) and
SIGHUP (the terminal closed) — as exceptions, raised only where Python code runs.

Python raises a signal's exception at the next bytecode of the main thread. While a compiled
kernel runs, that bytecode can be inside a callback the kernel makes (numba unpickles the class of
the result it returns), and an exception there crashes the process (SIGSEGV). Compiled work that a
signal may meet therefore runs inside `held`: the signal is noted, and raised when the block ends,
or at a checkpoint within it (`checkpointed`: the writing of a results file, between analyses).
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from typing import TypeVar

STOPPING = tuple(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)
)
"""The signals that stop a run (SIGHUP does not exist on Windows)."""


class Terminated(KeyboardInterrupt):
    """A run was asked to stop by SIGTERM or SIGHUP; handled like Ctrl-C.

    Parameters
    ----------
    signum
        The signal's number.
    """

    def __init__(self, signum: int = signal.SIGTERM):
        self.signum = int(signum)
        super().__init__(signal.Signals(signum).name)


def exit_status(stop: KeyboardInterrupt) -> int:
    """The exit status after a stopping signal: 128 + its number (the shell's convention: 130 after
    Ctrl-C, 143 after SIGTERM, 129 after SIGHUP)."""
    return 128 + (stop.signum if isinstance(stop, Terminated) else signal.SIGINT)


def stopped_by(stop: KeyboardInterrupt) -> str:
    """How a stop reads in a message: ``interrupted`` or ``terminated (SIGTERM)``."""
    if isinstance(stop, Terminated):
        return f"terminated ({signal.Signals(stop.signum).name})"
    return "interrupted"


def _terminate(signum: int, frame: object) -> None:
    raise Terminated(signum)


@contextmanager
def stoppable() -> Iterator[None]:
    """While the block runs, SIGTERM and SIGHUP raise `Terminated` (Ctrl-C raises
    ``KeyboardInterrupt``, as always); the handlers before are restored after it. Outside the main
    thread (which alone receives signals) it does nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught = [signum for signum in STOPPING if signum != signal.SIGINT]
    previous = {signum: signal.signal(signum, _terminate) for signum in caught}
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


@contextmanager
def held() -> Iterator[Callable[[], None]]:
    """Run code that a stopping signal must not interrupt just anywhere: a signal that arrives
    meanwhile is noted, and its handler called (raising its exception) at the next checkpoint,
    the function the block is given, or when the block ends.

    Compiled code is one such place. Writing an HDF5 file is another: h5py closes its objects in
    callbacks of Python's garbage collector, and an exception raised there is printed and
    dropped, so that a Ctrl-C there was lost, the run going on to exit 0 after a traceback
    (a second reviewer, 2026-11-28); the writer calls the checkpoint between analyses.

    Only signals with a Python handler are held: one that is ignored (a worker process's) or left
    to the system stays so. Outside the main thread it does nothing.
    """
    if threading.current_thread() is not threading.main_thread():
        yield lambda: None
        return
    noted: list[int] = []
    previous = {
        signum: handler for signum in STOPPING if callable(handler := signal.getsignal(signum))
    }

    def checkpoint() -> None:
        if noted:
            signum = noted.pop(0)
            previous[signum](signum, None)

    for signum in previous:
        signal.signal(signum, lambda signum, frame: noted.append(signum))
    try:
        yield checkpoint
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        checkpoint()


Item = TypeVar("Item")


def checkpointed(items: Iterable[Item], checkpoint: Callable[[], None]) -> Iterator[Item]:
    """``items``, with ``checkpoint`` (`held`'s) called before each."""
    for item in items:
        checkpoint()
        yield item
