"""Where a worker's time goes, per analysis: the solve, the Python call around it, building the
response, packing, the journal's commits, and the parent's share.

Each row is one fresh process that runs a study of the paper's three bridges × N/3 record
entries (`bench_study.write_study`: histories none) with `run_study` on W local workers, as
`bench_study.py` does, at each fidelity asked. Before the study runs, the process wraps timers
around the functions a worker calls for every analysis; the workers, forked from it, inherit
them, and each writes its sums after each batch into a file of its own, which the row adds up.
Nothing in the package changes: the timers exist only in the benchmark's process.

Per analysis it prints the wall time and the CPU time (``time.process_time``) of

- ``solve``: the integration (`core.solver.integrate`, as `Response.solve_time_s` times it), or
  on the compiled batch the call that integrates a bridge's cells (`core.batch.integrate_batch`);
- ``around the solve``: the rest of `core.analysis.analyze` but the response — its checks, the
  fidelity, the ground motion with its tail, the kinematics (a bridge's tables, built once per
  worker and bridge), the devices' laws; on the lean path of a study that keeps no histories,
  the rest of `study.work._lean` (the cell's record, the same checks and ground motion, the
  devices' rows; what a bridge's analyses share is prepared once per batch), and on the
  compiled batch the rest of `study.work._integrated_together` (preparing the bridge, joining
  the records, what each cell says); the cells' records and checks there fall in ``rest of the
  batch``;
- ``response``: the `Response` built from the integration (`core.analysis._response`), or on
  the lean path its `core.analysis.summary` alone, on the compiled batch `core.batch.summaries`;
- ``result row``: the peak row and events kept for the file (`AnalysisResult.from_response`;
  none on the lean path);
- ``packing``: `AnalysisResult.pack`, or on the lean path `results.packing.pack_summary`, on
  the compiled batch `results.packing.pack_summaries`;
- ``journal``: the batch's commit (`study.journal.Journal.add`), shared over its analyses;
- ``rest of the batch``: the rest of a batch (`executors.worker.run_batch`: the kernels'
  check, each cell's record, the outcomes);

then the worker's CPU outside its batches (its start: importing numba and scipy and loading the
kernels; the study's description, which the workers compute; receiving batches and sending back
outcomes) and the parent's CPU (from the loaded study to the closed file: the journal read back,
the results file, the progress), each per analysis, and the share of the run's CPU each took.
The timers cost a few microseconds per analysis (measured and printed), within the rows they time.

On a shared machine the wall times depend on the other processes; the CPU times much less.
With ``--repeat R`` each row runs R times (the fidelities in turn) and the table gives medians.
``--profile`` instead runs the study on one worker (in the process itself) under cProfile and
prints the functions that took the most time of their own. ``--start`` prints where a
worker's start goes, a cold run's time, and the teardown of a process that has loaded the
kernels, with its heap as is and frozen (as the ``rockbridge`` command ends).

    python benchmarks/bench_worker.py [--analyses 1500] [--fidelity fast default] [--workers 2]
                                      [--repeat 1] [--profile [--top 25]] [--start]
"""

from __future__ import annotations

import argparse
import cProfile
import functools
import importlib
import json
import os
import platform
import pstats
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from bench_study import child, measure, write_study

TIMED = (
    ("solve", "rockbridge_cli.core.analysis", "integrate"),
    ("solve", "rockbridge_cli.core.batch", "integrate_batch"),
    ("analyze", "rockbridge_cli.core.analysis", "analyze"),
    ("analyze", "rockbridge_cli.study.work", "_lean"),
    ("analyze", "rockbridge_cli.study.work", "_integrated_together"),
    ("response", "rockbridge_cli.core.analysis", "_response"),
    ("response", "rockbridge_cli.core.analysis", "summary"),
    ("response", "rockbridge_cli.core.batch", "summaries"),
    ("result row", "rockbridge_cli.results.packing:AnalysisResult", "from_response"),
    ("packing", "rockbridge_cli.results.packing:AnalysisResult", "pack"),
    ("packing", "rockbridge_cli.study.work", "pack_summary"),
    ("packing", "rockbridge_cli.study.work", "pack_summaries"),
    ("journal", "rockbridge_cli.study.journal:Journal", "add"),
    ("batch", "rockbridge_cli.study.executors.worker", "run_batch"),
)
"""What is timed: a name, where the function lives (a module, or ``module:class``), its name.
A name may time several functions: those of the per-analysis path and of the two paths of a
study that keeps no histories: the lean path (`study.work._lean`: the analysis,
`core.analysis.summary` in place of the `Response`, `results.packing.pack_summary` in place of
the result row and its packing) and the compiled batch (`study.work._integrated_together`: a
bridge's cells of a batch, `core.batch.integrate_batch` their solve, `core.batch.summaries`
their summaries, `results.packing.pack_summaries` their packing); a function the package does
not have (an older checkout's) is left out, and a call within a call of the same name counts once
(`_response` calls `summary`)."""

SUMS: dict[str, list[float]] = {}
"""Per timed name in this process: wall time [s], CPU time [s], calls."""

_RUNNING: set[str] = set()
"""The timed names being called."""


def timed(name: str, function: Callable) -> Callable:
    """``function`` with its wall and CPU time added to ``SUMS[name]`` at each call."""
    sums = SUMS.setdefault(name, [0.0, 0.0, 0])

    @functools.wraps(function)  # its name and module: a pickled reference finds the wrapper
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        if name in _RUNNING:  # within a call of the same name, which times it
            return function(*args, **kwargs)
        _RUNNING.add(name)
        wall, cpu = time.perf_counter(), time.process_time()
        try:
            return function(*args, **kwargs)
        finally:
            sums[0] += time.perf_counter() - wall
            sums[1] += time.process_time() - cpu
            sums[2] += 1
            _RUNNING.discard(name)

    return wrapper


def install(folder: Path) -> None:
    """Time a worker's batches (`TIMED`'s last); in a worker, at its first batch, wrap the other
    timers of `TIMED` around their functions (there, not in the parent, which would import the
    compiled kernels before it forks its workers). After each batch a worker writes its `SUMS`
    to ``folder/<pid>.json``."""
    from rockbridge_cli.study.executors import local, worker

    batch = timed("batch", worker.run_batch)

    @functools.wraps(worker.run_batch)  # the parent submits it by its name and module
    def timed_batch(cells: Any) -> Any:
        if len(SUMS) == 1:  # this worker's first batch
            wrap(TIMED[:-1])
        outcomes = batch(cells)
        path = folder / f"{os.getpid()}.json"
        path.with_suffix(".tmp").write_text(json.dumps(SUMS))
        path.with_suffix(".tmp").replace(path)
        return outcomes

    worker.run_batch = local.run_batch = timed_batch


def wrap(functions: tuple[tuple[str, str, str], ...]) -> None:
    """Wrap a timer around each function of ``functions`` (as `TIMED` names them)."""
    for name, where, attribute in functions:
        module_name, _, class_name = where.partition(":")
        owner = importlib.import_module(module_name)
        owner = getattr(owner, class_name) if class_name else owner
        function = owner.__dict__.get(attribute)
        if function is None:  # not in this checkout of the package
            continue
        if isinstance(function, classmethod):
            setattr(owner, attribute, classmethod(timed(name, function.__func__)))
        else:
            setattr(owner, attribute, timed(name, function))


def timer_cost() -> float:
    """What one timed call costs beyond the call itself [s]: both clocks read twice."""
    plain = timed("cost", lambda: None)
    calls = 20000
    started = time.perf_counter()
    for _ in range(calls):
        plain()
    SUMS.pop("cost")
    return (time.perf_counter() - started) / calls


def run_row(study: str, workers: int) -> dict:
    """The row's process: run ``study`` on ``workers`` workers with the timers; its sums."""
    import resource

    from rockbridge_cli.config.study import load_study
    from rockbridge_cli.study.run import run_study

    def cpu(who: int) -> float:
        usage = resource.getrusage(who)
        return usage.ru_utime + usage.ru_stime

    with tempfile.TemporaryDirectory() as folder:
        install(Path(folder))
        loaded = load_study(study)
        started, before = time.perf_counter(), cpu(resource.RUSAGE_SELF)
        report = run_study(loaded, workers=workers)
        elapsed, parent = time.perf_counter() - started, cpu(resource.RUSAGE_SELF) - before
        sums: dict[str, list[float]] = {}
        for path in Path(folder).glob("*.json"):
            for name, values in json.loads(path.read_text()).items():
                sums[name] = [a + b for a, b in zip(sums.get(name, [0, 0, 0]), values, strict=True)]
    return {"n": report.total, "e2e": elapsed, "parent": parent, "sums": sums,
            "worker": cpu(resource.RUSAGE_CHILDREN), "timer": timer_cost()}  # fmt: skip


def split(row: dict) -> dict[str, tuple[float, float]]:
    """A row's components per analysis, (wall, CPU) [µs]; the timed functions nest (`TIMED`):
    analyze holds the solve and the response, a batch all the others."""
    sums, n = row["sums"], row["n"]

    def own(name: str, *inner: str) -> tuple[float, float]:
        return tuple(  # type: ignore[return-value]
            1e6 * (sums[name][k] - sum(sums[i][k] for i in inner)) / n for k in (0, 1)
        )

    batches = 1e6 * sums["batch"][1] / n
    outside = 1e6 * row["worker"] / n - batches
    nan = float("nan")
    return {
        "solve": own("solve"),
        "around the solve": own("analyze", "solve", "response"),
        "response": own("response"),
        "result row": own("result row"),
        "packing": own("packing"),
        "journal": own("journal"),
        "rest of the batch": own("batch", "analyze", "result row", "packing", "journal"),
        "worker outside batches": (nan, outside),
        "parent": (nan, 1e6 * row["parent"] / n),
    }


def table(rows: dict[str, dict], workers: int) -> None:
    """Print the split of each fidelity's row side by side."""
    splits = {fidelity: split(row) for fidelity, row in rows.items()}
    names = list(next(iter(splits.values())))
    head = " | ".join(f"{f:^26}" for f in rows)
    print(f"{'per analysis':<24} | {head}")
    print(f"{'':<24} | " + " | ".join(f"{'wall µs':>8} {'CPU µs':>8} {'CPU %':>7}" for _ in rows))
    for name in names:
        cells = []
        for parts in splits.values():
            total = sum(cpu for _, cpu in parts.values())
            wall, cpu = parts[name]
            wall_text = "–" if wall != wall else f"{wall:.0f}"
            cells.append(f"{wall_text:>8} {cpu:8.0f} {100 * cpu / total:6.1f}%")
        print(f"{name:<24} | " + " | ".join(cells))
    cells = []
    for fidelity, row in rows.items():
        total = sum(cpu for _, cpu in splits[fidelity].values())
        cells.append(f"{1e6 * row['e2e'] * workers / row['n']:8.0f} {total:8.0f} {'100%':>7}")
    print(f"{'all (wall: e2e × W)':<24} | " + " | ".join(cells))
    print(", ".join(f"{f}: {row['n']} analyses in {row['e2e']:.2f} s, "
                    f"{row['n'] / row['e2e']:.0f} an./s" for f, row in rows.items()))  # fmt: skip
    timer = max(row["timer"] for row in rows.values())
    calls = max(  # per analysis; a batch's and a commit's are shared by its analyses
        sum(
            count for name, (_, _, count) in row["sums"].items() if name not in ("batch", "journal")
        )
        / row["n"]
        for row in rows.values()
    )
    print(f"the timers: {1e6 * timer:.1f} µs a call, ≈ {1e6 * timer * calls:.0f} µs an analysis "
          "(included above)")  # fmt: skip


def profile(study: Path, top: int) -> None:
    """Run ``study`` on one worker (this process) under cProfile; print the ``top`` functions
    by their own time."""
    from rockbridge_cli.config.study import load_study
    from rockbridge_cli.study import kernels
    from rockbridge_cli.study.run import run_study

    loaded = load_study(study)
    kernels.prepare()  # loaded before the profile: it times the analyses, not the start
    profiler = cProfile.Profile()
    profiler.runcall(run_study, loaded, workers=1)
    pstats.Stats(profiler).sort_stats("tottime").print_stats(top)


def median_row(rows: list[dict]) -> dict:
    """The medians of repeated rows, sum by sum."""
    sums = {name: [statistics.median(r["sums"][name][k] for r in rows) for k in range(3)]
            for name in rows[0]["sums"]}  # fmt: skip
    keys = ("n", "e2e", "parent", "worker", "timer")
    return {key: statistics.median(r[key] for r in rows) for key in keys} | {"sums": sums}


START = """
import json, sys, time
from rockbridge_cli.config.bridge import load_bridge  # the parent's modules, which a fork inherits
from rockbridge_cli.config.study import load_study
from rockbridge_cli.study.executors import LocalPool
models = [load_bridge(path).to_bridge().model for path in sys.argv[1:]]
clock = [time.perf_counter()]
import numba
clock.append(time.perf_counter())
import rockbridge_cli.core.analysis, rockbridge_cli.warmup
clock.append(time.perf_counter())
from rockbridge_cli.study import kernels
kernels.own_process()  # as a worker (`executors.worker.start_worker`)
kernels.prepare(compiling=False)
clock.append(time.perf_counter())
from rockbridge_cli.core.tables import tabulated
for model in models:
    tabulated(model)
clock.append(time.perf_counter())
scipy = sorted(m for m in sys.modules if m.startswith("scipy."))
print(json.dumps({"clock": clock, "scipy": scipy}))
"""
"""A worker's start, step by step, in a process that holds what a worker inherits from its
parent (the modules that load a study and start the pool): numba's import, the package's
compiled modules (scipy's too, where they import it), the kernels loaded from numba's cache as a
worker loads them (`study.kernels.own_process`), the tables of the bridges."""

STEPS = ("import numba", "import the kernels' modules", "load the kernels", "tables of 3 bridges")

TEARDOWN = """
import gc, sys, time
from rockbridge_cli.study import kernels
kernels.own_process()
kernels.prepare(compiling=False)
if sys.argv[1] == "frozen":
    gc.freeze()
print(time.time())
"""
"""A process that has loaded the kernels, as one that has analyzed ends: its objects left to the
garbage collector's passes at the interpreter's teardown (``as is``), or out of them
(``frozen``, `gc.freeze`, as the ``rockbridge`` command ends: `cli.entry`). It prints the
time at which its last statement ran; the teardown is from then to the process's end."""


def start(repeat: int) -> None:
    """Print where a worker's start goes (`START`, each step the median of ``repeat`` fresh
    processes), the wall time of a cold ``rockbridge run`` of a 3-analysis study on 1 and
    2 workers (from outside; ``bench_study.measure_command``), and a process's teardown once
    it has loaded the kernels, its heap as is and frozen (`teardown`), the medians of
    ``repeat``."""
    from bench_study import BRIDGES

    steps: list[list[float]] = [[] for _ in STEPS]
    commands: dict[int, list[float]] = {1: [], 2: []}
    for _ in range(repeat):
        out = json.loads(child([sys.executable, "-c", START, *map(str, BRIDGES)]))
        for k, (a, b) in enumerate(zip(out["clock"], out["clock"][1:], strict=False)):
            steps[k].append(b - a)
        for workers, times in commands.items():
            times.append(measure(3, "none", workers, "fast", command=True)["e2e"])
    print(
        f"a worker's start (median of {repeat} fresh processes); scipy modules it loaded: "
        f"{len(out['scipy'])} ({', '.join(out['scipy'][:6])}{' …' * (len(out['scipy']) > 6)})"
    )
    for name, times in zip(STEPS, steps, strict=True):
        print(f"{name:<30} {1e3 * statistics.median(times):7.0f} ms   "
              f"({1e3 * min(times):.0f}–{1e3 * max(times):.0f})")  # fmt: skip
    for workers, times in commands.items():
        print(
            f"{'rockbridge run, 3 analyses, ' + str(workers) + ' w.':<30} "
            f"{statistics.median(times):7.2f} s    ({min(times):.2f}–{max(times):.2f})"
        )
    for heap in ("as is", "frozen"):
        times = [teardown(heap) for _ in range(repeat)]
        print(f"{'teardown, the heap ' + heap:<30} {1e3 * statistics.median(times):7.0f} ms   "
              f"({1e3 * min(times):.0f}–{1e3 * max(times):.0f})")  # fmt: skip


def teardown(heap: str) -> float:
    """The teardown of a fresh process that has loaded the kernels (`TEARDOWN`), its heap ``as
    is`` or ``frozen``: from its last statement to its end, as this process sees it [s]."""
    done = float(child([sys.executable, "-c", TEARDOWN, heap]))
    return time.time() - done


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--analyses", type=int, default=1500)
    parser.add_argument("--fidelity", nargs="+", default=["fast", "default"])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--profile", action="store_true",
                        help="cProfile the first fidelity's study on one worker")  # fmt: skip
    parser.add_argument("--top", type=int, default=25, help="functions --profile prints")
    parser.add_argument("--start", action="store_true",
                        help="a worker's start, a cold run, a teardown")  # fmt: skip
    parser.add_argument("--row", nargs=2, help=argparse.SUPPRESS)  # a row's process: STUDY W
    options = parser.parse_args()
    if options.row:
        print(json.dumps(run_row(options.row[0], int(options.row[1]))))
        return
    if options.start:
        measure(3, "none", 1, "fast")  # compile the kernels into numba's cache
        start(options.repeat)
        return
    if options.workers < 2 and not options.profile:
        parser.error("--workers: at least 2 (with one, the parent analyzes; see --profile)")
    for fidelity in options.fidelity:
        measure(3, "none", 1, fidelity)  # compile the kernels into numba's cache
    print(f"{time.strftime('%Y-%m-%d %H:%M %Z')}; {platform.machine()}, {os.cpu_count()} CPUs "
          f"(load average {' '.join(f'{v:.1f}' for v in os.getloadavg())}), Python "
          f"{platform.python_version()}; {options.analyses} analyses, histories none, "
          + ("one worker under cProfile" if options.profile else
             f"{options.workers} workers; median of {options.repeat} run(s)"))  # fmt: skip
    with tempfile.TemporaryDirectory() as folder:
        studies = {}
        for fidelity in options.fidelity:  # each in a folder of its own: its output is out.h5
            (Path(folder) / fidelity).mkdir()
            studies[fidelity] = write_study(Path(folder) / fidelity, options.analyses, "none",
                                            fidelity)  # fmt: skip
        if options.profile:
            profile(studies[options.fidelity[0]], options.top)
            return
        runs: dict[str, list[dict]] = {f: [] for f in options.fidelity}
        for _ in range(options.repeat):  # interleaved: a drift of the host's speed hits all
            for fidelity, study in studies.items():
                out = child([sys.executable, __file__, "--row", str(study), str(options.workers)])
                runs[fidelity].append(json.loads(out.splitlines()[-1]))
    table({f: median_row(rs) for f, rs in runs.items()}, options.workers)


if __name__ == "__main__":
    main()
