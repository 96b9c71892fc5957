"""The notice of a stalled run: no batch has finished for `STALL_S`, and which of the local
workers are stopped."""

from __future__ import annotations

from collections.abc import Iterable

STALL_S = 300.0
"""How long a run on local workers waits with no batch finishing before it says so, naming the
workers that are stopped (SIGSTOP, a debugger: the run would otherwise wait for them without a
word, its progress line saying "about 1 s left") [s]."""


def notice(processes: Iterable[int], waited: float) -> str:
    """What a run says when no batch has finished for `STALL_S`: which of its worker
    ``processes`` (their ids) are stopped (their state ``T`` in ``/proc``, where there is one),
    and what to do; ``waited``: since the last batch finished [s]."""
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
