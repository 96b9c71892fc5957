"""Matching recorded seeds: per record the time, the fit on the dense grid, PGA, final velocity and
displacement, and the ground motion and durations beside the seed's (linearly scaled to a_g·S).

Run from the repository root:
    .venv/bin/python benchmarks/bench_seeds.py [--records 1,3,4 --components a | --all]
    .venv/bin/python benchmarks/bench_seeds.py --seeds FILE... [--units g] [--reqpy]

The target and settings are those of configs/records/seeds-fema-far-field-ec8-type1-C-ag0.6g.yaml
(EN 1998-1 type 1, ground C, a_g = 0.6 g, band 0.05–4 s, tolerance 10 %). The seeds are its ten
FEMA P695 far-field records (``pip install "rockbridge[fema]"``), others of the set
(``--records``, ``--components``, ``--all``: the 44), or files (``--seeds``). ``--reqpy`` also
matches each seed with REQPY (reqpy-M, Montejo; ``pip install reqpy-M``, not a dependency) and
checks its output with the same code.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from rockbridge_cli.config.loading import load  # noqa: E402
from rockbridge_cli.config.record_sets import RecordSetConfig  # noqa: E402
from rockbridge_cli.core.quantities import STANDARD_GRAVITY  # noqa: E402
from rockbridge_cli.motions import baseline, matching, seeds, spectral_fit  # noqa: E402
from rockbridge_cli.records.fema import read_fema_set  # noqa: E402
from rockbridge_cli.records.files import read_record  # noqa: E402
from rockbridge_cli.records.sets import compare_with_seed, match_settings  # noqa: E402
from rockbridge_cli.records.target import resolve_target  # noqa: E402

CONFIG = REPO / "configs" / "records" / "seeds-fema-far-field-ec8-type1-C-ag0.6g.yaml"


def chosen_seeds(args, config) -> list[tuple[str, float, np.ndarray]]:
    """(name, time step [s], acceleration [m/s²]) of each seed."""
    if args.seeds:
        return [(p.stem, r.time_step, r.acceleration)
                for p in args.seeds for r in [read_record(p, units=args.units)]]  # fmt: skip
    fema = config.seeds
    records = None if args.all else tuple(args.records or fema.records)
    components = ("a", "b") if args.all else tuple(args.components or fema.components)
    return [(r.name, r.time_step, r.acceleration)
            for r in read_fema_set("far-field", components, False, records)]  # fmt: skip


def reqpy(target, band, step: float, seed: np.ndarray) -> np.ndarray:
    import reqpy_M

    periods = np.geomspace(0.02, 5.0, 200)
    result = reqpy_M.generate_single_component_compatible_record(
        seed / STANDARD_GRAVITY, 1.0 / step, periods,
        target.evaluate(periods, extrapolate=True) / STANDARD_GRAVITY,
        T1PSA=band[0], T2PSA=band[1],
    )  # fmt: skip
    return np.asarray(result["sc"]) * STANDARD_GRAVITY


def row(name, tool, elapsed, matched, seed, target, band, resampled) -> str:
    fit = spectral_fit.measure_fit(matched.acceleration, matched.time_step, target.evaluate,
                                   band, target.damping)  # fmt: skip
    velocity, displacement = baseline.compute_final_motion(matched.acceleration,
                                                           matched.time_step)  # fmt: skip
    peak = np.max(np.abs(matched.acceleration)) / target.surface_pga
    change = compare_with_seed(matched, seed, target, resampled)
    new, old = change.record, change.seed
    return (
        f"{name:<7} {tool:<6} {elapsed:6.1f} {fit.min_ratio:6.3f} {fit.min_period:5.2f} "
        f"{fit.max_ratio:6.3f} {peak:8.5f} {abs(velocity) * 100:8.0e} "
        f"{abs(displacement) * 100:8.0e} {new.pgd:5.2f} {old.pgd:5.2f} {change.pgd_bound:5.2f} "
        f"{new.pgv:5.2f} {old.pgv:5.2f} {change.pgv_bound:5.2f} {new.d5_95 / old.d5_95:5.2f} "
        f"{new.d5_75 / old.d5_75:5.2f} {(new.arias_time - old.arias_time) / old.d5_95:+6.2f} "
        + (
            "ok"
            if change.ground_ok
            and abs(fit.min_ratio - 1.0) <= 0.1
            and fit.max_ratio <= 1.1
            and abs(new.d5_95 / old.d5_95 - 1.0) <= 0.25
            else "NO"
        )
        + (f"  {', '.join(change.flags)}" if change.flags else "")
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=lambda text: [int(x) for x in text.split(",")])
    parser.add_argument("--components", default=None, help="a, b or ab")
    parser.add_argument("--all", action="store_true", help="the 44 far-field components")
    parser.add_argument("--seeds", nargs="*", type=Path, default=[], help="seed files instead")
    parser.add_argument("--units", default=None, help="units of seed files that do not state them")
    parser.add_argument("--reqpy", action="store_true", help="also match with REQPY")
    args = parser.parse_args()
    config = load(RecordSetConfig, CONFIG)
    target, band = resolve_target(config), config.band
    settings = match_settings(config, target)
    tools = {"rb": lambda step, seed: seeds.match_seed(
        lambda p: target.evaluate(p, extrapolate=True), band, target.surface_pga, seed, step,
        settings, config.check_periods)}  # fmt: skip
    if args.reqpy:
        tools["REQPY"] = lambda step, seed: matching.MatchedRecord(
            reqpy(target, band, step, seed), step, 1, 0, float("nan"))  # fmt: skip
    print("dense grid:", spectral_fit.dense_periods(band, target.damping).size, "periods; "
          "PGD, PGV: matched, scaled seed, bound [m, m/s]; durations: matched/seed; "
          "Arias time: shift/D5-95 of the seed")  # fmt: skip
    print("seed    tool    time s   min    at s    max  PGA/agS   |v_end|  |d_end|   PGD  seed "
          "bound   PGV  seed bound D5-95 D5-75  T_A50")  # fmt: skip
    chosen = chosen_seeds(args, config)
    tools["rb"](chosen[0][1], chosen[0][2][:2000])  # compile the kernels outside the timing
    for name, step, acceleration in chosen:
        samples, new_step = seeds.resample_for_band(acceleration, step, band[0])
        resampled = None if new_step == step else (step, new_step)
        for tool, run in tools.items():
            start = time.perf_counter()
            matched = run(new_step, samples)
            elapsed = time.perf_counter() - start
            print(row(name, tool, elapsed, matched, samples, target, band, resampled), flush=True)


if __name__ == "__main__":
    main()
