"""The fragility fits on a busy machine: ``rockbridge fragility`` on the paper's stripes while
other processes keep every core busy, against its one-thread time.

On a machine that other jobs share (a cluster node, a CI runner), BLAS libraries that start a
thread per core spin them against the other jobs: a two-parameter fit that called a general
optimiser (scipy's L-BFGS-B, which calls BLAS) took 10-30× longer (issue 31). The command line
sets one BLAS/OpenMP thread before numpy loads, and the fits need no optimiser: Newton's method
on two parameters (`assessment.lognormal`). Each row is a fresh process, timed from its start to
its end (median of ``--repeat`` runs):

- ``command line``: ``rockbridge fragility RESULTS`` as a user runs it;
- ``one thread``: the same with ``OPENBLAS_NUM_THREADS=OMP_NUM_THREADS=MKL_NUM_THREADS=1`` set
  by the user (the one-thread time the ratio divides by);
- ``threads asked``: the same with the thread counts set to the number of CPUs (a user asking for
  threads; the command line keeps a value it finds);
- ``Python API``: ``fragilities(RESULTS)`` in a process that loaded numpy with its own default
  threads (nothing sets them).

Rows run idle and busy (one spinning process per CPU), interleaved.

    python benchmarks/bench_threads.py [--repeat 3] [--results RESULTS.h5]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
STUDY = REPO / "configs" / "studies" / "paper-stripes.yaml"
THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
CLI = "from rockbridge_cli.cli import main; main()"
API = (
    "import sys\nfrom rockbridge_cli.assessment.fragility import fragilities\n"
    "fragilities(sys.argv[1])"
)


def environment(threads: int | None) -> dict[str, str]:
    """This process's environment with the thread counts removed, or set to ``threads``."""
    clean = {k: v for k, v in os.environ.items() if k not in THREADS}
    return clean if threads is None else clean | dict.fromkeys(THREADS, str(threads))


ROWS = {
    "command line": (CLI, None),
    "one thread": (CLI, 1),
    "threads asked": (CLI, os.cpu_count() or 1),
    "Python API": (API, None),
}
"""Row → (code, thread counts set in its environment, None for none)."""


def timed(code: str, threads: int | None, results: Path) -> float:
    """Wall time of a fresh process running ``code`` on the results [s]."""
    arguments = ["fragility", str(results)] if code == CLI else [str(results)]
    started = time.perf_counter()
    subprocess.run([sys.executable, "-c", code, *arguments], env=environment(threads),
                   check=True, capture_output=True)  # fmt: skip
    return time.perf_counter() - started


@contextmanager
def busy(on: bool):
    """One process spinning on each CPU while the block runs (nothing when ``on`` is false)."""
    spinners = [
        subprocess.Popen([sys.executable, "-c", "while True: pass"])
        for _ in range((os.cpu_count() or 1) if on else 0)
    ]
    try:
        time.sleep(0.5 if on else 0.0)  # let them reach their stride
        yield
    finally:
        for spinner in spinners:
            spinner.kill()
            spinner.wait()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--results", type=Path, default=None,
                        help="the stripes' results [default: run the study first]")  # fmt: skip
    options = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        results = options.results or Path(folder) / "paper-stripes.h5"
        if options.results is None:
            subprocess.run([sys.executable, "-c", CLI, "run", str(STUDY), "-o", str(results)],
                           check=True, capture_output=True)  # fmt: skip
        times: dict[tuple[bool, str], list[float]] = {}
        for _ in range(options.repeat):
            for loaded in (False, True):
                with busy(loaded):
                    for name, (code, threads) in ROWS.items():
                        times.setdefault((loaded, name), []).append(timed(code, threads, results))
    print(f"machine: {platform.machine()}, {os.cpu_count()} CPUs, Python "
          f"{platform.python_version()}; median of {options.repeat} runs")  # fmt: skip
    print(f"{'machine':<8} {'how the threads are set':<24} {'time [s]':>9} {'/ one thread':>13}")
    for loaded in (False, True):
        one = statistics.median(times[(loaded, "one thread")])
        for name in ROWS:
            median = statistics.median(times[(loaded, name)])
            print(
                f"{'busy' if loaded else 'idle':<8} {name:<24} {median:9.2f} {median / one:13.2f}"
            )


if __name__ == "__main__":
    main()
