"""The study commands end to end with click's CliRunner: run → peaks → figures, and bad inputs."""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys

import pandas as pd
import pytest
from click.testing import CliRunner
from studies import BRIDGES, REPO, STUDIED, write_records, write_study

from rockbridge_cli.cli import main
from rockbridge_cli.cli.progress import ProgressDisplay
from rockbridge_cli.core.analysis import solve
from rockbridge_cli.paths import checked_output
from rockbridge_cli.results import read_peaks
from rockbridge_cli.study import kernels
from rockbridge_cli.study.grid import Cell
from rockbridge_cli.study.work import Finished

CELL = Cell(0, 0, 0)
"""A cell for what the progress display is shown (it reads only what an analysis says)."""


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # default outputs (results/<stem>.h5, figures) land in tmp_path


def invoke(*args: str):
    return CliRunner().invoke(main, [str(a) for a in args])


def assert_user_error(result, *fragments: str) -> None:
    """Exit status 2, one readable message naming the problem, no traceback."""
    assert result.exit_code == 2, result.output
    assert result.output.startswith("error: ") and "Traceback" not in result.output
    for fragment in fragments:
        assert fragment in result.output


def test_run_peaks_and_figures(tmp_path):
    study = write_study(tmp_path)
    result = invoke("run", study, "--workers", "1")
    assert result.exit_code == 0, result.output
    output = tmp_path / "results" / "study.h5"
    assert f"results: {output.relative_to(tmp_path)}" in result.output
    assert "analyses: 4 (4 run now, 0 already done): 4 ok, 0 solver errors" in result.output
    assert "wall" in result.output and "solving" in result.output
    for bridge in STUDIED:
        assert bridge in result.output  # the short table: one row per bridge

    again = invoke("run", study)
    assert again.exit_code == 0 and "(0 run now, 4 already done)" in again.output

    table = invoke("peaks", output)
    assert table.exit_code == 0 and "u_deck [mm]" in table.output
    assert "significant impacts" in table.output.splitlines()[0]  # n_impacts_significant, named
    assert len(table.output.strip().splitlines()) == 5  # header + 4 analyses

    csv = invoke("peaks", output, "--csv", "-")
    frame = pd.read_csv(io.StringIO(csv.output), keep_default_na=False)
    expected = read_peaks(output)
    assert list(frame.columns) == list(expected.columns)
    pd.testing.assert_series_equal(frame["u_deck_max"], expected["u_deck_max"])
    assert invoke("peaks", output, "--csv", tmp_path / "p.csv").exit_code == 0
    assert (tmp_path / "p.csv").read_text(encoding="utf-8") == csv.output

    data = json.loads(invoke("peaks", output, "--json").output)
    assert data["units"]["u_deck_max"] == "m"
    assert [row["record"] for row in data["rows"]] == ["R1", "R2", "R1", "R2"]
    assert data["rows"][0]["failure_time"] is None  # NaN → null

    figure = invoke("plot", "peaks", output)
    assert figure.exit_code == 0, figure.output
    assert (tmp_path / "results" / "study-peaks.png").stat().st_size > 10_000
    history = invoke("plot", "history", output, "--record", "R2", "--bridge", STUDIED[1],
                     "-o", tmp_path / "h.pdf")  # fmt: skip
    assert history.exit_code == 0 and (tmp_path / "h.pdf").read_bytes().startswith(b"%PDF")
    assert_user_error(invoke("plot", "history", output, "--record", "R9"), "no analysis")
    assert_user_error(invoke("plot", "peaks", output, "-o", "x.jpg"), "unknown figure format")


def test_other_settings_from_the_command_line(tmp_path):
    study = write_study(tmp_path)
    result = invoke("run", study, "--workers", "2", "--fidelity", "fast", "-o", tmp_path / "f.h5")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "f.h5").exists()
    refused = invoke("run", study, "-o", tmp_path / "f.h5")  # the default fidelity: another study
    assert_user_error(refused, "f.h5: holds results of a different study", "--overwrite",
                      "fidelity.preset: fast → default")  # fmt: skip
    rerun = invoke("run", study, "-o", tmp_path / "f.h5", "--overwrite", "--workers", "1")
    assert rerun.exit_code == 0 and "(4 run now, 0 already done)" in rerun.output
    recomputed = invoke("run", study, "-o", tmp_path / "f.h5", "--no-resume")
    assert "(4 run now, 0 already done)" in recomputed.output


def test_a_refused_output_names_what_changed(tmp_path):
    """The file holds another study: the refusal names the fields that differ (a tail, a bridge's
    gap of 0.20 → 0.21 m), not only that something does."""
    bridge = (BRIDGES / "studied-hbar1.25.yaml").read_text(encoding="utf-8")
    (tmp_path / "b.yaml").write_text(bridge.replace("gap: 0.12", "gap: 0.20"), encoding="utf-8")
    study = write_study(tmp_path, bridges=(), bridge_files=(tmp_path / "b.yaml",),
                        extra="fidelity: fast\noutput: {histories: none}\n")  # fmt: skip
    assert invoke("run", study, "-o", tmp_path / "f.h5").exit_code == 0
    tail = invoke("run", study, "-o", tmp_path / "f.h5", "--tail", "2")
    assert_user_error(tail, "different study or different inputs (fidelity.knobs.tail: 0 → 2)")
    (tmp_path / "b.yaml").write_text(bridge.replace("gap: 0.12", "gap: 0.21"), encoding="utf-8")
    gap = invoke("run", study, "-o", tmp_path / "f.h5")
    assert_user_error(gap, "(bridge b: abutments.gap: 0.2 → 0.21)")


def test_bad_inputs(tmp_path):
    study = write_study(tmp_path)
    (tmp_path / "R2.txt").unlink()
    assert_user_error(
        invoke("run", study),
        f"{study}: records.files.1.path: record file not found: R2.txt",
    )
    write_study(tmp_path)
    text = study.read_text(encoding="utf-8").replace("records:", "  - nowhere.yaml\nrecords:")
    (tmp_path / "b.yaml").write_text(text, encoding="utf-8")
    assert_user_error(invoke("run", tmp_path / "b.yaml"), "bridges.2: bridge file not found")
    (tmp_path / "file").write_text("", encoding="utf-8")
    assert_user_error(invoke("run", study, "-o", tmp_path / "file" / "x.h5"), "cannot write here")
    damaged = tmp_path / "damaged.h5"
    damaged.write_bytes(b"garbage" * 50)
    assert_user_error(invoke("peaks", damaged), "not a readable HDF5 file")
    assert_user_error(invoke("run", study, "-o", damaged), "not a rockbridge results file")
    assert damaged.read_bytes() == b"garbage" * 50  # nothing earlier lost
    assert_user_error(invoke("plot", "peaks", tmp_path / "none.h5"), "file not found")


def test_analyses_that_cannot_run_exit_1_after_writing_the_rest(tmp_path):
    study = write_study(tmp_path)
    (tmp_path / "R1.txt").write_text("0 1\n0.01 2\n", encoding="utf-8")  # units not stated
    result = invoke("run", study, "--workers", "1")
    assert result.exit_code == 1
    assert "studied-hbar1.00 × R1: error:" in result.output  # reported as it happens
    assert "2 analyses did not end ok" in result.output and "Traceback" not in result.output
    assert list(read_peaks(tmp_path / "results" / "study.h5")["status"]) == [
        "error", "ok", "error", "ok",
    ]  # fmt: skip


def test_ctrl_c_keeps_what_finished(tmp_path, monkeypatch):
    kernels.prepare()  # the kernels' warm-up first: its analyses are not the study's
    calls = []

    def interrupted(*args, **kwargs):
        calls.append(1)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return solve(*args, **kwargs)

    monkeypatch.setattr("rockbridge_cli.core.analysis.solve", interrupted)
    monkeypatch.setattr("rockbridge_cli.core.batch.AVAILABLE", False)  # the lean path: the
    # compiled batch has no Python call per analysis to stop in (test_run_signals stops one)
    result = invoke("run", write_study(tmp_path), "--workers", "1")
    assert result.exit_code == 130 and "Traceback" not in result.output
    assert "interrupted: the analyses finished so far are in results/study.h5" in result.output
    assert len(read_peaks(tmp_path / "results" / "study.h5")) == 2
    monkeypatch.setattr("rockbridge_cli.core.analysis.solve", solve)
    resumed = invoke("run", tmp_path / "study.yaml", "--workers", "1")
    assert "(2 run now, 2 already done)" in resumed.output


@pytest.mark.parametrize("terminal", [True, False])
def test_progress_display(capsys, terminal):
    display = ProgressDisplay(terminal=terminal)
    for done in range(1, 31):
        status = "error" if done == 7 else "ok"
        display(
            Finished(
                CELL, "b", f"AR{done:02d}", status, "boom" if done == 7 else "", 0.01, "none", 0.0
            ),
            done,
            30,
        )
    display.close()
    err = capsys.readouterr().err
    assert "b × AR07: error: boom" in err
    if terminal:
        assert "[" + "#" * 30 + "] 30/30" in err and err.endswith("left\n")
    else:  # one line per tenth, plus the error
        assert len(err.splitlines()) == 11 and "30/30 analyses (100%)" in err


@pytest.mark.parametrize("growing", [False, True])
def test_a_rounds_end_shows_no_time_left_where_more_rounds_follow(capsys, monkeypatch, growing):
    """An IDA's total grows round by round: at a round's 100 % it printed "about 0 s left",
    sixteen times in a new user's run. Where the total grows, a round's end gives no estimate
    (the bar's "?:?? left"); elsewhere the last line is the run's end, "about 0 s left". On a
    clock the test moves, an analysis a second."""
    from rockbridge_cli.cli import progress

    clock = [0.0]
    monkeypatch.setattr(progress.time, "monotonic", lambda: clock[0])
    display = ProgressDisplay(terminal=False, growing=growing)
    for done in range(1, 11):
        clock[0] = float(done)
        display(Finished(CELL, "b", f"R{done}", "ok", "", 0.01, "none", 0.0), done, 10)
    last = capsys.readouterr().err.splitlines()[-1]
    assert last.startswith("10/10 analyses (100%)")
    assert ("left" in last) is (not growing)


def test_a_plain_progress_line_comes_at_least_once_a_minute(capsys, monkeypatch):
    """Issue 39: a spectrum's first round of a million analyses printed its first plain line
    after a tenth of them (minutes; 10 min for a 1e7 map). On a clock that this test moves (no
    waiting), 1000 analyses every 10 s: a line at 60 s, 120 s, … although no tenth has passed,
    then the tenth's line at 1000 s (100 000 of 1 000 000 done)."""
    from rockbridge_cli.cli import progress

    clock = [0.0]
    monkeypatch.setattr(progress.time, "monotonic", lambda: clock[0])
    display = ProgressDisplay(terminal=False)
    for step in range(1, 101):
        clock[0] = 10.0 * step
        done = 1000 * step
        display(Finished(CELL, "b", f"R{done}", "ok", "", 0.01, "none", 0.0), done, 1_000_000)
    lines = capsys.readouterr().err.splitlines()
    assert [line.split(" analyses")[0] for line in lines] == [
        f"{done}/1000000" for done in range(6000, 100_001, 6000)
    ] + ["100000/1000000"]
    assert lines[-1].startswith("100000/1000000 analyses (10%), 1000.0 s elapsed")


@pytest.mark.parametrize("terminal", [True, False])
def test_progress_stays_short_for_a_big_study(capsys, terminal):
    """10 000 analyses, 500 of them failing: the heading once, ten failures by name, then one
    line for the rest; plain output one line per tenth; the results file's writing reported."""
    display = ProgressDisplay(heading="workers: 2 (--workers)", terminal=terminal)
    for done in range(1, 10_001):
        status = "solver_error" if done % 20 == 0 else "ok"
        display(
            Finished(
                CELL, "b", f"R{done}", status, "x" if status != "ok" else "", 0.001, "none", 0.0
            ),
            done,
            10_000,
        )
    for written in range(1, 10_001):
        display.assembling(written, 10_000)
    display.close()
    lines = capsys.readouterr().err.replace("\r", "\n").splitlines()
    assert lines[0] == "workers: 2 (--workers)"
    assert sum(": solver_error: x" in line for line in lines) == 10
    assert sum("more analyses did not end ok" in line for line in lines) == 1
    assert "writing the results file" in lines[-1] and "10000" in lines[-1]
    if not terminal:
        assert len(lines) == 1 + 11 + 10 + 2  # heading, problems, tenths, writing started/done
    else:
        assert len(lines) < 200  # redrawn every 0.1 s at most, and at the end


def test_a_long_writing_of_the_results_file_says_how_far_it_is(capsys, monkeypatch):
    """Issue 40: a Ctrl-C with a large journal saved for minutes without a line. The writing
    says it starts before its first block, then every 10 s how far it is; an interrupted run
    writes fewer analyses than the study's, so no "done" (the run's next line ends it)."""
    clock = [0.0]
    monkeypatch.setattr("rockbridge_cli.cli.progress.time.monotonic", lambda: clock[0] + 1.0)
    display = ProgressDisplay(terminal=False)
    for written, now in ((0, 0.0), (100, 4.0), (200, 10.5), (276, 12.0)):
        clock[0] = now
        display.assembling(written, 6000)
    assert capsys.readouterr().err.splitlines() == [
        "writing the results file (at most 6000 analyses): started",
        "writing the results file: 200 analyses written",
    ]


def test_outputs_that_cannot_be_written_exit_2_before_any_work(tmp_path):
    """A figure, a CSV export or a record folder under a path that is a file: one message, 2."""
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    bridge = REPO / "configs" / "bridges" / "studied-hbar1.25.yaml"
    for args in (
        ("plot", "onset", bridge, "-o", blocker / "fig.png"),
        ("generate-records", REPO / "configs" / "records" / "ec8-type1-C-ag0.6g.yaml",
         "--out", blocker / "set"),
    ):  # fmt: skip
        result = invoke(*args)
        assert result.exit_code == 2 and "cannot write here" in result.output, result.output
        assert "Traceback" not in result.output


def test_peaks_never_write_over_the_results_they_read(tmp_path):
    """`rockbridge peaks R.h5 --csv R.h5` used to replace the results with the CSV (issue 14)."""
    study = write_study(tmp_path)
    assert invoke("run", study, "--workers", "1").exit_code == 0
    output = tmp_path / "results" / "study.h5"
    before = output.read_bytes()
    assert_user_error(invoke("peaks", output, "--csv", output), "is the file being read")
    (tmp_path / "link.h5").symlink_to(output)
    assert_user_error(invoke("peaks", output, "--csv", tmp_path / "link.h5"), "being read")
    other = tmp_path / "other.h5"  # another study's results: a CSV never replaces them
    other.write_bytes(before)
    assert_user_error(invoke("peaks", output, "--csv", other), "is not a table of these columns")
    assert output.read_bytes() == before == other.read_bytes()


def test_no_command_writes_over_a_file_it_did_not_write(tmp_path):
    """`report -o OTHER.h5`, a figure onto results named *.png, `run s.yaml -o s.yaml
    --overwrite` (the study, a bridge, a record it reads), `-o` onto a device: one line, exit 2,
    nothing changed, and no invitation to --overwrite where it could not help (issue 32). What
    rockbridge wrote is replaced: results (with --overwrite), figures, reports, tables."""
    study = write_study(tmp_path)
    assert invoke("run", study, "--workers", "1").exit_code == 0
    results = tmp_path / "results" / "study.h5"
    other = tmp_path / "other.h5"
    other.write_bytes(results.read_bytes())
    disguised = tmp_path / "results.png"  # a results file under a figure's name
    disguised.write_bytes(results.read_bytes())
    bridge = tmp_path / "bridge.yaml"
    bridge.write_text((REPO / "configs" / "bridges" / f"{STUDIED[0]}.yaml").read_text())
    mine = study.read_text().replace(f"  - {(REPO / 'configs' / 'bridges' / STUDIED[0]).as_posix()}"
                                     ".yaml", f"  - {bridge.as_posix()}")  # fmt: skip
    study.write_text(mine)
    kept = {
        path: path.read_bytes() for path in (other, disguised, study, bridge, tmp_path / "R1.txt")
    }
    not_ours = "not replaced; choose another output"
    for args in (
        ("report", results, "-o", other),
        ("plot", "peaks", results, "-o", disguised),
        ("plot", "history", results, "--record", "R1", "-o", disguised),
        ("peaks", results, "--csv", study),
        ("merge", study, results, "--overwrite"),
    ):
        assert_user_error(invoke(*args), not_ours)
    for target in (study, bridge, tmp_path / "R1.txt"):
        for flag in ((), ("--overwrite",)):
            refusal = invoke("run", study, "-o", target, "--workers", "1", *flag)
            assert_user_error(refusal, f"{target}: exists and is not a rockbridge results file")
            assert "--overwrite" not in refusal.output
    fifo = tmp_path / "fifo.png"  # not a regular file, as a device is not
    os.mkfifo(fifo)
    for args in (("run", study, "-o", fifo, "--overwrite"), ("report", results, "-o", fifo),
                 ("peaks", results, "--csv", fifo), ("plot", "peaks", results, "-o", fifo),
                 ("report", results, "-o", "/dev/null")):  # fmt: skip
        assert_user_error(invoke(*args), "is not a regular file (a device, a pipe?)")
    assert {path: path.read_bytes() for path in kept} == kept
    page, figure = tmp_path / "page.html", tmp_path / "figure.pdf"
    assert invoke("report", results, "-o", page).exit_code == 0
    assert invoke("plot", "peaks", results, "-o", figure).exit_code == 0
    assert checked_output(page) == page and checked_output(figure) == figure  # replaceable
    for _ in range(2):
        assert invoke("peaks", results, "--csv", "p.csv").exit_code == 0
    assert invoke("run", study, "-o", other, "--overwrite", "--workers", "1").exit_code == 0


def test_an_output_whose_dots_climb_above_the_root_is_written(tmp_path):
    """``/../../x.h5`` is ``/x.h5`` on POSIX; SQLite could not open the journal beside it (issue
    32, a valid input refused)."""
    study = write_study(tmp_path)
    climbing = "/../.." + str(tmp_path / "out.h5")
    result = invoke("run", study, "-o", climbing, "--workers", "1")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "out.h5").is_file() and not list(tmp_path.glob("out.h5.journal*"))


@pytest.mark.slow
def test_the_command_line_and_its_workers_use_one_blas_thread():
    """rockbridge's parallelism is its processes: the command line sets one BLAS/OpenMP thread
    before numpy loads (unless the user sets a count), and a worker forked from it keeps it."""
    pytest.importorskip("threadpoolctl")
    code = (
        "import multiprocessing, sys\n"
        "import rockbridge_cli.cli, numpy, scipy.linalg\n"
        "from threadpoolctl import threadpool_info\n"
        "def threads(_=None):\n"
        "    return sorted({pool['num_threads'] for pool in threadpool_info()})\n"
        "with multiprocessing.get_context('fork').Pool(1) as pool:\n"
        "    print(threads(), pool.apply(threads))\n"
    )
    unset = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    found = subprocess.run([sys.executable, "-c", code], env=unset, capture_output=True,
                           text=True, timeout=120, check=True)  # fmt: skip
    assert found.stdout.split() == ["[1]", "[1]"]
    asked = subprocess.run([sys.executable, "-c", code], env=unset | {"OPENBLAS_NUM_THREADS": "2"},
                           capture_output=True, text=True, timeout=120, check=True)  # fmt: skip
    assert "2" in asked.stdout.split()[0]


def test_the_time_left_counts_from_the_first_analyses_back(capsys, monkeypatch):
    """The first batch comes back 30 s after the start (the kernels compiled), the next 8
    analyses 1 s later: the time left at 10 of 100 is the pace since the first batch, 1 s / 2
    analyses × 90 = 45 s (the pace since the start, 31 s / 10 × 90, said 279 s)."""
    clock = [0.0]
    monkeypatch.setattr("rockbridge_cli.cli.progress.time.monotonic", lambda: clock[0])
    display = ProgressDisplay(terminal=False)
    ok = Finished(CELL, "b", "r", "ok", "", 0.01, "none", 0.0)
    for done in range(1, 17):
        clock[0] = 30.0 if done <= 8 else 31.0
        display(ok, done, 100)
    assert "10/100 analyses (10%), 31.0 s elapsed, about 45 s left" in capsys.readouterr().err


def test_a_run_that_compiles_says_so_once_before_its_analyses(tmp_path, monkeypatch):
    """On a cold cache a worker compiles the kernels before any analysis, and the run says so
    once, after its heading, with about how long it takes, whether it runs in this process or on
    workers. (A function numba compiles afresh in each process stands for the kernels.)"""
    import numba

    from rockbridge_cli import warmup

    def compile_a_kernel(models=None):
        numba.njit(lambda x: x + 1.0)(1.0)

    monkeypatch.setattr(warmup, "analysis_kernels", compile_a_kernel)
    study = write_study(tmp_path)
    for workers in ("1", "2"):
        monkeypatch.setattr(kernels, "_ready", set())
        result = invoke("run", study, "--workers", workers, "--overwrite")
        assert result.exit_code == 0, result.output
        lines = result.output.splitlines()
        assert lines[0] == f"workers: {workers} (--workers)"
        assert lines[1].startswith("compiling the analysis kernels, once for this installation")
        assert f"about {kernels.COMPILE_TIME_S} s" in lines[1]
        assert result.output.count("compiling") == 1
    monkeypatch.setattr(kernels, "_ready", set())  # a refused run's workers compile nothing
    refused = invoke("run", tmp_path / "missing.yaml", "--workers", "2")
    assert refused.exit_code == 2 and "compiling" not in refused.output


@pytest.mark.usefixtures("vertical_kernels")  # the real ones: the run compiles the stand-in
def test_a_vertical_run_says_it_compiles_the_vertical_kernels_once(tmp_path, monkeypatch):
    """Issue 40: the kernels of a vertical ground motion, compiled for it of their own, were
    compiled silently in each worker at once on their first analysis, and counted as solve
    time. They are made ready with the others, one process at a time, and the run says so once
    (the horizontal kernels loaded, as here, only the vertical line)."""
    import numba

    from rockbridge_cli import warmup

    def compile_a_kernel(models=None):
        numba.njit(lambda x: x + 2.0)(1.0)

    monkeypatch.setattr(warmup, "vertical_kernels", compile_a_kernel)
    study = write_study(tmp_path, bridges=STUDIED[:1], records=("R1", "R2"), extra=(
        "fidelity: fast\noutput: {histories: none}\n"))  # fmt: skip
    text = study.read_text().replace("- path: R1.txt", "- {path: R1.txt, vertical: R2.txt}")
    study.write_text(text.replace("    - path: R2.txt\n", "").replace("records:\n",
                     "records:\n  vertical: true\n"))  # fmt: skip
    for workers in ("1", "2"):
        kernels.prepare()  # the horizontal kernels, loaded from the cache
        monkeypatch.setattr(kernels, "_ready", {"horizontal"})
        result = invoke("run", study, "--workers", workers, "--overwrite")
        assert result.exit_code == 0, result.output
        assert result.output.count("compiling") == 1, result.output
        assert result.output.splitlines()[1] == kernels.COMPILING_VERTICAL


@pytest.mark.usefixtures("vertical_kernels")  # compiled once a suite (conftest)
def test_analyze_says_it_compiles_and_counts_it_as_set_up(tmp_path, monkeypatch):
    """`analyze --vertical` was 4-7 times slower than `analyze`, unreported: its set-up now
    loads the vertical kernels too, and says so where numba compiles them."""
    import numba

    from rockbridge_cli.core import analysis

    real, calls = analysis.analyze, []

    def compiling_first(*args, **kwargs):
        if not calls:
            numba.njit(lambda x: x + 3.0)(1.0)
        calls.append(kwargs.get("vertical") is not None)
        return real(*args, **kwargs)

    monkeypatch.setattr(analysis, "analyze", compiling_first)
    files = write_records(tmp_path, ("R1", "R2"))
    result = invoke("analyze", BRIDGES / "studied-hbar1.00.yaml", files["R1"], "--vertical",
                    files["R2"], "--fidelity", "fast")  # fmt: skip
    assert result.exit_code == 0, result.output
    assert result.output.count(kernels.COMPILING_VERTICAL) == 1
    assert calls == [True, True]  # the set-up's analysis has a vertical motion too


def test_run_starts_its_workers_once_the_study_is_sized(tmp_path, monkeypatch):
    """Issue 39: the workers forked before the study was loaded (issue 31 started them early to
    load their kernels meanwhile), as many as asked: ``--workers 40`` on a one-analysis study
    forked 40 (3.6 GB), ``--workers 10000`` was still forking after 62 s. Now no worker starts
    before the study is loaded, and no more than its analyses."""
    import multiprocessing

    from rockbridge_cli.config import study as config
    from rockbridge_cli.study import executors

    children: list[int] = []
    load_study = config.load_study
    sizes: list[int] = []

    def loading(*args, **kwargs):
        children.append(len(multiprocessing.active_children()))
        return load_study(*args, **kwargs)

    class Pool(executors.LocalPool):
        def __init__(self, size: int):
            sizes.append(size)
            super().__init__(size)

    monkeypatch.setattr(config, "load_study", loading)
    monkeypatch.setattr(executors, "LocalPool", Pool)
    result = invoke("run", write_study(tmp_path, bridges=STUDIED[:1], records=("R1",)),
                    "--workers", "3")  # fmt: skip
    assert result.exit_code == 0, result.output
    assert result.output.splitlines()[0] == (
        "workers: 1 (--workers 3: as many as the study's analyses)"
    )
    assert children == [0] and sizes == []  # one analysis: run in this process
    result = invoke("run", write_study(tmp_path, name="two.yaml"), "--workers", "3")
    assert result.exit_code == 0, result.output
    assert children == [0, 0] and sizes == [3]  # 2 bridges × 2 records: 3 workers


def test_workers_beyond_a_multiple_of_the_cpus_are_refused_at_once(tmp_path, monkeypatch):
    """``--workers 10000`` forked for over a minute; now refused before anything is loaded."""
    import time

    from rockbridge_cli import cpus

    monkeypatch.setattr(cpus, "usable_cpus", lambda *args: 2)
    started = time.perf_counter()
    result = invoke("run", tmp_path / "missing.yaml", "--workers", 10000)
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert "--workers: 10000 workers are more than 8 (4 per CPU this process may use, 2)" in (
        result.output
    )
    assert time.perf_counter() - started < 2.0
    spectrum = invoke("spectrum", "overturning", tmp_path / "missing.yaml", "--workers", 10000)
    assert spectrum.exit_code == 2 and "10000 workers are more than 8" in spectrum.output
    from rockbridge_cli.config.study import load_study
    from rockbridge_cli.study.run import run_study

    with pytest.raises(ValueError, match="10000 workers are more than 8"):
        run_study(load_study(write_study(tmp_path)), workers=10000)


def interrupted_run(tmp_path, monkeypatch, extra: str, after: int):
    """Run a study of ``extra`` on one worker, stopped by Ctrl-C at analysis ``after``; returns
    the results file it leaves (analyses 1 … after − 1 in it). It stops in `core.analysis.solve`,
    which the per-analysis and lean paths of a study call (`study.work.run_cells`)."""
    kernels.prepare()  # the kernels' warm-up first: its analyses are not the study's
    calls = []

    def stopping(*args, **kwargs):
        calls.append(1)
        if len(calls) == after:
            raise KeyboardInterrupt
        return solve(*args, **kwargs)

    monkeypatch.setattr("rockbridge_cli.core.analysis.solve", stopping)
    monkeypatch.setattr("rockbridge_cli.core.batch.AVAILABLE", False)  # the lean path: the
    # compiled batch has no Python call per analysis to stop in (test_run_signals stops one)
    result = invoke("run", write_study(tmp_path, extra=extra), "--workers", "1")
    assert result.exit_code == 130, result.output
    monkeypatch.setattr("rockbridge_cli.core.analysis.solve", solve)
    return tmp_path / "results" / "study.h5"


@pytest.mark.slow
def test_every_reader_says_a_file_is_incomplete(tmp_path, monkeypatch):
    """Two bridges × two records × two levels, stopped after two analyses: every command that
    reads the file says "incomplete: 2 of 8 analyses" (and exits 0, having done its work on
    what the file holds); the report says it at the top of its page; peaks --json carries the
    file's counts. They said nothing (issue 31)."""
    results = interrupted_run(tmp_path, monkeypatch, STRIPES, after=3)
    notice = f"warning: {results}: incomplete: 2 of 8 analyses; run its study again to resume it"
    for command in (["peaks"], ["peaks", "--csv", "-"], ["fragility"],
                    ["plot", "peaks", "--level", "0.2"], ["plot", "fragility"],
                    ["report"]):  # fmt: skip
        result = invoke(*command, results)
        assert result.exit_code == 0, result.output
        assert result.output.count(notice) == 1, command
    page = (tmp_path / "results" / "study-report.html").read_text(encoding="utf-8")
    assert '<p class="bad">incomplete: 2 of 8 analyses: the run did not finish' in page
    counts = json.loads(invoke("peaks", results, "--json").output.split("\n", 1)[1])
    assert (counts["complete"], counts["n_complete"], counts["n_analyses"]) == (False, 2, 8)
    complete = invoke("run", tmp_path / "study.yaml", "--workers", "1")
    assert complete.exit_code == 0 and "incomplete" not in invoke("peaks", results).output


STRIPES = "intensity: {measure: pga_g, levels: [0.2, 0.8]}\nfidelity: fast\n"


def test_an_ida_stopped_before_its_end_is_incomplete(tmp_path, monkeypatch):
    """An IDA writes the levels it ran: stopped after two, its file holds all it ran (2 of 2),
    yet the curves have not ended: the file says it is incomplete (it said complete)."""
    ida = ("intensity: {measure: pga_g, ida: {start: 0.1, step: 0.4, max: 2.5, "
           "tolerance: 0.05, limit_states: [gap_closure]}}\nfidelity: fast\n")  # fmt: skip
    results = interrupted_run(tmp_path, monkeypatch, ida, after=3)
    shown = invoke("peaks", results).output
    assert f"warning: {results}: incomplete: the IDA stopped after 2 analyses" in shown


def test_peaks_points_at_the_journal_of_a_run_stopped_before_its_file(tmp_path):
    from rockbridge_cli.config.study import load_study
    from rockbridge_cli.study.journal import Journal

    study = load_study(write_study(tmp_path))
    study.output.parent.mkdir(parents=True)
    Journal(study.output, study.config_hash).close()  # what a SIGKILLed first run leaves
    assert_user_error(invoke("peaks", study.output), "file not found, but the journal of a run",
                      "study.h5.journal.db): run the study again to resume")  # fmt: skip


def test_a_closed_output_never_stops_a_run(tmp_path):
    """`rockbridge run … 2>&1 | head -1`: once the reader has gone, what the run says is dropped
    and the run goes on to its end, exiting by its analyses (here 1: a record cannot be read);
    it stopped at the first line it could not write and exited 0 (issue 31)."""
    study = write_study(tmp_path)
    (tmp_path / "R1.txt").write_text("0 1\n0.01 2\n", encoding="utf-8")  # units not stated
    read, write = os.pipe()
    os.close(read)  # the reader has gone before the run says anything
    try:
        command = [sys.executable, "-c", "from rockbridge_cli.cli import entry; entry()", "run",
                   str(study), "--workers", "2"]  # fmt: skip
        done = subprocess.run(command, stdout=write, stderr=write, cwd=tmp_path, timeout=300)
    finally:
        os.close(write)
    assert done.returncode == 1
    assert list(read_peaks(tmp_path / "results" / "study.h5")["status"]) == [
        "error", "ok", "error", "ok",
    ]  # fmt: skip


def test_the_summary_of_many_bridges_shows_the_rows_that_matter(tmp_path):
    """Issue 40: 1000 bridges printed 1000 rows. A sweep of 24 gaps (no failure) prints the 20
    with the largest backfill d/c, in the study's order, and says where every analysis is."""
    extra = ("sweep: {fields: {abutments.gap: {start: 0.01, stop: 0.24, count: 24}}}\n"
             "fidelity: fast\noutput: {histories: none}\n")  # fmt: skip
    study = write_study(tmp_path, bridges=STUDIED[:1], records=("R1",), extra=extra)
    result = invoke("run", study, "--workers", "1", "-o", str(tmp_path / "out.h5"))
    assert result.exit_code == 0, result.output
    table = result.output.split("peaks, largest over the records")[1].splitlines()
    assert table[0].startswith(", the 20 of 24 rows with the most failures")
    assert table[0].endswith(f"(every analysis: rockbridge peaks {tmp_path / 'out.h5'}):")
    assert len(table) == 2 + 20
    peaks = read_peaks(tmp_path / "out.h5")
    assert (peaks["failure_mode"] == "none").all()
    largest = peaks.nlargest(20, "dcr_backfill")["bridge"]
    assert [line.split()[0] for line in table[2:]] == [
        b for b in peaks["bridge"] if b in set(largest)
    ]
