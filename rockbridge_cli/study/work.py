"""What a worker does with a batch of cells: analyze each and pack its result."""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from ..assessment.limit_states import Verdict
from ..core.fidelity import RECHECK_MARGIN, Fidelity
from ..core.quantities import NO_FAILURE
from ..results.packing import (
    AnalysisResult,
    Packed,
    device_rows,
    device_states,
    outcome,
    pack_summaries,
    pack_summary,
)
from .grid import BridgeCase, Cell, Grid, RecordCase

NO_DEVICE_STATES = tuple(device_states(np.zeros(0)).values())
"""`Finished`'s device states of an analysis of a bridge without devices: NaN."""

if TYPE_CHECKING:
    from ..core.analysis import Prepared, Response, Summary
    from ..core.batch import Summaries


class Finished(NamedTuple):
    """One cell analyzed: which, and what it says (a tuple: it travels back from a worker with
    every analysis, whose results wait in the journal).

    Attributes
    ----------
    cell : the cell
    bridge, record : ids
    status : ``ok``, ``solver_error`` or ``error`` (`results.STATUSES`)
    message : why it stopped early or could not run; empty if ok
    solve_time_s : integration time, NaN if it could not run [s]
    failure_mode : how the bridge failed (``none`` if it did not, empty if it could not run)
    dcr_backfill : peak backfill demand/capacity ratio [-]
    busy_s : how long the worker took, from the start of the analysis to its packed result [s]
    tendon_yield, tendon_rupture, dissipator_fracture : whether its devices reached those
        limits: 1.0, 0.0, NaN where none states one (`results.packing.device_states`)
    """

    cell: Cell
    bridge: str
    record: str
    status: str
    message: str
    solve_time_s: float
    failure_mode: str
    dcr_backfill: float
    busy_s: float = float("nan")
    tendon_yield: float = float("nan")
    tendon_rupture: float = float("nan")
    dissipator_fracture: float = float("nan")

    @property
    def verdict(self) -> Verdict:
        """What decides its limit states."""
        return Verdict(
            self.status, self.failure_mode, self.dcr_backfill, self.tendon_yield,
            self.tendon_rupture, self.dissipator_fracture,
        )  # fmt: skip


def run_cells(grid: Grid, cells: Sequence[Cell]) -> list[tuple[Finished, Packed]]:
    """Analyze ``cells``: what each says, and its packed result. An exception fails only its own
    analysis.

    A study that keeps no histories integrates the analyses of each bridge without devices in
    one compiled call (`_batched`), and takes the lean path (`_lean`) where it cannot: what the
    analyses of a bridge share is prepared once per bridge and batch, and each result is packed
    straight from its integration's `core.analysis.Summary` (`pack_summary`). Both give the same
    bytes as the per-analysis path (`analyze_cell`), which the others take.
    """
    batched = {} if grid.keep else _batched(grid, cells)
    analyzed = []
    shared: dict[tuple[int, bool], Prepared] = {}  # `_lean`'s
    for cell in cells:
        if cell.index in batched:
            analyzed.append(batched[cell.index])
            continue
        start = time.perf_counter()
        lean = None if grid.keep else _lean(grid, cell, shared)
        if lean is not None:
            analyzed.append(_packed(cell, lean, start))
            continue
        result = analyze_cell(grid, cell)
        packed = result.pack()
        values = result.values
        finished = Finished(
            cell, result.bridge, result.record, values["status"], values["message"],
            values["solve_time_s"], values["failure_mode"], values["dcr_backfill"],
            time.perf_counter() - start, *device_states(result.devices).values(),
        )  # fmt: skip
        analyzed.append((finished, packed))
    return analyzed


def _batched(grid: Grid, cells: Sequence[Cell]) -> dict[int, tuple[Finished, Packed]]:
    """The cells of a bridge without devices, under a record that was read and has no vertical
    component, integrated bridge by bridge in one compiled call each (`core.batch`), by their
    index: what each says and its packed result, the same bytes as `_lean`'s. Left to the
    others: the rest, a motion that `core.analysis.check_motion` refuses, a batch that raised,
    and an analysis to recheck (`_near_a_limit`).

    The integration's wall time of each is measured by the kernel; its analysis's wall time
    (``wall_time_s``, ``busy_s``) is that plus an equal share of what its bridge's batch spent
    around the integrations before packing (preparing the bridge, joining the records,
    summarizing).
    """
    from ..core import analysis, batch  # the compiled kernels: a worker's, not the parent's

    if not batch.AVAILABLE:
        return {}
    groups: dict[int, list[tuple[Cell, RecordCase, np.ndarray]]] = {}
    for cell in cells:
        case, record = grid.bridges[cell.bridge_index], grid.record_of(cell)
        if case.bridge.devices or record.acceleration is None or record.vertical is not None:
            continue
        try:
            checked = analysis.check_motion(record.acceleration, record.time_step, grid.fidelity)
        except (TypeError, ValueError):  # the per-analysis path says why
            continue
        groups.setdefault(cell.bridge_index, []).append((cell, record, checked))
    done = {}
    for index, group in groups.items():
        try:
            done.update(_integrated_together(grid, grid.bridges[index], group))
        except Exception:  # the per-analysis path records it with its message
            continue
    return done


def _integrated_together(
    grid: Grid, case: BridgeCase, group: list[tuple[Cell, RecordCase, np.ndarray]]
) -> dict[int, tuple[Finished, Packed]]:
    """`_batched` of the cells of one bridge, each with its record and its accelerations as
    `core.analysis.check_motion` made them [m/s²]."""
    from ..core import analysis, batch

    start = time.perf_counter()
    prepared = analysis.prepare(case.bridge, grid.fidelity)
    records = [record for _, record, _ in group]
    found = batch.summarized(
        prepared, [motion for _, _, motion in group], [r.time_step for r in records]
    )
    kept = ~_near_limits(found, grid.recheck is not None)
    around = (time.perf_counter() - start - np.nansum(found.solve_time)) / len(group)
    timings = np.column_stack([found.solve_time, found.solve_time + around])
    packed = pack_summaries(
        case.id, [(r.id, r.base, r.level, r.scale) for r in records], found, timings
    )
    done = {}
    for (cell, record, _), ok, one, status, mode, dcr, (solve, wall) in zip(
        group, kept.tolist(), packed, found.status, found.failure_mode,
        found.dcr_backfill.tolist(), timings.tolist(), strict=True,
    ):  # fmt: skip
        if ok:
            said = outcome(status)
            done[cell.index] = (Finished(
                cell, case.id, record.id, said["status"], said["message"], solve, mode, dcr,
                wall, *NO_DEVICE_STATES,
            ), one)  # fmt: skip
    return done


class Lean(NamedTuple):
    """What the lean path (`_lean`) found of a cell: the bridge's id, the record as analyzed,
    the integration's summary, the devices' rows (`device_rows`), the solve's wall time [s], and
    the ``rechecked`` column (`analyze_cell`)."""

    bridge: str
    record: RecordCase
    summary: Summary
    devices: np.ndarray
    solve_time: float
    rechecked: int = 0


def _packed(cell: Cell, lean: Lean, start: float) -> tuple[Finished, Packed]:
    """What a cell that took the lean path says, and its packed result; ``start`` the
    `time.perf_counter` at its start [s]."""
    found, record, said = lean.summary, lean.record, outcome(lean.summary.status)
    packed = pack_summary(
        lean.bridge, record.id, found, lean.devices, (record.base, record.level, record.scale),
        (lean.solve_time, time.perf_counter() - start), lean.rechecked,
    )  # fmt: skip
    finished = Finished(
        cell, lean.bridge, record.id, said["status"], said["message"], lean.solve_time,
        found.failure_mode, found.dcr_backfill, time.perf_counter() - start,
        *device_states(lean.devices).values(),
    )  # fmt: skip
    return finished, packed


def _lean(grid: Grid, cell: Cell, shared: dict[tuple[int, bool], Prepared]) -> Lean | None:
    """A cell analyzed without a `core.analysis.Response`, and rechecked as `analyze_cell`
    says; what the analyses of a bridge share is in ``shared``, by the bridge's index and
    whether at ``grid.recheck`` (filled as needed). None where the cell takes the per-analysis
    path, which then records or repeats what is unusual: a record that could not be read, a
    vertical motion (a free flight cuts it), an exception."""
    case, record = grid.bridges[cell.bridge_index], grid.record_of(cell)
    if record.acceleration is None or record.vertical is not None:
        return None
    try:
        lean = _summarized(case, record, grid.fidelity, shared, (cell.bridge_index, False))
        if grid.recheck is not None and _near_a_limit(lean.summary):
            again = _summarized(case, record, grid.recheck, shared, (cell.bridge_index, True))
            lean = again._replace(rechecked=rechecked(lean.summary, again.summary))
    except Exception:  # the per-analysis path records it with its message
        return None
    return lean


def _summarized(
    case: BridgeCase,
    record: RecordCase,
    fidelity: Fidelity,
    shared: dict[tuple[int, bool], Prepared],
    key: tuple[int, bool],
) -> Lean:
    """The lean analysis of ``case`` under ``record`` at ``fidelity``, what they share under
    ``key`` in ``shared`` (`_lean`)."""
    from ..core import analysis  # the compiled kernels: a worker's, not the parent's

    bridge, step = case.bridge, record.time_step
    assert record.acceleration is not None, "a record that could not be read is not analyzed"
    if key not in shared:
        shared[key] = analysis.prepare(bridge, fidelity)
    ground = analysis.ground_motion(record.acceleration, step, fidelity, bridge.model.g)
    result, solve_time = analysis.solve(shared[key], ground.acc, step)
    found = analysis.summary(bridge, result)
    devices = device_rows(bridge.devices, analysis.device_peaks(bridge, result))
    return Lean(case.id, record, found, devices, solve_time)


def rechecked(first: Response | Summary, again: Response | Summary) -> int:
    """The ``rechecked`` column of an analysis run ``again`` at ``reference`` after a ``first``
    run near a limit: 1, or 2 where the failure mode (the verdict) changed."""
    return 1 + (again.failure_mode != first.failure_mode)


def analyze_cell(grid: Grid, cell: Cell) -> AnalysisResult:
    """Run one analysis; any exception becomes a result with status ``error`` and its message.

    With ``grid.recheck``, an analysis at a cheaper preset that ends in a failure of the bridge,
    or within `fidelity.RECHECK_MARGIN` of a capacity, is run again at ``reference``, and the
    result is that one (``rechecked`` = 1, or 2 where its failure mode differs from the cheaper
    preset's): a cheap preset's verdict can be wrong near a limit.
    """
    bridge, record = grid.bridges[cell.bridge_index], grid.record_of(cell)
    result = _analyzed(grid, bridge, record)
    result.values.update(base_record=record.base, intensity=record.level, scale=record.scale)
    return result


def _analyzed(grid: Grid, bridge: BridgeCase, record: RecordCase) -> AnalysisResult:
    from ..core.analysis import analyze  # the compiled kernels: a worker's, not the parent's

    if record.acceleration is None:
        return AnalysisResult.failed(bridge.id, record.id, record.error)
    start = time.perf_counter()
    try:
        response = analyze(
            bridge.bridge, record.acceleration, record.time_step, grid.fidelity,
            histories=bool(grid.keep), vertical=record.vertical,
        )  # fmt: skip
        checked = 0
        if grid.recheck is not None and _near_a_limit(response):
            again = analyze(
                bridge.bridge, record.acceleration, record.time_step, grid.recheck,
                histories=bool(grid.keep), vertical=record.vertical,
            )  # fmt: skip
            checked, response = rechecked(response, again), again
    except Exception as exc:  # one failed analysis must not stop the others
        return AnalysisResult.failed(
            bridge.id, record.id, f"{type(exc).__name__}: {exc}", time.perf_counter() - start
        )
    result = AnalysisResult.from_response(
        bridge.id,
        record.id,
        response,
        grid.keep,
        time.perf_counter() - start,
        bridge.bridge.devices,
    )
    result.values["rechecked"] = checked
    return result


def _near_limits(found: Summaries, recheck: bool) -> np.ndarray:
    """`_near_a_limit` of each analysis of a batch, where the study rechecks (else none)."""
    if not recheck:
        return np.zeros(len(found.failure_mode), bool)
    near = np.array([mode != NO_FAILURE for mode in found.failure_mode], bool)
    for ratios in (found.dcr_backfill, found.dcr_overturning):
        near |= ratios >= 1.0 - RECHECK_MARGIN  # NaN: no
    return near


def _near_a_limit(response: Response | Summary) -> bool:
    """Whether an analysis ended in a failure or within `RECHECK_MARGIN` of a capacity."""
    ratios = [r for r in (response.dcr_backfill, response.dcr_overturning) if r == r]  # not NaN
    return response.failure_mode != NO_FAILURE or any(r >= 1.0 - RECHECK_MARGIN for r in ratios)
