"""Ground-motion benchmark: generating the paper's record set, and one response spectrum.

Run from the repository root:  .venv/bin/python benchmarks/bench_records.py
Prints the time to generate the ten records of configs/records/ec8-type1-C-ag0.6g.yaml (into a
temporary folder), the time of a 100-period spectrum of a 40 s record at 0.01 s, and the
EN 1998-1 §3.2.3.1.2 numbers of the generated set.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

from rockbridge_cli.config.loading import load
from rockbridge_cli.config.record_sets import RecordSetConfig
from rockbridge_cli.motions.baseline import compute_final_motion
from rockbridge_cli.motions.spectra import compute_psa
from rockbridge_cli.records.set_files import read_record_set
from rockbridge_cli.records.sets import generate_record_set

CONFIG = Path(__file__).parents[1] / "configs" / "records" / "ec8-type1-C-ag0.6g.yaml"


def time_spectrum(repeats: int = 20) -> float:
    """Median time of a 100-period PSA of a 40 s record at 0.01 s [s] (after a warm-up)."""
    record = np.random.default_rng(0).normal(size=4001)
    periods = np.geomspace(0.05, 4.0, 100)
    compute_psa(record, 0.01, periods)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        compute_psa(record, 0.01, periods)
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def main() -> None:
    spectrum = time_spectrum()
    config = load(RecordSetConfig, CONFIG)
    with tempfile.TemporaryDirectory() as folder:
        generate_record_set(config.model_copy(update={"count": 1}), folder)  # warm the caches
        report = generate_record_set(config, folder)
        motion = [
            compute_final_motion(r.acceleration, r.time_step) for r in read_record_set(folder)
        ]
    c = report.compliance
    rows = [
        ("generate the 10 records (s)", f"{report.wall_time:.2f}", "< 10"),
        ("PSA, 40 s record, 100 periods (ms)", f"{spectrum * 1e3:.1f}", "< 50"),
        ("per-record min ratio", f"{min(c.record_min_ratio):.3f}", ">= 0.90 (aim 0.95)"),
        ("per-record max ratio", f"{max(c.record_max_ratio):.3f}", "<= 1.10 (aim 1.05)"),
        ("mean ratio range", f"{c.mean_min_ratio:.3f}-{c.mean_max_ratio:.3f}", "0.97-1.03"),
        (
            "max |PGA/(a_g*S) - 1|",
            f"{max(abs(s.peak_acceleration / c.surface_pga - 1) for s in report.records):.1e}",
            "< 0.01",
        ),
        ("max |final velocity| (cm/s)", f"{max(abs(v) for v, _ in motion) * 100:.1e}", "< 1"),
        ("max |final displacement| (cm)", f"{max(abs(d) for _, d in motion) * 100:.1e}", "< 1"),
        ("EN 1998-1 §3.2.3.1.2", "compliant" if c.compliant else "NOT compliant", "compliant"),
    ]
    width = max(len(name) for name, _, _ in rows)
    print(f"{'quantity':<{width}}  {'value':>12}  target")
    for name, value, target in rows:
        print(f"{name:<{width}}  {value:>12}  {target}")


if __name__ == "__main__":
    main()
