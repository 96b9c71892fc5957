"""Time of an overturning spectrum, end to end, as a user runs it.

Each row runs ``rockbridge run configs/studies/overturning-block.yaml`` (100 × 100 frequencies ×
amplitudes of a one-sine pulse on a block, then the bisection of its overturning boundary, at
`default` fidelity, no histories) in a fresh process into a new results file, and
``rockbridge plot overturning`` on it; it prints the wall time from the command to the closed
file, the analyses run (the map's and the bisection's), the integration time summed over them,
the CPU time of the command and its workers (which, unlike the wall time, other processes on a
shared machine barely change: a run takes at least CPU / workers), and the figure's time. With
``--repeat R`` every worker count runs R times, in turn, and the medians are printed (a shared
VM's speed drifts between runs). The numba kernels are compiled (or loaded from its cache)
before anything is timed.

    python benchmarks/bench_spectrum.py [--workers 1 2] [--repeat 3] [--study PATH]
"""

from __future__ import annotations

import argparse
import os
import platform
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
STUDY = REPO / "configs" / "studies" / "overturning-block.yaml"
ROCKBRIDGE = [sys.executable, "-c", "from rockbridge_cli.cli import main; main()"]


def run(study: Path, workers: int, folder: Path) -> dict[str, float]:
    """One timed run of the study and of its figure, each in a fresh process."""
    output = folder / f"spectrum-{workers}.h5"
    before = _children_cpu()
    started = time.perf_counter()
    done = subprocess.run(
        [*ROCKBRIDGE, "run", str(study), "--workers", str(workers), "-o", str(output),
         "--overwrite"], capture_output=True, text=True, check=True,
    )  # fmt: skip
    wall = time.perf_counter() - started
    cpu = _children_cpu() - before
    analyses = re.search(r"analyses: (\d+)", done.stdout)
    solve = re.search(r"([\d.]+) s solving", done.stdout)
    started = time.perf_counter()
    subprocess.run([*ROCKBRIDGE, "plot", "overturning", str(output), "-o",
                    str(folder / "spectrum.png")], capture_output=True, check=True)  # fmt: skip
    return {
        "wall": wall,
        "analyses": float(analyses.group(1)) if analyses else float("nan"),
        "solve": float(solve.group(1)) if solve else float("nan"),
        "cpu": cpu,
        "figure": time.perf_counter() - started,
    }


def _children_cpu() -> float:
    """User and system CPU time of the finished child processes (and theirs) [s]."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--study", type=Path, default=STUDY)
    arguments = parser.parse_args()
    subprocess.run([sys.executable, "-m", "rockbridge_cli.warmup"], check=True)
    print(f"# {platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()}, "
          f"{arguments.study.name}, {time.strftime('%Y-%m-%d')}")  # fmt: skip
    runs: dict[int, list[dict[str, float]]] = {n: [] for n in arguments.workers}
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(arguments.repeat):
            for workers in arguments.workers:
                runs[workers].append(run(arguments.study, workers, Path(folder)))
    print("| workers | analyses | run, command to file [s] | solving, summed [s] | CPU [s] | "
          "figure [s] |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    for workers, found in runs.items():
        median = {key: statistics.median(r[key] for r in found) for key in found[0]}
        spread = f" ({min(r['wall'] for r in found):.1f}–{max(r['wall'] for r in found):.1f})"
        print(f"| {workers} | {median['analyses']:.0f} | {median['wall']:.1f}"
              f"{spread if len(found) > 1 else ''} | {median['solve']:.1f} | "
              f"{median['cpu']:.1f} | {median['figure']:.1f} |")  # fmt: skip


if __name__ == "__main__":
    main()
