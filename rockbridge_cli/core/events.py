"""Event location inside a step of the integrator (`solver`; docs/model.md §11, the events of §5–7).

While the bridge rocks, the integrator watches one signed function per event (`watched`); an event
is due when its function turns positive over a step. `first_event` finds the first one due in a
step; `locate` finds when, by re-stepping from the step's start with shorter steps until the
event time is known to the event tolerance, and returns the step that ends just past it. Two
searches are available: the paper's plain bisection, and Illinois regula falsi (`_narrowed`) led
by an estimate of the event time on the step's quintic interpolant (`interpolated`,
`_estimated_event`). A turning point (θ̇1 = 0), where θ1 peaks but nothing else changes, is not
an event: `turning_point` finds it on the interpolant of the step that holds it.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ._jit import inlined, jit, uncounted
from .device_events import watch as device_watch
from .kinematics import Kinematics, displacements
from .schemes import Segment, Step, take_step

WATCH_IMPACT, WATCH_GAP, WATCH_ABUTMENT, WATCH_PIER1, WATCH_PIER2, WATCH_DEVICES = range(6)
"""What the integrator watches while rocking, one signed function each (`watched`): the return to
θ1 = 0 (an impact), the end gap (closing while open, reopening while closed), the abutment–backfill
limit, the overturning of each pier, and a yielding device's change of branch
(`device_events.watch`: the constant −1 without devices). Events within the event tolerance of
each other are taken in this order, except the two piers' overturning, taken in the order of
their limits in θ1 (`_first_of`)."""

_ESTIMATED_TRIALS = 4
"""Trials of an event's location placed by its estimated time (`locate`); Illinois after them."""


@inlined
def watched(segment: Segment, kin: Kinematics, theta: float, rate: float):
    """The watched functions at (θ1, θ̇1) = (theta, rate), indexed by ``WATCH_*``; an event is due
    when its function turns positive. Also returns the `kinematics.Displacements` there."""
    model, s = segment.model, segment.s
    d = displacements(model, s, theta, kin)
    gap = abs(d.u_deck) - model.u_jo
    functions = (
        -s * theta,  # WATCH_IMPACT
        -gap if segment.contact else gap,  # WATCH_GAP
        abs(d.u_deck) - (model.u_jo + model.u_ab),  # WATCH_ABUTMENT
        abs(d.u_pier1) - model.B,  # WATCH_PIER1
        abs(d.u_pier2) - model.B if model.m2 > 0.0 else -1.0,  # WATCH_PIER2 (a block has none)
        device_watch(segment.devices, model, s, theta, rate, kin),  # WATCH_DEVICES
    )
    return functions, d


@jit
def watched_one(segment: Segment, kin: Kinematics, theta: float, rate: float, watch: int) -> float:
    """The function of ``watch`` alone at (θ1, θ̇1) = (theta, rate), bit for bit `watched`'s:
    an impact's without the displacements of the linkage, which only the others need (locating
    an impact evaluates its function a dozen times).

    Called, not inlined: it runs where an event is located, not at every step, and each call
    site of an inlined `watched` is typed and compiled again (with `_past_limit`'s six, the
    search for a step's first event took 29 % of the kernels' compile,
    `benchmarks/bench_compile.py`)."""
    if watch == WATCH_IMPACT:
        return -segment.s * theta
    return watched(segment, kin, theta, rate)[0][watch]


@inlined
def _fired(before, after, skip: int) -> int:
    """The first of the watched functions (other than ``skip``) that turned positive over a
    step, or −1. A function that starts a step at exactly zero counts as negative: it is zero
    right after its own event."""
    for i in range(len(after)):
        if i != skip and after[i] > 0.0 and before[i] <= 0.0:
            return i
    return -1


class Bracket(NamedTuple):
    """Where an event lies in a step: its watched function is ≤ 0 at ``lo`` and > 0 at ``hi``.

    Attributes
    ----------
    lo, hi : times from the step's start [s]
    g_lo, g_hi : the function's values there, as Illinois scales them
    side : the end that moved last (+1 ``hi``, −1 ``lo``, 0 neither yet)
    """

    lo: float
    hi: float
    g_lo: float
    g_hi: float
    side: int


@inlined
def _falsi(b: Bracket) -> float:
    """The regula falsi point of a bracket, kept a hundredth of its width inside it [s]."""
    mid = b.hi - b.g_hi * (b.hi - b.lo) / (b.g_hi - b.g_lo)
    return min(max(mid, b.lo + 0.01 * (b.hi - b.lo)), b.hi - 0.01 * (b.hi - b.lo))


@inlined
def _narrowed(b: Bracket, mid: float, g: float) -> Bracket:
    """The bracket after a trial at ``mid`` where the function is ``g``; when the same end moves
    twice in a row, the value at the end that stayed is halved (Illinois)."""
    if g > 0.0:
        return Bracket(b.lo, mid, 0.5 * b.g_lo if b.side == 1 else b.g_lo, g, 1)
    return Bracket(mid, b.hi, g, 0.5 * b.g_hi if b.side == -1 else b.g_hi, -1)


@inlined
def interpolated(step: Step, tau: float):
    """(θ1, θ̇1) at τ [s] into a step, on the quintic Hermite interpolant of (θ1, θ̇1, θ̈1) at its
    ends: within O(h⁶) of the solution, which is smooth inside a step."""
    (y, w, f0), (y1, w1, f1), h = step.start, step.end, step.h
    x = tau / h
    v0, v1, a0, a1, rise = h * w, h * w1, h * h * f0, h * h * f1, y1 - y
    c3 = 10.0 * rise - 6.0 * v0 - 4.0 * v1 - 1.5 * a0 + 0.5 * a1
    c4 = -15.0 * rise + 8.0 * v0 + 7.0 * v1 + 1.5 * a0 - a1
    c5 = 6.0 * rise - 3.0 * v0 - 3.0 * v1 - 0.5 * a0 + 0.5 * a1
    theta = y + x * (v0 + x * (0.5 * a0 + x * (c3 + x * (c4 + x * c5))))
    rate = (v0 + x * (a0 + x * (3.0 * c3 + x * (4.0 * c4 + x * 5.0 * c5)))) / h
    return theta, rate


@inlined
def holds_turning_point(s: float, step: Step) -> bool:
    """Whether a step of mode s holds a turning point: θ̇1 changes sign from rocking away
    (s·θ̇1 > 0) to rocking back, so that θ1 peaks inside it. A step that starts at θ̇1 = 0 (a
    release from rest) starts at one, which it does not count; one that ends at θ̇1 = 0 ends at
    it, where the step's end is taken anyway."""
    return s * step.start.rate > 0.0 and s * step.end.rate < 0.0


@jit
def turning_point(step: Step, s: float, tol: float):
    """The turning point inside a step of mode s that `holds_turning_point`: its time from the
    step's start [s], the root of θ̇1 on the step's interpolant (`interpolated`; θ̈1 known at
    both ends) found by Illinois to ``tol`` [s], and θ1 there [rad].

    Not located by re-stepping, as an event is: nothing jumps at a turning point, and θ1 on the
    interpolant is within 5e-12 (relative) of θ1 after a step of that length at the `default`
    tolerances (FEMA P695 far-field components × the studied bridges, docs/benchmarks.md)."""
    b = Bracket(0.0, step.h, -s * step.start.rate, -s * step.end.rate, 0)
    for _ in range(60):
        if b.hi - b.lo <= tol:
            break
        mid = _falsi(b)
        b = _narrowed(b, mid, -s * interpolated(step, mid)[1])
    tau = 0.5 * (b.lo + b.hi)
    return tau, interpolated(step, tau)[0]


@jit
def _on_interpolant(segment: Segment, kin: Kinematics, step: Step, watch: int, tau: float):
    """The function of ``watch`` τ [s] into a step, on its interpolant (`interpolated`)."""
    theta, rate = interpolated(step, tau)
    return watched_one(segment, kin, theta, rate, watch)


@jit
def _estimated_event(segment: Segment, kin: Kinematics, step: Step, watch: int, lo: float, tol):
    """Estimated time of the event of ``watch`` in (lo, h) of a step [s] and the event function's
    slope there [1/s], from the step's interpolant (`interpolated`); (−1, 0) when there is none
    (RK4 leaves θ̈1 unknown, or the interpolant does not cross zero). ``tol``: the event
    tolerance [s]."""
    if not (np.isfinite(step.start.accel) and np.isfinite(step.end.accel)):
        return -1.0, 0.0
    g_end = watched_one(segment, kin, step.end.theta, step.end.rate, watch)
    ends = Bracket(lo, step.h, _on_interpolant(segment, kin, step, watch, lo), g_end, 0)
    if not (ends.g_lo <= 0.0 < ends.g_hi):
        return -1.0, 0.0
    b = ends
    for _ in range(60):  # Illinois on the interpolant
        if b.hi - b.lo <= 0.01 * tol:
            break
        mid = _falsi(b)
        b = _narrowed(b, mid, _on_interpolant(segment, kin, step, watch, mid))
    estimate = 0.5 * (b.lo + b.hi)
    delta = 1e-6 * step.h
    ga = _on_interpolant(segment, kin, step, watch, estimate - delta)
    gb = _on_interpolant(segment, kin, step, watch, estimate + delta)
    return estimate, (gb - ga) / (2.0 * delta)


@jit
def _left_zero(segment, kin, ground, step: Step, watch: int, b: Bracket, settings):
    """A bracket whose function starts at exactly zero (right after another event): halve the step
    until the function is negative at its middle. Returns the bracket, with ``g_lo`` still zero if
    no such point lies above the event tolerance, and the step that ends at its ``hi``. Arguments
    as in `locate`."""
    while b.hi > settings.event_tol:
        probe = 0.5 * b.hi
        end = take_step(segment, kin, ground, step.k, step.t, step.start, probe, settings.scheme)[0]
        g = watched_one(segment, kin, end.theta, end.rate, watch)
        if g < 0.0:
            return Bracket(probe, b.hi, g, b.g_hi, b.side), step
        b = Bracket(b.lo, probe, b.g_lo, g, b.side)
        step = Step(step.k, step.t, probe, step.start, end)
    return b, step


@jit
def locate(segment, kin, ground, step: Step, watch: int, g_start, g_end, settings) -> Step:
    """The step shortened to end just past the event of ``watch``, and the state there.

    The step is one of a `schemes.Segment` under the `schemes.Ground` motion, with the linkage from
    ``kin`` (`kinematics.Kinematics`) and the knobs of ``settings`` (`solver.Settings`). The event
    function is ``g_start`` ≤ 0 at the step's start and ``g_end`` > 0 at its end. Each trial
    re-steps from the start. When the function starts at exactly zero (right after another event)
    a point where it is negative is searched first (`_left_zero`); if none is found above the
    event tolerance, the event happens at once (a step of length 0).

    Illinois regula falsi is led by an estimate of the event time (`_estimated_event`), corrected
    by Newton's method after each trial: the first trials straddle it, just past it by a twentieth
    of the event tolerance and before it by nine tenths, so that most events take two or three
    trials instead of ten and end a small fraction of the tolerance past the event.
    """
    tol = settings.event_tol
    b = Bracket(0.0, step.h, g_start, g_end, 0)
    if g_start == 0.0:
        b, step = _left_zero(segment, kin, ground, step, watch, b, settings)
        if b.g_lo == 0.0:
            return Step(step.k, step.t, 0.0, step.start, step.start)
    estimate, slope = -1.0, 0.0
    if not settings.bisection:
        estimate, slope = _estimated_event(segment, kin, step, watch, b.lo, tol)
    trials = 0
    while b.hi - b.lo > tol:
        if settings.bisection:
            mid = 0.5 * (b.lo + b.hi)
        else:
            mid = _falsi(b)
            if trials < _ESTIMATED_TRIALS and slope > 0.0:
                straddle = estimate + (-0.9 if b.side == 1 else 0.05) * tol
                if b.lo < straddle < b.hi:
                    mid = straddle
        end = take_step(segment, kin, ground, step.k, step.t, step.start, mid, settings.scheme)[0]
        g = watched_one(segment, kin, end.theta, end.rate, watch)
        trials += 1
        estimate = mid - g / slope if slope > 0.0 else estimate
        if g > 0.0:
            step = Step(step.k, step.t, mid, step.start, end)
        b = _narrowed(b, mid, g)
    return step


@inlined
def _first_of(segment: Segment, kin: Kinematics, theta: float, watch: int, previous: int) -> int:
    """Of two events located within the event tolerance of each other, the one that came first:
    the first in ``WATCH_*`` order, except between the two piers' overturning. Both are functions
    of θ1 alone, so the first is the one whose limit θ1 passed first, the one further past it
    at ``theta``: whatever a preset's tolerance, a bridge whose piers reach their limits a
    nanosecond apart fails the same way (issue 32, finding 16)."""
    if min(watch, previous) != WATCH_PIER1 or max(watch, previous) != WATCH_PIER2:
        return min(watch, previous)
    pier1 = _past_limit(segment, kin, theta, WATCH_PIER1)
    return WATCH_PIER2 if _past_limit(segment, kin, theta, WATCH_PIER2) > pier1 else WATCH_PIER1


@inlined
def _past_limit(segment: Segment, kin: Kinematics, theta: float, watch: int) -> float:
    """How far θ1 = ``theta`` is past the limit of ``watch`` [rad]: its function over the
    function's slope in θ1 (a central difference)."""
    delta = 1e-6 * abs(theta) + 1e-12
    ahead = watched_one(segment, kin, theta + delta, 0.0, watch)
    behind = watched_one(segment, kin, theta - delta, 0.0, watch)
    slope = abs(ahead - behind) / (2.0 * delta)
    g = watched_one(segment, kin, theta, 0.0, watch)
    return g / slope if slope > 0.0 else np.copysign(np.inf, g)


@uncounted
def first_event(segment, kin, ground, step: Step, g_start, settings):
    """The first event due within a step, if any (arguments as in `locate`).

    ``g_start`` are the watched functions at the step's start. Returns the watch that fired
    (−1: none), the step to take (ending just past that event, or the whole step), and the
    watched functions and `kinematics.Displacements` at its end. When another event fires
    earlier inside a shortened step, that one is located instead; two events within the event
    tolerance of each other are simultaneous, and `_first_of` takes one.

    Called after every step, compiled without reference counting (`_jit.uncounted`): most
    steps have no event, and their check is a handful of subtractions, which counting the
    tables' arrays in and out of each look-up outweighed; the search of a step with one
    (`_located_first`) counts its own.
    """
    g_end, d = watched(segment, kin, step.end.theta, step.end.rate)
    watch = _fired(g_start, g_end, -1)
    if watch < 0:
        return watch, step, g_end, d
    return _located_first(segment, kin, ground, step, g_start, g_end, d, watch, settings)


@jit
def _located_first(segment, kin, ground, step: Step, g_start, g_end, d, watch, settings):
    """`first_event` of a step in which ``watch`` fired first at its end, where the watched
    functions are ``g_end`` and the displacements ``d``: the event located, or an earlier one
    that fires inside the shortened step. Returns as `first_event`."""
    previous = -1
    while watch >= 0:
        located = locate(segment, kin, ground, step, watch, g_start[watch], g_end[watch], settings)
        g_end, d = watched(segment, kin, located.end.theta, located.end.rate)
        if previous >= 0 and step.h - located.h <= settings.event_tol:
            return _first_of(segment, kin, located.end.theta, watch, previous), located, g_end, d
        step = located
        earlier = _fired(g_start, g_end, watch)
        if earlier < 0:
            break
        previous, watch = watch, earlier
    return watch, step, g_end, d
