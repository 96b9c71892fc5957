"""The paths of a study that keeps no histories, the compiled batch (`study.work._batched`,
`core.batch`) and the lean path (`study.work._lean`): their packed results are the
per-analysis path's (`study.work.analyze_cell`, then `AnalysisResult.pack`), bit for bit but the
timings, for a failing analysis, a solver error, a recheck, an exception, a record that could
not be read, scaled records and devices. The expected bytes are computed independently by the
per-analysis path, the one that builds a `core.analysis.Response` and an `AnalysisResult`
(issue 43, item 2)."""

from __future__ import annotations

import dataclasses
import time

import numba
import numpy as np
import pytest
from studies import BRIDGES, SLENDER_BLOCK, write_study

from rockbridge_cli.config.study import load_study
from rockbridge_cli.core import batch
from rockbridge_cli.core._jit import clock_ns
from rockbridge_cli.core.fidelity import resolve
from rockbridge_cli.results.packing import NUMBERS, Packed
from rockbridge_cli.study import work
from rockbridge_cli.study.grid import Cell, Grid

TIMINGS = [NUMBERS.index("solve_time_s"), NUMBERS.index("wall_time_s")]
"""The columns that differ between two runs of the same analysis."""


@pytest.fixture(scope="module")
def grid(tmp_path_factory) -> Grid:
    """Two studied bridges and the slender block (R1 overturns it) × R1, R2 and R3, a file
    without units (it cannot be read), at ``fast``, keeping no histories."""
    folder = tmp_path_factory.mktemp("lean")
    block = folder / "block.yaml"
    block.write_text(SLENDER_BLOCK, encoding="utf-8")
    path = write_study(folder, extra="fidelity: fast\noutput: {histories: none}\n",
                       bridge_files=(block,))  # fmt: skip
    (folder / "R3.txt").write_text("0.0 1.0\n0.01 2.0\n", encoding="utf-8")
    listed = path.read_text(encoding="utf-8").replace("R2.txt\n", "R2.txt\n    - path: R3.txt\n")
    path.write_text(listed, encoding="utf-8")
    return Grid.of(load_study(path))


def every_cell(grid: Grid) -> list[Cell]:
    pairs = [(b, r) for b in range(len(grid.bridges)) for r in range(len(grid.records))]
    return [Cell(index, b, r) for index, (b, r) in enumerate(pairs)]


def timeless(packed: Packed) -> Packed:
    """``packed`` with its timings zeroed."""
    numbers = np.frombuffer(packed.numbers, np.float64).copy()
    numbers[TIMINGS] = 0.0
    return packed._replace(numbers=numbers.tobytes())


def assert_as_per_analysis(grid: Grid) -> list[work.Finished]:
    """Run every cell of ``grid`` in one batch (`run_cells`) and compare each packed result
    and what it says with the per-analysis path's; what the batch says."""
    cells = every_cell(grid)
    batch = work.run_cells(grid, cells)
    for cell, (finished, packed) in zip(cells, batch, strict=True):
        expected = work.analyze_cell(grid, cell)
        assert timeless(packed) == timeless(expected.pack()), cell
        values = expected.values
        assert (finished.status, finished.message, finished.failure_mode) == (
            values["status"], values["message"], values["failure_mode"]
        )  # fmt: skip
        assert finished.dcr_backfill == values["dcr_backfill"] or np.isnan(values["dcr_backfill"])
    return [finished for finished, _ in batch]


def taken(grid: Grid) -> list[bool]:
    """Whether each cell takes the lean path."""
    return [work._lean(grid, cell, {}) is not None for cell in every_cell(grid)]


def batched(grid: Grid, cells: list[Cell] | None = None) -> list[int]:
    """The indices of the cells that the compiled batch integrates."""
    return sorted(work._batched(grid, cells or every_cell(grid)))


needs_batches = pytest.mark.skipif(not batch.AVAILABLE, reason="no compiled batch here")


def test_a_batch_is_the_per_analysis_path_bit_for_bit(grid):
    finished = assert_as_per_analysis(grid)
    assert taken(grid) == [True, True, False] * 3  # R3 could not be read
    said = [(f.status, f.failure_mode) for f in finished]
    assert said[6] == ("ok", "overturning_pier1")  # the block under R1 (tests/studies.py)
    assert [status for status, _ in said[2::3]] == ["error"] * 3


@needs_batches
def test_the_compiled_batch_takes_every_readable_record_of_a_bridge_without_devices(grid):
    assert batched(grid) == [0, 1, 3, 4, 6, 7]  # R3 could not be read
    finished = work.run_cells(grid, every_cell(grid))
    for one in finished[:2]:
        assert 0.0 < one[0].solve_time_s <= one[0].busy_s < 10.0  # the kernel's clock [s]


@needs_batches
def test_scaled_records_are_the_per_analysis_paths(grid):
    grid = dataclasses.replace(grid, measure="pga_g")
    scaled = [Cell(i, b, r, 0.1 * (i + 1), 0.5 + 0.3 * i)  # an IDA's cells: levels and factors
              for i, (b, r) in enumerate([(0, 0), (0, 1), (1, 0), (1, 1), (2, 1)])]  # fmt: skip
    analyzed = work.run_cells(grid, scaled)
    assert batched(grid, scaled) == [0, 1, 2, 3, 4]
    for cell, (_, packed) in zip(scaled, analyzed, strict=True):
        assert timeless(packed) == timeless(work.analyze_cell(grid, cell).pack()), cell


def test_a_solver_error_is_the_per_analysis_paths(grid):
    few = dataclasses.replace(grid, fidelity=grid.fidelity.changed(max_events=2))
    finished = assert_as_per_analysis(few)
    assert {f.status for f in finished if f.record != "R3"} == {"solver_error"}
    assert batched(few) == ([0, 1, 3, 4, 6, 7] if batch.AVAILABLE else [])


def test_a_recheck_is_the_per_analysis_paths(grid):
    keeps = {name: grid.fidelity.knobs[name] for name in ("tail", "output_step")}
    rechecking = dataclasses.replace(grid, recheck=resolve("reference", **keeps))
    assert_as_per_analysis(rechecking)
    lean = work._lean(rechecking, every_cell(grid)[6], {})
    assert lean is not None and lean.rechecked >= 1  # the block's failure is run again
    assert 6 not in batched(rechecking)  # (by the lean path)


def test_an_exception_takes_the_per_analysis_path(grid):
    records = list(grid.records)
    bad = records[1].acceleration.copy()
    bad[10] = np.nan
    records[1] = records[1]._replace(acceleration=bad)
    broken = dataclasses.replace(grid, records=tuple(records))
    finished = assert_as_per_analysis(broken)
    assert taken(broken) == [True, False, False] * 3
    assert batched(broken) == ([0, 3, 6] if batch.AVAILABLE else [])
    assert finished[1].message == "ValueError: the ground motion has non-finite values"


def test_devices_take_the_lean_path(tmp_path):
    path = write_study(tmp_path, bridges=("studied-hbar1.25-dissipators",),
                       extra="fidelity: fast\noutput: {histories: none}\n")  # fmt: skip
    grid = Grid.of(load_study(path))
    assert_as_per_analysis(grid)
    assert taken(grid) == [True, True]
    assert batched(grid) == []  # the batch is not compiled for devices
    lean = work._lean(grid, every_cell(grid)[0], {})
    assert lean is not None and lean.devices.size == 4  # four dissipators in its config


@needs_batches
def test_a_mirrored_bridge_is_the_per_analysis_paths(tmp_path):
    mirrored = tmp_path / "mirrored.yaml"  # the tall pier on the right: the core's frame flips
    text = (BRIDGES / "studied-hbar2.00.yaml").read_text(encoding="utf-8")
    mirrored.write_text(text.replace("[26.0, 13.0]", "[13.0, 26.0]"), encoding="utf-8")
    path = write_study(tmp_path, bridges=(), bridge_files=(mirrored,),
                       extra="fidelity: fast\noutput: {histories: none}\n")  # fmt: skip
    grid = Grid.of(load_study(path))
    assert grid.bridges[0].bridge.sign == -1.0
    finished = assert_as_per_analysis(grid)
    assert batched(grid) == [0, 1]
    assert all(f.status == "ok" for f in finished)


@numba.njit
def clock_now() -> int:
    """The kernels' clock, read in a compiled function [ns]."""
    return clock_ns()


@needs_batches
def test_the_kernels_clock_is_pythons():
    clock_now()  # compiled
    before = time.monotonic_ns()
    read = clock_now()
    after = time.monotonic_ns()
    assert before <= read <= after  # time.monotonic_ns reads the same clock
