"""Scaling of a study with the worker count: 1, 2, …, N workers, N the CPUs this process may use.

Each row is a study of the paper's three bridges × N/3 record entries run in a fresh process by
`run_study`, as `bench_study.py` builds and times it (its `measure`: the same study, the same
clocks). Per worker count p it prints the wall time from the study's loading to the closed
results file T(p), the throughput (analyses per second), the speed-up T(1)/T(p), the efficiency
(speed-up / p) and the parent's CPU share, P / (P + W) with P the CPU time of the parent process
(journal, progress, the results file) and W that of its workers. With one worker the run is the
parent itself, so its share is 1 and says nothing. ``busy`` is (P + W) / T(p), the cores the run
kept busy on average: near p on an idle machine; well below it, other processes of a shared
machine took the rest (the load averages before and after the runs say how many ran).

Then it fits Amdahl's law (Amdahl 1967),

    T(p) = T1 · (s + (1 − s) / p),

to the measured T(p) by linear least squares in a = T1·s and b = T1·(1 − s), T(p) = a + b/p,
which gives the serial fraction s = a / (a + b) (two worker counts determine it exactly,
s = 2·T(2)/T(1) − 1; with more, the fitted T(p) is printed beside the measured, to show how
well the law holds), and projects the speed-up on p cores,

    S(p) = min(1 / (s + (1 − s) / p), 1 / share),

where ``share`` is the parent's CPU share at the largest worker count measured: the parent is one
process, busy for P seconds of every run, so a run keeps at most (P + W) / P = 1 / share cores
busy whatever the cores. The projection assumes that the serial part (loading the study, starting
the workers, writing the file) takes as long on a bigger machine, that a worker on p cores runs
as fast as on two (no shared memory bandwidth or hyper-threaded siblings between them) and that
the study holds enough batches to keep p workers busy (a batch holds about a second of work, at
most 512 analyses). Only measured rows are measurements: on a bigger machine the same command
measures what is projected here.

The host's speed drifts on a shared machine (up to 1.5× between hours): with ``--repeat R`` the
worker counts run in turn R times and the table gives the medians of T(p) and of P and W.

    python benchmarks/bench_scaling.py [--analyses 3000] [--fidelity fast] [--histories none]
                                       [--workers 1 2 4 8] [--repeat 1] [--session]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time

import numpy as np
from bench_study import measure

from rockbridge_cli.cpus import usable_cpus

PROJECTED = (4, 8, 16, 32)
"""Core counts of the projection."""


def fit_amdahl(workers: list[int], times: list[float]) -> tuple[float, float]:
    """Amdahl's law fitted to measured wall times by least squares.

    Parameters
    ----------
    workers
        Worker counts p, at least two different ones [-].
    times
        The wall time at each count, T(p) [s].

    Returns
    -------
    T1, the fitted one-worker time [s], and s, the serial fraction [-] (not clipped: measured
    noise can put it below 0 or above 1).
    """
    if len(set(workers)) < 2:
        raise ValueError(f"Amdahl's law needs at least two worker counts, got {workers}")
    design = np.column_stack([np.ones(len(workers)), 1.0 / np.asarray(workers, dtype=float)])
    (serial, parallel), *_ = np.linalg.lstsq(design, np.asarray(times, dtype=float), rcond=None)
    t1 = float(serial + parallel)
    return t1, float(serial) / t1


def projected_speedup(cores: int, serial_fraction: float, parent_share: float) -> float:
    """Amdahl's speed-up on ``cores`` cores, capped at 1 / ``parent_share`` [-]."""
    amdahl = 1.0 / (serial_fraction + (1.0 - serial_fraction) / cores)
    return min(amdahl, 1.0 / parent_share) if parent_share > 0 else amdahl


def load() -> str:
    """The system's load averages over 1, 5 and 15 minutes: on a shared machine, how many
    processes were running beside the benchmark's."""
    if not hasattr(os, "getloadavg"):
        return "unknown"
    return " ".join(f"{value:.1f}" for value in os.getloadavg())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--analyses", type=int, default=3000)
    parser.add_argument("--fidelity", default="fast")
    parser.add_argument("--histories", default="none")
    parser.add_argument("--workers", type=int, nargs="+", default=None,
                        help="worker counts (default: 1 to the CPUs it may use)")  # fmt: skip
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--session", action="store_true", help="the kernels loaded before "
                        "the clock starts, as in a session that has analyzed before")  # fmt: skip
    options = parser.parse_args()
    cpus = usable_cpus()
    counts = sorted(set(options.workers or range(1, cpus + 1)) | {1})

    measure(3, "none", 1, options.fidelity)  # compile the kernels into numba's cache
    print(
        f"{time.strftime('%Y-%m-%d %H:%M %Z')}; {platform.machine()}, {cpus} usable CPUs of "
        f"{os.cpu_count()} (load average {load()}), Python {platform.python_version()}; "
        f"{options.analyses} analyses, fidelity {options.fidelity}, histories "
        f"{options.histories}; median of {options.repeat} run(s)"
        + ("; kernels loaded before the clock" if options.session else "")
    )
    runs: dict[int, list[dict]] = {p: [] for p in counts}
    for _ in range(options.repeat):  # interleaved: a drift of the host's speed hits every count
        for p in counts:
            runs[p].append(measure(options.analyses, options.histories, p, options.fidelity,
                                   session=options.session))  # fmt: skip
    rows = {
        p: {key: statistics.median(r[key] for r in rs) for key in rs[0]} for p, rs in runs.items()
    }

    print(f"{'workers':>7} | {'T [s]':>7} {'an./s':>7} {'speed-up':>8} {'effic.':>6} | "
          f"{'parent CPU':>10} {'worker CPU':>10} {'share':>6} {'busy':>5}")  # fmt: skip
    t1 = rows[1]["e2e"]
    for p, row in rows.items():
        share = row["parent"] / (row["parent"] + row["worker"]) if p > 1 else float("nan")
        print(
            f"{p:>7} | {row['e2e']:7.2f} {row['n'] / row['e2e']:7.0f} {t1 / row['e2e']:8.2f} "
            f"{t1 / row['e2e'] / p:6.2f} | {row['parent']:9.2f}s {row['worker']:9.2f}s "
            f"{share:6.3f} {(row['parent'] + row['worker']) / row['e2e']:5.2f}"
        )
    print(f"load average after the runs: {load()}")
    if len(counts) < 2:
        print("one worker count: no serial fraction to fit")
        return
    fitted_t1, serial = fit_amdahl(counts, [rows[p]["e2e"] for p in counts])
    last = rows[counts[-1]]
    share = last["parent"] / (last["parent"] + last["worker"])
    print(
        f"Amdahl's law T(p) = T1·(s + (1 − s)/p), least squares over {len(counts)} worker "
        f"counts: T1 = {fitted_t1:.2f} s, serial fraction s = {serial:.3f}; parent's CPU share "
        f"at {counts[-1]} workers {share:.4f}, a cap of {1 / share:.0f} cores"
    )
    if len(counts) > 2:  # two counts fix s exactly; more say how well the law fits
        fitted = ", ".join(
            f"{p}: {fitted_t1 * (serial + (1 - serial) / p):.2f} s ({rows[p]['e2e']:.2f})"
            for p in counts
        )
        print(f"Amdahl's T(p) (measured): {fitted}")
    projection = ", ".join(
        f"{p}: {projected_speedup(p, min(max(serial, 0.0), 1.0), share):.1f}×" for p in PROJECTED
    )
    print(f"projected speed-up (s and the cap held as measured, each worker as fast): {projection}")


if __name__ == "__main__":
    main()
