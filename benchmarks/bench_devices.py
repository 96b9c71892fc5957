"""What the piers' devices cost: time per analysis of the h̄ = 1.25 studied bridge free-standing,
with a tendon in each pier, with two dampers at each pier's base, and with both (issue 41).

Each bridge runs the ten bundled EC8 records (`records/ec8-type1-C-ag0.6g`) at the `fast` and
`default` presets, after one untimed analysis that loads (or compiles) its kernels; the table
gives the median solve time of an analysis (`Response.solve_time_s`, no start-up), its ratio to
the free-standing bridge's, and the median number of steps.

    python benchmarks/bench_devices.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import statistics
from pathlib import Path

from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.core.analysis import analyze
from rockbridge_cli.core.bridge import Bridge
from rockbridge_cli.records.set_files import read_record_set

REPO = Path(__file__).resolve().parents[1]
BRIDGES = REPO / "configs" / "bridges"
RECORDS = REPO / "records" / "ec8-type1-C-ag0.6g"


def variants() -> list[tuple[str, Bridge]]:
    """The free-standing bridge and its restrained variants, as the bundled configs give them."""
    free = load_bridge(BRIDGES / "studied-hbar1.25.yaml").to_bridge()
    tendons = load_bridge(BRIDGES / "studied-hbar1.25-tendons.yaml").to_bridge()
    dampers = load_bridge(BRIDGES / "studied-hbar1.25-dampers.yaml").to_bridge()
    both = Bridge(free.model, devices=tendons.devices + dampers.devices)
    return [("free-standing", free), ("2 tendons", tendons), ("4 dampers", dampers),
            ("2 tendons + 4 dampers", both)]  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="timings of each analysis [-]")
    args = parser.parse_args()
    records = list(read_record_set(RECORDS))
    print(f"{'preset':8} {'bridge':24} {'median solve [ms]':>18} {'× free':>7} {'steps':>7}")
    for preset in ("fast", "default"):
        base = None
        for label, bridge in variants():
            analyze(bridge, records[0].acceleration, records[0].time_step, preset)  # kernels
            times, steps = [], []
            for record in records:
                runs = [
                    analyze(bridge, record.acceleration, record.time_step, preset, histories=False)
                    for _ in range(args.repeat)
                ]
                times.append(min(run.solve_time_s for run in runs))
                steps.append(runs[0].steps)
            median = statistics.median(times)
            base = base or median
            print(f"{preset:8} {label:24} {1e3 * median:18.2f} {median / base:7.2f} "
                  f"{statistics.median(steps):7.0f}")  # fmt: skip


if __name__ == "__main__":
    main()
