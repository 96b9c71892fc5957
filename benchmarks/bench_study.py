"""Throughput of the study layer: what a study of N analyses costs end to end, and where.

Each row is one fresh process that loads a study of the paper's three bridges × N/3 record
entries (the ten bundled records, each listed several times under its own id) and runs it with
`run_study` into a new results file. It prints, per analysis:

- ``e2e``: wall time from the start of the study's loading to the closed results file;
- ``solve``: integration time (`Response.solve_time_s`) summed over the analyses;
- ``over``: e2e × workers − solve, the cost beyond the solve, per analysis;
- ``parent``, ``worker``: CPU time of the parent process (from the loaded study to the closed
  file: journal, progress, the results file) and of the workers (each loads the kernels from
  numba's cache, then runs its batches); their ratio is the ceiling on any number of cores:
  with N cores at most ``worker/parent`` of them stay busy;
- peak resident memory of the parent and of the largest worker;
- with ``--repeat R``, the medians of R runs of each row, the rows of one N run in turn (so that
  a drift of the host's speed, which reaches 1.5× between hours on a shared VM, hits them all),
  and the speed-up of each worker count over one worker: the median of the R pairs of runs.

The kernels are compiled (or loaded from numba's cache) before the rows are timed.

With ``--session`` each row's process loads the kernels before the clock starts, as a Python
session does that has analyzed before (a notebook, a script that runs study after study): the
forked workers inherit them, and a run's start is only the study's loading.

With ``--command`` each row is ``rockbridge run STUDY --workers N`` instead, as a user runs it
(its workers start while it loads the study), timed from outside the process: only e2e, total
and the speed-up are measured.

A second table times the bundled intensity studies end to end, as the manual runs them: the
multiple-stripe study and the IDA of the paper's bridges (``rockbridge run``, then
``rockbridge fragility``), each in a fresh process.

    python benchmarks/bench_study.py [--sizes 30 300 3000 10000] [--workers 1 2]
                                     [--fidelity default] [--histories none all] [--bridges 3]
                                     [--bundled paper-stripes paper-ida] [--repeat 1]
                                     [--command | --session]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py

REPO = Path(__file__).resolve().parents[1]
BRIDGES = [REPO / "configs" / "bridges" / f"studied-hbar{h}.yaml" for h in ("1.00", "1.25", "2.00")]
RECORDS = sorted((REPO / "records" / "ec8-type1-C-ag0.6g").glob("AR*.txt"))
CLI = "from rockbridge_cli.cli import entry; entry()"
NAMED = os.pathsep.join(filter(None, (os.environ.get("ROCKBRIDGE_PATHS"), str(REPO))))
ENV = os.environ | {"ROCKBRIDGE_PATHS": NAMED}
"""The generated rows' environment: their studies, written in temporary folders, name the
repository's bridges and records by absolute paths, which a study may reach only where the user
says so (docs/studies.md, "Paths in configs"). The bundled studies run in the user's
environment, as the manual runs them: they reach the records through the repository's
.rockbridge marker."""


def child(command: list[str], cwd: str | Path | None = None, env: dict | None = ENV) -> str:
    """Run ``command`` (a row's process) and return its output; where it fails, stop with the
    command's own last lines of error output, not a traceback of this script."""
    done = subprocess.run(command, capture_output=True, text=True, cwd=cwd, env=env)
    if done.returncode != 0:
        tail = "\n".join(done.stderr.strip().splitlines()[-5:])
        sys.exit(f"bench_study.py: a row's process failed (exit {done.returncode}) in "
                 f"{cwd or Path.cwd()}:\n{tail}")  # fmt: skip
    return done.stdout


ROW = """
import json, resource, sys, time
if sys.argv[3] == "session":  # as after an analysis: imported, the kernels loaded (forks inherit)
    import rockbridge_cli.config.study
    from rockbridge_cli.study import kernels
    kernels.prepare()
started = time.perf_counter()
from rockbridge_cli.config.study import load_study
from rockbridge_cli.study.run import run_study

def cpu(who):
    usage = resource.getrusage(who)
    return usage.ru_utime + usage.ru_stime

study = load_study(sys.argv[1])
loaded = time.perf_counter()
before = cpu(resource.RUSAGE_SELF)
report = run_study(study, workers=int(sys.argv[2]))
print(json.dumps({
    "n": report.total, "load": loaded - started, "e2e": time.perf_counter() - started,
    "solve": report.solve_time_s, "parent": cpu(resource.RUSAGE_SELF) - before,
    "worker": cpu(resource.RUSAGE_CHILDREN),
    "rss_parent": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    "rss_worker": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024,
    "size": report.output.stat().st_size / 2**20,
}))
"""


def write_study(
    folder: Path, analyses: int, histories: str, fidelity: str, bridges: int = len(BRIDGES)
) -> Path:
    """A study of ``bridges`` bridges × ``analyses / bridges`` record entries: the three studied
    bridges, each swept over ``bridges / 3`` end-joint gaps (0.06–0.24 m) beyond three."""
    variants = max(1, round(bridges / len(BRIDGES)))
    entries = max(1, analyses // (variants * len(BRIDGES)))
    lines = ["bridges:"] + [f"  - {path}" for path in BRIDGES]
    if variants > 1:
        lines += [f"sweep: {{fields: {{abutments.gap: {{start: 0.06, stop: 0.24, count: "
                  f"{variants}}}}}}}"]  # fmt: skip
    lines += ["records:", "  files:"]
    lines += [f"    - {{path: {RECORDS[i % len(RECORDS)]}, id: R{i:05d}}}" for i in range(entries)]
    lines += [f"fidelity: {fidelity}", f"output: {{path: {folder / 'out.h5'}, histories: "
              f"{histories}}}"]  # fmt: skip
    path = folder / f"study-{analyses}-{histories}-{bridges}.yaml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def measure(
    analyses: int,
    histories: str,
    workers: int,
    fidelity: str,
    bridges: int = len(BRIDGES),
    command: bool = False,
    session: bool = False,
) -> dict:
    with tempfile.TemporaryDirectory() as folder:
        study = write_study(Path(folder), analyses, histories, fidelity, bridges)
        if command:
            return measure_command(study, workers)
        out = child([sys.executable, "-c", ROW, str(study), str(workers), "session" * session])
    return json.loads(out)


def measure_command(study: Path, workers: int) -> dict:
    """``rockbridge run STUDY --workers N`` in a fresh process, timed from outside."""
    started = time.perf_counter()
    child([sys.executable, "-c", CLI, "run", str(study), "--workers", str(workers)])
    nan = float("nan")
    row = dict.fromkeys(("load", "solve", "parent", "worker", "rss_parent", "rss_worker"), nan)
    elapsed = time.perf_counter() - started
    output = study.parent / "out.h5"
    with h5py.File(output, "r") as file:
        analyses = len(file["peaks/bridge"])
    return row | {"n": analyses, "e2e": elapsed, "size": output.stat().st_size / 2**20}


def measure_bundled(name: str, workers: int) -> dict:
    """A bundled study run as the manual runs it, in a fresh folder: the run, then its fragility."""
    with tempfile.TemporaryDirectory() as folder:
        study = REPO / "configs" / "studies" / f"{name}.yaml"
        run = [sys.executable, "-c", ROW, str(study), str(workers), ""]
        row = json.loads(child(run, folder, env=None))
        started = time.perf_counter()
        child([sys.executable, "-c", CLI, "fragility", f"results/{name}.h5"], folder, env=None)
        row["fragility"] = time.perf_counter() - started
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[30, 300, 3000, 10000])
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--histories", nargs="+", default=["none", "all"])
    parser.add_argument("--fidelity", default="default")
    parser.add_argument("--bridges", type=int, default=len(BRIDGES), help="bridges of each "
                        "study: the three studied, each swept over gaps beyond three")  # fmt: skip
    parser.add_argument("--bundled", nargs="*", default=["paper-stripes", "paper-ida"])
    parser.add_argument("--repeat", type=int, default=1, help="runs of each row, interleaved; "
                        "the table gives their medians")  # fmt: skip
    parser.add_argument("--command", action="store_true",
                        help="time `rockbridge run` as a user runs it, not run_study")  # fmt: skip
    parser.add_argument("--session", action="store_true", help="the kernels loaded before "
                        "the clock starts, as in a session that has analyzed before")  # fmt: skip
    options = parser.parse_args()

    measure(3, "none", 1, options.fidelity)  # compile the kernels into numba's cache
    machine = f"{platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()}"
    print(
        f"machine: {machine}; fidelity {options.fidelity}; histories at 0.01 s; "
        f"{options.bridges} bridges" + "; kernels loaded before the clock" * options.session
    )
    print(
        f"{'N':>6} {'hist':>4} {'wrk':>3} | {'e2e':>7} {'solve':>7} {'over':>7} "
        f"{'parent':>7} {'worker':>7} {'ceiling':>7} | {'load':>6} {'total':>7} | "
        f"{'RSS par':>7} {'RSS wrk':>7} {'file':>7}"
    )
    print(f"{'':>6} {'':>4} {'':>3} | {'ms/analysis':^39} {'':>7} | {'s':^14} | {'MiB':^23}")
    for analyses in options.sizes:
        for histories in options.histories:
            runs: dict[int, list[dict]] = {workers: [] for workers in options.workers}
            for _ in range(options.repeat):  # interleaved: a drift of the host's speed hits all
                for workers in options.workers:
                    runs[workers].append(measure(analyses, histories, workers, options.fidelity,
                                                 options.bridges, options.command,
                                                 options.session))  # fmt: skip
            for workers, rows in runs.items():
                row = {key: statistics.median(r[key] for r in rows) for key in rows[0]}
                n = row["n"]
                ms = {key: 1e3 * row[key] / n for key in ("e2e", "solve", "parent", "worker")}
                over = ms["e2e"] * workers - ms["solve"]
                ceiling = (row["worker"] / row["parent"]) if workers > 1 else float("nan")
                print(
                    f"{n:>6} {histories:>4} {workers:>3} | {ms['e2e']:7.3f} {ms['solve']:7.3f} "
                    f"{over:7.3f} {ms['parent']:7.3f} {ms['worker']:7.3f} {ceiling:7.1f} | "
                    f"{row['load']:6.2f} {row['e2e']:7.2f} | {row['rss_parent']:7.0f} "
                    f"{row['rss_worker']:7.0f} {row['size']:7.1f}",
                    flush=True,
                )
            if 1 in runs and len(runs) > 1:
                for workers in sorted(runs)[1:]:
                    ratios = [a["e2e"] / b["e2e"] for a, b in zip(runs[1], runs[workers],
                                                                  strict=True)]  # fmt: skip
                    print(f"{'':>6} {histories:>4} {workers:>3} | speed-up over 1 worker "
                          f"{statistics.median(ratios):.2f} (each pair of runs: "
                          f"{min(ratios):.2f}-{max(ratios):.2f})", flush=True)  # fmt: skip
    if options.bundled:
        print(f"\n{'bundled study':<14} {'wrk':>3} | {'analyses':>8} {'run':>7} {'solve':>7} "
              f"{'ms/an.':>7} | {'fragility':>9}")  # fmt: skip
        print(f"{'':<14} {'':>3} | {'':>8} {'s':^15} {'':>7} | {'s':^9}")
    for name in options.bundled:
        for workers in options.workers:
            row = measure_bundled(name, workers)
            print(
                f"{name:<14} {workers:>3} | {row['n']:>8} {row['e2e']:7.2f} {row['solve']:7.2f} "
                f"{1e3 * row['e2e'] * workers / row['n']:7.2f} | {row['fragility']:9.2f}",
                flush=True,
            )


if __name__ == "__main__":
    main()
