"""One bridge under one record (`rockbridge analyze`), by the route every study's analysis takes:
its study of one cell (`config.study.single_analysis`) analyzed as a worker analyzes a cell
(`work.analyze_cell`), in this process, or run into a results file (`run.run_study`) when one is
asked for. The two give the same peak row, bit for bit."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from ..interrupts import held
from .grid import Grid
from .work import analyze_cell

if TYPE_CHECKING:
    from ..config.study import Study


class Single(NamedTuple):
    """What one analysis says.

    Attributes
    ----------
    values : its row of the peak table (`results.layout.PEAK_COLUMNS`, with the ids) [SI]
    time : the sample times of its histories [s]
    theta1 : θ1 at ``time`` [rad]
    mode : the rocking mode at ``time`` (−1, 0, +1) [-]
    output : the results file it was written to, None for none
    """

    values: dict
    time: np.ndarray
    theta1: np.ndarray
    mode: np.ndarray
    output: Path | None


def grid_of(study: Study) -> Grid:
    """The grid of a study of one analysis; its bridge, built once, is ``bridges[0].bridge``."""
    grid = Grid.of(study)
    if len(grid.cells) != 1:
        raise ValueError(f"a study of one analysis has {len(grid.cells)}")
    return grid


def analyze_single(
    study: Study, grid: Grid, output: Path | None = None, overwrite: bool = False
) -> Single:
    """The analysis of a study of one cell, ``grid`` its grid (`grid_of`): in this process (a
    stop waits for the compiled integrator to return), or, with an ``output`` file, run into it
    as `rockbridge run` would (one worker; ``overwrite``: replace a file that holds other
    results). Its values have each device's peaks too (`device_peaks`)."""
    if output is None:
        with held():
            result = analyze_cell(grid, grid.cells[0])
        values = {"bridge": result.bridge, "record": result.record, **result.values}
        values.update(device_peaks(result.devices))
        histories = result.histories
        return Single(values, result.time, histories["theta1"], histories["mode"], None)
    from ..results import open_results, read_history
    from ..results.reading import device_tables
    from .run import run_study

    report = run_study(study, workers=1, overwrite=overwrite)
    values = report.peaks.iloc[0].to_dict()
    ids = str(values["bridge"]), str(values["record"])
    with open_results(report.output) as file:
        values.update(device_peaks(device_tables(file).get(ids, ())))
    stored = read_history(report.output, *ids)
    return Single(
        values, stored.index.to_numpy(), stored["theta1"].to_numpy(), stored["mode"].to_numpy(),
        report.output,
    )  # fmt: skip


def device_peaks(rows) -> dict[str, float]:
    """Each device's peaks as ``analyze`` shows them, from its rows of the device table
    (`results.packing.DEVICE_RECORD`): ``tendon1_elongation_max`` [m], ``…_elongation_time``
    [s], ``…_force_max`` [N], ``…_force_time`` [s], …"""
    return {
        f"{row['device'].decode()}_{column}": float(row[column])
        for row in rows
        for column in ("elongation_max", "elongation_time", "force_max", "force_time")
    }
