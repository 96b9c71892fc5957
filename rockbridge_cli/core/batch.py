"""Many ground motions of one bridge in one compiled call: what a study that keeps no histories
asks of the integrator, without Python between its analyses.

`integrate_batch` integrates each motion of a batch as `analysis.solve` would (the same
`solver.integrate`, the same arguments, the same bits) and keeps what `analysis.summary` reads of
each: the peaks, the event log, the counts and the integration's wall time, measured by the
kernel. `summaries` turns them into the batch's summary columns in the user's frame, each the
same bits as the field of the same name of `analysis.Summary`, analysis by analysis. A bridge
with devices or a vertical motion takes the lean path (`study.work`): the batch is compiled for
neither.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from ._jit import CLOCK, clock_ns, jit
from .analysis import ABSENT_IN_A_BLOCK, Events, Prepared
from .geometry import kind
from .quantities import PEAK_NAMES, PEAK_U_DECK, PEAK_U_PIER1, PEAK_U_PIER2, SIGNIFICANT_RATE
from .solver import (
    EVENT_KIND,
    EVENT_MODE,
    EVENT_RATE_AFTER,
    EVENT_RATE_BEFORE,
    EVENT_TIME,
    FAILURE_MODE,
    IMPACT,
    NO_ERROR,
    NOT_FAILED,
    ONSET,
    POUNDING,
    SOLVER_ERRORS,
    integrate,
)

FAILURE, ERROR, STEPS, REJECTED, IMPACTS, POUNDINGS, SIGNIFICANT = range(7)
"""Columns of `Integrated.counts`: the failure event (`solver.NOT_FAILED` if none), the solver's
error code, steps taken and rejected, impacts, poundings, and impacts with |θ̇1| above
`quantities.SIGNIFICANT_RATE` before them."""

END_TIME, ONSET_TIME, SOLVE_TIME = range(3)
"""Columns of `Integrated.times`: where the integration stopped, the first onset (NaN if none)
and the integration's wall time [s]."""


class Integrated(NamedTuple):
    """What `integrate_batch` keeps of n integrations.

    Attributes
    ----------
    peaks : (n, len(`PEAK_NAMES`), 2) each quantity's peak and its time [s], unmasked
    events : every analysis's event log, one after the other (core frame; `solver.EVENT_TIME` …)
    event_starts : (n + 1) where each analysis's events start in ``events``, then their count
    counts : (n, 7) int64, columns `FAILURE` … `SIGNIFICANT`
    times : (n, 3) [s], columns `END_TIME` … `SOLVE_TIME`
    """

    peaks: np.ndarray
    events: np.ndarray
    event_starts: np.ndarray
    counts: np.ndarray
    times: np.ndarray


@jit
def _counted(events: np.ndarray, counts: np.ndarray, times: np.ndarray) -> None:
    """The impacts, poundings and significant impacts of one analysis's ``events`` into its row of
    ``counts``, its first onset into its row of ``times`` (NaN if none)."""
    times[ONSET_TIME] = np.nan
    for row in range(events.shape[0]):
        code = int(events[row, EVENT_KIND])
        if code == ONSET and times[ONSET_TIME] != times[ONSET_TIME]:
            times[ONSET_TIME] = events[row, EVENT_TIME]
        elif code == IMPACT:
            counts[IMPACTS] += 1
            counts[SIGNIFICANT] += abs(events[row, EVENT_RATE_BEFORE]) > SIGNIFICANT_RATE
        elif code == POUNDING:
            counts[POUNDINGS] += 1


@jit
def integrate_batch(model, laws, kin, settings, sign, motions, starts, time_steps, tails):
    """Integrate n ground motions of one bridge, each as `analysis.solve` does.

    Parameters
    ----------
    model, laws, kin, settings
        As `solver.integrate` takes them (`analysis.Prepared`).
    sign
        The bridge's `Bridge.sign`: the motions in the core's frame are ``sign`` × the user's [-].
    motions
        The records one after the other, as analyzed (scaled, checked by
        `analysis.check_motion`), in the user's frame [m/s²].
    starts
        (n + 1) where each analysis's record starts in ``motions``, then their length [-].
    time_steps
        (n) the records' sample intervals [s].
    tails
        (n) the samples of rest after each record (`analysis.ground_motion`) [-].

    Returns
    -------
    `Integrated`
    """
    n = starts.size - 1
    peaks = np.full((n, len(PEAK_NAMES), 2), np.nan)
    counts = np.zeros((n, 7), np.int64)
    times = np.full((n, 3), np.nan)
    event_starts = np.zeros(n + 1, np.int64)
    events = np.empty((1024, 5))
    for i in range(n):
        record = motions[starts[i] : starts[i + 1]]
        acc = np.empty(record.size + tails[i])
        for j in range(record.size):
            acc[j] = sign * record[j]
        acc[record.size :] = sign * 0.0
        begin = clock_ns()
        result = integrate(model, laws, kin, acc, time_steps[i], settings, sign * 0.0, sign * 0.0)
        times[i, SOLVE_TIME] = (clock_ns() - begin) * 1e-9
        logged = result.events.shape[0]
        if event_starts[i] + logged > events.shape[0]:
            grown = np.empty((2 * (event_starts[i] + logged), 5))
            grown[: event_starts[i]] = events[: event_starts[i]]
            events = grown
        events[event_starts[i] : event_starts[i] + logged] = result.events
        event_starts[i + 1] = event_starts[i] + logged
        peaks[i] = result.peaks
        counts[i, FAILURE], counts[i, ERROR] = result.failure, result.error
        counts[i, STEPS], counts[i, REJECTED] = result.steps, result.rejected
        times[i, END_TIME] = result.end_time
        _counted(result.events, counts[i], times[i])
    return Integrated(peaks, events[: event_starts[n]].copy(), event_starts, counts, times)


AVAILABLE = CLOCK is not None and hasattr(integrate_batch, "py_func")
"""Whether batches can be integrated here: the kernel reads the C library's clock (none on
Windows) and is machine code only (not with ``NUMBA_DISABLE_JIT``, where it is plain Python)."""


class Summaries(NamedTuple):
    """The `analysis.Summary` of each analysis of a batch, by column: each the same values as
    the summary's field of the same name (``events`` those of the whole batch, each analysis's
    from ``event_starts``), with the integrations' wall times [s]."""

    model: str
    peaks: np.ndarray
    events: Events
    event_starts: np.ndarray
    t_onset: np.ndarray
    n_impacts: np.ndarray
    n_poundings: np.ndarray
    failure_mode: list[str]
    failure_time: np.ndarray
    n_impacts_significant: np.ndarray
    dcr_backfill: np.ndarray
    dcr_overturning: np.ndarray
    status: list[str]
    steps: np.ndarray
    rejected_steps: np.ndarray
    solve_time: np.ndarray


def summarized(
    prepared: Prepared, motions: Sequence[np.ndarray], time_steps: Sequence[float]
) -> Summaries:
    """The summaries of a ``prepared`` bridge without devices under each of ``motions``
    (horizontal, checked by `analysis.check_motion`) [m/s²], at ``time_steps`` [s], integrated
    in one compiled call (`integrate_batch`): each the same bits as `analysis.summary` of
    `analysis.solve` of its `analysis.ground_motion`."""
    bridge, tail = prepared.bridge, prepared.fidelity.knobs["tail"]
    found = integrate_batch(
        bridge.model, prepared.laws, prepared.kin, prepared.settings, bridge.sign,
        np.concatenate(motions), np.cumsum([0] + [motion.size for motion in motions]),
        np.array(time_steps, dtype=float), np.array([round(tail / step) for step in time_steps]),
    )  # fmt: skip
    return summaries(prepared, found)


def summaries(prepared: Prepared, found: Integrated) -> Summaries:
    """The summaries of a batch integrated for a ``prepared`` bridge (`integrate_batch`), the
    same bits as `analysis.summary` of each analysis (its ``max`` and its masks, by column)."""
    model, sign = prepared.bridge.model, prepared.bridge.sign
    counts, peaks = found.counts, found.peaks
    if kind(model) == "single-block":
        peaks[:, [PEAK_NAMES.index(name) for name in ABSENT_IN_A_BLOCK]] = np.nan
    error = counts[:, ERROR]
    peaks[error != NO_ERROR] = np.nan
    u_deck, u_pier1 = peaks[:, PEAK_U_DECK, 0], peaks[:, PEAK_U_PIER1, 0]
    u_pier2 = peaks[:, PEAK_U_PIER2, 0] if model.m2 else np.zeros(len(peaks))
    dcr_backfill = np.full(len(peaks), np.nan)
    if model.has_abutments:
        opened = u_deck - model.u_jo
        dcr_backfill = np.where(np.isfinite(u_deck), np.where(opened > 0.0, opened, 0.0), np.nan)
        dcr_backfill = dcr_backfill / model.u_ab
    events = found.events
    failed = counts[:, FAILURE] != NOT_FAILED
    return Summaries(
        model=kind(model),
        peaks=peaks,
        events=Events(
            events[:, EVENT_TIME],
            events[:, EVENT_KIND].astype(int),
            sign * events[:, EVENT_MODE],
            sign * events[:, EVENT_RATE_BEFORE],
            sign * events[:, EVENT_RATE_AFTER],
        ),  # fmt: skip
        event_starts=found.event_starts,
        t_onset=found.times[:, ONSET_TIME],
        n_impacts=counts[:, IMPACTS],
        n_poundings=counts[:, POUNDINGS],
        failure_mode=[FAILURE_MODE[code] for code in counts[:, FAILURE].tolist()],
        failure_time=np.where(failed, found.times[:, END_TIME], np.nan),
        n_impacts_significant=counts[:, SIGNIFICANT],
        dcr_backfill=dcr_backfill,
        dcr_overturning=np.where(u_pier2 > u_pier1, u_pier2, u_pier1) / model.B,  # Python's max
        status=[SOLVER_ERRORS[code] for code in error.tolist()],
        steps=counts[:, STEPS],
        rejected_steps=counts[:, REJECTED],
        solve_time=found.times[:, SOLVE_TIME],
    )
