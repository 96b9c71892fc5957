"""Small studies for the tests of the end-to-end job (config, runner, results, CLI, figures).

The records are synthetic, short and strong enough to rock the studied bridges: a sine burst under
a Gaussian envelope, 6 s at 0.01 s, peak 5.0 and 4.0 m/s² (0.51 g and 0.41 g), well above the
onset thresholds of the studied bridges, 0.10–0.15 g (docs/model.md §10). They are written with
`records.files.write_record`, so the files state their units and time step.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

from rockbridge_cli.records.files import Record, write_record

REPO = Path(__file__).resolve().parents[1]
BRIDGES = REPO / "configs" / "bridges"
STUDIED = ("studied-hbar1.00", "studied-hbar2.00")

RECORDS = {"R1": (5.0, 1.0), "R2": (4.0, 0.7)}
"""Record id → (peak acceleration [m/s²], period of the burst [s])."""

TIME_STEP = 0.01  # [s]
DURATION = 6.0  # [s]

SLENDER_BLOCK = "name: slender block\npiers: {width: 0.4, heights: [4.0]}\n"
"""A free-standing 0.4 m × 4 m block (α = 0.1 rad, p = 2.7 rad/s): R1's 0.51 g, 1 s burst
overturns it."""

VOLATILE = {"created", "finished", "solve_time_s", "wall_time_s"}
"""Attributes and peak columns that differ between two runs of the same study (timings)."""


def burst(peak: float, period: float) -> np.ndarray:
    """A sine burst under a Gaussian envelope centred at 2.5 s, scaled to ``peak`` [m/s²]."""
    t = np.arange(0.0, DURATION, TIME_STEP)
    signal = np.sin(2.0 * np.pi * t / period) * np.exp(-(((t - 2.5) / 1.5) ** 2))
    return peak * signal / np.abs(signal).max()


def write_records(folder: Path, names=tuple(RECORDS)) -> dict[str, Path]:
    """Write the records into ``folder``; returns id → file."""
    folder.mkdir(parents=True, exist_ok=True)
    files = {}
    for name in names:
        files[name] = folder / f"{name}.txt"
        write_record(files[name], Record(name, TIME_STEP, burst(*RECORDS[name])))
    return files


def write_study(
    folder: Path,
    bridges=STUDIED,
    records=tuple(RECORDS),
    extra: str = "",
    name: str = "study.yaml",
    bridge_files: tuple[Path, ...] = (),
) -> Path:
    """A study of the given bridge configs (then ``bridge_files``, any bridge YAML files) ×
    records in ``folder``; ``extra`` is appended YAML."""
    write_records(folder, records)
    paths = [BRIDGES / f"{b}.yaml" for b in bridges] + list(bridge_files)
    lines = ["bridges:"] + [f"  - {p.as_posix()}" for p in paths]
    lines += ["records:", "  files:"] + [f"    - path: {r}.txt" for r in records]
    path = folder / name
    path.write_text("\n".join(lines) + "\n" + extra, encoding="utf-8")
    return path


STRIPE_LEVELS = (0.3, 0.6, 0.9, 1.2, 1.6, 2.0, 2.6, 3.4)
"""Stripes of the synthetic stripe studies [g]."""


def stripes_table(capacities: dict[str, float]) -> dict[str, np.ndarray]:
    """A synthetic stripe study's peak table at `STRIPE_LEVELS` (pga_g): each record (id →
    capacity [g]) reaches gap closure and backfill_50 at and above its capacity (``dcr_backfill``
    1 there, else 0), never a failure; the levels and capacities are the expected fit's data."""
    rows = [(r, x, float(x >= c)) for r, c in capacities.items() for x in STRIPE_LEVELS]
    return {
        "bridge": np.array(["b"] * len(rows)), "status": np.array(["ok"] * len(rows)),
        "base_record": np.array([r for r, _, _ in rows]),
        "record": np.array([f"{r}+{x:g}g" for r, x, _ in rows]),
        "intensity": np.array([x for _, x, _ in rows]),
        "dcr_backfill": np.array([d for _, _, d in rows]),
        "failure_mode": np.array(["none"] * len(rows)),
    }  # fmt: skip


def contents(path: Path) -> dict[str, tuple]:
    """Every group and dataset of an HDF5 file with its attributes and data, timings left out.

    Values are compared as bytes, so NaN equals NaN and floats must match exactly.
    """
    found: dict[str, tuple] = {}

    def canonical(value):
        array = np.asarray(value)
        if array.dtype.kind in "OSU":
            return tuple(v.decode() if isinstance(v, bytes) else str(v) for v in array.ravel())
        return (array.dtype.str, array.shape, array.tobytes())

    def visit(name: str, node) -> None:
        attrs = {k: canonical(v) for k, v in node.attrs.items() if k not in VOLATILE}
        data = None
        if isinstance(node, h5py.Dataset) and name.rsplit("/", 1)[-1] not in VOLATILE:
            data = canonical(node[()])
        found[name] = (attrs, data)

    with h5py.File(path, "r") as file:
        visit("/", file)
        file.visititems(visit)
    return found
