"""What compiling the kernels costs: a fresh numba cache, each kernel variant in turn.

Each round is one fresh process on an empty numba cache of its own (``NUMBA_CACHE_DIR`` and a
kernel lock in a temporary folder) that makes the kernels of a run ready (`study.kernels.prepare`)
as a first run on a fresh install does: those of an analysis, then those of a vertical ground
motion, of a bridge with devices, and of a bridge with devices under a vertical motion. It prints
the wall and CPU seconds of each variant, and the kernels whose own compile takes longest: numba's
compile events, each kernel's time less that of the kernels compiled inside it (what `inlined`
kernels cost is in their callers'), summed over the variants.

A compile is typing and lowering in Python more than LLVM's optimization (``NUMBA_OPT=1`` gave
the same time as the default 3 on 2026-11-29), and its time follows the code typed: an `inlined`
kernel is typed again at each of its call sites.

    python benchmarks/bench_compile.py [--repeat 1] [--top 12]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

VARIANTS = {
    "analysis": {},
    "vertical ground motion": {"vertical": True},
    "devices": {"devices": True},
    "devices, vertical motion": {"devices": True, "vertical": True},
}
"""The kernel variants a run may need, in the order a warm-up compiles them: `kernels.prepare`'s
arguments."""

ROUND = """
import json, sys, time
from numba.core import event
sys.path.insert(0, sys.argv[1])  # this benchmark, for VARIANTS and own_times
from bench_compile import VARIANTS, own_times

events = []

class Recorder(event.Listener):
    def on_start(self, started):
        events.append((started.data["dispatcher"].py_func.__qualname__, time.perf_counter()))

    def on_end(self, ended):
        events.append((None, time.perf_counter()))

event.register("numba:compile", Recorder())
from rockbridge_cli.study import kernels

kernels.own_process()
variants = {}
for name, arguments in VARIANTS.items():
    wall, cpu = time.perf_counter(), time.process_time()
    kernels.prepare(**arguments)
    variants[name] = {"wall": time.perf_counter() - wall, "cpu": time.process_time() - cpu}
print(json.dumps({"variants": variants, "kernels": own_times(events)}))
"""


def own_times(events: list[tuple[str | None, float]]) -> dict[str, float]:
    """Each kernel's own compile time [s] from numba's nested compile events, in order: a name and
    a time where one starts, None and a time where the last started ends; a kernel's time less
    that of the kernels compiled inside it, summed over its compiles."""
    own: dict[str, float] = {}
    open_: list[list] = []  # name, start, time of the kernels inside
    for name, at in events:
        if name is not None:
            open_.append([name, at, 0.0])
            continue
        name, start, inside = open_.pop()
        spent = at - start
        own[name] = own.get(name, 0.0) + spent - inside
        if open_:
            open_[-1][2] += spent
    return own


def compile_round() -> dict:
    """One round in a fresh process on an empty cache: the variants' times and the kernels'."""
    from bench_study import child  # its failure stops with the round's own last lines

    with tempfile.TemporaryDirectory() as folder:
        environment = os.environ | {"NUMBA_CACHE_DIR": folder, "TMPDIR": folder}
        out = child([sys.executable, "-c", ROUND, str(REPO / "benchmarks")], env=environment)
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=1, help="rounds; the table gives medians")
    parser.add_argument("--top", type=int, default=12, help="kernels listed")
    options = parser.parse_args()
    if options.repeat < 1:
        parser.error("--repeat: at least 1")
    print(f"{time.strftime('%Y-%m-%d %H:%M %Z')}; {platform.machine()}, {os.cpu_count()} CPUs "
          f"(load average {' '.join(f'{v:.1f}' for v in os.getloadavg())}), Python "
          f"{platform.python_version()}; median of {options.repeat} round(s)")  # fmt: skip
    rounds = [compile_round() for _ in range(options.repeat)]
    print(f"{'kernel variant':<26} {'wall [s]':>9} {'CPU [s]':>9}")
    for name in VARIANTS:
        wall = statistics.median(r["variants"][name]["wall"] for r in rounds)
        cpu = statistics.median(r["variants"][name]["cpu"] for r in rounds)
        print(f"{name:<26} {wall:>9.1f} {cpu:>9.1f}")
    total = [sum(v["cpu"] for v in r["variants"].values()) for r in rounds]
    print(f"{'all four':<26} {'':>9} {statistics.median(total):>9.1f}")
    names = {name for r in rounds for name in r["kernels"]}
    own = {name: statistics.median(r["kernels"].get(name, 0.0) for r in rounds) for name in names}
    print(f"\n{'kernel (its own compile, over the four)':<44} {'wall [s]':>9}")
    for name, spent in sorted(own.items(), key=lambda item: -item[1])[: options.top]:
        print(f"{name:<44} {spent:>9.1f}")


if __name__ == "__main__":
    main()
