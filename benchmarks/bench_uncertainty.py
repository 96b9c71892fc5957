"""The scale a sampled study creates (issue 37): a saltelli design of six bridge fields at n base
samples, n·(6 + 2) bridges of the studied bridge h̄ = 1.25, each under the ten bundled records
(n = 512: 4096 bridges, 40 960 analyses), run end to end as a user runs it, then its
sensitivity indices and figure.

Each row is ``rockbridge run STUDY`` in a fresh process (kernels compiled beforehand), timed from
outside, with the peak resident memory of its largest process (the parent or a worker:
``getrusage(RUSAGE_CHILDREN)`` of the command's tree), and then ``rockbridge sensitivity`` and
``rockbridge plot sensitivity`` of its file, each with its time and peak memory. The results
file's size is printed too.

    python benchmarks/bench_uncertainty.py [--size 512] [--fidelity fast default] [--workers 2]
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
CLI = [sys.executable, "-c", "from rockbridge_cli.cli import entry; entry()"]

STUDY = """bridges: [{bridge}]
records: {{set: {records}}}
uncertainty:
  design: saltelli
  size: {size}
  seed: 1
  fields:
    abutments.gap: {{distribution: uniform, low: 0.06, high: 0.18}}
    abutments.stiffness: {{distribution: lognormal, median: 132.0e6, beta: 0.3}}
    abutments.damping: {{distribution: lognormal, median: 48.0e6, beta: 0.3}}
    abutments.ultimate_displacement: {{distribution: lognormal, median: 0.10, beta: 0.3}}
    rocking_restitution:
      {{distribution: truncated-normal, mean: 0.94, std: 0.03, low: 0.85, high: 0.99}}
    abutments.pounding.restitution: {{distribution: uniform, low: 0.4, high: 0.8}}
fidelity: {fidelity}
output: {{histories: none}}
"""


def timed(command: list[str], folder: Path) -> tuple[float, float]:
    """Wall time [s] of a command and the peak resident memory of its largest process [MiB]
    (Linux reports ru_maxrss in KiB; each command runs in a fresh child, so the maximum seen so
    far by RUSAGE_CHILDREN is reset by running it in its own ``python -c`` wrapper)."""
    wrapper = (
        "import resource, subprocess, sys; "
        "subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL); "
        "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)"
    )
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", wrapper, *command], cwd=folder, check=True,
                          capture_output=True, text=True, env={**os.environ,
                          "ROCKBRIDGE_PATHS": "/"})  # fmt: skip
    return time.perf_counter() - start, int(done.stdout.strip().splitlines()[-1]) / 1024


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=512, help="n, a power of two")
    parser.add_argument("--fidelity", nargs="+", default=["fast", "default"])
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    subprocess.run(
        [
            *CLI,
            "analyze",
            str(REPO / "configs/bridges/studied-hbar1.25.yaml"),
            str(REPO / "records/ec8-type1-C-ag0.6g/AR01.txt"),
        ],
        check=True,
        capture_output=True,
    )  # fmt: skip  (compile the kernels)
    bridges = args.size * 8
    print(f"# saltelli, 6 fields, n = {args.size}: {bridges} bridges × 10 records = "
          f"{bridges * 10} analyses; {args.workers} workers; {platform.node()}, "
          f"{os.cpu_count()} CPUs, Python {platform.python_version()}")  # fmt: skip
    print(f"{'fidelity':<9} {'run [s]':>8} {'analyses/s':>11} {'peak MiB':>9} {'file MiB':>9} "
          f"{'sensitivity [s]':>16} {'MiB':>6} {'plot [s]':>9} {'MiB':>6}")  # fmt: skip
    for fidelity in args.fidelity:
        with tempfile.TemporaryDirectory() as name:
            folder = Path(name)
            study = folder / "study.yaml"
            study.write_text(STUDY.format(
                bridge=REPO / "configs/bridges/studied-hbar1.25.yaml",
                records=REPO / "records/ec8-type1-C-ag0.6g", size=args.size, fidelity=fidelity,
            ), encoding="utf-8")  # fmt: skip
            run, run_memory = timed([*CLI, "run", "study.yaml", "-o", "s.h5", "--workers",
                                     str(args.workers)], folder)  # fmt: skip
            size = (folder / "s.h5").stat().st_size / 2**20
            sens, sens_memory = timed([*CLI, "sensitivity", "s.h5"], folder)
            plot, plot_memory = timed([*CLI, "plot", "sensitivity", "s.h5", "-o", "s.png"], folder)
            print(f"{fidelity:<9} {run:8.1f} {bridges * 10 / run:11.0f} {run_memory:9.0f} "
                  f"{size:9.1f} {sens:16.1f} {sens_memory:6.0f} {plot:9.1f} "
                  f"{plot_memory:6.0f}")  # fmt: skip
    print(f"# resource limits: {resource.getrlimit(resource.RLIMIT_AS)}")


if __name__ == "__main__":
    main()
