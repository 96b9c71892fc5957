"""Seed matching against REQPY: time per record, spectral fit, PGA and final drift, same seeds and
target (EN 1998-1 type 1, ground C, a_g = 0.6 g, 5 %, band 0.05–4 s).

Run from the repository root:  .venv/bin/python benchmarks/bench_seeds.py [--seeds FILE...]

REQPY (reqpy-M, Montejo) is an optional comparison, not a dependency: ``pip install reqpy-M``;
without it only rockbridge's rows are printed. The seeds are recorded motions given with
``--seeds`` (any format rockbridge reads; ``--units`` where a file does not state them), or
by default ten recorded-like stand-ins (`tests/test_seeds.py`: no recorded motion ships with the
repository). Both outputs are checked by the same spectrum code (`motions.spectra`, Nigam–Jennings,
exact for piecewise-linear records) at 100 log-spaced periods over the band.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))  # the recorded-like stand-ins of the seed tests

from test_seeds import recorded_like  # noqa: E402

from rockbridge_cli.core.quantities import STANDARD_GRAVITY  # noqa: E402
from rockbridge_cli.motions import baseline, ec8, matching, spectra  # noqa: E402
from rockbridge_cli.records.files import read_record  # noqa: E402

BAND = (0.05, 4.0)
DESIGN = 0.6 * 9.81  # a_g [m/s²], as the paper's set
PGA = DESIGN * ec8.get_spectrum_shape(1, "C").soil_factor


def seeds(paths: list[Path], units: str | None) -> list[tuple[str, float, np.ndarray]]:
    """(name, time step [s], acceleration [m/s²]) of each seed."""
    if paths:
        return [(p.stem, r.time_step, r.acceleration)
                for p in paths for r in [read_record(p, units=units)]]  # fmt: skip
    return [(f"like{k:02d}", step, STANDARD_GRAVITY * recorded_like(k, step, 30.0))
            for k in range(10) for step in [0.005 if k % 2 else 0.01]]  # fmt: skip


def measure(acceleration: np.ndarray, step: float) -> tuple[float, float, float, float, float]:
    """min and max of spectrum/target over the band, PGA/(a_g·S), final |v| [m/s], |d| [m]."""
    check = np.geomspace(*BAND, 100)
    ratio = spectra.compute_psa(acceleration, step, check, 0.05) / ec8.compute_elastic_spectrum(
        check, 1, "C", design_acceleration=DESIGN
    )
    velocity, displacement = baseline.compute_final_motion(acceleration, step)
    peak = np.abs(acceleration).max() / PGA
    return ratio.min(), ratio.max(), peak, abs(velocity), abs(displacement)


def rockbridge(step: float, seed: np.ndarray) -> np.ndarray:
    periods = matching.compute_matching_periods(BAND, 100, step)
    target = ec8.compute_elastic_spectrum(periods, 1, "C", design_acceleration=DESIGN,
                                          extrapolate=True)  # fmt: skip
    return matching.match_seed(periods, target, PGA, seed, step, band=BAND).acceleration


def reqpy(step: float, seed: np.ndarray) -> np.ndarray:
    import reqpy_M

    periods = np.geomspace(0.02, 5.0, 200)
    target = ec8.compute_elastic_spectrum(periods, 1, "C", design_acceleration=DESIGN,
                                          extrapolate=True) / STANDARD_GRAVITY  # fmt: skip
    result = reqpy_M.generate_single_component_compatible_record(
        seed / STANDARD_GRAVITY, 1.0 / step, periods, target, T1PSA=BAND[0], T2PSA=BAND[1]
    )
    return np.asarray(result["sc"]) * STANDARD_GRAVITY


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", nargs="*", type=Path, default=[], help="recorded seed files")
    parser.add_argument("--units", default=None, help="units of seed files that do not state them")
    args = parser.parse_args()
    try:
        import reqpy_M  # noqa: F401

        tools = {"rockbridge": rockbridge, "REQPY": reqpy}
    except ImportError:
        print("REQPY not installed (pip install reqpy-M): rockbridge only")
        tools = {"rockbridge": rockbridge}
    chosen = seeds(args.seeds, args.units)
    rockbridge(chosen[0][1], chosen[0][2][:2000])  # compile the kernels outside the timing
    print(f"{'seed':<10} {'tool':<11} {'time s':>7} {'min':>6} {'max':>6} {'PGA/agS':>8} "
          f"{'|v_end| m/s':>12} {'|d_end| m':>10}")  # fmt: skip
    totals: dict[str, list[float]] = {name: [] for name in tools}
    for name, step, seed in chosen:
        for tool, run in tools.items():
            start = time.perf_counter()
            matched = run(step, seed)
            elapsed = time.perf_counter() - start
            totals[tool].append(elapsed)
            low, high, peak, velocity, displacement = measure(matched, step)
            print(f"{name:<10} {tool:<11} {elapsed:7.2f} {low:6.3f} {high:6.3f} {peak:8.4f} "
                  f"{velocity:12.1e} {displacement:10.1e}")  # fmt: skip
    for tool, times in totals.items():
        print(f"{tool}: median {np.median(times):.2f} s per record")


if __name__ == "__main__":
    main()
