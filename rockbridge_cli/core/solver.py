"""Event-driven response-history integration of one bridge under one ground motion.

The response is a chain of smooth segments cut by events (docs/model.md §5–7). The integrator is a
small state machine:

* **at rest** until the ground acceleration, linear between samples, crosses an onset threshold
  (Eq. 8; times (g + ü_v)/g under a vertical ground acceleration ü_v): the crossing time is
  solved exactly;
* **rocking in mode s** (+1 or −1), integrating θ̈1 = f(θ1, θ̇1, ü_g) with the end gap **open** or
  **closed** (spring–dashpot on), until an event:

  - *impact* at the rocking interfaces (θ1 back to 0): θ̇1 ← η_s·θ̇1, mode ← −s; right after, if
    |θ̇1| is below the rest velocity and the ground cannot drive the new mode, back **at rest**
    (the chatter guard);
  - *pounding* (|u_deck| reaches u_jo from inside): θ̇1 ← ratio·θ̇1, gap closed;
  - *reopening* (|u_deck| back to u_jo): gap open, no impulse;
  - *failure* of the abutment–backfill (|u_deck| = u_jo + u_ab) or overturning of a pier
    (|u_pier| = B): the analysis stops;
  - a yielding device's *change of branch* (yield, elastic unloading, rupture or fracture,
    `device_events`): its state changes, θ1 and θ̇1 do not;

and, optionally, each *turning point* (θ̇1 = 0), where θ1 peaks, is found on the interpolant of
the step that holds it (`events.turning_point`) to catch each peak exactly; nothing jumps there,
so the step is not cut.

Steps never straddle a record sample, so the ground acceleration is linear within each step. An
event is located (`events`) by re-stepping from the step's start with a shorter step (Illinois
regula falsi, or the paper's plain bisection) until the event time is known to ``event_tol``; the
state is then taken just past the event. Two one-step schemes are available (`schemes`): the
classical fixed-step Runge–Kutta of order 4 (the paper's) and the adaptive embedded Dormand–Prince
5(4) pair (Dormand & Prince 1980) with error control on θ1 and θ̇1.

What stays fixed for the whole integration is a `Problem`, what stays fixed from one event to the
next a `schemes.Segment`, and what changes with every step a `Motion`; the integrator writes
`Histories` and a `Log` of the events. `integrate` goes from segment to segment (the onsets, the
events, the log); `_rocking` takes the steps of one segment.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from . import quantities
from ._jit import inlined, jit, uncounted
from .device_events import fresh, settle
from .device_histories import histories_of, sampled
from .device_mechanics import peaks_of, tracked
from .events import (
    WATCH_ABUTMENT,
    WATCH_DEVICES,
    WATCH_GAP,
    WATCH_IMPACT,
    WATCH_PIER1,
    first_event,
    holds_turning_point,
    turning_point,
    watched,
)
from .geometry import Model
from .impacts import onsets_at_rest
from .kinematics import Displacements, Kinematics, displacements
from .quantities import PEAK_NAMES
from .schemes import (
    RK4,
    Ground,
    Segment,
    State,
    Step,
    accel_called,
    ground_at,
    ground_of,
    lift_at,
    take_step,
)

ONSET, IMPACT, POUNDING, REOPENING, REST, ABUTMENT_FAILURE, PIER1_OVERTURNING, PIER2_OVERTURNING = (
    range(8)
)
"""Event kinds as the log records them: codes of `quantities.EVENT_NAMES`."""

EVENT_TIME, EVENT_KIND, EVENT_MODE, EVENT_RATE_BEFORE, EVENT_RATE_AFTER = range(5)
"""Columns of the event log: time [s], kind (`EVENT_NAMES`), rocking mode after the event (0 at
rest), θ̇1 before and after it [rad/s]."""

NO_ERROR, STEP_UNDERFLOW, TOO_MANY_EVENTS, NON_FINITE_STATE, FREE_FLIGHT = range(5)
SOLVER_ERRORS = (
    "ok",
    "the step size fell below 1e-14 s",
    "too many events (chattering that the rest guard did not stop)",
    "the state became non-finite",
    "free flight: the vertical ground acceleration reached -g, lifting the bridge off the "
    "ground, which the model does not represent",
)
"""Why the integrator stopped before the end of the record, by code (`NO_ERROR` is none).
`FREE_FLIGHT` is the analysis's (`analysis.analyze`), which integrates only until g + ü_v ≤ 0."""

NOT_FAILED = -1
"""`Integration.failure` of an analysis in which nothing failed."""

FAILURE_MODE = {
    NOT_FAILED: quantities.NO_FAILURE,
    ABUTMENT_FAILURE: quantities.ABUTMENT,
    PIER1_OVERTURNING: quantities.PIER1_OVERTURNING,
    PIER2_OVERTURNING: quantities.PIER2_OVERTURNING,
}
"""The failure mode (`quantities.FAILURE_MODES`) of each failure event."""

_THETA1_PEAK = PEAK_NAMES.index("theta1")

_EVENT_ROWS = 1024
"""Rows of the event log at the start, doubled when full up to `Settings.max_events`: zeroing the
whole log (200 000 rows, 8 MB) would cost 0.15 ms an analysis, most analyses log 100–300."""

_EVENTS_PER_ITERATION = 3
"""Most events one pass of the integrator's loop logs: an onset, then an impact and a rest."""

_FULL_GROWTH = 0.99 * (0.9 / 5.0) ** 5
"""The error ratio below which a step grows by the most DOPRI5's control allows, 5× (its
0.9·ratio^(−1/5) ≥ 5.01): 1 % inside the bound, so that the power is spared only where it could
not have changed the step [-]."""


class Settings(NamedTuple):
    """The fidelity knobs of one analysis, as the solver reads them (`fidelity.Fidelity.settings`).

    Attributes
    ----------
    scheme : `RK4` (fixed step) or `DOPRI5` (adaptive) [-]
    step : fixed step (RK4) or first trial step (DOPRI5) [s]
    rtol, atol : relative and absolute (θ1 [rad], θ̇1 [rad/s]) tolerances of DOPRI5 [-]
    max_step : largest step [s]
    event_tol : event times are located to within this [s]
    bisection : True for the paper's bisection, False for Illinois regula falsi
    turning_points : find every θ̇1 = 0 inside a step to catch the peaks exactly
    rest_velocity : chatter guard, |θ̇1| below which an impact may end in rest [rad/s]
    output_step : time step of the stored histories [s]
    max_events : the analysis stops with a solver error beyond this many events, the devices'
        changes of branch included [-]
    """

    scheme: int
    step: float
    rtol: float
    atol: float
    max_step: float
    event_tol: float
    bisection: bool
    turning_points: bool
    rest_velocity: float
    output_step: float
    max_events: int


class Laws(NamedTuple):
    """Event laws of one bridge, from `impacts` (signs as in the core's frame).

    Attributes
    ----------
    onset_p, onset_n : signed onset thresholds (Eq. 8) [m/s²]
    eta_p, eta_n : restitution of the impact that ends mode p / mode n [-]
    pounding : velocity ratio at a deck–backwall pounding (Eq. 20) [-]
    """

    onset_p: float
    onset_n: float
    eta_p: float
    eta_n: float
    pounding: float


class Integration(NamedTuple):
    """What `integrate` returns.

    Attributes
    ----------
    theta1, rate : histories of θ1 [rad] and θ̇1 [rad/s] every ``output_step`` from t = 0; NaN
        after a failure or a solver error
    mode : rocking mode at each sample, 0 at rest [-]
    events : event log, one row per event, columns `EVENT_TIME` … `EVENT_RATE_AFTER`
    peaks : (len(`PEAK_NAMES`), 2): each quantity's peak and its time [s]
    end_time : time at which the integration stopped [s]
    failure : the failure event (`ABUTMENT_FAILURE`, `PIER1_OVERTURNING`, `PIER2_OVERTURNING`) or
        `NOT_FAILED`
    steps, rejected : steps taken and rejected by the error control [-]
    error : `NO_ERROR` or why the integrator stopped early (`SOLVER_ERRORS`)
    device_peaks : one row per device (`device_mechanics.PEAK_LENGTH` …), none without devices
    device_histories : (samples, devices, 3): each device's force [N], elongation [m] and plastic
        elongation [m] at the samples (`device_histories.HISTORY_FORCE` …), NaN where θ1 is; no
        device column without devices
    devices : the devices' table (`devices.table`) in its state at the end (branch, plastic
        elongation Δp, …), None without devices
    """

    theta1: np.ndarray
    rate: np.ndarray
    mode: np.ndarray
    events: np.ndarray
    peaks: np.ndarray
    end_time: float
    failure: int
    steps: int
    rejected: int
    error: int
    device_peaks: np.ndarray
    devices: np.ndarray | None
    device_histories: np.ndarray


class Problem(NamedTuple):
    """What stays fixed for a whole integration: the arguments of `integrate` but the initial
    state, the ground motion as a `schemes.Ground`."""

    model: Model
    laws: Laws
    kin: Kinematics
    ground: Ground
    settings: Settings
    devices: np.ndarray | None


class Motion(NamedTuple):
    """Where the integration stands between two steps.

    Attributes
    ----------
    t : time [s]
    k : the sample interval that holds t (at a sample, the one it starts) [-]
    state : θ1, θ̇1 and θ̈1 (`schemes.State`; θ̈1 NaN at rest)
    g : the watched functions at ``state`` (`events.watched`; zeros at rest)
    sample : the next history sample to write [-]
    """

    t: float
    k: int
    state: State
    g: tuple[float, float, float, float, float, float]
    sample: int


class Histories(NamedTuple):
    """The histories `integrate` writes in place: ``theta1``, ``rate`` and ``mode``, as in
    `Integration`."""

    theta1: np.ndarray
    rate: np.ndarray
    mode: np.ndarray


class Log(NamedTuple):
    """The event log: ``rows`` (columns `EVENT_TIME` … `EVENT_RATE_AFTER`, more than are written,
    grown as needed) and the number of rows ``written`` [-]."""

    rows: np.ndarray
    written: int


_AT_REST = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
"""`Motion.g` at rest, where nothing is watched (and of a motion not yet `_refreshed`)."""


@jit
def _refreshed(segment: Segment, kin: Kinematics, ground: Ground, motion: Motion) -> Motion:
    """``motion`` with θ̈1 and the watched functions at its state filled in (none at rest, nor at
    the record's end)."""
    t, k, (theta, rate, _), _, sample = motion
    if segment.s == 0.0 or k >= ground.acc.size - 1:
        return motion
    accel = accel_called(segment, kin, ground, k, t, theta, rate)
    g = watched(segment, kin, theta, rate)[0]
    return Motion(t, k, State(theta, rate, accel), g, sample)


@inlined
def _logged(log: Log, t: float, kind: int, s: float, before: float, after: float) -> Log:
    """The log with an event of ``kind`` (`EVENT_NAMES`) at time t [s] written: mode s after it,
    θ̇1 before and after it [rad/s]."""
    log.rows[log.written, EVENT_TIME] = t
    log.rows[log.written, EVENT_KIND] = kind
    log.rows[log.written, EVENT_MODE] = s
    log.rows[log.written, EVENT_RATE_BEFORE] = before
    log.rows[log.written, EVENT_RATE_AFTER] = after
    return Log(log.rows, log.written + 1)


@jit
def _grown(log: Log, most: int) -> Log:
    """The log with twice the rows (at most ``most``)."""
    grown = np.zeros((min(2 * log.rows.shape[0], most), log.rows.shape[1]))
    grown[: log.rows.shape[0]] = log.rows
    return Log(grown, log.written)


@inlined
def _room(log: Log, most: int) -> Log:
    """The log, grown (`_grown`) if it might not hold the events of one more pass of the
    integrator's loop."""
    if log.rows.shape[0] >= log.written + _EVENTS_PER_ITERATION or log.rows.shape[0] >= most:
        return log
    return _grown(log, most)


@jit
def _started(problem: Problem, theta0: float, omega0: float):
    """The histories, the peaks, the segment, the motion and the log at t = 0: at rest, or rocking
    in the mode of the sign of the initial state (θ1, θ̇1) = (theta0, omega0) [rad, rad/s], which
    is logged as an onset. Sample 0 of the histories is written (and again by the first step)."""
    model, settings = problem.model, problem.settings
    t_end = (problem.ground.acc.size - 1) * problem.ground.dt
    n_out = int(np.floor(t_end / settings.output_step + 1e-9)) + 1
    histories = Histories(np.zeros(n_out), np.zeros(n_out), np.zeros(n_out, dtype=np.int8))
    peaks = np.zeros((len(PEAK_NAMES), 2))
    log = Log(np.zeros((min(_EVENT_ROWS, settings.max_events), 5)), 0)
    s = np.sign(theta0) if theta0 != 0.0 else np.sign(omega0)
    deck = displacements(model, s, theta0, problem.kin).u_deck
    segment = Segment(model, s, model.u_jo <= 0.0 or abs(deck) > model.u_jo, problem.devices)
    histories.theta1[0], histories.rate[0], histories.mode[0] = theta0, omega0, np.int8(s)
    if s != 0.0:
        log = _logged(log, 0.0, ONSET, s, 0.0, omega0)
        peaks[_THETA1_PEAK, 0] = abs(theta0)
    motion = Motion(0.0, 0, State(theta0, omega0, np.nan), _AT_REST, 0)
    motion = _refreshed(segment, problem.kin, problem.ground, motion)
    return histories, peaks, segment, motion, log


@jit
def _next_onset(ground, g: float, onset_p: float, onset_n: float, k: int, t: float):
    """At rest from time t in sample interval k: the mode (±1, or 0 if none before the record
    ends), the time and the interval of the next onset (Eq. 8: the thresholds ``onset_p`` and
    ``onset_n`` [m/s²]) on the piecewise-linear motion.

    Under a vertical ground acceleration the thresholds are times (g + ü_v)/g (`lift_at`, ``g``
    the model's gravity [m/s²]), linear between samples too, so that the crossing stays exact;
    without one the factors are the constant 1, which the compiler folds away."""
    acc, dt = ground.acc, ground.dt
    while k < acc.size - 1:
        start = max(t, k * dt)
        a0, lift0 = ground_at(acc, dt, k, start), lift_at(ground, g, k, start)
        a1, lift1 = acc[k + 1], lift_at(ground, g, k, (k + 1) * dt)
        if a0 > onset_p * lift0 or a0 < onset_n * lift0:
            return (1.0 if a0 > onset_p * lift0 else -1.0), start, k
        if a1 > onset_p * lift1 or a1 < onset_n * lift1:
            s = 1.0 if a1 > onset_p * lift1 else -1.0
            target = onset_p if s > 0.0 else onset_n
            before, after = target * lift_at(ground, g, k, k * dt), target * lift1  # thresholds
            rise = (a1 - acc[k]) - (after - before)  # of ü_g less the threshold over the interval
            t = min(max(t, k * dt + dt * (before - acc[k]) / rise), (k + 1) * dt)
            return s, t, k
        k += 1
    return 0.0, t, k


@jit
def _onset(problem: Problem, motion: Motion, log: Log, samples: int):
    """At rest: the segment and the motion from the next onset (Eq. 8) on, and the log with the
    onset; the history samples until then, of the ``samples``, stay zero. Without an onset before
    the record ends, the segment at rest and the motion in the record's last interval."""
    dt = problem.ground.dt
    laws, model = problem.laws, problem.model
    onset_p, onset_n = onsets_at_rest(laws.onset_p, laws.onset_n, model, problem.devices)
    s, t, k = _next_onset(problem.ground, model.g, onset_p, onset_n, motion.k, motion.t)
    segment = Segment(problem.model, s, problem.model.u_jo <= 0.0, problem.devices)
    if s == 0.0:
        return segment, Motion(t, k, motion.state, motion.g, motion.sample), log
    log = _logged(log, t, ONSET, s, 0.0, 0.0)
    sample = motion.sample
    while sample < samples and sample * problem.settings.output_step <= t:
        sample += 1
    if t >= (k + 1) * dt:  # the onset ends its interval
        k += 1
    motion = Motion(t, k, State(0.0, 0.0, np.nan), _AT_REST, sample)
    return segment, _refreshed(segment, problem.kin, problem.ground, motion), log


@inlined
def _controlled(settings: Settings, step: Step, err_y: float, err_w: float, h: float):
    """The verdict on a trial step asked for as h [s], with its error estimates of θ1 [rad] and
    θ̇1 [rad/s]: the step size to ask for next [s], whether DOPRI5's error control rejects the
    step, and `NO_ERROR` or why the integration stops."""
    (y, w, _), (y1, w1, _), h_step = step.start, step.end, step.h
    finite = np.isfinite(y1) and np.isfinite(w1)
    if settings.scheme == RK4:
        return h, False, (NO_ERROR if finite else NON_FINITE_STATE)
    if not finite:
        err_y = np.inf
    scale = max(
        abs(err_y) / (settings.atol + settings.rtol * max(abs(y), abs(y1))),
        abs(err_w) / (settings.atol + settings.rtol * max(abs(w), abs(w1))),
    )
    if not scale <= 1.0:
        h = h_step * (max(0.2, 0.9 * scale**-0.2) if np.isfinite(scale) else 0.2)
        return h, True, (STEP_UNDERFLOW if h < 1e-14 else NO_ERROR)
    # 0.9·scale^(−1/5) ≥ 5 below _FULL_GROWTH: the power, on the chain of every step, is spared
    grown = h_step * (min(5.0, 0.9 * scale**-0.2) if scale >= _FULL_GROWTH else 5.0)
    return (grown if h_step == h else max(h, grown)), False, NO_ERROR


@inlined
def _tracked(theta1: float, d: Displacements):
    """The peak quantities at one state, in the order of `PEAK_NAMES` (absolute values except
    the deck's uplift)."""
    return (
        abs(d.u_deck), d.v_deck, abs(d.theta_deck), abs(theta1), abs(d.theta2), abs(d.u_pier1),
        abs(d.u_pier2),
    )  # fmt: skip


@inlined
def _peaked(peaks: np.ndarray, values, t: float) -> None:
    """Raise each peak in ``peaks`` (one row per `PEAK_NAMES`: value, time [s]) that the
    quantities ``values`` (`_tracked`) at time t exceed."""
    for i in range(len(PEAK_NAMES)):
        if values[i] > peaks[i, 0]:
            peaks[i, 0], peaks[i, 1] = values[i], t


@jit
def _accelerated(problem: Problem, segment: Segment, step: Step) -> Step:
    """The step with θ̈1 at both ends, which its interpolant needs (RK4 leaves it unknown)."""
    if np.isfinite(step.start.accel) and np.isfinite(step.end.accel):
        return step
    (y, w, f0), (y1, w1, f1) = step.start, step.end
    kin, ground, k = problem.kin, problem.ground, step.k
    if not np.isfinite(f0):
        f0 = accel_called(segment, kin, ground, k, step.t, y, w)
    if not np.isfinite(f1):
        f1 = accel_called(segment, kin, ground, k, step.t + step.h, y1, w1)
    return Step(k, step.t, step.h, State(y, w, f0), State(y1, w1, f1))


@jit
def _turning_peaks(problem: Problem, segment: Segment, step: Step, peaks, device_peaks) -> None:
    """Raise the peaks (and the devices' peaks) to their values at the turning point inside a
    step that `events.holds_turning_point`."""
    model, kin, s = problem.model, problem.kin, segment.s
    tau, theta = turning_point(_accelerated(problem, segment, step), s, problem.settings.event_tol)
    _peaked(peaks, _tracked(theta, displacements(model, s, theta, kin)), step.t + tau)
    tracked(problem.devices, device_peaks, model, s, theta, 0.0, step.t + tau, kin)


@uncounted
def _sample(histories: Histories, sample: int, output_step: float, s: float, step: Step, t_new):
    """Write the history samples from ``sample`` on that fall in an accepted step of mode s, which
    ends at t_new [s], by cubic Hermite interpolation between its ends; returns the next sample.

    Called after every step, compiled without reference counting (`_jit.uncounted`): it writes
    into the histories and allocates nothing; counting its three arrays in and out at every call
    took about 3 % of a `fast` solve's CPU (perf, 2026-11-29)."""
    t, tau = step.t, step.h
    (y, w, _), (y1, w1, _) = step.start, step.end
    theta1, rate, mode = histories
    while sample < theta1.size and sample * output_step <= t_new + 1e-12:
        if tau > 0.0:
            x = (sample * output_step - t) / tau
            theta1[sample] = (
                (1.0 + 2.0 * x) * (1.0 - x) ** 2 * y + x * (1.0 - x) ** 2 * tau * w
                + x * x * (3.0 - 2.0 * x) * y1 + x * x * (x - 1.0) * tau * w1
            )  # fmt: skip
            rate[sample] = (
                6.0 * x * (x - 1.0) * (y - y1) / tau
                + (1.0 - x) * (1.0 - 3.0 * x) * w + x * (3.0 * x - 2.0) * w1
            )  # fmt: skip
        else:
            theta1[sample], rate[sample] = y1, w1
        mode[sample] = np.int8(s)
        sample += 1
    return sample


@jit
def _impact(problem: Problem, segment: Segment, motion: Motion, log: Log):
    """An impact at the rocking interfaces ends mode s: θ̇1 ← η_s·θ̇1 and the mode reverses;
    then the chatter guard puts a slow bridge the ground cannot drive back at rest.

    Returns the new mode, θ̇1 [rad/s] and log.
    """
    laws, t, before = problem.laws, motion.t, motion.state.rate
    w = before * (laws.eta_p if segment.s > 0.0 else laws.eta_n)
    s = -segment.s
    log = _logged(log, t, IMPACT, s, before, w)
    acc, dt = problem.ground.acc, problem.ground.dt
    k = min(motion.k, acc.size - 2)
    lift = lift_at(problem.ground, problem.model.g, k, t)
    a_g = ground_at(acc, dt, k, t)
    onset_p, onset_n = onsets_at_rest(laws.onset_p, laws.onset_n, problem.model, problem.devices)
    driven = a_g > onset_p * lift if s > 0.0 else a_g < onset_n * lift
    if abs(w) < problem.settings.rest_velocity and not driven:
        return 0.0, 0.0, _logged(log, t, REST, 0.0, before, 0.0)
    return s, w, log


@inlined
def _failure_event(watch: int) -> int:
    """The failure event of a failure watch."""
    if watch == WATCH_ABUTMENT:
        return ABUTMENT_FAILURE
    if watch == WATCH_PIER1:
        return PIER1_OVERTURNING
    return PIER2_OVERTURNING


@jit
def _applied(problem: Problem, segment: Segment, motion: Motion, log: Log, watch: int):
    """Apply the event of ``watch`` that ends the segment: the state jumps and the event is
    logged (a device's change of branch, `WATCH_DEVICES`, is not: its times are in the devices'
    peaks); then the yielding devices take their branches at the new state
    (`device_events.settle`). Returns the next segment, the motion at its start, the log, and the
    failure event (the segment and motion unchanged) or `NOT_FAILED`."""
    t, s, contact = motion.t, segment.s, segment.contact
    theta, w = motion.state.theta, motion.state.rate
    if watch == WATCH_IMPACT:
        s, w, log = _impact(problem, segment, motion, log)
        theta = 0.0
    elif watch == WATCH_GAP and contact:  # the end gap reopens
        contact = False
        log = _logged(log, t, REOPENING, s, w, w)
    elif watch == WATCH_GAP:  # the deck pounds on the backwall and the gap closes
        before = w
        w *= problem.laws.pounding
        contact = problem.laws.pounding > 0.0
        log = _logged(log, t, POUNDING, s, before, w)
    elif watch != WATCH_DEVICES:  # a failure ends the analysis
        failure = _failure_event(watch)
        return segment, motion, _logged(log, t, failure, s, w, w), failure
    settle(problem.devices, problem.model, s, theta, w, t, problem.kin)  # a device's new branch
    segment = Segment(problem.model, s, contact, problem.devices)
    motion = Motion(t, motion.k, State(theta, w, np.nan), _AT_REST, motion.sample)
    return segment, _refreshed(segment, problem.kin, problem.ground, motion), log, NOT_FAILED


@uncounted
def _rocking(problem: Problem, segment: Segment, motion: Motion, h: float, histories: Histories,
             peaks, device_peaks, device_series):  # fmt: skip
    """Step a segment of mode s from ``motion``, asking first for a step of h [s], until an event
    is due, the record ends or the scheme fails; write the histories (`_sample`) and raise the
    peaks on the way.

    Compiled without reference counting (`_jit.uncounted`), like every kernel of a step, and
    no array is assigned in its loop: numba counts a variable that holds an array in and out at
    every pass of a loop that assigns it anywhere, and in `integrate`'s loop, which assigns the
    event log at the events, that was every step, about 3 % of a `fast` solve's CPU (perf,
    2026-11-29).

    Returns
    -------
    The watch whose event is due at the new motion's time (−1: none, the record ended or the
    scheme failed), the new `Motion`, the step size to ask for next [s], the steps tried and
    rejected [-], and `NO_ERROR` or why the integration stops (the motion is then the last
    accepted).
    """
    model, kin, ground, settings, devices = (
        problem.model, problem.kin, problem.ground, problem.settings, problem.devices
    )  # fmt: skip
    dt, end_of_record = ground.dt, ground.acc.size - 1
    theta1, rate, _ = histories
    steps, rejected, error = 0, 0, NO_ERROR
    while motion.k < end_of_record:
        # A step of the h the scheme asks for, never past the end of the sample interval.
        k, t, start = motion.k, motion.t, motion.state
        boundary = (k + 1) * dt
        h_step = min(h, settings.max_step, boundary - t)
        end, err_y, err_w = take_step(segment, kin, ground, k, t, start, h_step, settings.scheme)
        step = Step(k, t, h_step, start, end)
        h, rejection, error = _controlled(settings, step, err_y, err_w, h)
        steps, rejected = steps + 1, rejected + rejection
        if error != NO_ERROR:
            break
        if rejection:
            continue
        watch, step, g_end, d = first_event(segment, kin, ground, step, motion.g, settings)
        t = boundary if (watch < 0 and step.h == boundary - t) else t + step.h
        sample = _sample(histories, motion.sample, settings.output_step, segment.s, step, t)
        sampled(devices, device_series, model, segment.s, theta1, rate, motion.sample, sample, kin)
        if settings.turning_points and holds_turning_point(segment.s, step):
            _turning_peaks(problem, segment, step, peaks, device_peaks)
        _peaked(peaks, _tracked(step.end.theta, d), t)
        tracked(devices, device_peaks, model, segment.s, step.end.theta, step.end.rate, t, kin)
        motion = Motion(t, k + 1 if t >= boundary else k, step.end, g_end, sample)
        if watch >= 0:
            return watch, motion, h, steps, rejected, error
    return -1, motion, h, steps, rejected, error


@jit
def integrate(
    model: Model,
    laws: Laws,
    kin: Kinematics,
    acc: np.ndarray,
    dt: float,
    settings: Settings,
    theta0: float = 0.0,
    omega0: float = 0.0,
    vertical: np.ndarray | None = None,
    devices: np.ndarray | None = None,
) -> Integration:
    """Integrate one ground motion.

    Parameters
    ----------
    model, laws, kin
        The bridge (core frame: tall pier on the left), its onset thresholds and restitution
        coefficients, and how to compute its linkage (`kinematics.Kinematics`).
    acc, dt
        Ground acceleration at uniform samples, positive to the right [m/s²]; their interval [s].
    settings
        `Settings`.
    theta0, omega0
        Initial rotation [rad] and angular velocity [rad/s]; when either is non-zero the bridge
        starts rocking at t = 0 in the mode of their sign (free-vibration tests), else at rest.
    vertical
        Vertical ground acceleration at the same samples, positive up, with g + ü_v > 0 [m/s²];
        None without one (the kernels are then compiled for a `Ground`, else for a
        `VerticalGround`).
    devices
        The piers' tendons, dampers and dissipators (`devices.table`), or None without any (the
        kernels are then compiled without them); the integrator changes the state of a copy.

    Returns
    -------
    `Integration`
    """
    ground = ground_of(acc, dt, vertical)
    devices = fresh(devices)  # its state changes at the events
    problem = Problem(model, laws, kin, ground, settings, devices)
    histories, peaks, segment, motion, log = _started(problem, theta0, omega0)
    device_peaks = peaks_of(devices)
    theta1, rate, mode = histories
    device_series = histories_of(devices, theta1.size)
    h, steps, rejected, error, failure = settings.step, 0, 0, NO_ERROR, NOT_FAILED
    changes = 0  # the devices' changes of branch, which count as events
    while motion.k < acc.size - 1:
        log = _room(log, settings.max_events)
        if segment.s == 0.0:  # at rest until the next onset (or the record's end)
            first = motion.sample
            segment, motion, log = _onset(problem, motion, log, theta1.size)
            sampled(devices, device_series, model, 0.0, theta1, rate, first, motion.sample, kin)
            h = settings.step
            continue
        watch, motion, h, tried, refused, error = _rocking(
            problem, segment, motion, h, histories, peaks, device_peaks, device_series
        )
        steps, rejected = steps + tried, rejected + refused
        if error != NO_ERROR:
            break
        if watch < 0:  # the record's end
            continue
        changes += watch == WATCH_DEVICES  # a device's change of branch is not logged
        if log.written + changes >= settings.max_events - 2:
            error = TOO_MANY_EVENTS
            break
        segment, motion, log, failure = _applied(problem, segment, motion, log, watch)
        if failure != NOT_FAILED:
            break
    if failure != NOT_FAILED or error != NO_ERROR:  # samples after the end are not defined
        theta1[motion.sample :] = np.nan
        rate[motion.sample :] = np.nan
        device_series[motion.sample :] = np.nan
    else:  # at rest from the last onset search on
        sampled(devices, device_series, model, 0.0, theta1, rate, motion.sample, theta1.size, kin)
    events = log.rows[: log.written].copy()
    return Integration(
        theta1,
        rate,
        mode,
        events,
        peaks,
        motion.t,
        failure,
        steps,
        rejected,
        error,
        device_peaks,
        devices,
        device_series,
    )
