"""The rocking literature's anchors, computed independently of rockbridge's integrator, and the
few calls that put rockbridge beside them. Used by tests/test_overturning.py and printed by
benchmarks/validate_paper.py.

References (closed forms derived here from the equations the papers state; each function says
which):
* Housner (1963), BSSA 53(2) 403–417: the block's equation θ̈ = −p²·[sin(α·sgn θ − θ) +
  (ü_g/g)·cos(α·sgn θ − θ)], p² = 3g/(4R), and its linearised form for slender blocks,
  θ̈ = p²·(θ − α) + p²·ü_g/g for θ > 0 (pulse driving θ > 0).
* Makris & Roussos (2000), Géotechnique 50(3) 243–262; Zhang & Makris (2001), J. Eng. Mech.
  127(5) 473–483: the overturning of a block by one-sine and cycloidal pulses, with and without
  an impact, from the closed-form solution of the linearised equation.
* Dimitrakopoulos & DeJong (2012), Proc. R. Soc. A 468: 2294–2318: similarity of blocks of equal
  α under pulses of equal ω_p/p and a_p/(g·tan α).
* Makris & Vassiliou (2013), Earthq. Eng. Struct. Dyn. 42: 431–449: a symmetric frame with a rigid
  cap rocks as one block of size R·(1 + 3γ)/(1 + 2γ), γ = m_cap/(2·m_column).

In the linearised closed forms lengths of time are in units of 1/p and accelerations in units of
g·α (A = a_p/(g·α), Ω = ω_p/p); in Housner's nonlinear equation, in units of 1/p and g.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from rockbridge_cli.config.spectrum import frequency_parameter
from rockbridge_cli.core.analysis import Response, analyze
from rockbridge_cli.core.bridge import Bridge
from rockbridge_cli.core.geometry import single_block
from rockbridge_cli.motions.pulses import Pulse, type_c_phase

# ---------------------------------------------------------------- linearised closed forms


def housner_rectangular(p_t1: float) -> float:
    """Least A = a_p/(g·α) that overturns a slender block by a rectangular pulse of duration t1:
    A = 1/(1 − e^(−p·t1)). With x = α − θ, the linearised equation is ẍ = p²·x − p²·a/g; the
    block starts at x = α, ẋ = 0; s = ẋ + p·x obeys ṡ = p·s − p²·a/g, and the free motion after
    the pulse reaches x = 0 (θ = α) exactly when s ≤ 0 at the pulse's end."""
    return 1.0 / (1.0 - math.exp(-p_t1))


def housner_half_sine(omega_ratio: float) -> float:
    """Least A that overturns a slender block by a half-sine pulse a_p·sin(ω·t), 0 ≤ t ≤ π/ω:
    the root of √(A² − 1) + A·exp(−(π − asin(1/A))/Ω) = Ω (the criterion s ≤ 0 of
    `housner_rectangular`, integrated from the uplift at sin(ω·t) = 1/A). For long pulses
    (Ω → 0) it tends to √(1 + Ω²)."""
    omega = omega_ratio

    def excess(a: float) -> float:
        return (
            math.sqrt(a * a - 1.0) + a * math.exp(-(math.pi - math.asin(1.0 / a)) / omega) - omega
        )

    return brentq(excess, 1.0, omega + 2.0, xtol=1e-15, rtol=1e-14)


def linear_overturns_without_impact(
    amplitude: float, omega_ratio: float, phase: float, duration: float, points: int = 20001
) -> bool:
    """Whether a slender block overturns without any impact under a_p·sin(ω·t + φ), 0 ≤ t ≤
    ``duration`` (in 1/p), by the closed-form solution of the linearised equation (Makris &
    Roussos 2000; Zhang & Makris 2001).

    From the uplift (the first t where A·|sin(ω·t + φ)| ≥ 1, direction σ), with y = 1 − σθ/α and
    the forcing F = σA·sin(Ω·τ + φ): s = y' + y and r = y' − y obey s' = s − F and r' = −r − F,
    solved exactly with ∫e^(kτ)·sin(Ωτ + φ)dτ = e^(kτ)·(k·sin − Ω·cos)/(k² + Ω²). The block
    overturns if y reaches 0 before it returns to 1 during the pulse, or if s ≤ 0 at its end.
    """
    a, omega = amplitude, omega_ratio
    tau = np.linspace(0.0, duration, points)
    forcing = a * np.sin(omega * tau + phase)
    uplifted = np.flatnonzero(np.abs(forcing) >= 1.0)
    if not uplifted.size:
        return False
    start = _crossing(a, omega, phase, tau, uplifted[0])
    sign = math.copysign(1.0, forcing[uplifted[0]])
    tau = np.linspace(start, duration, points)

    def integral(k: float, t: np.ndarray) -> np.ndarray:  # ∫_start^t e^(k(u−start))·F(u) du
        def primitive(u):
            angle = omega * u + phase
            return np.exp(k * (u - start)) * (k * np.sin(angle) - omega * np.cos(angle))

        return sign * a * (primitive(t) - primitive(start)) / (k * k + omega * omega)

    s = np.exp(tau - start) * (1.0 - integral(-1.0, tau))  # s(start) = 1
    r = np.exp(start - tau) * (-1.0 - integral(1.0, tau))  # r(start) = −1
    y, rate = 0.5 * (s - r), 0.5 * (s + r)
    over = np.flatnonzero(y <= 0.0)
    back = np.flatnonzero((y >= 1.0) & (rate > 0.0) & (tau > start))
    if over.size or back.size:
        return bool(over.size) and (not back.size or over[0] < back[0])
    return bool(s[-1] <= 0.0)


def _crossing(a: float, omega: float, phase: float, tau: np.ndarray, index: int) -> float:
    """The uplift time between grid points: where a·|sin(Ωτ + φ)| = 1 (0 if already at τ = 0)."""
    if index == 0:
        return 0.0
    level = math.copysign(1.0, math.sin(omega * tau[index] + phase))
    return brentq(lambda t: a * math.sin(omega * t + phase) - level, tau[index - 1], tau[index],
                  xtol=1e-15)  # fmt: skip


def least(overturns: Callable[[float], bool], low: float, high: float, rtol: float) -> float:
    """The least amplitude in (low, high] at which ``overturns`` holds, by bisection (it must not
    hold at ``low`` and hold at ``high``)."""
    assert not overturns(low) and overturns(high), (low, high)
    while high - low > rtol * high:
        middle = 0.5 * (low + high)
        low, high = (low, middle) if overturns(middle) else (middle, high)
    return high


# ---------------------------------------------------------------- Housner's nonlinear block


def exact_rectangular_minimum(alpha: float, p_t1: float) -> float:
    """Least a_p/(g·tan α) that overturns a block of any slenderness by a rectangular pulse, from
    Housner's nonlinear equation by energy: during the pulse (u = a_p/g) θ̇²/(2p²) = K(θ) =
    u·(sin α − sin(α − θ)) − (cos(α − θ) − cos α) = 2·sin(θ/2)·(u·cos(α − θ/2) − sin(α − θ/2)),
    so the time to reach θ is ∫dθ/√(2p²K), a quadrature (Gauss–Legendre, 64 points, in w = √θ,
    where K(w²)/w² is smooth); after it the block topples if K(θ1) ≥ 1 − cos(α − θ1), with
    equality at the least amplitude."""
    nodes, weights = np.polynomial.legendre.leggauss(64)

    def time_to(theta: float, u: float) -> float:
        w = 0.5 * math.sqrt(theta) * (nodes + 1.0)
        half = 0.5 * w * w
        shape = np.where(half > 0.0, np.sin(half) / np.where(half > 0.0, half, 1.0), 1.0)
        slope = shape * (u * np.cos(alpha - half) - np.sin(alpha - half))  # K(w²)/w²
        return float(0.5 * math.sqrt(theta) * np.sum(weights * 2.0 / np.sqrt(2.0 * slope)))

    def margin(ratio: float) -> float:  # energy at the pulse's end beyond what topples it
        u = ratio * math.tan(alpha)
        if time_to(alpha, u) <= p_t1:
            return 1.0  # over the top during the pulse
        theta = brentq(lambda t: time_to(t, u) - p_t1, 0.0, alpha, xtol=1e-15, rtol=1e-15)
        half = 0.5 * theta
        energy = 2.0 * math.sin(half) * (u * math.cos(alpha - half) - math.sin(alpha - half))
        return energy - (1.0 - math.cos(alpha - theta))

    return brentq(margin, 1.0 + 1e-9, 100.0, xtol=1e-14, rtol=1e-14)


class Sinusoid(NamedTuple):
    """u(τ) = amplitude·sin(Ω·τ + φ) for 0 ≤ τ ≤ duration, else 0: the one-sine, one-cosine,
    half-sine and cycloidal pulses as Makris & Roussos (2000) and Zhang & Makris (2001) define
    them, written out here from the papers (motions.pulses is the code under test)."""

    amplitude: float
    omega: float
    phase: float
    duration: float

    @classmethod
    def of(cls, shape: str, amplitude: float, omega: float, cycles: float = 1.0) -> Sinusoid:
        """``one-sine-a`` (sin, N periods), ``one-sine-b`` (cos, N periods) or ``cycloidal-c``
        (cos(ω·t + φ_n) for (n + 1/2 − φ_n/π) periods, 2·cos φ_n = ((2n + 1)π − 2φ_n)·sin φ_n)."""
        period = 2.0 * math.pi / omega
        if shape == "one-sine-a":
            return cls(amplitude, omega, 0.0, cycles * period)
        if shape == "one-sine-b":
            return cls(amplitude, omega, 0.5 * math.pi, cycles * period)
        n = int(cycles)
        phi = brentq(lambda f: 2.0 * math.cos(f) - ((2 * n + 1) * math.pi - 2.0 * f) * math.sin(f),
                     1e-9, 0.5 * math.pi, xtol=1e-15)  # fmt: skip
        return cls(amplitude, omega, 0.5 * math.pi + phi, (n + 0.5 - phi / math.pi) * period)

    def at(self, tau: float) -> float:
        if 0.0 <= tau <= self.duration:
            return self.amplitude * math.sin(self.omega * tau + self.phase)
        return 0.0


def housner_ends(
    alpha: float, eta: float, ground: Sinusoid, end: float, max_impacts: int = 50
) -> tuple[bool, int]:
    """Whether Housner's block overturns under a pulse, and after how many impacts: his nonlinear
    equation θ'' = u·cos(σα − θ) − sin(σα − θ) (σ the side it rocks on, u = ü_g/g, time in 1/p)
    integrated by scipy's DOP853 (rtol 1e-11) from the uplift (σ·u > tan α) to θ = σα
    (overturning) or θ = 0 (an impact, θ' ← η·θ'), until ``end``. Turning points are located
    too: near the least amplitude the block may pass the top within one step and be pulled back
    by the ground, which a check at the steps' ends would miss."""
    tau, theta, rate, side, impacts = 0.0, 0.0, 0.0, 0.0, 0
    while tau < end and impacts <= max_impacts:
        if side == 0.0:
            started = _uplift(alpha, ground, tau)
            if started is None:
                return False, impacts
            tau, side = started
        segment = ground.duration if tau < ground.duration - 1e-12 else end

        def motion(t, y, side=side):
            angle = side * alpha - y[0]
            return (y[1], ground.at(t) * math.cos(angle) - math.sin(angle))

        def top(t, y, side=side):
            return side * y[0] - alpha

        def impact(t, y, side=side, since=tau):
            return side * y[0] if t > since + 1e-12 else 1.0

        def turning(t, y):
            return y[1]

        top.terminal, impact.terminal, impact.direction = True, True, -1
        found = solve_ivp(motion, (tau, segment), (theta, rate), method="DOP853", rtol=1e-11,
                          atol=1e-13, events=(top, impact, turning))  # fmt: skip
        tau, (theta, rate) = found.t[-1], found.y[:, -1]
        grazed = found.y_events[2].size and np.max(side * found.y_events[2][:, 0]) >= alpha
        if found.t_events[0].size or grazed:
            return True, impacts
        if found.t_events[1].size:
            impacts, theta, rate, side = impacts + 1, 0.0, eta * rate, -side
            if abs(rate) < 1e-9:
                side, rate = 0.0, 0.0
    return False, impacts


def _uplift(alpha: float, ground: Sinusoid, after: float) -> tuple[float, float] | None:
    """(time, side) of the first uplift after ``after`` during the pulse, or None."""
    if after >= ground.duration:
        return None
    tau = np.linspace(after, ground.duration, 100001)
    u = ground.amplitude * np.sin(ground.omega * tau + ground.phase)
    beyond = np.flatnonzero(np.abs(u) > math.tan(alpha))
    if not beyond.size:
        return None
    i, side = beyond[0], math.copysign(1.0, u[beyond[0]])
    if i == 0:
        return after, side
    level = side * math.tan(alpha)
    return brentq(lambda t: ground.at(t) - level, tau[i - 1], tau[i], xtol=1e-15), side


# ---------------------------------------------------------------- rockbridge beside them


def under_pulse(
    bridge: Bridge, shape: str, omega_ratio: float, amplitude_ratio: float, *,
    phase: float = 0.0, cycles: float | None = None, samples: int = 2000, rest: float = 3.0,
    preset: str = "default", histories: bool = False, **overrides,
) -> Response:  # fmt: skip
    """rockbridge's response to a pulse at ω_p/p and a_p/(g·tan α1), sampled at about
    T_p/``samples`` (the pulse's end midway between two samples) and followed by ``rest``
    periods 2π/p of rest."""
    model = bridge.model
    p = frequency_parameter(model)
    period = 2.0 * math.pi / (omega_ratio * p)
    pulse = Pulse(shape, amplitude_ratio * model.g * model.B / model.H1, period, phase, cycles)
    step = pulse.time_step(samples)
    return analyze(bridge, pulse.sampled(step, rest * 2.0 * math.pi / p), step, preset,
                   histories=histories, **overrides)  # fmt: skip


def rectangular(amplitude: float, duration: float, samples: int, rest: float) -> tuple:
    """A rectangular pulse as samples (acceleration [m/s²], time step [s]): ``amplitude`` from
    t = 0 to the sample before ``duration``, then 0, with ``duration`` midway between the two, so
    that the piecewise-linear ramp between them has the rectangle's impulse and centre."""
    step = duration / (samples + 0.5)
    motion = np.concatenate([np.full(samples + 1, amplitude), np.zeros(round(rest / step))])
    return motion, step


def toppled(response: Response, without_impact: bool = False) -> bool:
    """Whether a response ends in overturning (and, if asked, without any impact)."""
    return response.failure_mode.startswith("overturning") and not (
        without_impact and response.n_impacts
    )


# ---------------------------------------------------------------- the anchors, one by one

G = 9.81  # the blocks' gravity [m/s²]
SLENDER_ALPHA, STOCKY_ALPHA = 0.02, 0.25  # [rad]
LINEARISATION = SLENDER_ALPHA**2
"""The linearised closed forms neglect terms of order α²: their tolerance at α = 0.02 [-]."""
EXACT = 1e-6
"""Tolerance against exact forms and the independent integrator: pulses sampled at T_p/2000,
whose piecewise-linear interpolant lowers a sine's crest by ~5e-7 [-]."""


class Anchor(NamedTuple):
    """rockbridge beside an independent value: ``found`` agrees with ``expected`` within
    ``tolerance``, relative (or absolute, for a difference expected to be 0)."""

    quantity: str
    expected: float
    found: float
    tolerance: float
    source: str
    absolute: bool = False

    @property
    def agrees(self) -> bool:
        miss = self.found - self.expected
        return abs(miss if self.absolute else miss / self.expected) <= self.tolerance


def block(alpha: float, size: float = 2.0, restitution: float | None = None) -> Bridge:
    """Housner's block of slenderness α and semi-diagonal R = ``size`` [m]."""
    model = single_block(size * math.sin(alpha), size * math.cos(alpha), 2500.0, G)
    return Bridge(model, restitution=restitution)


def frame(cap: float) -> Bridge:
    """A symmetric frame of two 0.8 m × 6 m columns and a rigid cap of ``cap`` columns' mass."""
    column = single_block(0.4, 3.0, 2500.0, G)
    return Bridge(column._replace(m2=column.m1, I2=column.I1, md=cap * column.m1,
                                  Id=column.m1, L2=6.0, h=0.2))  # fmt: skip


def in_tan_alpha(bridge: Bridge, a: float) -> float:
    """A linearised A = a_p/(g·α) as a_p/(g·tan α) of the bridge."""
    alpha = bridge.model.alpha1
    return a * alpha / math.tan(alpha)


def rectangular_pulse(p_t1: float, slender: bool) -> Anchor:
    """Housner (1963): the least a_p/(g·tan α) of a rectangular pulse of duration t1, for the
    slender block from his linearised equation, for the stocky one by energy (exact)."""
    if slender:
        bridge = block(SLENDER_ALPHA)
        expected = in_tan_alpha(bridge, housner_rectangular(p_t1))
        tolerance, samples = LINEARISATION, 500
        source = "Housner (1963) linearised: 1/(1 − e^(−p·t1)); α = 0.02"
    else:
        bridge = block(STOCKY_ALPHA)
        expected, tolerance, samples = exact_rectangular_minimum(STOCKY_ALPHA, p_t1), EXACT, 2000
        source = "Housner's nonlinear equation, by energy (quadrature); α = 0.25"
    model, p = bridge.model, frequency_parameter(bridge.model)

    def overturns(ratio: float) -> bool:
        motion, step = rectangular(ratio * G * model.B / model.H1, p_t1 / p, samples,
                                   3.0 * math.pi / p)  # fmt: skip
        return toppled(analyze(bridge, motion, step, histories=False))

    found = least(overturns, 0.8 * expected, 1.2 * expected, 1e-8)
    return Anchor(f"rectangular pulse, p·t1 = {p_t1:g}, α = {model.alpha1:.2f}: least "
                  "a_p/(g·tan α)", expected, found, tolerance, source)  # fmt: skip


def half_sine_pulse(omega_ratio: float) -> Anchor:
    """Housner (1963): the least a_p/(g·tan α) of a half-sine pulse, linearised closed form."""
    bridge = block(SLENDER_ALPHA)
    expected = in_tan_alpha(bridge, housner_half_sine(omega_ratio))
    found = least(lambda a: toppled(under_pulse(bridge, "one-sine-a", omega_ratio, a,
                                                cycles=0.5)), 1.0, 20.0, 1e-9)  # fmt: skip
    return Anchor(
        f"half-sine pulse, ω_p/p = {omega_ratio:g}: least a_p/(g·tan α)",
        expected,
        found,
        LINEARISATION,
        "Housner (1963) linearised, closed form; α = 0.02",
    )


PHASES = {
    "one-sine-a": (0.0, 1.0), "one-sine-b": (0.5 * math.pi, 1.0),
    "cycloidal-b": (0.5 * math.pi, 1.0),
    "cycloidal-c": (0.5 * math.pi + type_c_phase(1), 1.5 - type_c_phase(1) / math.pi),
}  # fmt: skip
"""Each pulse as a_p·sin(ω_p·t + φ0) over a number of periods (C_1: φ0 = π/2 + φ_1)."""

SOURCES = {
    "one-sine-a": "Makris & Roussos (2000) type A", "one-sine-b": "Makris & Roussos (2000) type B",
    "cycloidal-b": "Zhang & Makris (2001) type B", "cycloidal-c": "Zhang & Makris (2001) type C_1",
}  # fmt: skip


def without_impact(shape: str, omega_ratio: float) -> Anchor:
    """Makris & Roussos (2000), Zhang & Makris (2001): the least a_p/(g·tan α) that overturns a
    slender block without an impact, closed-form solution of the linearised equation."""
    bridge = block(SLENDER_ALPHA)
    phase, periods = PHASES[shape]
    duration = periods * 2.0 * math.pi / omega_ratio
    linear = least(lambda a: linear_overturns_without_impact(a, omega_ratio, phase, duration),
                   1.0, 60.0, 1e-11)  # fmt: skip
    found = least(lambda a: toppled(under_pulse(bridge, shape, omega_ratio, a), True),
                  1.0, 60.0, 1e-9)  # fmt: skip
    return Anchor(f"{shape}, ω_p/p = {omega_ratio:g}: least a_p/(g·tan α) without impact",
                  in_tan_alpha(bridge, linear), found, LINEARISATION,
                  f"{SOURCES[shape]}, linearised closed form; α = 0.02")  # fmt: skip


def at_all(shape: str, omega_ratio: float, bracket: tuple[float, float]) -> Anchor:
    """The least a_p/(g·tan α) that overturns the stocky block at all (after an impact too), by
    bisection in ``bracket``: Housner's nonlinear equation integrated by scipy's DOP853 with his
    η = 1 − 1.5·sin²α."""
    bridge = block(STOCKY_ALPHA)
    eta = 1.0 - 1.5 * math.sin(STOCKY_ALPHA) ** 2

    def reference(a: float) -> bool:
        ground = Sinusoid.of(shape, a * math.tan(STOCKY_ALPHA), omega_ratio)
        return housner_ends(STOCKY_ALPHA, eta, ground, 40.0)[0]

    expected = least(reference, *bracket, 1e-8)
    found = least(lambda a: toppled(under_pulse(bridge, shape, omega_ratio, a, samples=2000)),
                  *bracket, 1e-8)  # fmt: skip
    return Anchor(f"{shape}, ω_p/p = {omega_ratio:g}: least a_p/(g·tan α), after an impact",
                  expected, found, EXACT,
                  "Housner's nonlinear equation by scipy's DOP853; α = 0.25")  # fmt: skip


def similarity() -> Anchor:
    """Dimitrakopoulos & DeJong (2012): blocks of one α and different sizes under a pulse of the
    same ω_p/p and a_p/(g·tan α): the largest difference of θ/α against p·t (expected 0)."""
    histories = []
    for size in (0.5, 8.0):
        bridge = block(0.2, size)
        p = frequency_parameter(bridge.model)
        response = under_pulse(
            bridge,
            "one-sine-a",
            5.0,
            2.5,
            samples=500,
            rest=1.5,
            preset="reference",
            histories=True,
            output_step=0.01 / p,
        )
        assert response.n_impacts >= 2 and response.failure_mode == "none"
        histories.append(response.histories["theta1"] / bridge.model.alpha1)
    size = min(h.size for h in histories)
    difference = float(np.max(np.abs(histories[1][:size] - histories[0][:size])))
    return Anchor("similarity: θ/α against p·t, blocks of R = 0.5 and 8 m (difference)", 0.0,
                  difference, 1e-9, "Dimitrakopoulos & DeJong (2012); ω_p/p = 5, "
                  "a_p/(g·tan α) = 2.5, 3 impacts", absolute=True)  # fmt: skip


def frame_and_block() -> Anchor:
    """Makris & Vassiliou (2013): the least a_p/(g·tan α) of a one-sine pulse at ω_p/p = 3 that
    overturns a frame with a rigid cap (γ = 0.75) and its block, R·(1 + 3γ)/(1 + 2γ) with the
    frame's restitution."""
    rigid = frame(1.5)
    gamma = 0.75
    twin = block(rigid.model.alpha1, rigid.model.R1 * (1 + 3 * gamma) / (1 + 2 * gamma),
                 restitution=rigid.eta(1.0))  # fmt: skip
    found = [least(lambda a, b=b: toppled(under_pulse(b, "one-sine-a", 3.0, a)), 1.0, 8.0, 1e-9)
             for b in (twin, rigid)]  # fmt: skip
    return Anchor("frame with a rigid cap (γ = 0.75) and its block: least a_p/(g·tan α), "
                  "ω_p/p = 3", *found, 1e-7, "Makris & Vassiliou (2013)")  # fmt: skip


def every_anchor() -> list[Anchor]:
    """The anchors validate_paper.py prints (the tests hold each)."""
    return [
        *(rectangular_pulse(p_t1, slender) for p_t1 in (0.5, 2.0) for slender in (True, False)),
        *(half_sine_pulse(omega) for omega in (0.5, 2.0, 5.0)),
        *(without_impact(shape, omega) for shape in PHASES for omega in (1.0, 2.0, 4.0)),
        at_all("one-sine-a", 3.0, (1.3, 1.5)),
        at_all("cycloidal-c", 3.0, (2.0, 2.2)),
        similarity(),
        frame_and_block(),
    ]
