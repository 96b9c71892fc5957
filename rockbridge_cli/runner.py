"""Run a study: every bridge × record an independent analysis, in parallel, resumable.

Each finished analysis is journalled at once (`storage.Journal`); when the run ends — completed,
interrupted by Ctrl-C or stopped by an exception — the results file is assembled from the earlier
results file and the journal (`storage.assemble`). A run killed outright (SIGKILL) loses only the
analyses in flight: the next run finds the journal and the earlier file, skips what they hold and
assembles the same file an uninterrupted run would have written.
"""

from __future__ import annotations

import signal
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from contextlib import closing
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from . import results, storage
from .config.study import Study
from .core.analysis import analyze
from .core.geometry import Model
from .cpus import usable_cpus
from .results import AnalysisResult
from .storage import Journal, Pair

Progress = Callable[["Finished", int, int], None]
"""Called after each analysis is journalled with (what finished, analyses done, analyses to run)."""


@dataclass(frozen=True)
class Task:
    """One analysis, as a worker process receives it (plain data, cheap to send)."""

    bridge: str
    record: str
    model: Model
    mirrored: bool
    restitution: float | None
    acceleration: np.ndarray
    time_step: float
    preset: str
    overrides: dict[str, Any]
    keep: tuple[str, ...]


@dataclass(frozen=True)
class Finished:
    """One analysis done and journalled.

    Attributes
    ----------
    bridge, record : ids
    status : ``ok``, ``solver_error`` or ``error`` (`results.STATUSES`)
    message : why it stopped early or could not run; empty if ok
    solve_time_s : integration time, NaN if it could not run [s]
    """

    bridge: str
    record: str
    status: str
    message: str
    solve_time_s: float


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
    peaks : the peak table of the results file (`results.read_peaks`)
    """

    output: Path
    total: int
    resumed: int
    ran: int
    workers: int
    wall_time_s: float
    solve_time_s: float
    peaks: pd.DataFrame


def run_study(
    study: Study,
    workers: int | None = None,
    resume: bool = True,
    overwrite: bool = False,
    progress: Progress | None = None,
) -> RunReport:
    """Run every analysis of a study that is not complete yet and write the results file.

    Parameters
    ----------
    study
        The resolved study (`config.study.load_study`); its ``output`` is the results file.
    workers
        Worker processes; default: the CPUs this process may use (`cpus.usable_cpus`: its
        affinity and cgroup quota). 1 runs in this process. The results do not depend on it.
    resume
        Skip the analyses already complete in the results file or its journal (those that could
        not run, status ``error``, are tried again). False recomputes everything.
    overwrite
        Start afresh: delete the results file and its journal, whatever study they belong to or
        if they cannot be read, and recompute everything. Without it, a results file or journal
        of another study, or one that cannot be read, is refused and left untouched.
    progress
        Called after each analysis (`Progress`).

    Raises
    ------
    InputError
        The output cannot be written, or holds results of another study (without ``overwrite``).
    KeyboardInterrupt
        After the results file has been assembled from the analyses finished so far.
    """
    started = time.perf_counter()
    workers = workers or usable_cpus()
    created = storage.timestamp()
    output = study.output
    journal = Journal(output)
    storage.prepare(output, journal)
    if overwrite:
        journal.clear()
        output.unlink(missing_ok=True)
    earlier = storage.stored_in_output(output, study)
    journalled = journal.entries(study.config_hash)
    if not resume:  # recompute everything; what is stored stays until it is replaced
        journal.clear()
        journalled = {}
    stored = earlier | journalled
    pairs = results.study_pairs(study)
    pending = [
        pair for pair in pairs if not resume or pair not in stored or stored[pair].status == "error"
    ]
    solve_time, done = 0.0, 0
    try:
        tasks = _tasks(study, pending)
        with closing(_execute(tasks, workers, journal, study.config_hash)) as finished:
            for item in finished:
                solve_time += np.nan_to_num(item.solve_time_s)
                done += 1
                if progress is not None:
                    progress(item, done, len(pending))
    finally:
        if done or journalled or not output.exists():
            # the journal again: entries of analyses in flight at an interruption count too
            stored = earlier | journal.entries(study.config_hash)
            sources = [stored[pair].path if pair in stored else None for pair in pairs]
            storage.assemble(output, study, sources, created)
            journal.clear()
    return RunReport(
        output=output,
        total=len(pairs),
        resumed=len(pairs) - len(pending),
        ran=done,
        workers=workers,
        wall_time_s=time.perf_counter() - started,
        solve_time_s=float(solve_time),
        peaks=results.read_peaks(output),
    )


def _tasks(study: Study, pending: Sequence[Pair]) -> list[Task | AnalysisResult]:
    """A task per pending analysis, or at once an error result if its record could not be read."""
    bridges = {b.id: b for b in study.bridges}
    records = {r.id: r for r in study.records}
    tasks: list[Task | AnalysisResult] = []
    for bridge_id, record_id in pending:
        bridge, item = bridges[bridge_id], records[record_id]
        if item.record is None:
            tasks.append(AnalysisResult.failed(bridge_id, record_id, item.error))
            continue
        tasks.append(
            Task(
                bridge_id, record_id, bridge.config.to_model(), bridge.config.mirrored,
                bridge.config.rocking_restitution, item.record.acceleration,
                item.record.time_step, study.preset, study.overrides, study.histories,
            )
        )  # fmt: skip
    return tasks


def _execute(
    tasks: list[Task | AnalysisResult], workers: int, journal: Journal, config_hash: str
) -> Iterator[Finished]:
    """Run and journal the tasks, in this process or in a pool of worker processes; yield each
    as it finishes.

    With a pool, the first task runs here first: it compiles the numerical kernels (or loads them
    from numba's disk cache) once, and the workers, forked afterwards, inherit them instead of
    each compiling them again.
    """
    if not tasks:
        return
    yield _run(tasks[0], journal, config_hash)
    rest = tasks[1:]
    count = min(workers, len(rest))
    if count <= 1:
        yield from (_run(task, journal, config_hash) for task in rest)
        return
    with ProcessPoolExecutor(count, initializer=_start_worker) as pool:
        futures = [pool.submit(_run, task, journal, config_hash) for task in rest]
        try:
            for future in as_completed(futures):
                yield future.result()
        finally:  # interrupted: drop the tasks not started, wait for the few in flight
            pool.shutdown(cancel_futures=True)


def _start_worker() -> None:
    """Worker start-up: leave Ctrl-C to the parent, which stops the pool and saves the results.

    The numerical core is imported with this module, once per worker (nothing with ``fork``).
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _run(task: Task | AnalysisResult, journal: Journal, config_hash: str) -> Finished:
    """Run one analysis (unless it is already a result) and journal it."""
    result = task if isinstance(task, AnalysisResult) else _analyze(task)
    journal.write(result, config_hash)
    values = result.values
    return Finished(
        result.bridge, result.record, values["status"], values["message"], values["solve_time_s"]
    )


def _analyze(task: Task) -> AnalysisResult:
    """Run one analysis; any exception becomes a result with status ``error`` and its message."""
    start = time.perf_counter()
    try:
        response = analyze(
            task.model, task.acceleration, task.time_step, task.preset, mirrored=task.mirrored,
            restitution=task.restitution, **task.overrides,
        )  # fmt: skip
    except Exception as exc:  # one failed analysis must not stop the others
        return AnalysisResult.failed(
            task.bridge, task.record, f"{type(exc).__name__}: {exc}", time.perf_counter() - start
        )
    return AnalysisResult.from_response(
        task.bridge, task.record, response, task.keep, time.perf_counter() - start
    )
