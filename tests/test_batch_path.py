"""The lean path of a study that keeps no histories (`study.work._lean`): its packed results are
the per-analysis path's (`study.work.analyze_cell`, then `AnalysisResult.pack`), bit for bit but
the timings, for a failing analysis, a solver error, a recheck, an exception and a record that
could not be read. The expected bytes are computed independently by the per-analysis path, the
one that builds a `core.analysis.Response` and an `AnalysisResult` (issue 43, item 2)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from studies import SLENDER_BLOCK, write_study

from rockbridge_cli.config.study import load_study
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


def test_a_batch_is_the_per_analysis_path_bit_for_bit(grid):
    finished = assert_as_per_analysis(grid)
    assert taken(grid) == [True, True, False] * 3  # R3 could not be read
    said = [(f.status, f.failure_mode) for f in finished]
    assert said[6] == ("ok", "overturning_pier1")  # the block under R1 (tests/studies.py)
    assert [status for status, _ in said[2::3]] == ["error"] * 3


def test_a_solver_error_is_the_per_analysis_paths(grid):
    few = dataclasses.replace(grid, fidelity=grid.fidelity.changed(max_events=2))
    finished = assert_as_per_analysis(few)
    assert {f.status for f in finished if f.record != "R3"} == {"solver_error"}


def test_a_recheck_is_the_per_analysis_paths(grid):
    keeps = {name: grid.fidelity.knobs[name] for name in ("tail", "output_step")}
    rechecking = dataclasses.replace(grid, recheck=resolve("reference", **keeps))
    assert_as_per_analysis(rechecking)
    lean = work._lean(rechecking, every_cell(grid)[6], {})
    assert lean is not None and lean.rechecked >= 1  # the block's failure is run again


def test_an_exception_takes_the_per_analysis_path(grid):
    records = list(grid.records)
    bad = records[1].acceleration.copy()
    bad[10] = np.nan
    records[1] = records[1]._replace(acceleration=bad)
    broken = dataclasses.replace(grid, records=tuple(records))
    finished = assert_as_per_analysis(broken)
    assert taken(broken) == [True, False, False] * 3
    assert finished[1].message == "ValueError: the ground motion has non-finite values"


def test_devices_take_the_lean_path(tmp_path):
    path = write_study(tmp_path, bridges=("studied-hbar1.25-dissipators",),
                       extra="fidelity: fast\noutput: {histories: none}\n")  # fmt: skip
    grid = Grid.of(load_study(path))
    assert_as_per_analysis(grid)
    assert taken(grid) == [True, True]
    lean = work._lean(grid, every_cell(grid)[0], {})
    assert lean is not None and lean.devices.size == 4  # four dissipators in its config
