"""The integrator's step: CPU per record sample of the solve alone, at each preset asked.

The FEMA P695 far-field components (the first ``--records`` of the 44), each scaled to the
design PGA (0.69 g), under the paper's three studied bridges, histories none: for each preset,
the record samples, the steps per sample, the rejected share, and the CPU time of
`core.analysis.solve` (the compiled integration and its call) per sample, the best of
``--passes`` passes over the ensemble in one process (the kernels loaded before the first).

A fingerprint (SHA-256 of every analysis's peaks, events, failure and solver error, in order)
closes each row: two checkouts that print the same fingerprint gave the same numbers, bit for
bit. To compare two trees, run the benchmark in each, alternately, in the same minutes: the CPU
time of the same build varies by ±20 % from one minute to the next on a shared machine.

    python benchmarks/bench_step.py [--fidelity fast default] [--records 20] [--passes 15]
"""

from __future__ import annotations

import argparse
import hashlib
import os
import platform
import time
from pathlib import Path

from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.core import analysis
from rockbridge_cli.core.fidelity import resolve
from rockbridge_cli.records.fema import read_fema_set

REPO = Path(__file__).resolve().parents[1]
BRIDGES = [REPO / "configs" / "bridges" / f"studied-hbar{h}.yaml" for h in ("1.00", "1.25", "2.00")]
PGA = 0.69 * 9.80665
"""The design a_g·S of the studied bridges [m/s²]."""


def row(preset: str, records: list, bridges: list, passes: int) -> str:
    """The table's row of one preset."""
    fidelity = resolve(preset)
    prepared = [analysis.prepare(bridge, fidelity) for bridge in bridges]
    motions = [
        (step, analysis.ground_motion(acc, step, fidelity, bridges[0].model.g).acc)
        for step, acc in records
    ]
    analysis.solve(prepared[0], motions[0][1], motions[0][0])  # the kernels, loaded or compiled
    best, fingerprint, samples, steps, rejected = float("inf"), hashlib.sha256(), 0, 0, 0
    for done in range(passes):
        cpu = 0.0
        for shared in prepared:
            for step, acc in motions:
                start = time.process_time()
                result, _ = analysis.solve(shared, acc, step)
                cpu += time.process_time() - start
                if done == 0:
                    samples, steps, rejected = (
                        samples + acc.size, steps + result.steps, rejected + result.rejected
                    )  # fmt: skip
                    for part in (result.peaks, result.events):
                        fingerprint.update(part.tobytes())
                    fingerprint.update(f"{result.failure} {result.error}".encode())
        best = min(best, cpu)
    return (
        f"{preset:10s} {len(prepared) * len(motions):9d} {samples:9d} {steps / samples:12.3f}"
        f" {rejected / steps:9.2%} {best / samples * 1e6:11.3f}  {fingerprint.hexdigest()[:16]}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fidelity", nargs="+", default=["fast", "default"])
    parser.add_argument("--records", type=int, default=20, help="FEMA far-field components")
    parser.add_argument("--passes", type=int, default=15)
    args = parser.parse_args()
    records = [
        (record.time_step, PGA * record.acceleration / record.peak_acceleration)
        for record in read_fema_set("far-field")[: args.records]
    ]
    bridges = [load_bridge(path).to_bridge() for path in BRIDGES]
    when = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    print(
        f"{when}; {platform.machine()}, {os.cpu_count()} CPUs, Python "
        f"{platform.python_version()}; {REPO}; best of {args.passes} passes"
    )
    print("preset      analyses   samples steps/sample  rejected  CPU µs/sample  fingerprint")
    for preset in args.fidelity:
        print(row(preset, records, bridges, args.passes), flush=True)
    print(f"load average {' '.join(f'{x:.1f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
