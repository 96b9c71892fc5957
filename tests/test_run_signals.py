"""What batch schedulers do to a run: SIGTERM (``docker stop``, Kubernetes, SLURM) is handled like
Ctrl-C, the workers die with the parent however it dies, and a second run on the same output is
refused while the first is writing it.

Each scenario runs ``rockbridge run`` in a child process whose analyses are slowed down (each
analysis first appends its process id to a file, then sleeps), so that the test can act while
analyses are in flight.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
import weakref
from pathlib import Path

import pytest
from studies import BRIDGES, contents, write_study

from rockbridge_cli.config.study import load_study
from rockbridge_cli.core import batch
from rockbridge_cli.errors import InputError
from rockbridge_cli.results import read_peaks
from rockbridge_cli.results.writing import ResultsWriter
from rockbridge_cli.study.journal import Journal
from rockbridge_cli.study.merge import merge_results
from rockbridge_cli.study.run import run_study

pytestmark = pytest.mark.skipif(os.name != "posix", reason="POSIX signals")

SLOW_RUN = """
import os, sys, time
from rockbridge_cli.cli import main
from rockbridge_cli.core import analysis, batch
from rockbridge_cli.study import kernels

kernels.prepare()  # the kernels' warm-up first (and inherited by the workers): not slowed down

started = sys.argv[1]
solve = analysis.solve

def slow(*args, **kwargs):
    with open(started, "a") as file:
        file.write(f"{os.getpid()}\\n")
    time.sleep(0.5)
    return solve(*args, **kwargs)

analysis.solve = slow  # what a worker calls once per analysis on the per-analysis and lean
# paths (a study that keeps no histories calls no `analyze`: slowing that left a spectrum's map
# too fast to stop)
summarized = batch.summarized

def slow_batch(prepared, motions, time_steps):
    with open(started, "a") as file:
        file.write(f"{os.getpid()}\\n" * len(motions))
    time.sleep(0.5 * len(motions))
    return summarized(prepared, motions, time_steps)

batch.summarized = slow_batch  # the compiled batch's, once per bridge and batch (`core.batch`)
main(sys.argv[2:], prog_name="rockbridge")
"""

LONG_CALL = """
import os, sys, time
from rockbridge_cli.cli import main
from rockbridge_cli.core import MODULE
from rockbridge_cli.study import kernels

kernels.prepare()  # the kernels' warm-up first: not slowed down

started = sys.argv[1]
compiled = MODULE.KERNEL

def long(*args):
    with open(started, "a") as file:
        file.write(f"{os.getpid()}\\n")
    finish = time.perf_counter() + 0.3
    while True:  # the compiled kernel again and again: a signal arrives while it runs
        result = compiled(*args)
        if time.perf_counter() > finish:
            return result

MODULE.KERNEL = long
main(sys.argv[2:], prog_name="rockbridge")
"""
"""A run whose compiled kernel ``MODULE.KERNEL`` takes at least 0.3 s a call."""

LONG_KERNEL = LONG_CALL.replace("MODULE", "analysis").replace("KERNEL", "integrate")
"""The integrator, once per analysis (the per-analysis and lean paths)."""

LONG_BATCH = LONG_CALL.replace("MODULE", "batch").replace("KERNEL", "integrate_batch")
"""The compiled batch, once per bridge and batch (`core.batch`)."""


def start_run(
    tmp_path: Path, study: Path | None, workers: int, script: str = SLOW_RUN,
    arguments: list[str] | None = None,
) -> tuple[subprocess.Popen, Path]:  # fmt: skip
    """``rockbridge run`` (or the command of ``arguments``) in a child process, slowed down by
    ``script``; returns it and its file of pids.

    Its output goes to files, not pipes: a worker that outlived it would hold a pipe open."""
    started = tmp_path / "started.txt"
    arguments = arguments or ["run", str(study), "--workers", str(workers)]
    command = [sys.executable, "-c", script, str(started), *arguments]
    with open(tmp_path / "stdout.txt", "w") as out, open(tmp_path / "stderr.txt", "w") as err:
        child = subprocess.Popen(command, cwd=tmp_path, stdout=out, stderr=err)
    return child, started


def wait_for(condition, timeout: float = 60.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.05)


def stop_when(
    child: subprocess.Popen, ready, how: int = signal.SIGINT, timeout: float = 120.0
) -> None:
    """Send ``child`` the signal ``how`` once ``ready()`` holds (within ``timeout`` s) and wait
    up to 60 s for it to end; it is killed either way (a watchdog, not a measure)."""
    try:
        wait_for(ready, timeout=timeout)
        child.send_signal(how)
        child.wait(timeout=60)
    finally:
        child.kill()
        child.wait()


def pids(started: Path) -> set[int]:
    return {int(line) for line in started.read_text().split()} if started.exists() else set()


def alive(pid: int) -> bool:
    """Whether a process exists and is not a zombie waiting to be reaped."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except FileNotFoundError:
        return False
    except OSError:  # no /proc: ask the kernel
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return False
        return True
    return state != "Z"


@pytest.fixture
def study(tmp_path):
    """The four-analysis test study, with the results of an uninterrupted run for comparison."""
    path = write_study(tmp_path, extra=f"output: {{path: {tmp_path / 'out.h5'}}}\n")
    reference = load_study(path)
    run_study(reference, workers=1)
    expected = contents(reference.output)
    reference.output.unlink()
    return path, expected


@pytest.mark.parametrize(
    ("how", "status", "said"),
    [(signal.SIGTERM, 143, "terminated (SIGTERM)"),
     pytest.param(signal.SIGHUP, 129, "terminated (SIGHUP)", marks=pytest.mark.slow)],
)  # fmt: skip
def test_a_signal_in_the_compiled_integrator_saves_the_finished_analyses(
    tmp_path, study, how, status, said
):
    """A one-worker run analyses in this process: a signal that arrives while the compiled
    integrator runs stops the run once the batch is journalled, never inside the kernel (which
    crashed with SIGSEGV, issue 32), and the next run resumes to the file an uninterrupted run
    writes. SIGHUP (a closed terminal) is handled as SIGTERM; Ctrl-C as both (and below, in
    ``analyze``)."""
    path, expected = study
    child, started = start_run(tmp_path, path, workers=1, script=LONG_KERNEL)
    wait_for(lambda: len(started.read_text().split()) >= 2 if started.exists() else False)
    child.send_signal(how)  # the second analysis is integrating
    child.wait(timeout=120)
    err = (tmp_path / "stderr.txt").read_text()
    assert child.returncode == status, err
    assert f"{said}: " in err and "run the same command again to resume" in err
    assert "Traceback" not in err
    saved = read_peaks(tmp_path / "out.h5")  # a readable file with what finished
    assert 1 <= len(saved) < 4
    report = run_study(load_study(path), workers=1)
    assert report.resumed == len(saved) and report.ran == 4 - len(saved)
    assert contents(tmp_path / "out.h5") == expected


@pytest.mark.skipif(not batch.AVAILABLE, reason="no compiled batch here")
def test_a_signal_in_the_compiled_batch_saves_the_finished_analyses(tmp_path):
    """The same for a study that keeps no histories, whose analyses of a bridge run in one
    compiled call a batch (`core.batch`): SIGTERM while it runs stops the run once the batch is
    journalled, and the next run resumes to the file an uninterrupted run writes."""
    output = tmp_path / "out.h5"
    path = write_study(tmp_path, extra=f"output: {{path: {output}, histories: none}}\n")
    run_study(load_study(path), workers=1)
    expected = contents(output)
    output.unlink()
    child, started = start_run(tmp_path, path, workers=1, script=LONG_BATCH)
    wait_for(lambda: len(started.read_text().split()) >= 2 if started.exists() else False)
    child.send_signal(signal.SIGTERM)  # the second batch is integrating
    child.wait(timeout=120)
    err = (tmp_path / "stderr.txt").read_text()
    assert child.returncode == 143, err
    assert "terminated (SIGTERM): " in err and "Traceback" not in err
    saved = read_peaks(output)
    assert 1 <= len(saved) < 4
    report = run_study(load_study(path), workers=1)
    assert report.resumed == len(saved) and report.ran == 4 - len(saved)
    assert contents(output) == expected


@pytest.mark.slow
def test_ctrl_c_in_analyze_stops_it_after_the_integrator(tmp_path):
    """``rockbridge analyze`` runs its one analysis in this process: Ctrl-C while the integrator
    runs ends it with status 130 and one line, not a crash (issue 32)."""
    write_study(tmp_path)
    bridge = BRIDGES / "studied-hbar1.00.yaml"
    child, started = start_run(tmp_path, None, 1, LONG_KERNEL, ["analyze", str(bridge), "R1.txt"])
    wait_for(lambda: len(pids(started)) >= 1)
    child.send_signal(signal.SIGINT)
    child.wait(timeout=120)
    err = (tmp_path / "stderr.txt").read_text()
    assert child.returncode == 130, err
    assert err.strip().splitlines()[-1] == "interrupted"


def test_ctrl_c_says_at_once_what_it_saves(tmp_path, study):
    """Ctrl-C on a two-worker run says at once that it saves what finished, and where, while the
    analyses running (1.5 s each here) have yet to end and the file to be written (it said nothing
    until the end, 7–15 s on a big study, issue 31); then, as before, where the analyses are and
    how to resume."""
    path, _ = study
    slower = SLOW_RUN.replace("time.sleep(0.5)", "time.sleep(1.5)")
    child, started = start_run(tmp_path, path, workers=2, script=slower)
    wait_for(lambda: len(pids(started) - {child.pid}) >= 1)  # a worker is analyzing
    child.send_signal(signal.SIGINT)
    saving = f"interrupted: saving the analyses finished so far to {tmp_path / 'out.h5'} "
    said = tmp_path / "stderr.txt"
    wait_for(lambda: saving in said.read_text() or child.poll() is not None)
    assert child.poll() is None  # said while the run still waits for its analyses
    child.wait(timeout=120)
    lines = said.read_text().splitlines()
    assert child.returncode == 130, lines
    assert sum(line.startswith(saving) for line in lines) == 1
    assert lines[-1].startswith("interrupted: the analyses finished so far are in")


@pytest.mark.slow
@pytest.mark.parametrize("how", [signal.SIGKILL, signal.SIGTERM])
def test_the_workers_end_with_the_run(tmp_path, study, how):
    path, _ = study
    child, started = start_run(tmp_path, path, workers=2)
    wait_for(lambda: len(pids(started) - {child.pid}) >= 1)  # a worker is analyzing
    workers = pids(started) - {child.pid}
    child.send_signal(how)
    child.wait(timeout=120)
    wait_for(lambda: not any(alive(pid) for pid in workers), timeout=10)


@pytest.mark.slow
def test_the_batches_of_a_killed_worker_run_again(tmp_path, study):
    """SIGKILL of one local worker (as the out-of-memory killer sends) used to abort the run
    (BrokenProcessPool, exit 1, issue 32); a new pool now runs the batches in flight again, as
    Dask does, and the run ends ok with the file an uninterrupted run writes."""
    path, expected = study
    child, started = start_run(tmp_path, path, workers=2)
    wait_for(lambda: len(pids(started) - {child.pid}) >= 1)  # a worker is analyzing
    os.kill(min(pids(started) - {child.pid}), signal.SIGKILL)
    child.wait(timeout=120)
    assert child.returncode == 0, (tmp_path / "stderr.txt").read_text()
    assert contents(tmp_path / "out.h5") == expected


@pytest.mark.slow
def test_a_second_run_on_the_same_output_is_refused(tmp_path, study):
    path, _ = study
    child, started = start_run(tmp_path, path, workers=1)
    try:
        wait_for(lambda: len(pids(started)) >= 1)
        running = rf"another rockbridge run or merge \(process {child.pid}\)"
        with pytest.raises(InputError, match=running):
            run_study(load_study(path), workers=1)
    finally:
        child.kill()
        child.wait()
    assert run_study(load_study(path), workers=1).total == 4  # the lock died with the run


@pytest.mark.slow
def test_a_merge_into_the_output_of_a_running_study_is_refused(tmp_path, study):
    """`merge` into the file a run is writing is refused, before it reads its parts: it used to
    write the merged file, which the run then replaced with its own results, exit 0 for both
    (a second reviewer, 2026-11-28). The run's results come out whole."""
    path, expected = study
    child, started = start_run(tmp_path, path, workers=1)
    try:
        wait_for(lambda: len(pids(started)) >= 1)
        running = rf"another rockbridge run or merge \(process {child.pid}\)"
        with pytest.raises(InputError, match=running):
            merge_results(tmp_path / "out.h5", [tmp_path / "a part.h5"], overwrite=True)
    finally:
        child.wait(timeout=120)
    assert child.returncode == 0, (tmp_path / "stderr.txt").read_text()
    assert contents(tmp_path / "out.h5") == expected


def test_a_full_disk_is_one_line_and_the_finished_analyses_stay(tmp_path, monkeypatch):
    """The journal's disk fills up after the first batch: one line naming the journal, exit 1,
    no temporary file left, and the next run resumes to the file an uninterrupted run writes."""
    import sqlite3

    from click.testing import CliRunner

    from rockbridge_cli.cli import main
    from rockbridge_cli.study.journal import Journal

    path = write_study(tmp_path, extra=f"output: {{path: {tmp_path / 'out.h5'}}}\n")
    reference = load_study(path, output=tmp_path / "ref.h5")
    run_study(reference, workers=1)
    add, calls = Journal.add, []

    def fill_up(self, rows):
        calls.append(1)
        if len(calls) > 1:
            raise OSError(f"{self.path}: cannot write the journal "
                          f"({sqlite3.OperationalError('database or disk is full')})")  # fmt: skip
        add(self, rows)

    monkeypatch.setattr(Journal, "add", fill_up)
    result = CliRunner().invoke(main, ["run", str(path), "--workers", "1"])
    assert result.exit_code == 1
    lines = [line for line in result.output.splitlines() if line.startswith("error")]
    assert lines == [f"error: {tmp_path / 'out.h5.journal.db'}: cannot write the journal "
                     "(database or disk is full)"]  # fmt: skip
    assert "Traceback" not in result.output and not list(tmp_path.glob(".*.tmp"))
    monkeypatch.setattr(Journal, "add", add)
    resumed = run_study(load_study(path), workers=1)
    assert resumed.ran == 4 - resumed.resumed and resumed.resumed >= 1
    expected = contents(reference.output)
    found = contents(tmp_path / "out.h5")
    assert {k: v for k, v in found.items() if k != "/"} == {
        k: v for k, v in expected.items() if k != "/"
    }


@pytest.mark.slow
def test_a_sigkill_keeps_what_the_workers_journalled(tmp_path, study):
    """After a SIGKILL of a two-worker run (the workers die with it), the journal holds the
    analyses that finished (the workers commit their own batches), and the next run resumes from
    it to the file an uninterrupted run writes."""
    path, expected = study
    child, started = start_run(tmp_path, path, workers=2)
    # a third analysis starts once a worker has committed its first (batches of one)
    wait_for(lambda: len(started.read_text().split()) >= 3 if started.exists() else False)
    child.send_signal(signal.SIGKILL)
    child.wait(timeout=120)
    assert not (tmp_path / "out.h5").exists()
    command = [sys.executable, "-c", "from rockbridge_cli.cli import entry; entry()", "peaks",
               "out.h5"]  # fmt: skip
    peaks = subprocess.run(command, cwd=tmp_path, capture_output=True, text=True, check=False)
    assert peaks.returncode == 2 and "out.h5.journal.db): run the study again" in peaks.stderr
    journal = Journal(tmp_path / "out.h5", load_study(path).config_hash)
    journalled = len(journal)
    journal.close()
    assert 1 <= journalled < 4
    report = run_study(load_study(path), workers=1)
    assert report.resumed == journalled and report.ran == 4 - journalled
    assert contents(tmp_path / "out.h5") == expected


def test_a_stop_in_h5pys_teardown_while_the_results_are_written_still_stops(
    tmp_path, study, monkeypatch
):
    """Ctrl-C while the results file is written stops the run between two analyses, even when
    the signal lands in a callback of Python's garbage collector, where h5py closes its objects
    and an exception is printed and dropped: a second reviewer's run (2026-11-28) printed a
    traceback there, went on and exited 0. The journal keeps every analysis, no results file
    is left, and the next run writes the one an uninterrupted run writes."""
    path, expected = study
    add = ResultsWriter.add

    def stopped_in_a_callback(self, analyses, written=None):
        def analyses_then_a_signal():
            for number, packed in enumerate(analyses):
                if number == 1:
                    closed = _Closed()
                    kept = weakref.ref(closed, _interrupt)  # noqa: F841 (its callback runs)
                    del closed  # the callback runs here: the signal arrives inside it
                yield packed

        add(self, analyses_then_a_signal(), written)

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)  # an xdist worker's
    try:
        monkeypatch.setattr(ResultsWriter, "add", stopped_in_a_callback)
        with pytest.raises(KeyboardInterrupt):
            run_study(load_study(path), workers=1)
    finally:
        signal.signal(signal.SIGINT, previous)
    monkeypatch.setattr(ResultsWriter, "add", add)
    assert not (tmp_path / "out.h5").exists()
    journal = Journal(tmp_path / "out.h5", load_study(path).config_hash)
    journalled = len(journal)
    journal.close()
    assert journalled == 4
    assert run_study(load_study(path), workers=1).resumed == 4
    assert contents(tmp_path / "out.h5") == expected


class _Closed:
    """An object whose weak reference's callback stands for h5py's teardown of its objects."""


def _interrupt(reference: weakref.ref) -> None:
    """A Ctrl-C delivered inside a garbage collector's callback, then Python code that runs in
    it (where the signal's exception would be raised, printed and dropped)."""
    os.kill(os.getpid(), signal.SIGINT)
    sum(range(1000))


def test_a_stop_while_the_results_are_written_names_the_journal(tmp_path, monkeypatch):
    """A second Ctrl-C while the results file is written leaves the analyses in the journal
    only: the message said they were in the results file (issue 32)."""
    from click.testing import CliRunner

    from rockbridge_cli.cli import main
    from rockbridge_cli.results.writing import ResultsWriter

    def interrupted(self, *args, **kwargs):
        raise KeyboardInterrupt

    path = write_study(tmp_path, extra=f"output: {{path: {tmp_path / 'out.h5'}}}\n")
    monkeypatch.setattr(ResultsWriter, "add", interrupted)
    result = CliRunner().invoke(main, ["run", str(path), "--workers", "1"])
    assert result.exit_code == 130
    assert (f"interrupted: the analyses finished so far are in {tmp_path / 'out.h5.journal.db'}; "
            "run the same command again to resume") in result.output  # fmt: skip
    assert not (tmp_path / "out.h5").exists()


def test_after_the_command_ctrl_c_is_left_to_the_system(monkeypatch):
    """A Ctrl-C while the interpreter tears down printed "Exception ignored … KeyboardInterrupt"
    and exited 0: once the command has ended, SIGINT has its default action (the process ends
    at once, quietly, status 130). The objects it holds are out of the collector's passes at the
    teardown (`gc.freeze`; what that saves: ``benchmarks/bench_worker.py --start``)."""
    import gc

    import rockbridge_cli.cli as cli

    monkeypatch.setattr(cli, "main", lambda: None)
    previous = signal.getsignal(signal.SIGINT)
    gc.unfreeze()
    try:
        cli.entry()
        assert signal.getsignal(signal.SIGINT) == signal.SIG_DFL
        assert gc.get_freeze_count() > 0
    finally:
        signal.signal(signal.SIGINT, previous)
        gc.unfreeze()  # this test process's objects: collected again


def test_a_stopped_worker_is_named_when_the_run_stalls(tmp_path, monkeypatch):
    """Issue 39: a worker stopped (SIGSTOP) hung the run with "about 1 s left", nothing saying
    why. A run whose batches make no progress for `executors.stall.STALL_S` now says so, naming the
    stopped workers and how to resume them; resumed, the run ends ok."""
    import multiprocessing
    import threading

    from rockbridge_cli.study.executors import stall

    monkeypatch.setattr(stall, "STALL_S", 1.0)
    stopped: list[int] = []
    said: list[str] = []
    timers: list[threading.Timer] = []

    def progress(finished, done, total):
        if not stopped and done < total:  # every worker stopped after the first analysis
            stopped.extend(child.pid for child in multiprocessing.active_children())
            for pid in stopped:
                os.kill(pid, signal.SIGSTOP)
            resume = threading.Timer(20.0, lambda: [os.kill(p, signal.SIGCONT) for p in stopped
                                                    if alive(p)])  # fmt: skip
            resume.daemon = True  # unsaid, the run would wait for ever: fail instead
            resume.start()
            timers.append(resume)

    def notice(line: str) -> None:
        said.append(line)
        if "stopped" in line:
            for pid in stopped:
                os.kill(pid, signal.SIGCONT)

    study = load_study(write_study(tmp_path, extra="output: {path: out.h5}\n"))
    try:
        report = run_study(study, workers=2, progress=progress, notice=notice)
    finally:
        for timer in timers:  # the workers are resumed here, or have ended
            timer.cancel()
        for pid in stopped:
            os.kill(pid, signal.SIGCONT) if alive(pid) else None
    assert report.total == 4 and report.statuses == {"ok": 4}
    stalls = [line for line in said if line.startswith("no analysis has finished for")]
    assert stalls and "stopped (SIGSTOP, a debugger?); kill -CONT" in stalls[-1]  # (1 s: the
    assert stopped and all(str(pid) in stalls[-1] for pid in stopped)  # start may stall too)


def kernels_cached(environment: dict[str, str]) -> bool:
    """Whether numba's cache of ``environment`` holds every kernel of an analysis (a fresh
    process loads them all without compiling one)."""
    code = "from rockbridge_cli.study import kernels; print(kernels.prepare(compiling=False))"
    checked = subprocess.run([sys.executable, "-c", code], env=environment, capture_output=True,
                             text=True, check=True, timeout=300)  # fmt: skip
    return checked.stdout.split()[-1] == "True"


def with_cache(pid: int, cache: Path) -> bool:
    """Whether process ``pid`` runs with ``NUMBA_CACHE_DIR=cache`` (one of the run's, not yet
    reaped); False where its environment cannot be read (it has ended)."""
    try:
        environment = Path(f"/proc/{pid}/environ").read_bytes().split(b"\0")
    except OSError:
        return False
    return f"NUMBA_CACHE_DIR={cache}".encode() in environment and alive(pid)


@pytest.mark.skipif(not Path("/proc/self/environ").exists(), reason="reads /proc")
@pytest.mark.parametrize(
    ("workers", "how", "status"), [(1, signal.SIGTERM, 143), (2, signal.SIGINT, 130)]
)  # fmt: skip
def test_a_stop_while_the_first_run_compiles_does_not_wait_for_the_compile(
    tmp_path, workers, how, status
):
    """Issue 39: a stopping signal while a run compiled its kernels on a cold cache waited for the
    compile (85–133 s on a busy host; ``docker stop`` killed the run first). The compile now runs
    where the stop can end it (a child of a one-worker run, the pool's workers), so the run ends
    with its one line and status before the compile does: numba's cache is still cold after it,
    where waiting would have filled it. Nothing had finished, so no results file is written, and
    no process of the run is left. A watchdog (``timeout``) fails a regression instead of hanging
    (the compile takes ≥ 15 s on an idle core; this test never lets it end)."""
    cache = tmp_path / "numba-cache"  # cold: the run must compile
    environment = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    path = write_study(tmp_path, extra=f"output: {{path: {tmp_path / 'out.h5'}}}\n")
    command = [sys.executable, "-c", "from rockbridge_cli.cli import entry; entry()", "run",
               str(path), "--workers", str(workers)]  # fmt: skip
    said = tmp_path / "stderr.txt"
    with open(tmp_path / "stdout.txt", "w") as out, open(said, "w") as err:
        child = subprocess.Popen(command, cwd=tmp_path, stdout=out, stderr=err, env=environment)
    stop_when(child, lambda: "compiling the analysis kernels" in said.read_text(), how)
    err = said.read_text()
    assert child.returncode == status, err
    last = err.strip().splitlines()[-1]
    assert "no analysis had finished, nothing to keep; run the same command again to start" in last
    assert "Traceback" not in err and not (tmp_path / "out.h5").exists()
    own = [int(p.name) for p in Path("/proc").iterdir() if p.name.isdigit()]
    wait_for(lambda: not any(with_cache(pid, cache) for pid in own), timeout=10)
    assert not kernels_cached(environment)  # the compile was stopped, not waited for


@pytest.mark.slow
def test_a_stopped_spectrum_keeps_every_finished_point(tmp_path):
    """Issue 39: Ctrl-C on a spectrum of 1e6 points took ~25 s to exit, most of it re-deriving
    the map point by point (an id formatted per point, in the plan and in the stored spectrum)
    and recomputing in the parent the description's numerics a worker had computed. A stop
    after the first progress line ends with status 130 and the one line saying where the map
    is, and the file holds at least the analyses that line counted (every one finished).
    ``timeout`` is a watchdog, not a measure."""
    bridge = tmp_path / "block.yaml"
    bridge.write_text("name: block\npiers: {width: 0.8, heights: [2.0]}\n", encoding="utf-8")
    output = tmp_path / "block.h5"
    arguments = ["spectrum", "overturning", str(bridge), "--frequencies", "1:5:4",
                 "--amplitudes", "1:4:10", "--fidelity", "fast", "--workers", "2",
                 "-o", str(output)]  # fmt: skip
    child, _ = start_run(tmp_path, None, 2, SLOW_RUN, arguments)
    said = tmp_path / "stderr.txt"
    stop_when(child, lambda: " analyses (" in said.read_text() or child.poll() is not None,
              timeout=60)  # fmt: skip
    lines = said.read_text().splitlines()
    assert child.returncode == 130, lines
    assert "Traceback" not in said.read_text()
    assert lines[-1] == (f"interrupted: the analyses finished so far are in {output}; run the "
                         "same command again to resume")  # fmt: skip
    counted = [line for line in lines if " analyses (" in line][0]  # "k/40 analyses (…"
    finished, total = map(int, counted.split()[0].split("/"))
    assert total == 40  # the map: 4 frequencies × 10 amplitudes
    assert finished <= len(read_peaks(output)) < total


def test_a_stopped_run_takes_the_description_the_workers_computed(monkeypatch):
    """Issue 39: a stopped run recomputed its description's numerics in the parent (4.9 s of a
    1e6-point spectrum's stop) although a worker had computed them. A stop now takes a worker's
    where it has them, and neither waits for nor computes one it does not have (the file's
    writing computes it then, as before)."""
    from concurrent.futures import Future
    from types import SimpleNamespace

    from rockbridge_cli.study.describe import Numerics
    from rockbridge_cli.study.executors.interface import collector
    from rockbridge_cli.study.run import _Rounds

    worker = Numerics([{"from": "the worker"}], {}, {})

    def never(*args):
        raise AssertionError("computed in the parent")

    def stopped(futures):
        offered = SimpleNamespace(
            call=lambda function, *args: collector(never, args, futures),
            run=lambda cells: (_ for _ in ()).throw(KeyboardInterrupt),
        )
        plan = SimpleNamespace(round=lambda verdicts: ["a cell"])
        grid = SimpleNamespace(bridges=[SimpleNamespace(bridge=None)])
        rounds = _Rounds()
        with pytest.raises(KeyboardInterrupt):
            rounds.run(offered, plan, grid, {}, None, None)
        return rounds.numerics

    computed, running = Future(), Future()
    computed.set_result(worker)
    assert stopped([computed]) == worker
    assert stopped([running]) is None  # not waited for, not computed here
    assert stopped([]) is None  # no worker (a one-worker run): computed where the file is written


@pytest.mark.slow
@pytest.mark.skipif(not Path("/proc/self/environ").exists(), reason="reads /proc")
def test_ctrl_c_while_analyze_compiles_does_not_wait_for_the_compile(tmp_path):
    """Issue 39: ``rockbridge analyze`` compiled its kernels in its own process with the signal
    held, so Ctrl-C during a first compile (a cold cache) waited for all of it (minutes on a busy
    host). It now compiles in a child process that the stop kills, as ``run`` does: it ends with
    status 130 and the one line "interrupted", and numba's cache is still cold after it, where
    waiting would have filled it. ``timeout`` is a watchdog, not a measure."""
    cache = tmp_path / "numba-cache"  # cold: analyze must compile
    environment = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    write_study(tmp_path)
    command = [sys.executable, "-c", "from rockbridge_cli.cli import entry; entry()", "analyze",
               str(BRIDGES / "studied-hbar1.00.yaml"), "R1.txt"]  # fmt: skip
    said = tmp_path / "stderr.txt"
    with open(tmp_path / "stdout.txt", "w") as out, open(said, "w") as err:
        child = subprocess.Popen(command, cwd=tmp_path, stdout=out, stderr=err, env=environment)
    stop_when(child, lambda: "compiling the analysis kernels" in said.read_text())
    lines = said.read_text().strip().splitlines()
    assert child.returncode == 130, lines
    assert lines[-1] == "interrupted" and lines[-2].startswith("compiling the analysis kernels")
    own = [int(p.name) for p in Path("/proc").iterdir() if p.name.isdigit()]
    wait_for(lambda: not any(with_cache(pid, cache) for pid in own), timeout=10)
    assert not kernels_cached(environment)  # the compile was stopped, not waited for


def waits_for_a_lock(pid: int) -> bool:
    """Whether process ``pid`` is blocked waiting for a ``flock`` (a ``->`` line of
    /proc/locks)."""
    return any(
        "->" in line and line.split()[5] == str(pid)
        for line in Path("/proc/locks").read_text().splitlines()
    )


@pytest.mark.slow
@pytest.mark.skipif(not Path("/proc/locks").exists(), reason="reads /proc/locks")
def test_a_stop_while_another_process_compiles_does_not_wait_for_it(tmp_path, study):
    """Issue 39: a one-worker run that started while another process of the installation
    compiled the kernels (two runs started together on a cold cache) waited for that compile
    with the signal held: Ctrl-C waited for the other process. The wait for its lock now comes
    before the signal is held. Here this test holds the compiling process's (exclusive) lock for
    the whole test: the run ends on Ctrl-C with its one line while the lock is still held, where
    before it could not end at all (``timeout`` is the watchdog)."""
    import rockbridge_cli
    from rockbridge_cli.study import kernels

    path, _ = study
    command = [sys.executable, "-c", "from rockbridge_cli.cli import entry; entry()", "run",
               str(path), "--workers", "1"]  # fmt: skip
    # the lock is the installation's (named after the package's folder): the run must import the
    # copy this test imports, not another one installed (CI's `pip install .` beside a checkout)
    here = str(Path(rockbridge_cli.__file__).resolve().parents[1])
    paths = os.pathsep.join(filter(None, (here, os.environ.get("PYTHONPATH"))))
    said = tmp_path / "stderr.txt"
    with kernels._kernel_lock(exclusive=True):  # "another process compiles"
        with open(tmp_path / "stdout.txt", "w") as out, open(said, "w") as err:
            child = subprocess.Popen(command, cwd=tmp_path, stdout=out, stderr=err,
                                     env={**os.environ, "PYTHONPATH": paths})  # fmt: skip
        stop_when(child, lambda: waits_for_a_lock(child.pid) or child.poll() is not None)
    lines = said.read_text().strip().splitlines()
    assert child.returncode == 130, lines
    assert lines[-1] == ("interrupted: no analysis had finished, nothing to keep; run the same "
                         "command again to start")  # fmt: skip
    assert "Traceback" not in said.read_text()
