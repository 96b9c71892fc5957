"""The benchmarks run as their docstrings say, from any folder (issue 40: `bench_study.py`
without ``--bundled`` crashed timing the bundled studies from a temporary folder, where the
confinement of a config's paths refused their ``../../records``)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from studies import REPO


@pytest.mark.slow
def test_bench_study_times_a_bundled_study_from_another_folder(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "ROCKBRIDGE_PATHS"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, (str(REPO), env.get("PYTHONPATH"))))
    done = subprocess.run(
        [sys.executable, str(REPO / "benchmarks" / "bench_study.py"), "--sizes", "3",
         "--workers", "1", "--histories", "none", "--bundled", "paper-stripes"],
        capture_output=True, text=True, cwd=tmp_path, env=env, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    rows = [line.split() for line in done.stdout.splitlines()]
    assert ["3", "none", "1"] == next(r for r in rows if r[:1] == ["3"])[:3]
    stripes = next(r for r in rows if r[:1] == ["paper-stripes"])
    assert stripes[3] == "420"  # 3 bridges × 10 records × 14 PGAs (configs/studies)


def test_the_amdahl_fit_of_bench_scaling_recovers_the_serial_fraction(monkeypatch):
    """Times made by Amdahl's law T(p) = T1·(s + (1 − s)/p) give back T1 and s; two worker
    counts give the closed form s = 2·T(2)/T(1) − 1; the parent's share caps the projection."""
    monkeypatch.syspath_prepend(str(REPO / "benchmarks"))
    from bench_scaling import fit_amdahl, projected_speedup

    workers = [1, 2, 4, 8]
    t1, serial = fit_amdahl(workers, [12.0 * (0.15 + 0.85 / p) for p in workers])
    assert t1 == pytest.approx(12.0, rel=1e-12) and serial == pytest.approx(0.15, rel=1e-12)
    assert fit_amdahl([1, 2], [5.37, 3.45])[1] == pytest.approx(2 * 3.45 / 5.37 - 1, rel=1e-12)
    assert projected_speedup(4, 0.0, 0.0) == pytest.approx(4.0)
    assert projected_speedup(32, 0.0, 0.05) == pytest.approx(20.0)  # 1 / share
    assert projected_speedup(8, 0.1, 0.001) == pytest.approx(1 / (0.1 + 0.9 / 8))
    with pytest.raises(ValueError, match="two worker counts"):
        fit_amdahl([2, 2], [1.0, 1.0])


@pytest.mark.slow
def test_bench_scaling_prints_the_table_and_the_fit(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "ROCKBRIDGE_PATHS"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, (str(REPO), env.get("PYTHONPATH"))))
    done = subprocess.run(
        [sys.executable, str(REPO / "benchmarks" / "bench_scaling.py"), "--analyses", "6",
         "--workers", "1", "2"],
        capture_output=True, text=True, cwd=tmp_path, env=env, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    rows = [line.split() for line in done.stdout.splitlines()]
    assert [r[0] for r in rows if r[1:2] == ["|"]] == ["workers", "1", "2"]
    assert "serial fraction s =" in done.stdout and "projected speed-up" in done.stdout


def test_bench_worker_splits_nested_timers_into_their_own_parts(monkeypatch):
    """The timed functions nest (a batch holds the analyses, packing and the commit; analyze
    holds the solve and the response): each part is its own time, and the parts with the
    worker's time outside its batches and the parent's add up to the run's CPU time."""
    monkeypatch.syspath_prepend(str(REPO / "benchmarks"))
    from bench_worker import split

    sums = {  # [wall, CPU, calls] [s], made up for 10 analyses
        "batch": [1.0, 0.9, 1], "analyze": [0.8, 0.7, 10], "solve": [0.5, 0.45, 10],
        "response": [0.1, 0.08, 10], "result row": [0.02, 0.02, 10],
        "packing": [0.03, 0.03, 10], "journal": [0.05, 0.04, 1],
    }  # fmt: skip
    parts = split({"n": 10, "sums": sums, "worker": 1.5, "parent": 0.2})
    assert parts["solve"] == pytest.approx((50000.0, 45000.0))  # µs an analysis
    assert parts["around the solve"] == pytest.approx((20000.0, 17000.0))  # 0.8 − 0.5 − 0.1
    assert parts["rest of the batch"][1] == pytest.approx(1e5 * (0.9 - 0.7 - 0.02 - 0.03 - 0.04))
    assert parts["worker outside batches"][1] == pytest.approx(1e5 * (1.5 - 0.9))
    assert sum(cpu for _, cpu in parts.values()) == pytest.approx(1e5 * (1.5 + 0.2))


def test_bench_compile_gives_each_kernel_its_own_compile_time(monkeypatch):
    """numba's compile events nest (a kernel compiles its callees as it types them): each
    kernel's time is its span less those of the kernels compiled inside it, summed over its
    compiles, and the times add up to the outermost spans."""
    monkeypatch.syspath_prepend(str(REPO / "benchmarks"))
    from bench_compile import own_times

    events = [  # integrate [0, 10] holds step [1, 4] and locate [5, 9], which holds watched [6, 8]
        ("integrate", 0.0), ("step", 1.0), (None, 4.0), ("locate", 5.0), ("watched", 6.0),
        (None, 8.0), (None, 9.0), (None, 10.0), ("step", 20.0), (None, 21.5),
    ]  # fmt: skip
    own = own_times(events)
    assert own == pytest.approx({"integrate": 10 - 3 - 4, "step": 3 + 1.5, "locate": 4 - 2,
                                 "watched": 2})  # fmt: skip
    assert sum(own.values()) == pytest.approx(10 + 1.5)


@pytest.mark.slow
def test_bench_worker_prints_the_split_of_each_fidelity(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "ROCKBRIDGE_PATHS"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, (str(REPO), env.get("PYTHONPATH"))))
    done = subprocess.run(
        [sys.executable, str(REPO / "benchmarks" / "bench_worker.py"), "--analyses", "6",
         "--fidelity", "fast", "default"],
        capture_output=True, text=True, cwd=tmp_path, env=env, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    rows = {line.split("|")[0].strip(): line for line in done.stdout.splitlines()}
    for part in ("solve", "around the solve", "packing", "journal", "parent"):
        assert rows[part].count("%") == 2, part  # a column for each fidelity
    assert "fast: 6 analyses" in done.stdout and "default: 6 analyses" in done.stdout
