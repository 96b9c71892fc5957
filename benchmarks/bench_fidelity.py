"""Speed/accuracy of the fidelity presets: time per analysis and error of each Fig. 9 peak.

Runs every preset (and a few tolerances or steps around them) on the paper's three studied bridges
× a record set (the bundled EC8 set if it is there, else synthetic records), and prints for each:
the median and total wall time of the integration (`Response.solve_time_s`, no start-up), the
median number of steps, and the maximum relative error of each Fig. 9 peak against ``reference``.
With ``--plot FILE`` it also draws the work-precision diagram.

A second table gives, per preset, what an ensemble of records asks: the time per analysis and
per record sample, the worst and median error of an analysis's peaks, the error of the ensemble
mean of each Fig. 9 quantity, and the share of failure verdicts that differ from ``reference``
with the records at 1× and 2× the design PGA and within 1 % of each record's own capacity (the
lowest factor at which ``reference`` fails, found by scan and bisection), where verdicts are most
fragile.

A third table puts each preset on extreme geometries (h̄ = 8, very slender and very stocky piers,
a frame without abutments) under the same records at twice their intensity.

Records: ``--records DIR`` reads any folder (a set `generate-records` wrote, or plain record
files: PEER .AT2, rockbridge or two-column text; ``--units`` for files that do not state them);
``--fema SET`` reads a FEMA P695 set (``pip install "rockbridge[fema]"``); ``--pga G`` scales
every record to that peak first (the design a_g·S of the studied bridges is 0.69 g).

    python benchmarks/bench_fidelity.py [--records DIR | --fema far-field] [--pga 0.69]
        [--units g] [--plot docs/work-precision.png]
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.core.analysis import analyze
from rockbridge_cli.errors import InputError

REPO = Path(__file__).resolve().parents[1]
BRIDGES = [REPO / "configs" / "bridges" / f"studied-hbar{h}.yaml" for h in ("1.00", "1.25", "2.00")]
BUNDLED = REPO / "records" / "ec8-type1-C-ag0.6g"
PEAKS = ("u_deck", "v_deck", "theta_deck", "theta1", "theta2")
VARIANTS = [  # (label, preset, knob overrides)
    ("reference", "reference", {}),
    ("default rtol=1e-9", "default", {"rtol": 1e-9, "atol": 1e-14}),
    ("default", "default", {}),
    ("default, exact kinematics", "default", {"kinematics": "exact"}),
    ("default atol=1e-11", "default", {"atol": 1e-11}),
    ("default rtol=1e-7", "default", {"rtol": 1e-7, "atol": 1e-12}),
    ("default rtol=1e-6", "default", {"rtol": 1e-6, "atol": 1e-11}),
    ("default event_tol=1e-11", "default", {"event_tol": 1e-11}),
    ("default event_tol=1e-9", "default", {"event_tol": 1e-9}),
    ("default, peaks at steps", "default", {"turning_points": False}),
    ("fast", "fast", {}),
    ("fast, turning points", "fast", {"turning_points": True}),
    ("fast rtol=1e-4", "fast", {"rtol": 1e-4, "atol": 1e-7}),
    ("paper dt=5e-4", "paper", {"step": 5e-4, "max_step": 5e-4}),
    ("paper", "paper", {}),
    ("paper dt=2e-3", "paper", {"step": 2e-3, "max_step": 2e-3}),
    ("paper, exact kinematics", "paper", {"kinematics": "exact"}),
]


def synthetic_records(count: int = 10, duration: float = 30.0, dt: float = 0.01):
    """Broadband sines under an envelope, PGA 0.69 g, when no bundled set exists."""
    t = np.arange(0.0, duration + dt / 2, dt)
    records = []
    for seed in range(count):
        rng = np.random.default_rng(seed)
        acc = sum(
            rng.uniform(0.5, 1) * np.sin(2 * np.pi * rng.uniform(0.3, 6) * t + rng.uniform(0, 6.3))
            for _ in range(40)
        )
        acc = acc * np.minimum(1, t / 2) * np.exp(-np.maximum(0, t - 15) / 4)
        records.append((f"synthetic{seed + 1:02d}", dt, 0.69 * 9.81 * acc / np.abs(acc).max()))
    return records


def load_records(args) -> tuple[str, list[tuple[str, float, np.ndarray]]]:
    """The records the options name, as (name, time step [s], acceleration [m/s²])."""
    from rockbridge_cli.records.fema import read_fema_set
    from rockbridge_cli.records.files import read_record
    from rockbridge_cli.records.set_files import MANIFEST, read_record_set

    if args.fema:
        name, records = f"FEMA P695 {args.fema}", read_fema_set(args.fema)
    elif args.records is None and not (BUNDLED / MANIFEST).exists():
        return "synthetic", synthetic_records()
    else:
        folder = args.records or BUNDLED
        name = folder.name
        if _is_a_set(folder / MANIFEST):
            records = read_record_set(folder)
        else:  # a plain folder, or one whose manifest.json is not a record set's
            files = sorted(p for p in folder.iterdir() if p.suffix.lower() in RECORD_SUFFIXES)
            records = [read_record(p, units=args.units, time_step=args.time_step) for p in files]
    scale = [1.0 if args.pga is None else args.pga * G / r.peak_acceleration for r in records]
    return name, [
        (r.name, r.time_step, f * r.acceleration) for r, f in zip(records, scale, strict=True)
    ]


def _is_a_set(manifest: Path) -> bool:
    """Whether a folder's ``manifest.json`` is a record set's (a JSON object with its
    ``records``), rather than a file of the user's own."""
    import json

    try:
        found = json.loads(manifest.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return isinstance(found, dict) and "records" in found


RECORD_SUFFIXES = (".txt", ".at2", ".csv", ".dat", ".acc")
"""Files of a plain folder read as records."""

G = 9.80665
"""Standard gravity, the g of ``--pga`` [m/s²]."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=Path, help="a folder of records (default: bundled)")
    parser.add_argument("--fema", choices=("far-field", "near-field-pulse", "near-field-no-pulse"),
                        help="a FEMA P695 set instead")  # fmt: skip
    parser.add_argument("--units", choices=("g", "m/s2", "cm/s2"), help="of files without")
    parser.add_argument("--time-step", type=float, help="of one-column files [s]")
    parser.add_argument("--pga", type=float, help="scale every record to this PGA first [g]")
    parser.add_argument("--plot", type=Path, help="write the work-precision diagram here")
    args = parser.parse_args()
    try:
        set_name, records = load_records(args)
    except InputError as exc:  # one line, as the command line says it
        raise SystemExit(f"error: {exc}") from None
    bridges = [load_bridge(path) for path in BRIDGES]
    analyzed = [b.to_bridge() for b in bridges]

    # Warm up the compiled kernels (compilation is not part of any timing).
    name, dt, acc = records[0]
    for _, preset, overrides in VARIANTS:
        analyze(analyzed[0], acc[:500], dt, preset, **overrides)

    results = {}
    for label, preset, overrides in VARIANTS:
        results[label] = [
            analyze(bridge, acc, dt, preset, **overrides)
            for bridge in analyzed
            for _, dt, acc in records
        ]
    reference = results["reference"]

    print(f"records: {set_name} ({len(records)}), bridges: {len(analyzed)}, "
          f"analyses per row: {len(reference)}")  # fmt: skip
    header = f"{'variant':<26}{'median ms':>10}{'total s':>9}{'steps':>7}"
    header += "".join(f"{'err ' + p:>15}" for p in PEAKS) + f"{'vs ref':>8}"
    print(header)
    ref_median = statistics.median(r.solve_time_s for r in reference)
    rows = []
    for label, responses in results.items():
        median = statistics.median(r.solve_time_s for r in responses)
        total = sum(r.solve_time_s for r in responses)
        steps = statistics.median(r.steps for r in responses)
        errors = [max_relative_error(responses, reference, peak) for peak in PEAKS]
        rows.append((label, median, max(errors)))
        line = f"{label:<26}{median * 1e3:>10.2f}{total:>9.3f}{steps:>7.0f}"
        line += "".join(f"{e:>15.1e}" for e in errors) + f"{ref_median / median:>7.1f}x"
        print(line)
    if args.plot:
        plot(rows, args.plot)
    ensemble(records, analyzed, results)
    verdicts(records)


ENSEMBLE_PRESETS = ("reference", "default", "fast", "paper")
FIG9 = (*PEAKS, "dcr_backfill")
"""The Fig. 9 quantities whose ensemble means the second table compares."""


def ensemble(records, analyzed, results) -> None:
    """The second table: time, errors and failure verdicts per preset over the ensemble."""
    reference = results["reference"]
    samples = [acc.size for bridge in analyzed for _, _, acc in records]
    design = [0.69 * G / np.abs(acc).max() for bridge in analyzed for _, _, acc in records]
    near = [capacity(bridge, acc, dt) for bridge in analyzed for _, dt, acc in records]
    cases = {  # the factor of each bridge × record, and the margins around it
        "1x": (design, (1.0,)), "2x": ([2.0 * f for f in design], (1.0,)),
        "±1%": (near, (0.99, 1.01)),
    }  # fmt: skip
    expected = {
        case: verdicts_at(analyzed, records, "reference", *how) for case, how in cases.items()
    }
    print(f"\nensemble: {len(reference)} analyses; failure verdicts that differ from reference "
          "at 1x and 2x the design PGA 0.69 g and at 0.99x and 1.01x each record's "
          "capacity")  # fmt: skip
    print(f"{'preset':<10}{'ms/analysis':>12}{'µs/sample':>10}{'worst err':>10}"
          f"{'median err':>11}" + "".join(f"{'mean ' + q:>17}" for q in FIG9)
          + "".join(f"{'differ ' + case:>12}" for case in cases))  # fmt: skip
    for preset in ENSEMBLE_PRESETS:
        responses = results[preset]
        times = [r.solve_time_s for r in responses]
        per_sample = statistics.median(t / n for t, n in zip(times, samples, strict=True))
        worst = [
            max(relative(r, ref, p) for p in PEAKS)
            for r, ref in zip(responses, reference, strict=True)
        ]
        means = [abs(mean(responses, q) / mean(reference, q) - 1.0) for q in FIG9]
        differ = []
        for case, how in cases.items():
            found = verdicts_at(analyzed, records, preset, *how)
            count = sum(a != b for a, b in zip(found, expected[case], strict=True))
            differ.append(f"{count}/{len(found)}")
        print(f"{preset:<10}{statistics.median(times) * 1e3:>12.2f}{per_sample * 1e6:>10.3f}"
              f"{max(worst):>10.1e}{statistics.median(worst):>11.1e}"
              + "".join(f"{m:>17.1e}" for m in means)
              + "".join(f"{d:>12}" for d in differ))  # fmt: skip


def relative(response, reference, peak: str) -> float:
    """|peak − reference| / |reference| of one analysis (0 where the reference is 0)."""
    ref = abs(reference.peaks[peak][0])
    return abs(response.peaks[peak][0] - reference.peaks[peak][0]) / ref if ref > 1e-12 else 0.0


def mean(responses, quantity: str) -> float:
    """The ensemble mean of a Fig. 9 quantity."""
    if quantity == "dcr_backfill":
        return float(np.mean([r.dcr_backfill for r in responses]))
    return float(np.mean([abs(r.peaks[quantity][0]) for r in responses]))


def capacity(bridge, acc, dt, tolerance: float = 0.0025) -> float:
    """The lowest factor of a record at which ``reference`` ends in a failure: scanned by 0.25
    from 0.25, then bisected to ``tolerance`` (relative); NaN if none up to 10."""
    fails = lambda factor: analyze(bridge, factor * acc, dt, "reference").failure_mode != "none"  # noqa: E731
    low, high = 0.0, 0.25
    while not fails(high):
        low, high = high, high + 0.25
        if high > 10.0:
            return float("nan")
    while high - low > tolerance * high:
        middle = 0.5 * (low + high)
        low, high = (low, middle) if fails(middle) else (middle, high)
    return high


def verdicts_at(analyzed, records, preset, factors, margins) -> list[str]:
    """The failure mode of each bridge × record scaled by its factor times each margin (records
    without a factor, NaN, are left out)."""
    pairs = [(bridge, dt, acc) for bridge in analyzed for _, dt, acc in records]
    return [
        analyze(bridge, margin * factor * acc, dt, preset).failure_mode
        for (bridge, dt, acc), factor in zip(pairs, factors, strict=True)
        if np.isfinite(factor)
        for margin in margins
    ]


EXTREMES = {  # name: (bridge config, changes to its YAML data)
    "h̄ = 8": ("studied-hbar1.00", {"piers": {"width": 2.6, "heights": [26.0, 26.0 / 8]}}),
    "slender, H/B = 26": ("studied-hbar1.25", {"piers": {"width": 1.0, "heights": [26.0, 20.8]}}),
    "stocky, H/B = 4": ("studied-hbar1.25", {"piers": {"width": 6.5, "heights": [26.0, 20.8]}}),
    "frame": ("studied-hbar1.25", {"abutments": None}),
}
"""Extreme geometries of the verdict table, made from the studied bridges."""

PRESETS_COMPARED = ("default", "fast", "paper")


def extreme_models():
    import yaml

    from rockbridge_cli.config.bridge import BridgeConfig

    for name, (source, changes) in EXTREMES.items():
        data = yaml.safe_load((REPO / "configs" / "bridges" / f"{source}.yaml").read_text())
        data.update(changes)
        yield name, BridgeConfig.model_validate({k: v for k, v in data.items() if v is not None})


def verdicts(records, intensity: float = 2.0) -> None:
    analyzed = [config.to_bridge() for _, config in extreme_models()]
    runs = {
        preset: [
            analyze(bridge, intensity * acc, dt, preset)
            for bridge in analyzed
            for _, dt, acc in records
        ]
        for preset in ("reference", *PRESETS_COMPARED)
    }
    reference = runs["reference"]
    failures = sum(r.failure_mode != "none" for r in reference)
    print(f"\nextreme geometries ({', '.join(EXTREMES)}) × the records at {intensity:g}× "
          f"({len(reference)} analyses, {failures} failures at reference)")  # fmt: skip
    print(f"{'preset':<10}{'verdicts differ':>17}{'median err θ1':>15}{'worst err θ1':>14}"
          f"{'err of mean θ1':>16}")  # fmt: skip
    mean_reference = np.mean([r.peaks["theta1"][0] for r in reference])
    for preset in PRESETS_COMPARED:
        responses = runs[preset]
        differ = sum(
            a.failure_mode != b.failure_mode for a, b in zip(responses, reference, strict=True)
        )
        errors = [
            abs(a.peaks["theta1"][0] - b.peaks["theta1"][0]) / b.peaks["theta1"][0]
            for a, b in zip(responses, reference, strict=True)
            if a.failure_mode == b.failure_mode and b.peaks["theta1"][0] > 0
        ]
        mean = np.mean([r.peaks["theta1"][0] for r in responses])
        print(f"{preset:<10}{f'{differ}/{len(reference)}':>17}{np.median(errors):>15.1e}"
              f"{max(errors):>14.1e}{abs(mean / mean_reference - 1):>16.1e}")  # fmt: skip


def max_relative_error(responses, reference, peak: str) -> float:
    """Largest |peak − reference| / |reference| over the analyses; the symmetric bridge's θ_deck
    (identically zero) is skipped."""
    errors = [
        abs(r.peaks[peak][0] - ref.peaks[peak][0]) / abs(ref.peaks[peak][0])
        for r, ref in zip(responses, reference, strict=True)
        if abs(ref.peaks[peak][0]) > 1e-12
    ]
    return max(errors) if errors else 0.0


LABEL_PLACES = {
    "fast": ((0, 11), "center"),
    "paper": ((0, -12), "center"),
    "default": ((8, -6), "left"),
    "default, exact kinematics": ((8, 0), "left"),
    "reference": ((8, 0), "left"),
}
"""Where each named point's label goes (offset in points, alignment), clear of the others."""


def plot(rows, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FixedLocator, NullFormatter, ScalarFormatter

    fig, ax = plt.subplots(figsize=(7, 4.5))
    markers = {"reference": "*", "default": "o", "fast": "s", "paper": "^"}
    for label, median, error in rows:
        preset = label.split()[0].rstrip(",")
        named = label == preset or label == "default, exact kinematics"
        ax.loglog(median * 1e3, max(error, 1e-16), markers[preset], color="k", markersize=8,
                  markerfacecolor="k" if label == preset else "white")  # fmt: skip
        if named:  # variants unlabelled: the table beside the figure names them
            offset, align = LABEL_PLACES.get(label, ((8, -3), "left"))
            ax.annotate(label, (median * 1e3, max(error, 1e-16)), textcoords="offset points",
                        xytext=offset, ha=align, va="center", fontsize=8)  # fmt: skip
    ticks = [1, 2, 5, 10, 20, 50, 100]
    ax.xaxis.set_major_locator(FixedLocator(ticks))
    ax.xaxis.set_major_formatter(ScalarFormatter())
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlim(1.0, 150.0)
    ax.axhline(1e-3, linestyle="--", color="0.5", linewidth=0.8)
    ax.annotate("target 1e-3", (140.0, 1.4e-3), ha="right", va="bottom", fontsize=7, color="0.4")
    ax.plot([], [], "o", color="k", label="preset")
    ax.plot([], [], "o", color="k", markerfacecolor="white", label="variant (see the table)")
    ax.legend(loc="lower left", frameon=False, fontsize=8)
    ax.set_xlabel("median integration time per 30 s analysis [ms]")
    ax.set_ylabel("max relative error of the Fig. 9 peaks [-]")
    ax.set_title("Work–precision of the fidelity presets")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=150)


if __name__ == "__main__":
    start = time.perf_counter()
    main()
    print(f"wall time {time.perf_counter() - start:.1f} s")
