"""Record-selection benchmark: `rockbridge select-records` on the FEMA P695 far-field example
(44 components) and on all three FEMA P695 sets (100 components), cold and warm.

Run from the repository root (needs ``pip install ".[fema]"``):
    .venv/bin/python benchmarks/bench_selection.py [CONFIG]

Each row is a fresh process. *Cold*: a new, empty numba cache (``NUMBA_CACHE_DIR``), so the
spectra kernel (`motions.spectra`) compiles, as on the first run after an install that skipped
``python -m rockbridge_cli.warmup``; *warm*: the same cache again, the kernel loaded. Printed, in
CPU time (the process's own, user + system): the imports, reading the pool, the pool's spectra on
the selection grid (the compile included when cold), then `select_record_set` as the command
runs it (the pool read again, its spectra again with the kernel compiled, the choice, the dense
check and the writing), and the whole process; the wall time beside it, and the load average,
since the machine may be shared.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

REPO = Path(__file__).resolve().parents[1]
CONFIG = REPO / "configs" / "records" / "select-fema-far-field-ec8-type1-C.yaml"
ALL_FEMA = ["far-field", "near-field-pulse", "near-field-no-pulse"]
SPECTRA = "the pool's spectra"

CHILD = """
import json, sys, time
started = time.perf_counter()
cpu = time.process_time()
from pathlib import Path
import numpy as np
from rockbridge_cli.config.loading import load
from rockbridge_cli.config.selection import SelectionConfig
from rockbridge_cli.motions import spectra
from rockbridge_cli.records.pool import read_pool
from rockbridge_cli.records.selection import select_record_set
parts = {"imports": time.process_time() - cpu}
request = load(SelectionConfig, Path(sys.argv[1])).request()
mark = time.process_time()
pool = read_pool(request.fema, request.folders)
parts["read the pool"] = time.process_time() - mark
usable = [c for c in pool if not c.lowest_usable_frequency > 1.0 / request.periods[1]]
grid = np.geomspace(*request.periods, request.period_count)
mark = time.process_time()
for c in usable:
    spectra.compute_psa(c.record.acceleration, c.record.time_step, grid, request.target.damping)
parts["the pool's spectra"] = time.process_time() - mark
mark = time.process_time()
report = select_record_set(request, sys.argv[2])
parts["select_record_set"] = time.process_time() - mark
print(json.dumps({"parts": parts, "pool": len(pool), "usable": len(usable),
                  "chosen": [c.record.name for c in report.chosen],
                  "wall": time.perf_counter() - started}))
"""


def run(config: Path, cache: Path, out: Path) -> dict:
    """One fresh process selecting by ``config`` into ``out`` with numba's cache in ``cache``:
    its parts (CPU [s]), its whole CPU and wall time [s]."""
    environment = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "PYTHONPATH": str(REPO)}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", CHILD, str(config), str(out)], env=environment,
                          capture_output=True, text=True, check=True)  # fmt: skip
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    found = json.loads(done.stdout.strip().splitlines()[-1])
    found["cpu"] = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    found["process wall"] = wall
    found["load"] = os.getloadavg()[0]
    return found


def main() -> None:
    config = Path(sys.argv[1]) if len(sys.argv) > 1 else CONFIG
    with tempfile.TemporaryDirectory() as folder:
        every = Path(folder) / "all-fema.yaml"
        data = yaml.safe_load(config.read_text(encoding="utf-8"))
        every.write_text(yaml.safe_dump({**data, "pool": {"fema_p695": ALL_FEMA}}), "utf-8")
        rows = []
        for name, chosen in ((config.name, config), ("all three FEMA P695 sets", every)):
            cache = Path(folder) / f"numba-{len(rows)}"
            for state in ("cold", "warm"):
                out = Path(folder) / f"set-{len(rows)}"
                rows.append((name, state, run(chosen, cache, out)))
    print(f"{'pool':<44} {'numba':<5} {'cands':>5} {'imports':>8} {'read':>6} {'spectra':>8} "
          f"{'select':>7} {'process':>8} {'wall':>6} {'load':>5}")  # fmt: skip
    for name, state, row in rows:
        parts = row["parts"]
        print(f"{name:<44} {state:<5} {row['usable']:>5} {parts['imports']:>8.2f} "
              f"{parts['read the pool']:>6.2f} {parts[SPECTRA]:>8.2f} "
              f"{parts['select_record_set']:>7.2f} {row['cpu']:>8.2f} {row['process wall']:>6.1f} "
              f"{row['load']:>5.1f}")  # fmt: skip
    print("CPU seconds (process: the whole child, user + system); wall seconds; load: the 1-min "
          "load average after the row; select: select_record_set, the kernel compiled")  # fmt: skip


if __name__ == "__main__":
    main()
