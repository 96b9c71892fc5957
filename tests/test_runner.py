"""The runner: results equal the integrator's, whatever the worker count; failures are isolated;
interrupted runs resume without recomputing and end with the file an uninterrupted run writes."""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys

import h5py
import numpy as np
import pandas as pd
import pytest
from studies import VOLATILE, contents, write_study

from rockbridge_cli import results
from rockbridge_cli.cli.study import stopped_line
from rockbridge_cli.config.study import load_study
from rockbridge_cli.core.analysis import analyze
from rockbridge_cli.errors import InputError
from rockbridge_cli.results import AnalysisResult, read_history, read_peaks
from rockbridge_cli.study.grid import Cell
from rockbridge_cli.study.journal import Journal, journal_path
from rockbridge_cli.study.run import run_study
from rockbridge_cli.study.work import Finished


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # default outputs (results/<stem>.h5) land in tmp_path


PAIRS = [(b, r) for b in ("studied-hbar1.00", "studied-hbar2.00") for r in ("R1", "R2")]


def _reference(tmp_path):
    """A study in tmp_path, the contents of its uninterrupted run; the output is removed again."""
    path = write_study(tmp_path, extra=f"output: {{path: {tmp_path / 'out.h5'}}}\n")
    study = load_study(path)
    run_study(study, workers=1)
    expected = contents(study.output)
    study.output.unlink()
    return study, expected


class Recorder:
    """A progress callback that remembers what ran and can interrupt the run after ``stop``."""

    def __init__(self, stop: int | None = None):
        self.stop = stop
        self.pairs: list[tuple[str, str]] = []

    def __call__(self, item, done, total):
        self.pairs.append((item.bridge, item.record))
        if done == self.stop:
            raise KeyboardInterrupt


def test_peaks_and_histories_are_the_integrators(tmp_path):
    study = load_study(write_study(tmp_path, extra=f"output: {{path: {tmp_path / 'o.h5'}}}\n"))
    report = run_study(study, workers=1)
    assert (report.total, report.ran, report.resumed) == (4, 4, 0)
    peaks = read_peaks(study.output)
    assert list(zip(peaks["bridge"], peaks["record"], strict=True)) == PAIRS  # the study's order
    for bridge, item in ((b, r) for b in study.bridges for r in study.records):
        expected = analyze(
            bridge.config.to_bridge(), item.record.acceleration, item.record.time_step, "default"
        )
        row = peaks[(peaks["bridge"] == bridge.id) & (peaks["record"] == item.id)].iloc[0]
        for name, value in expected.peak_row().items():
            if name in row.index and name not in VOLATILE:
                assert row[name] == value or (pd.isna(row[name]) and pd.isna(value)), name
        history = read_history(study.output, bridge.id, item.id)
        np.testing.assert_array_equal(history.index, expected.time)
        for name, values in expected.histories.items():
            np.testing.assert_array_equal(history[name], values, err_msg=name)
    assert set(peaks["status"]) == {"ok"}
    assert report.peaks.equals(peaks)


def test_worker_count_does_not_change_the_results(tmp_path):
    """The same file, every byte but the timings, from one process or two workers (which also
    compute the bridges' summaries of /bridges, `executors.Workers.call`)."""
    study, expected = _reference(tmp_path)
    report = run_study(study, workers=2)
    assert report.ran == 4
    assert contents(study.output) == expected


def test_a_failing_analysis_does_not_stop_the_others(tmp_path, monkeypatch):
    study, expected = _reference(tmp_path)

    def flaky(bridge, acceleration, *args, **kwargs):
        if np.abs(acceleration).max() < 4.5:  # R2 (peak 4 m/s²)
            raise RuntimeError("boom")
        return analyze(bridge, acceleration, *args, **kwargs)

    monkeypatch.setattr("rockbridge_cli.core.analysis.analyze", flaky)
    report = run_study(study, workers=1)
    peaks = report.peaks.set_index(["bridge", "record"])
    assert list(peaks["status"]) == ["ok", "error", "ok", "error"]
    assert list(peaks["message"]) == ["", "RuntimeError: boom", "", "RuntimeError: boom"]
    assert peaks["n_impacts"].isna().tolist() == [False, True, False, True]
    assert np.isnan(peaks.loc[("studied-hbar1.00", "R2"), "u_deck_max"])
    monkeypatch.setattr("rockbridge_cli.core.analysis.analyze", analyze)
    again = Recorder()
    assert run_study(study, workers=1, progress=again).ran == 2  # only the failed ones
    assert again.pairs == [("studied-hbar1.00", "R2"), ("studied-hbar2.00", "R2")]
    assert contents(study.output) == expected


def test_an_unreadable_record_fails_only_its_analyses(tmp_path):
    path = write_study(tmp_path)
    (tmp_path / "R1.txt").write_text("0.0 1.0\n0.01 2.0\n", encoding="utf-8")  # no units
    report = run_study(load_study(path), workers=1)
    peaks = report.peaks
    assert list(peaks["status"]) == ["error", "ok", "error", "ok"]
    assert "R1.txt: units: the file does not state its units" in peaks["message"][0]


@pytest.mark.parametrize("workers", [1, 2])
def test_interrupted_run_resumes(tmp_path, workers):
    study, expected = _reference(tmp_path)
    first = Recorder(stop=2)  # with workers, the second comes from the pool
    with pytest.raises(KeyboardInterrupt):
        run_study(study, workers=workers, progress=first)
    partial = read_peaks(study.output)  # the file is written with what finished
    saved = set(zip(partial["bridge"], partial["record"], strict=True))
    assert set(first.pairs) <= saved
    if workers == 1:
        assert saved == set(PAIRS[:2])
    assert not journal_path(study.output).exists()
    second = Recorder()
    report = run_study(study, workers=workers, progress=second)
    assert report.resumed == len(saved) and report.ran == 4 - len(saved)
    assert not saved & set(second.pairs)  # nothing finished before is run again
    assert contents(study.output) == expected


_KILLED_RUN = """
import os, signal, sys
from rockbridge_cli.config.study import load_study
from rockbridge_cli.study import run
from rockbridge_cli.study.run import run_study

def kill_after_two(item, done, total):
    if done == 2:
        os.kill(os.getpid(), signal.SIGKILL)

def kill_while_writing(file, *args):
    file.create_group("half-written")
    file.flush()
    os.kill(os.getpid(), signal.SIGKILL)

if sys.argv[2] == "analyses":
    run_study(load_study(sys.argv[1]), workers=1, progress=kill_after_two)
else:
    run.ResultsWriter = kill_while_writing
    run_study(load_study(sys.argv[1]), workers=1, resume=False)
"""


def _killed(study, when: str) -> None:
    done = subprocess.run(
        [sys.executable, "-c", _KILLED_RUN, str(study.path), when], capture_output=True, timeout=120
    )
    assert done.returncode == -signal.SIGKILL, done.stderr.decode()


@pytest.mark.slow
def test_sigkill_loses_only_what_was_in_flight(tmp_path):
    study, expected = _reference(tmp_path)
    _killed(study, "analyses")
    assert not study.output.exists()
    journal = Journal(study.output, study.config_hash)
    journalled = journal.verdicts()
    journal.close()
    assert sorted(journalled) == PAIRS[:2]
    resumed = Recorder()
    report = run_study(study, workers=1, progress=resumed)
    assert resumed.pairs == PAIRS[2:] and report.resumed == 2
    assert contents(study.output) == expected
    assert not journal_path(study.output).exists()


@pytest.mark.slow
def test_sigkill_while_writing_leaves_the_previous_file(tmp_path):
    study, expected = _reference(tmp_path)
    run_study(study, workers=1)
    _killed(study, "assembly")
    assert contents(study.output) == expected  # untouched and readable
    stale = list(tmp_path.glob(".out.h5.*.tmp"))
    assert len(stale) == 1
    report = run_study(study, workers=1)  # the journal holds the four new analyses
    assert report.ran == 0 and report.resumed == 4
    assert contents(study.output) == expected
    assert not list(tmp_path.glob(".out.h5.*")) and not journal_path(study.output).exists()


def test_interrupted_recomputation_keeps_the_earlier_results(tmp_path):
    """--no-resume recomputes; a Ctrl-C halfway keeps every earlier analysis in the file."""
    study, expected = _reference(tmp_path)
    run_study(study, workers=1)
    with pytest.raises(KeyboardInterrupt):
        run_study(study, workers=1, resume=False, progress=Recorder(stop=1))
    partial = read_peaks(study.output)
    assert set(zip(partial["bridge"], partial["record"], strict=True)) == set(PAIRS)
    assert contents(study.output) == expected


def test_a_stopped_recomputation_says_that_no_run_resumes_it(tmp_path):
    """A stopped --no-resume run does not advise "the same command again to resume": that
    command starts the recomputation over (a second reviewer, 2026-11-28); it says what the
    file holds and what each rerun does."""
    study, _ = _reference(tmp_path)
    run_study(study, workers=1)
    with pytest.raises(KeyboardInterrupt) as stop:
        run_study(study, workers=1, resume=False, progress=Recorder(stop=1))
    said = stopped_line(stop.value, study.output, resume=False)
    assert "resume" not in said.replace("--no-resume", "")
    assert said.startswith(f"interrupted: the analyses recomputed so far are in {study.output}")
    assert "the same command starts the recomputation over" in said
    assert stopped_line(stop.value, study.output).endswith("run the same command again to resume")


def test_nothing_to_do_leaves_the_file_alone(tmp_path):
    study, _ = _reference(tmp_path)
    run_study(study, workers=1)
    stamp = study.output.stat().st_mtime_ns
    report = run_study(study, workers=1)
    assert (report.ran, report.resumed) == (0, 4)
    assert study.output.stat().st_mtime_ns == stamp
    assert run_study(study, workers=1, resume=False).ran == 4


def test_results_of_another_study_are_refused(tmp_path):
    study, _ = _reference(tmp_path)
    run_study(study, workers=1)
    before = study.output.read_bytes()
    other = load_study(study.path, preset="fast")
    with pytest.raises(InputError, match="different study or different inputs.*--overwrite"):
        run_study(other, workers=1)
    with pytest.raises(InputError, match="different study"):
        run_study(other, workers=1, resume=False)
    assert study.output.read_bytes() == before
    assert run_study(other, workers=1, overwrite=True).ran == 4
    assert results.read_config_hash(study.output) == other.config_hash


def test_a_journal_of_another_study_is_refused(tmp_path):
    study = load_study(write_study(tmp_path))
    study.output.parent.mkdir(parents=True)
    journal = Journal(study.output, "another study's hash")
    nan = float("nan")
    failed = Finished(Cell(0, 0, 0), "studied-hbar1.00", "R1", "error", "x", nan, "", nan)
    journal.add([(failed, AnalysisResult.failed("b", "r", "x").pack())])
    journal.close()
    with pytest.raises(InputError, match="journal.db: holds analyses of a different study"):
        run_study(study, workers=1)
    assert run_study(study, workers=1, overwrite=True).ran == 4


@pytest.mark.parametrize("damage", ["empty", "truncated", "log lost"])
def test_a_damaged_journal_is_diagnosed_and_kept(tmp_path, damage):
    """A journal cut to zero bytes, cut in half, or whose write-ahead log (which holds what a
    killed run committed) is gone, was read as a new journal (its analyses discarded silently)
    or as another study's (issue 32): it is diagnosed as damaged, kept as it is, and only
    --overwrite discards it."""
    study = load_study(write_study(tmp_path))
    study.output.parent.mkdir(parents=True)
    journal = Journal(study.output, study.config_hash)
    nan = float("nan")
    failed = Finished(Cell(0, 0, 0), "studied-hbar1.00", "R1", "error", "x", nan, "", nan)
    journal.add([(failed, AnalysisResult.failed("b", "r", "x").pack())])
    path = journal_path(study.output)
    without_log = path.read_bytes()  # as a killed run leaves it, less its log
    journal.close()
    if damage == "log lost":
        path.write_bytes(without_log)
    else:
        os.truncate(path, 0 if damage == "empty" else path.stat().st_size // 2)
    before = path.read_bytes()
    with pytest.raises(InputError, match=r"journal.db: is damaged \(.*--overwrite to discard"):
        run_study(study, workers=1)
    assert path.read_bytes() == before
    assert run_study(study, workers=1, overwrite=True).ran == 4


def test_a_journal_of_an_older_rockbridge_is_refused(tmp_path):
    """A journal an interrupted run of rockbridge before the verdict columns left (SQLite
    user_version 0, five columns) is one clear error, and --overwrite discards it."""
    study = load_study(write_study(tmp_path))
    study.output.parent.mkdir(parents=True)
    with sqlite3.connect(journal_path(study.output)) as old:
        old.executescript(
            "CREATE TABLE study (config_hash TEXT NOT NULL);"
            "CREATE TABLE analyses (cell INTEGER PRIMARY KEY, bridge TEXT NOT NULL, "
            "record TEXT NOT NULL, status TEXT NOT NULL, packed BLOB NOT NULL);"
        )
        old.execute("INSERT INTO study VALUES (?)", (study.config_hash,))
    old.close()
    with pytest.raises(InputError, match="journal.db: was written by another version"):
        run_study(study, workers=1)
    assert run_study(study, workers=1, overwrite=True).ran == 4


def test_a_damaged_output_is_refused(tmp_path):
    """A file at the output that is not a results file (here not even HDF5) is refused, with
    --overwrite too: only results are ever replaced (issue 32)."""
    study = load_study(write_study(tmp_path))
    study.output.parent.mkdir(parents=True)
    study.output.write_bytes(b"not HDF5 at all" * 100)
    for overwrite in (False, True):
        with pytest.raises(InputError, match="is not a rockbridge results file: not replaced"):
            run_study(study, workers=1, overwrite=overwrite)
    assert study.output.read_bytes() == b"not HDF5 at all" * 100


def test_an_output_that_cannot_be_written_is_refused_before_any_work(tmp_path, monkeypatch):
    (tmp_path / "file").write_text("", encoding="utf-8")
    study = load_study(write_study(tmp_path), output=tmp_path / "file" / "out.h5")
    monkeypatch.setattr("rockbridge_cli.core.analysis.analyze", None)  # would fail if anything ran
    with pytest.raises(InputError, match="cannot write here"):
        run_study(study, workers=1)


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root writes anywhere")
def test_a_read_only_folder_is_refused(tmp_path):
    folder = tmp_path / "locked"
    folder.mkdir()
    folder.chmod(0o555)
    study = load_study(write_study(tmp_path), output=folder / "out.h5")
    try:
        with pytest.raises(InputError, match="Permission denied"):
            run_study(study, workers=1)
    finally:
        folder.chmod(0o755)


def test_recheck_runs_near_a_capacity_again_at_reference(tmp_path):
    """`fidelity.recheck`: an analysis at `fast` that ends in a failure (here a 3× stronger
    burst fails the abutment) is run again at `reference`, whose result the row holds; the
    analyses far from every capacity keep `fast`'s."""
    from studies import RECORDS, burst

    from rockbridge_cli.records.files import Record, write_record

    write_record(tmp_path / "strong.txt", Record("strong", 0.01, 3.0 * burst(*RECORDS["R1"])))
    path = write_study(
        tmp_path, records=("R2",),
        extra="    - {path: strong.txt}\nfidelity: {preset: fast, recheck: true}\n"
        f"output: {{path: {tmp_path / 'o.h5'}}}\n",
    )  # fmt: skip
    study = load_study(path)
    peaks = run_study(study, workers=1).peaks.set_index(["bridge", "record"])
    for bridge in study.bridges:
        strong, weak = peaks.loc[(bridge.id, "strong")], peaks.loc[(bridge.id, "R2")]
        record = study.records[1].record
        reference = analyze(
            bridge.config.to_bridge(), record.acceleration, record.time_step, "reference"
        )
        fast = analyze(bridge.config.to_bridge(), record.acceleration, record.time_step, "fast")
        changed = fast.failure_mode != reference.failure_mode  # 2: the verdict changed
        assert strong["failure_mode"] == "abutment" and strong["rechecked"] == 1 + changed
        assert weak["failure_mode"] == "none" and weak["rechecked"] == 0
        assert strong["u_deck_max"] == reference.peaks["u_deck"][0]
        assert strong["failure_time"] == reference.failure_time


def test_the_recheck_line_names_the_verdicts_that_changed():
    """The run's summary counts the analyses run again (``rechecked`` ≥ 1) and names those whose
    verdict changed (2), or says none did."""
    from rockbridge_cli.cli.study import _rechecks

    columns = {"bridge": np.array(["b", "b", "b"]), "record": np.array(["R1", "R2", "R3"]),
               "failure_mode": np.array(["none", "abutment", "none"]),
               "rechecked": np.array([0, 1, 2])}  # fmt: skip
    line = _rechecks(columns, recheck=True)
    assert "recheck: 2 of 3 analyses ran again" in line
    assert line.endswith("1 verdict changed: b/R3 (now none)")
    columns["rechecked"] = np.array([0, 1, 1])
    assert _rechecks(columns, recheck=True).endswith("; no verdict changed")
    assert _rechecks({**columns, "rechecked": np.zeros(3)}, recheck=False) == ""


def test_what_is_called_runs_on_a_worker_once_the_pool_runs(tmp_path):
    """`Workers.call` computes on a worker when the pool has started (asked before or after it
    starts), in this process when no pool ever starts (one worker, or nothing to run)."""
    from rockbridge_cli.study.executors import local_workers
    from rockbridge_cli.study.grid import Grid

    study = load_study(write_study(tmp_path))
    grid = Grid.of(study)
    study.output.parent.mkdir(parents=True)
    journal = Journal(study.output, study.config_hash)
    with local_workers(grid, journal, 2) as workers:
        before = workers.call(os.getpid)
        outcomes = [o for batch in workers.run(grid.cells) for o in batch]
        after = workers.call(os.getpid)
        assert len(outcomes) == len(grid.cells)
        assert before() != os.getpid() and after() != os.getpid()
    for count, cells in ((1, grid.cells), (2, [])):
        with local_workers(grid, journal, count) as workers:
            here = workers.call(os.getpid)
            list(workers.run(cells))
            assert here() == os.getpid()


@pytest.mark.parametrize("seconds", [None, 2**-8, 0.03, 0.0])
@pytest.mark.parametrize("cells, workers", [(10_000, 2), (10_000, 16), (37, 2), (3, 4), (1, 1)])
def test_batches_hold_a_second_of_work_and_shrink_at_the_end(cells, workers, seconds):
    """Every cell once, in order; a batch holds at most `BATCH_SECONDS` of work at the pace the
    analyses have come back at (`FIRST_BATCH` cells before any has), at most `MAX_BATCH` cells,
    and at most a `BATCHES_PER_WORKER`-th of what is left per worker (guided scheduling), so
    the last ones hold a single cell. ``seconds``: each analysis's time in its worker, None
    before any came back, 0 for analyses too short to time."""
    from rockbridge_cli.study.executors import (
        BATCH_SECONDS,
        BATCHES_PER_WORKER,
        FIRST_BATCH,
        MAX_BATCH,
        Pace,
        batched,
    )  # fmt: skip

    pace = Pace()
    if seconds is not None:
        done = Finished(Cell(0, 0, 0), "b", "r", "ok", "", 0.9 * seconds, "none", 0.0, seconds)
        pace.record([done] * 10)
    timed = {None: FIRST_BATCH, 0.0: MAX_BATCH}.get(seconds) or int(BATCH_SECONDS / seconds)
    grid = [Cell(index, 0, index) for index in range(cells)]
    batches = list(batched(grid, workers, pace))
    assert [cell for batch in batches for cell in batch] == grid
    left = cells
    for batch in batches:
        guided = -(-left // (workers * BATCHES_PER_WORKER))
        assert 1 <= len(batch) <= min(MAX_BATCH, timed, guided)
        assert len(batch) == min(MAX_BATCH, timed, guided)
        left -= len(batch)
    sizes = [len(batch) for batch in batches]
    assert sizes == sorted(sizes, reverse=True) and sizes[-1] == 1


def test_a_description_written_early_is_copied_in_as_it_would_be_written(tmp_path, monkeypatch):
    """Issue 39: the end of a run (a stop's too) wrote the description, 2.9 s of HDF5 attributes
    for a spectrum's 1000 records. A worker now writes it while the run goes on, into a file of
    its own beside the output, and the end copies it in (`prewritten.Prewritten`): the copy
    holds every attribute, dataset and value the writing does (compared as bytes), and the side
    file is gone after. Where the worker has not written it (its call still pending, or failed:
    a full disk), the end writes it, and no side file is left."""
    from concurrent.futures import Future

    from rockbridge_cli.study import prewritten
    from rockbridge_cli.study.describe import motions_of, numerics
    from rockbridge_cli.study.executors.interface import collector
    from rockbridge_cli.study.grid import Grid

    def worker(function, *args):  # a worker's call, done at once
        future = Future()
        future.set_result(function(*args))
        return collector(function, args, [future])

    def pending(function, *args):  # a call no worker has started
        return collector(function, args, [Future()])

    study = load_study(write_study(tmp_path))
    bridges = [case.bridge for case in Grid.of(study).bridges]
    computed = numerics(bridges, motions_of(study))
    files = {}
    for how, call in (("copied", worker), ("written", pending)):
        early = prewritten.Prewritten(tmp_path / "out.h5", study, bridges, "2026-01-01", None)
        early.write(computed, call)
        assert early.written == (how == "copied") == early.path.exists()
        files[how] = tmp_path / f"{how}.h5"
        with h5py.File(files[how], "w") as file:
            early.into(file, computed)
        early.remove()
        assert not early.path.exists()
    assert contents(files["copied"]) == contents(files["written"])

    def full(*args):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(prewritten, "write_description", full)
    failed = prewritten.Prewritten(tmp_path / "out.h5", study, bridges, "2026-01-01", None)
    failed.write(computed, worker)
    assert not failed.written and not failed.path.exists()


def test_the_description_is_handed_over_once_the_workers_computed_it():
    """`run._Rounds` hands the description's numerics to ``described`` between two batches, once
    the worker's call is done, and once only; not before (a call still running)."""
    from concurrent.futures import Future
    from types import SimpleNamespace

    from rockbridge_cli.study.describe import Numerics
    from rockbridge_cli.study.executors.interface import collector
    from rockbridge_cli.study.run import _Rounds

    worker = Numerics([{"from": "the worker"}], {}, {})
    call = Future()
    seen, handed = [], []

    def batches(cells):
        for cell in cells:
            seen.append(len(handed))  # what was handed over before this batch came back
            if cell == 1:
                call.set_result(worker)  # done while the second batch runs
            yield []

    offered = SimpleNamespace(call=lambda function, *args: collector(None, args, [call]),
                              run=batches)  # fmt: skip
    rounds = iter([[0, 1, 2], []])
    plan = SimpleNamespace(round=lambda verdicts: next(rounds))
    grid = SimpleNamespace(bridges=[SimpleNamespace(bridge=None)])
    ran = _Rounds(described=lambda computed, call: handed.append(computed))
    ran.run(offered, plan, grid, {}, None, None)
    assert seen == [0, 0, 1] and handed == [worker] and ran.numerics == worker
