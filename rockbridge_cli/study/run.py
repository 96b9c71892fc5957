"""Run a study: every cell an independent analysis, in parallel, journalled, resumable.

The parent process journals what the workers send back (`journal.Journal`, SQLite) and, when
the run ends — completed, interrupted by Ctrl-C, SIGTERM or SIGHUP, or stopped by an exception —
writes the results file in one streaming pass from the earlier results file and the journal, into a
temporary file that is then renamed over the output. A run killed outright (SIGKILL) loses only
the analyses in flight: the next run finds the journal and the earlier file, skips what they
hold and writes the same file an uninterrupted run would have written. One run at a time may
write an output (a lock), and the workers end with the parent however it ends.
"""

from __future__ import annotations

import dataclasses
import errno
import heapq
import json
import math
import os
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import TYPE_CHECKING, Any

import h5py
import numpy as np

from ..assessment.limit_states import Verdict, stored_verdicts
from ..config.changes import what_differs
from ..core.quantities import NO_FAILURE
from ..core.summary import summarize_all
from ..cpus import excess_workers, usable_cpus
from ..errors import InputError
from ..interrupts import checkpointed, held, stoppable
from ..paths import checked_output, replace_atomically
from ..results.packing import AnalysisResult, Packed
from ..results.reading import (
    is_results_file,
    open_results,
    peak_columns,
    stored_results,
    stored_shard_of,
    verify,
)
from ..results.writing import ResultsWriter
from .describe import Motions, Numerics, motions_of, numerics
from .executors import LocalPool, Notice, executor
from .grid import Grid
from .journal import Journal, remove_journal
from .output_lock import exclusive
from .plan import OneRound, Plan, plan_of
from .prewritten import Prewritten
from .shards import shard_label
from .work import Finished

if TYPE_CHECKING:
    import pandas as pd

    from ..config.study import Study

Progress = Callable[[Finished, int, int], None]
"""Called after each analysis is journalled with (what finished, analyses done, analyses to run)."""

Assembly = Callable[[int, int], None]
"""Called while the results file is written with (analyses written, analyses to write)."""

DESCRIBING = (
    "every analysis has run; the results file's description (each record's intensity measures "
    "and velocity pulses, each bridge's summary) is still being computed"
)
"""What a run says when its analyses end before the numerics of its description (a set of many
records, or of pairs swept over angles, takes seconds to minutes)."""

SLOW_S = 2.0
"""How long a run's wait for its description goes unannounced [s] (`DESCRIBING`)."""


@dataclass(frozen=True)
class RunReport:
    """What `run_study` did.

    Attributes
    ----------
    output : the results file
    total : analyses in the study
    resumed : analyses already complete before this run (not recomputed)
    ran : analyses run now
    workers : worker processes the run was allowed (fewer start when fewer analyses remain)
    wall_time_s : wall time of the whole run [s]
    solve_time_s : integration time summed over the analyses run now [s]
    statuses : how many analyses of the file ended with each status
    failures : how many analyses of the file ended with a failure of the bridge
    """

    output: Path
    total: int
    resumed: int
    ran: int
    workers: int
    wall_time_s: float
    solve_time_s: float
    statuses: dict[str, int]
    failures: int

    @property
    def peaks(self) -> pd.DataFrame:
        """The peak table of the results file (`results.read_peaks`)."""
        from ..results import read_peaks

        return read_peaks(self.output)


def run_study(
    study: Study,
    workers: int | None = None,
    resume: bool = True,
    overwrite: bool = False,
    progress: Progress | None = None,
    assembly: Assembly | None = None,
    shard: tuple[int, int] | None = None,
    scheduler: str | None = None,
    notice: Notice | None = None,
    pool: LocalPool | None = None,
) -> RunReport:
    """Run every analysis of a study that is not complete yet and write the results file.

    Parameters
    ----------
    study
        The resolved study (`config.study.load_study`); its ``output`` is the results file.
    workers
        Worker processes; default: the CPUs this process may use (`cpus.usable_cpus`: its
        affinity and cgroup quota), at most `cpus.WORKERS_PER_CPU` per CPU. 1 runs in this
        process. The results do not depend on it.
    resume
        Skip the analyses already complete in the results file or its journal (those that could
        not run, status ``error``, are tried again). False recomputes everything.
    overwrite
        Start afresh: delete the results file and its journal, whatever study they belong to,
        and recompute everything; without it, those of another study, or that cannot be read,
        are refused. What is not a results file is refused either way (`paths.checked_output`).
    progress
        Called after each analysis (`Progress`).
    assembly
        Called while the results file is written (`Assembly`).
    shard
        (index, count), 0-based: run only that shard of the study (`grid.Grid.shard`) into an
        output of its own, to be merged with the others (`merge.merge_results`).
    scheduler
        Address of a Dask distributed scheduler (``tcp://host:8786``) to run the analyses on,
        instead of local worker processes; ``workers`` is then ignored.
    notice
        Called with a line to show while the run goes on (`kernels.COMPILING`).
    pool
        Local worker processes started before (`executors.LocalPool`: while the study loaded),
        used instead of ``workers`` new ones; the run closes it.

    Raises
    ------
    InputError
        The output cannot be written, is not a results file, another run is writing it, or it
        holds results of another study (without ``overwrite``).
    TypeError, ValueError
        ``study`` is not a `config.study.Study` (a path: `load_study` it), or ``workers`` or
        ``shard`` is not a count, or not a shard, or ``workers`` are more than the CPUs can
        share (`cpus.excess_workers`).
    KeyboardInterrupt
        Once the analyses finished are written (`interrupts.Terminated`: SIGTERM, SIGHUP); a
        run stopped before any finished (while its kernels compiled) writes no file.
    """
    _check_arguments(study, workers, shard, local=scheduler is None)
    started, created = time.perf_counter(), _timestamp()
    workers = workers or usable_cpus()
    if study.output.name.endswith((".journal.db", ".journal.db-wal", ".journal.db-shm")):
        reason = "is named as a results file's journal (SQLite): choose another output"
        raise InputError(study.output, [("", reason)])
    output = checked_output(study.output, ours=is_results_file, what="a rockbridge results file")
    grid = Grid.of(study)
    plan = plan_of(study, grid, grid.cells if shard is None else grid.shard(*shard))
    described = Prewritten(output, study, [case.bridge for case in grid.bridges], created, shard)
    with exclusive(output), stoppable():
        journal, verdicts = _resumed(output, study, shard, resume, overwrite)
        early = described.write if scheduler is None else None  # a Dask worker's folder differs
        resumed, rounds, stopped = len(verdicts), _Rounds(described=early), False
        try:
            try:
                with executor(grid, journal, workers, scheduler, notice, pool) as offered:
                    rounds.run(offered, plan, grid, verdicts, progress, motions_of(study),
                               notice)  # fmt: skip
            except KeyboardInterrupt:
                stopped = True
                raise
            finally:  # the plan as far as it got, the batches in flight included
                # what ran: a sized plan's cells, an IDA's as its rule replays every verdict
                # (reading the journal's back took 0.11-0.15 s of a 10 000-analysis run)
                known = verdicts if plan.sized else verdicts | journal.verdicts()
                ran = tuple(plan.ran(known))
                grid = dataclasses.replace(grid, listed=ran)
                tally = _finish(output, study, grid, shard, journal, described, assembly, rounds,
                                plan.sized, stopped)  # fmt: skip
        finally:
            journal.close()
            described.remove()
    statuses, failures = tally or _tally(output)
    total = len(grid.cells)
    return RunReport(output, total, min(resumed, total), rounds.done, workers,
                     time.perf_counter() - started, rounds.solve_time, statuses,
                     failures)  # fmt: skip


def _resumed(
    output: Path, study: Study, shard: tuple[int, int] | None, resume: bool, overwrite: bool
) -> tuple[Journal, dict[tuple[str, str], Verdict]]:
    """The run's journal (of the study, or of its shard), and the verdicts of the analyses that
    need not run again: those of the earlier results file and of the journal (none of either
    without ``resume``, none of the file with ``overwrite``); analyses that could not run
    (status ``error``) are retried."""
    earlier = _earlier_verdicts(output, study, shard, overwrite)
    scope = study.config_hash + ("" if shard is None else f" shard {shard[0]}/{shard[1]}")
    journal = Journal(output, scope)
    try:
        if not resume:  # recompute everything; what is stored stays until it is replaced
            journal.remove()
            journal = Journal(output, scope)
        return journal, {
            ids: verdict
            for ids, verdict in ((earlier if resume else {}) | journal.verdicts()).items()
            if verdict.status != "error"
        }
    except BaseException:
        journal.close()
        raise


def _finish(
    output: Path, study: Study, grid: Grid, shard: tuple[int, int] | None, journal: Journal,
    described: Prewritten, assembly: Assembly | None, rounds: _Rounds, sized: bool,
    stopped: bool = False,
) -> tuple[dict[str, int], int] | None:  # fmt: skip
    """Write the results file of ``grid``'s cells where the journal holds anything new (or no
    file exists yet, unless a signal ``stopped`` the run: its description would need the
    compiled kernels, whose compile the stop may have cut short), then remove the journal; the
    statuses and failures written, None where nothing was. A plan that is not ``sized`` (an IDA)
    is complete only if its rounds ended."""
    tally = None
    if len(journal) or not (output.exists() or stopped):
        tally = _write(output, study, grid, shard, journal, described, assembly, rounds.numerics,
                       rounds.ended or sized)  # fmt: skip
    journal.remove()
    return tally


SUMMARIES_AT_ONCE = 256
"""Bridges a worker summarizes in one call: a large sweep's or sampled study's summaries are
shared by the workers, and a small study's are one call."""


@dataclass
class _Rounds:
    """What a run's rounds have done so far (read when they end, or are stopped).

    Attributes
    ----------
    done, total : analyses finished, and offered, in this run
    solve_time : their integration time [s]
    numerics : what the results file's description needs of the compiled kernels and the slower
        numerics (`describe.numerics`, from a worker), None until they come back
    ended : every round run (an IDA: its rule calls for no more levels)
    described : called once with the numerics and the executor's ``call``, between two batches,
        as soon as the workers have computed them (`prewritten.Prewritten.write`: the
        description written early, by a worker)
    """

    done: int = 0
    total: int = 0
    solve_time: float = 0.0
    numerics: Numerics | None = None
    ended: bool = False
    described: Callable[[Numerics, Any], None] | None = None

    def run(
        self, offered: Any, plan: OneRound | Plan, grid: Grid,
        verdicts: dict[tuple[str, str], Verdict], progress: Progress | None, motions: Motions,
        notice: Notice | None = None,
    ) -> None:  # fmt: skip
        """Run the plan's rounds on the executor ``offered``, each on the verdicts so far, and
        the numerics of the description (of the records' ``motions``) beside them: the bridges'
        summaries in parts, which the workers share (a summary costs about 16 ms)."""
        bridges = [case.bridge for case in grid.bridges]
        first = offered.call(numerics, bridges[:SUMMARIES_AT_ONCE], motions)
        rest = [
            offered.call(summarize_all, bridges[start : start + SUMMARIES_AT_ONCE])
            for start in range(SUMMARIES_AT_ONCE, len(bridges), SUMMARIES_AT_ONCE)
        ]
        try:
            while pending := plan.round(verdicts):
                self.total += len(pending)
                for batch in offered.run(pending):  # journalled
                    for finished in batch:
                        verdicts[grid.ids(finished.cell)] = finished.verdict
                        if math.isfinite(finished.solve_time_s):
                            self.solve_time += finished.solve_time_s
                        self.done += 1
                        if progress is not None:
                            progress(finished, self.done, self.total)
                    if self.numerics is None and self.described is not None:
                        self._describe([first, *rest], offered.call)
        except KeyboardInterrupt:
            self.numerics = _ready([first, *rest])
            raise
        with _said_if_slow(notice, DESCRIBING):
            self.numerics = _joined(first(), [part() for part in rest])
        self.ended = True

    def _describe(self, collectors: list[Callable[..., Any]], call: Any) -> None:
        """Hand the numerics to `described` if the workers have computed them (`_ready`)."""
        self.numerics = _ready(collectors)
        if self.numerics is not None and self.described is not None:
            self.described(self.numerics, call)


@contextmanager
def _said_if_slow(notice: Notice | None, line: str) -> Iterator[None]:
    """Have ``notice`` say ``line`` if the block takes `SLOW_S` or more (from a timer's thread:
    the block may hold this one)."""
    if notice is None:
        yield
        return
    timer = threading.Timer(SLOW_S, notice, (line,))
    timer.daemon = True
    timer.start()
    try:
        yield
    finally:
        timer.cancel()


def _ready(collectors: list[Callable[..., Any]]) -> Numerics | None:
    """The numerics of a stopped run where the workers have computed every part already, else
    None (`describe` computes them): a stop neither waits for them nor fails on them."""
    try:
        parts = [collect(wait=False) for collect in collectors]
    except Exception:  # a worker's failure: computed again, and met, where the file is written
        return None
    return None if None in parts else _joined(parts[0], parts[1:])


def _joined(computed: Numerics, rest: list[list[dict[str, object]]]) -> Numerics:
    """The numerics of the description, the summaries of the ``rest`` of the bridges added."""
    return computed._replace(summaries=computed.summaries + [s for part in rest for s in part])


def _check_arguments(
    study: Study, workers: int | None, shard: tuple[int, int] | None, local: bool = True
) -> None:
    """Raise TypeError or ValueError for arguments `run_study` cannot take (``local``: the
    workers are this machine's, bounded by its CPUs)."""
    from ..config.study import Study

    if not isinstance(study, Study):
        raise TypeError(f"run_study takes a Study (config.study.load_study(path)), not "
                        f"{type(study).__name__}")  # fmt: skip
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or workers < 1):  # fmt: skip
        raise ValueError(f"workers is a count of processes, at least 1, not {workers!r}")
    if local and workers is not None and (excess := excess_workers(workers)) is not None:
        raise ValueError(excess)
    if shard is not None and not (
        isinstance(shard, tuple) and len(shard) == 2 and all(type(n) is int for n in shard)
        and 0 <= shard[0] < shard[1]
    ):  # fmt: skip
        raise ValueError(f"shard is (index, count) with 0 ≤ index < count, not {shard!r}")


def _write(
    output: Path, study: Study, grid: Grid, shard: tuple[int, int] | None, journal: Journal,
    described: Prewritten, assembly: Assembly | None, computed: Numerics | None,
    finished: bool = True,
) -> tuple[dict[str, int], int]:  # fmt: skip
    """Write the results file of ``grid``'s cells from the journal and the earlier file, in the
    study's order, into a temporary file renamed over the output at the end; its description
    is ``described``'s (`Prewritten.into`: copied where it was written while the run went on,
    else written with ``computed``, the numerics of `describe.numerics`, None: computed here);
    ``finished``
    False for an IDA stopped before its rule called for no more levels (the file is incomplete
    however many of its analyses it holds). Returns how many analyses of the file ended with
    each status, and with a failure."""
    temporary = output.with_name(f".{output.name}.{os.getpid()}.tmp")
    try:
        with held() as checkpoint:  # a stop between analyses, not in h5py's teardown (dropped)
            with h5py.File(temporary, "w") as file, _earlier_results(output, grid) as earlier:
                described.into(file, computed)
                cells = grid.cells
                writer = ResultsWriter(file, len(cells))
                merged = _merged(journal, earlier, {cell.index for cell in cells})
                if assembly is not None and len(journal):  # before the first block: a large
                    assembly(0, len(cells))  # journal takes a while
                writer.add(
                    checkpointed(merged, checkpoint),
                    None if assembly is None else lambda n: assembly(n, len(cells)),
                )
                writer.close(_timestamp())
                if not finished:
                    file.attrs["complete"] = False
                if shard is None and study.intensity is not None:
                    from ..assessment.fragility import (
                        store,  # scipy's optimizers: only an intensity study's
                    )

                    store(file)
            checkpoint()  # a stop before the file replaces the output's
            replace_atomically(temporary, output)
    except (OSError, RuntimeError) as exc:  # a full disk (h5py: RuntimeError), a removed folder
        reason = getattr(exc, "strerror", None) or str(exc)
        if getattr(exc, "errno", None) == errno.ENOSPC or f"errno = {errno.ENOSPC}," in str(exc):
            reason = "no space left on the device"  # not HDF5's own words (issue 39)
        raise OSError(f"{output}: cannot write the results file ({reason}); the finished "
                      "analyses stay in the journal: rerun to resume") from None  # fmt: skip
    finally:
        temporary.unlink(missing_ok=True)
    return dict(writer.statuses), writer.failures


def _merged(
    journal: Journal, earlier: Iterator[tuple[int, AnalysisResult]], wanted: set[int]
) -> Iterator[Packed]:
    """The analyses of ``wanted`` cells in the journal and in the earlier file, in the order of
    the results; the journal's where both have one."""
    journalled = ((cell, packed) for cell, packed in journal.packed() if cell in wanted)
    stored = ((cell, result.pack()) for cell, result in earlier)
    last = None
    both: Iterator[tuple[int, Packed]] = heapq.merge(journalled, stored, key=lambda item: item[0])
    for cell, analysis in both:
        if cell != last:  # on a tie the journal's comes first: heapq.merge is stable
            yield analysis
        last = cell


@contextmanager
def _earlier_results(output: Path, grid: Grid) -> Iterator[Iterator[tuple[int, AnalysisResult]]]:
    """The analyses of the earlier results file with their cells, in the order of the results,
    read one at a time."""
    if not output.exists():
        yield iter(())
        return
    cells = {grid.ids(cell): cell.index for cell in grid.cells}
    with open_results(output) as file:  # an analysis the grid does not hold is left out
        yield (
            (cells[(r.bridge, r.record)], r)
            for r in stored_results(file)
            if (r.bridge, r.record) in cells
        )


def _earlier_verdicts(
    output: Path, study: Study, shard: tuple[int, int] | None, overwrite: bool
) -> dict[tuple[str, str], Verdict]:
    """The verdict of each analysis an earlier results file of the same study (and shard) holds;
    none with ``overwrite``, which first deletes the file and its journal.

    Raises
    ------
    InputError
        The file cannot be read, belongs to another study (the message names what differs), or
        holds another shard.
    """
    if overwrite:
        remove_journal(output)
        output.unlink(missing_ok=True)
    if not output.exists():
        return {}
    hint = "rerun with --overwrite to replace it, or choose another output"
    try:
        with open_results(output) as file:
            same = file.attrs.get("config_hash") == study.config_hash
            stored_shard = stored_shard_of(file)
            if same and stored_shard == shard:  # its analyses are called done: read them all
                verify(file)
            stored = stored_verdicts(file) if same and stored_shard == shard else {}
            config = json.loads(file.attrs.get("config", "{}")) if not same else {}
    except InputError as exc:  # unreadable or not a results file
        raise InputError(output, [("", f"{exc.problems[0][1]}; {hint}")]) from None
    if not same:
        changed = what_differs(config, study.resolved())
        reason = f"holds results of a different study or different inputs ({changed}); {hint}"
        raise InputError(output, [("", reason)])
    if stored_shard != shard:
        which = "the whole study" if stored_shard is None else f"shard {shard_label(stored_shard)}"
        raise InputError(output, [("", f"holds {which}; {hint}")])
    return stored


def _tally(output: Path) -> tuple[dict[str, int], int]:
    """How many analyses of a results file ended with each status, and with a failure."""
    with open_results(output) as file:
        columns = peak_columns(file)
    names, counts = np.unique(columns["status"], return_counts=True)
    failures = int(np.isin(columns["failure_mode"], ("", NO_FAILURE), invert=True).sum())
    return dict(zip(names.tolist(), counts.tolist(), strict=True)), failures


def _timestamp() -> str:
    """The current time in UTC, ISO 8601 to the second."""
    return datetime.now(timezone.utc).isoformat(timespec="seconds")
