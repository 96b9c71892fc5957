"""One rockbridge process writes a results file at a time: the output's lock.

A run holds it from its start to its results file, and a merge while it writes the merged file.
Without it, a merge into the file a run was writing was replaced by the run's results at its
end, with exit 0 for both (a cluster user's merged shards, lost).
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from ..errors import InputError

ORPHAN_WAIT_S = 10.0
"""How long a lock whose process has died is waited for, while its dying worker processes
release it [s]."""


@contextmanager
def exclusive(output: Path) -> Iterator[None]:
    """Hold the output's lock while the block runs: another process that asks for it is refused.
    Once it is held, the temporary files a killed writer left beside the output
    (``.<output>.<pid>….tmp``) are removed: no living process writes them.

    The lock is an advisory ``flock`` on ``.<output>.lock`` beside it; the operating system
    releases it when the process ends, however it ends, so a killed run never blocks the next.
    A run's worker processes share the lock until they have died with it, a few milliseconds
    later: a lock whose holder has died is waited for, up to `ORPHAN_WAIT_S`. (Where ``fcntl``
    does not exist, Windows, nothing is locked.)

    Raises
    ------
    InputError
        Another rockbridge process holds the lock.
    """
    try:
        import fcntl
    except ImportError:
        yield
        return
    path = output.with_name(f".{output.name}.lock")
    descriptor = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        deadline = time.monotonic() + ORPHAN_WAIT_S
        while True:
            try:
                fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except BlockingIOError:
                holder = os.pread(descriptor, 32, 0).decode(errors="replace").strip() or "?"
                if _alive(holder) or time.monotonic() > deadline:
                    reason = (
                        f"another rockbridge run or merge (process {holder}) is writing this "
                        "file; wait for it to end, or choose another output"
                    )
                    raise InputError(output, [("", reason)]) from None
                time.sleep(0.02)
        os.ftruncate(descriptor, 0)
        os.pwrite(descriptor, str(os.getpid()).encode(), 0)
        for stale in output.parent.glob(f".{output.name}.*.tmp"):  # a killed writer's
            stale.unlink(missing_ok=True)
        try:
            yield
        finally:
            path.unlink(missing_ok=True)
    finally:
        os.close(descriptor)


def _alive(pid: str) -> bool:
    """Whether the process of that id (as a lock file states it) exists; unknown ids count as
    alive."""
    try:
        os.kill(int(pid), 0)
    except ProcessLookupError:
        return False
    except (ValueError, OSError):  # not a number, or another user's process
        return True
    return True
