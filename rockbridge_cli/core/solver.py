"""Event-driven response-history integration of one bridge under one ground motion.

The response is a chain of smooth segments cut by events (docs/model.md §5–7). The integrator is a
small state machine:

* **at rest** until the ground acceleration, linear between samples, crosses an onset threshold
  (Eq. 8): the crossing time is solved exactly;
* **rocking in mode s** (+1 or −1), integrating θ̈1 = f(θ1, θ̇1, ü_g) with the end gap **open** or
  **closed** (spring–dashpot on), until an event:

  - *impact* at the rocking interfaces (θ1 back to 0): θ̇1 ← η_s·θ̇1, mode ← −s; right after, if
    |θ̇1| is below the rest velocity and the ground cannot drive the new mode, back **at rest**
    (the chatter guard);
  - *pounding* (|u_deck| reaches u_jo from inside): θ̇1 ← ratio·θ̇1, gap closed;
  - *reopening* (|u_deck| back to u_jo): gap open, no impulse;
  - *failure* of the abutment–backfill (|u_deck| = u_jo + u_ab) or overturning of a pier
    (|u_pier| = B): the analysis stops;
  - optionally a *turning point* (θ̇1 = 0) to catch each peak exactly.

Steps never straddle a record sample, so the ground acceleration is linear within each step. An
event is located by re-stepping from the step's start with a shorter step (Illinois regula falsi,
or the paper's plain bisection) until the event time is known to ``event_tol``; the state is then
taken just past the event. Two one-step schemes are available (`schemes`): the classical fixed-step
Runge–Kutta of order 4 (the paper's) and the adaptive embedded Dormand–Prince 5(4) pair
(Dormand & Prince 1980) with error control on θ1 and θ̇1.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from . import quantities
from ._jit import inlined, jit
from .dynamics import acceleration
from .geometry import Model
from .kinematics import Displacements, Kinematics, displacements
from .quantities import PEAK_NAMES
from .schemes import DOPRI5, RK4, ground_at, take_step

ONSET, IMPACT, POUNDING, REOPENING, REST, ABUTMENT_FAILURE, PIER1_OVERTURNING, PIER2_OVERTURNING = (
    range(8)
)
"""Event kinds as the log records them: codes of `quantities.EVENT_NAMES`."""

EVENT_TIME, EVENT_KIND, EVENT_MODE, EVENT_RATE_BEFORE, EVENT_RATE_AFTER = range(5)
"""Columns of the event log: time [s], kind (`EVENT_NAMES`), rocking mode after the event (0 at
rest), θ̇1 before and after it [rad/s]."""

WATCH_IMPACT, WATCH_GAP, WATCH_ABUTMENT, WATCH_PIER1, WATCH_PIER2, WATCH_TURNING = range(6)
"""What the integrator watches while rocking, one signed function each (`_watch`): the return to
θ1 = 0 (an impact), the end gap (closing while open, reopening while closed), the abutment–backfill
limit, the overturning of each pier, and θ̇1 = 0 (a turning point, only when asked for). Events
within the event tolerance of each other are taken in this order."""

NO_ERROR, STEP_UNDERFLOW, TOO_MANY_EVENTS, NON_FINITE_STATE = range(4)
SOLVER_ERRORS = (
    "ok",
    "the step size fell below 1e-14 s",
    "too many events (chattering that the rest guard did not stop)",
    "the state became non-finite",
)
"""Why the integrator stopped before the end of the record, by code (`NO_ERROR` is none)."""

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


class Settings(NamedTuple):
    """The fidelity knobs of one analysis, as the solver reads them (`fidelity.settings`).

    Attributes
    ----------
    scheme : `RK4` (fixed step) or `DOPRI5` (adaptive) [-]
    step : fixed step (RK4) or first trial step (DOPRI5) [s]
    rtol, atol : relative and absolute (θ1 [rad], θ̇1 [rad/s]) tolerances of DOPRI5 [-]
    max_step : largest step [s]
    event_tol : event times are located to within this [s]
    bisection : True for the paper's bisection, False for Illinois regula falsi
    turning_points : locate every θ̇1 = 0 to catch the peaks exactly
    rest_velocity : chatter guard, |θ̇1| below which an impact may end in rest [rad/s]
    output_step : time step of the stored histories [s]
    max_events : the analysis stops with a solver error beyond this many events [-]
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


@inlined
def _watch(model, s, contact, y, w, kin):
    """The watched functions at (θ1, θ̇1) = (y, w), indexed by ``WATCH_*``; an event is due when
    its function turns positive. Also returns the `Displacements` there."""
    d = displacements(model, s, y, kin)
    gap = abs(d.u_deck) - model.u_jo
    functions = (
        -s * y,  # WATCH_IMPACT
        -gap if contact else gap,  # WATCH_GAP
        abs(d.u_deck) - (model.u_jo + model.u_ab),  # WATCH_ABUTMENT
        abs(d.u_pier1) - model.B,  # WATCH_PIER1
        abs(d.u_pier2) - model.B if model.m2 > 0.0 else -1.0,  # WATCH_PIER2 (a block has none)
        -s * w,  # WATCH_TURNING
    )
    return functions, d


@inlined
def _fired(before, after, watched, skip):
    """The first of the first ``watched`` functions (other than ``skip``) that turned positive
    over a step, or −1.

    A function that starts a step at exactly zero counts as negative (it is zero right after its
    own event), except the turning point's: a step that starts with θ̇1 = 0 starts at the turning
    point itself (a release from rest), which is not an event.
    """
    for i in range(watched):
        if i != skip and after[i] > 0.0:
            if before[i] < 0.0 or (before[i] == 0.0 and i != WATCH_TURNING):
                return i
    return -1


@inlined
def _tracked(theta1: float, d: Displacements):
    """The peak quantities at one state, in the order of `PEAK_NAMES` (absolute values except
    the deck's uplift)."""
    return (
        abs(d.u_deck), d.v_deck, abs(d.theta_deck), abs(theta1), abs(d.theta2), abs(d.u_pier1),
        abs(d.u_pier2),
    )  # fmt: skip


@inlined
def _failure_event(watch: int) -> int:
    """The failure event of a failure watch."""
    if watch == WATCH_ABUTMENT:
        return ABUTMENT_FAILURE
    if watch == WATCH_PIER1:
        return PIER1_OVERTURNING
    return PIER2_OVERTURNING


@jit
def _locate(
    model, kin, s, contact, acc, dt, k, t, y, w, f0, h, watch, glo, ghi, y1, w1, f1, settings
):
    """Length τ ≤ h of the step that ends just past the event of ``watch``, and the state there
    (θ1, θ̇1, θ̈1).

    The event function is ``glo`` ≤ 0 at the step's start (state ``y, w``, θ̈1 = ``f0``) and
    ``ghi`` > 0 after the full step (state ``y1, w1, f1``). Each trial re-steps from t. When the
    function starts at exactly zero (right after another event) a point where it is negative is
    searched first by halving; if none is found above the event tolerance, the event happens at
    once (τ = 0).

    Illinois regula falsi is led by an estimate of the event time (`_estimated_event`), corrected
    by Newton's method after each trial: the first trials straddle it, just past it by a twentieth
    of the event tolerance and before it by nine tenths, so that most events take two or three
    trials instead of ten and end a small fraction of the tolerance past the event.
    """
    lo, hi = 0.0, h
    if glo == 0.0:
        while hi > settings.event_tol:
            probe = 0.5 * hi
            yp, wp, _, _, fp = take_step(
                model, kin, s, contact, acc, dt, k, t, y, w, f0, probe, settings.scheme
            )
            gp = _watch(model, s, contact, yp, wp, kin)[0][watch]
            if gp < 0.0:
                lo, glo = probe, gp
                break
            hi, ghi, y1, w1, f1 = probe, gp, yp, wp, fp
        if glo == 0.0:
            return 0.0, y, w, f0
    estimate, slope = -1.0, 0.0
    if not settings.bisection:
        estimate, slope = _estimated_event(
            model, kin, s, contact, watch, y, w, f0, y1, w1, f1, lo, hi, settings.event_tol
        )
    side = trials = 0
    while hi - lo > settings.event_tol:
        if settings.bisection:
            mid = 0.5 * (lo + hi)
        else:
            mid = hi - ghi * (hi - lo) / (ghi - glo)
            mid = min(max(mid, lo + 0.01 * (hi - lo)), hi - 0.01 * (hi - lo))
            if trials < _ESTIMATED_TRIALS and slope > 0.0:
                straddle = estimate + (-0.9 if side == 1 else 0.05) * settings.event_tol
                if lo < straddle < hi:
                    mid = straddle
        ym, wm, _, _, fm = take_step(
            model, kin, s, contact, acc, dt, k, t, y, w, f0, mid, settings.scheme
        )
        gm = _watch(model, s, contact, ym, wm, kin)[0][watch]
        trials += 1
        estimate = mid - gm / slope if slope > 0.0 else estimate
        if gm > 0.0:
            hi, ghi, y1, w1, f1 = mid, gm, ym, wm, fm
            if side == 1:
                glo *= 0.5  # Illinois: halve the value at the end that stayed
            side = 1
        else:
            lo, glo = mid, gm
            if side == -1:
                ghi *= 0.5
            side = -1
    return hi, y1, w1, f1


_ESTIMATED_TRIALS = 4
"""Trials of an event's location placed by its estimated time (`_locate`); Illinois after them."""


@inlined
def _interpolated(y, w, f0, y1, w1, f1, h, tau):
    """(θ1, θ̇1) at τ in a step of length h, on the quintic Hermite interpolant of (θ1, θ̇1, θ̈1)
    at its ends: within O(h⁶) of the solution, which is smooth inside a step."""
    x = tau / h
    v0, v1, a0, a1, rise = h * w, h * w1, h * h * f0, h * h * f1, y1 - y
    c3 = 10.0 * rise - 6.0 * v0 - 4.0 * v1 - 1.5 * a0 + 0.5 * a1
    c4 = -15.0 * rise + 8.0 * v0 + 7.0 * v1 + 1.5 * a0 - a1
    c5 = 6.0 * rise - 3.0 * v0 - 3.0 * v1 - 0.5 * a0 + 0.5 * a1
    theta = y + x * (v0 + x * (0.5 * a0 + x * (c3 + x * (c4 + x * c5))))
    rate = (v0 + x * (a0 + x * (3.0 * c3 + x * (4.0 * c4 + x * 5.0 * c5)))) / h
    return theta, rate


@jit
def _estimated_event(model, kin, s, contact, watch, y, w, f0, y1, w1, f1, lo, hi, tol):
    """Estimated time of the event of ``watch`` in (lo, hi) and the event function's slope there
    [1/s], from the step's interpolant (`_interpolated`, ends at 0 and hi); (−1, 0) when there is
    none (RK4 leaves θ̈1 unknown, or the interpolant does not cross zero)."""
    if not (np.isfinite(f0) and np.isfinite(f1)):
        return -1.0, 0.0
    h = hi
    yl, wl = _interpolated(y, w, f0, y1, w1, f1, h, lo)
    glo = _watch(model, s, contact, yl, wl, kin)[0][watch]
    ghi = _watch(model, s, contact, y1, w1, kin)[0][watch]
    if not (glo <= 0.0 < ghi):
        return -1.0, 0.0
    side = 0
    for _ in range(60):  # Illinois on the interpolant
        if hi - lo <= 0.01 * tol:
            break
        mid = hi - ghi * (hi - lo) / (ghi - glo)
        mid = min(max(mid, lo + 0.01 * (hi - lo)), hi - 0.01 * (hi - lo))
        ym, wm = _interpolated(y, w, f0, y1, w1, f1, h, mid)
        gm = _watch(model, s, contact, ym, wm, kin)[0][watch]
        if gm > 0.0:
            hi, ghi = mid, gm
            if side == 1:
                glo *= 0.5
            side = 1
        else:
            lo, glo = mid, gm
            if side == -1:
                ghi *= 0.5
            side = -1
    estimate = 0.5 * (lo + hi)
    delta = 1e-6 * h
    ya, wa = _interpolated(y, w, f0, y1, w1, f1, h, estimate - delta)
    yb, wb = _interpolated(y, w, f0, y1, w1, f1, h, estimate + delta)
    ga = _watch(model, s, contact, ya, wa, kin)[0][watch]
    gb = _watch(model, s, contact, yb, wb, kin)[0][watch]
    return estimate, (gb - ga) / (2.0 * delta)


@jit
def _grown(events, most):
    """The event log with twice the rows (at most ``most``), its rows kept."""
    grown = np.zeros((min(2 * events.shape[0], most), events.shape[1]))
    grown[: events.shape[0]] = events
    return grown


@jit
def _log(events, n, t, kind, s, before, after):
    """Write event n of ``kind`` (`EVENT_NAMES`) to the log; returns n + 1."""
    events[n, EVENT_TIME] = t
    events[n, EVENT_KIND] = kind
    events[n, EVENT_MODE] = s
    events[n, EVENT_RATE_BEFORE] = before
    events[n, EVENT_RATE_AFTER] = after
    return n + 1


@jit
def _next_onset(acc, dt, laws, k, t):
    """At rest from time t in sample interval k: the mode (±1, or 0 if none before the record
    ends), the time and the interval of the next onset (Eq. 8) on the piecewise-linear motion."""
    while k < acc.size - 1:
        a0 = ground_at(acc, dt, k, max(t, k * dt))
        a1 = acc[k + 1]
        if a0 > laws.onset_p or a0 < laws.onset_n:
            return (1.0 if a0 > laws.onset_p else -1.0), max(t, k * dt), k
        if a1 > laws.onset_p or a1 < laws.onset_n:
            s = 1.0 if a1 > laws.onset_p else -1.0
            target = laws.onset_p if s > 0.0 else laws.onset_n
            t = min(max(t, k * dt + dt * (target - acc[k]) / (a1 - acc[k])), (k + 1) * dt)
            return s, t, k
        k += 1
    return 0.0, t, k


@inlined
def _controlled(settings, y, w, y1, w1, err_y, err_w, h, h_step):
    """DOPRI5's error control after a trial step of h_step: (accepted, next step size)."""
    scale = max(
        abs(err_y) / (settings.atol + settings.rtol * max(abs(y), abs(y1))),
        abs(err_w) / (settings.atol + settings.rtol * max(abs(w), abs(w1))),
    )
    if not scale <= 1.0:
        return False, h_step * (max(0.2, 0.9 * scale**-0.2) if np.isfinite(scale) else 0.2)
    grown = h_step * (min(5.0, 0.9 * scale**-0.2) if scale > 0.0 else 5.0)
    return True, (grown if h_step == h else max(h, grown))


@jit
def _first_event(
    model, kin, s, contact, acc, dt, k, t, y, w, f0, g0, h, y1, w1, f1, watched, settings
):
    """The first event due within a step of length h from t, if any.

    ``g0`` are the watched functions at the step's start, (y1, w1, f1) the state after the full
    step. Returns the watch that fired (−1: none), the length τ of the step to take (just past
    that event, or h), the state there (θ1, θ̇1, θ̈1) and its watched functions and
    `Displacements`. When another event fires earlier inside a shortened step, that one is
    located instead; two events within the event tolerance of each other are simultaneous, and
    the first in the ``WATCH_*`` order is taken.
    """
    g1, d1 = _watch(model, s, contact, y1, w1, kin)
    tau = h
    watch = _fired(g0, g1, watched, -1)
    previous = -1
    while watch >= 0:
        located, y1, w1, f1 = _locate(
            model, kin, s, contact, acc, dt, k, t, y, w, f0, tau, watch, g0[watch], g1[watch],
            y1, w1, f1, settings,
        )  # fmt: skip
        g1, d1 = _watch(model, s, contact, y1, w1, kin)
        if previous >= 0 and tau - located <= settings.event_tol:
            return min(watch, previous), located, y1, w1, f1, g1, d1
        tau = located
        earlier = _fired(g0, g1, watched, watch)
        if earlier < 0:
            break
        previous, watch = watch, earlier
    return watch, tau, y1, w1, f1, g1, d1


@jit
def _sample(theta1, rate, mode, next_out, output_step, s, t, tau, t_new, y, w, y1, w1):
    """Write the history samples that fall in the accepted step (t, t_new], by cubic Hermite
    interpolation between its ends (θ1, θ̇1) = (y, w) and (y1, w1); returns the next sample."""
    while next_out < theta1.size and next_out * output_step <= t_new + 1e-12:
        if tau > 0.0:
            x = (next_out * output_step - t) / tau
            theta1[next_out] = (
                (1.0 + 2.0 * x) * (1.0 - x) ** 2 * y + x * (1.0 - x) ** 2 * tau * w
                + x * x * (3.0 - 2.0 * x) * y1 + x * x * (x - 1.0) * tau * w1
            )  # fmt: skip
            rate[next_out] = (
                6.0 * x * (x - 1.0) * (y - y1) / tau
                + (1.0 - x) * (1.0 - 3.0 * x) * w + x * (3.0 * x - 2.0) * w1
            )  # fmt: skip
        else:
            theta1[next_out], rate[next_out] = y1, w1
        mode[next_out] = np.int8(s)
        next_out += 1
    return next_out


@jit
def _impact(events, n_events, t, s, w, laws, acc, dt, k, settings):
    """An impact at the rocking interfaces ends mode s: θ̇1 ← η_s·θ̇1 and the mode reverses;
    then the chatter guard puts a slow bridge the ground cannot drive back at rest.

    Returns the new mode, θ̇1 and event count.
    """
    before = w
    w *= laws.eta_p if s > 0.0 else laws.eta_n
    s = -s
    n_events = _log(events, n_events, t, IMPACT, s, before, w)
    ground = ground_at(acc, dt, min(k, acc.size - 2), t)
    driven = ground > laws.onset_p if s > 0.0 else ground < laws.onset_n
    if abs(w) < settings.rest_velocity and not driven:
        s, w = 0.0, 0.0
        n_events = _log(events, n_events, t, REST, 0.0, before, 0.0)
    return s, w, n_events


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
) -> Integration:
    """Integrate one ground motion.

    Parameters
    ----------
    model
        The bridge (core frame: tall pier on the left).
    laws
        Onset thresholds and restitution coefficients.
    kin
        How to compute the linkage (`kinematics.Kinematics`: exact, the paper's fits, tables).
    acc
        Ground acceleration at uniform samples, positive to the right [m/s²].
    dt
        Sample interval [s].
    settings
        `Settings`.
    theta0, omega0
        Initial rotation [rad] and angular velocity [rad/s]; when either is non-zero the bridge
        starts rocking at t = 0 in the mode of their sign (free-vibration tests), else at rest.

    Returns
    -------
    `Integration`
    """
    t_end = (acc.size - 1) * dt
    n_out = int(np.floor(t_end / settings.output_step + 1e-9)) + 1
    theta1 = np.zeros(n_out)
    rate = np.zeros(n_out)
    mode = np.zeros(n_out, dtype=np.int8)
    most = settings.max_events
    events = np.zeros((min(_EVENT_ROWS, most), 5))
    peaks = np.zeros((len(PEAK_NAMES), 2))
    n_events = next_out = steps = rejected = 0
    error, failure = NO_ERROR, NOT_FAILED
    watched = WATCH_TURNING + 1 if settings.turning_points else WATCH_TURNING
    t, k, y, w, h = 0.0, 0, theta0, omega0, settings.step
    # θ̈1 and the watched functions at the current state, carried from one step to the next
    # (known = False after anything that changes the state other than a step).
    f0, g0, known = np.nan, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0), False
    s = np.sign(theta0) if theta0 != 0.0 else np.sign(omega0)
    contact = model.u_jo <= 0.0 or abs(displacements(model, s, y, kin).u_deck) > model.u_jo
    theta1[0], rate[0], mode[0] = y, w, np.int8(s)
    if s != 0.0:
        n_events = _log(events, n_events, 0.0, ONSET, s, 0.0, w)
        peaks[_THETA1_PEAK, 0] = abs(y)
    while k < acc.size - 1:
        if events.shape[0] < n_events + _EVENTS_PER_ITERATION and events.shape[0] < most:
            events = _grown(events, most)
        if s == 0.0:  # at rest until the next onset
            s, t, k = _next_onset(acc, dt, laws, k, t)
            if s == 0.0:
                break
            y, w, h, known = 0.0, 0.0, settings.step, False
            contact = model.u_jo <= 0.0
            n_events = _log(events, n_events, t, ONSET, s, 0.0, 0.0)
            while next_out < n_out and next_out * settings.output_step <= t:
                next_out += 1  # samples at rest stay zero
            if t >= (k + 1) * dt:
                k += 1
                continue

        # Rocking: one step, never past the end of the current sample interval. h is the step the
        # scheme asks for (fixed for RK4), h_step the one taken.
        if not known:
            f0 = acceleration(model, s, y, w, ground_at(acc, dt, k, t), contact, kin)
            g0 = _watch(model, s, contact, y, w, kin)[0]
            known = True
        boundary = (k + 1) * dt
        h_step = min(h, settings.max_step, boundary - t)
        y1, w1, err_y, err_w, f1 = take_step(
            model, kin, s, contact, acc, dt, k, t, y, w, f0, h_step, settings.scheme
        )
        steps += 1
        if not (np.isfinite(y1) and np.isfinite(w1)):
            if settings.scheme == RK4:
                error = NON_FINITE_STATE
                break
            err_y = np.inf
        if settings.scheme == DOPRI5:
            accepted, h = _controlled(settings, y, w, y1, w1, err_y, err_w, h, h_step)
            if not accepted:
                rejected += 1
                if h < 1e-14:
                    error = STEP_UNDERFLOW
                    break
                continue
        watch, tau, y1, w1, f1, g1, d1 = _first_event(
            model,
            kin,
            s,
            contact,
            acc,
            dt,
            k,
            t,
            y,
            w,
            f0,
            g0,
            h_step,
            y1,
            w1,
            f1,
            watched,
            settings,
        )

        # Accept the step: histories and peaks.
        t_new = boundary if (watch < 0 and tau == boundary - t) else t + tau
        next_out = _sample(
            theta1, rate, mode, next_out, settings.output_step, s, t, tau, t_new, y, w, y1, w1
        )
        values = _tracked(y1, d1)
        for i in range(len(PEAK_NAMES)):
            if values[i] > peaks[i, 0]:
                peaks[i, 0], peaks[i, 1] = values[i], t_new
        t, y, w, f0, g0 = t_new, y1, w1, f1, g1
        if t >= boundary:
            k += 1
        if watch < 0 or watch == WATCH_TURNING:  # nothing changes but the peaks
            continue

        # Apply the event: the state changes.
        known = False
        if n_events >= settings.max_events - 2:
            error = TOO_MANY_EVENTS
            break
        if watch == WATCH_IMPACT:
            s, w, n_events = _impact(events, n_events, t, s, w, laws, acc, dt, k, settings)
            y = 0.0
        elif watch == WATCH_GAP and contact:  # the end gap reopens
            contact = False
            n_events = _log(events, n_events, t, REOPENING, s, w, w)
        elif watch == WATCH_GAP:  # the deck pounds on the backwall and the gap closes
            before = w
            w *= laws.pounding
            contact = laws.pounding > 0.0
            n_events = _log(events, n_events, t, POUNDING, s, before, w)
        else:  # a failure ends the analysis
            failure = _failure_event(watch)
            n_events = _log(events, n_events, t, failure, s, w, w)
            break

    if failure != NOT_FAILED or error != NO_ERROR:  # samples after the end are not defined
        theta1[next_out:] = np.nan
        rate[next_out:] = np.nan
    return Integration(
        theta1, rate, mode, events[:n_events].copy(), peaks, t, failure, steps, rejected, error
    )
