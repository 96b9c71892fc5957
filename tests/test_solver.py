"""The event-driven integrator against closed forms, conservation laws and independent solvers.

Sources of the expected values are given test by test: Housner (1963) energy balance; an
independent integration with scipy's DOP853; conservation of energy between impacts
(docs/model.md §6); the dynamic equivalence of a symmetric frame and a single block (Makris &
Vassiliou 2013; DeJong & Dimitrakopoulos 2014); Eq. (8) onset; mirror symmetry; and convergence
of the scheme itself.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import (
    REPO,
    G,
    RefLinkage,
    conservative_laws,
    make_bridge,
    ref_onset,
    studied_bridge,
    with_,
)
from scipy.integrate import solve_ivp

from rockbridge_cli.core import fidelity, impacts, tables
from rockbridge_cli.core.analysis import analyze, dcr_backfill
from rockbridge_cli.core.bridge import Bridge
from rockbridge_cli.core.dynamics import acceleration, coefficients
from rockbridge_cli.core.events import (
    WATCH_IMPACT,
    Bracket,
    _falsi,
    _narrowed,
    first_event,
    holds_turning_point,
    interpolated,
    locate,
    turning_point,
    watched,
    watched_one,
)
from rockbridge_cli.core.geometry import single_block
from rockbridge_cli.core.kinematics import EXACT
from rockbridge_cli.core.quantities import SIGNIFICANT_RATE
from rockbridge_cli.core.schemes import DOPRI5, Ground, Segment, State, Step, take_step
from rockbridge_cli.core.solver import (
    EVENT_KIND,
    EVENT_MODE,
    EVENT_RATE_AFTER,
    EVENT_RATE_BEFORE,
    IMPACT,
    NO_ERROR,
    integrate,
)

DT = 0.01  # record sample interval [s]


def ground_motion(duration: float = 12.0, pga: float = 0.6 * G, seed: int = 7) -> np.ndarray:
    """A broadband synthetic accelerogram: 40 random sines (0.3–6 Hz) under a rise–hold–decay
    envelope, scaled to ``pga`` [m/s²]. Deterministic in ``seed``."""
    t = np.arange(0.0, duration + DT / 2, DT)
    rng = np.random.default_rng(seed)
    acc = sum(
        rng.uniform(0.5, 1.0) * np.sin(2 * np.pi * rng.uniform(0.3, 6.0) * t + rng.uniform(0, 6.3))
        for _ in range(40)
    )
    acc = acc * np.minimum(1.0, t / 2.0) * np.exp(-np.maximum(0.0, t - 0.5 * duration) / 2.0)
    return pga * acc / np.abs(acc).max()


def half_sine(amplitude: float, period: float = 1.0, duration: float = 6.0) -> np.ndarray:
    """One positive half-sine pulse of the given amplitude [m/s²], from t = 0.5 s, then zero."""
    t = np.arange(0.0, duration + DT / 2, DT)
    pulse = np.sin(np.pi * (t - 0.5) / (0.5 * period))
    return np.where((t >= 0.5) & (t <= 0.5 + 0.5 * period), amplitude * pulse, 0.0)


def relative_peak_difference(a, b) -> float:
    return max(abs(a.peaks[k][0] - b.peaks[k][0]) / max(abs(b.peaks[k][0]), 1e-300)
               for k in ("u_deck", "v_deck", "theta1", "theta2"))  # fmt: skip


# ---------------------------------------------------------------- single block (Housner 1963)


def test_housner_block_released_from_rest():
    """A block released at θ0 reaches the impact with ½·I0·ω² = m·g·R·(cos(α − θ0) − cos α) and
    leaves it with Housner's η; the time of the first impact agrees with scipy's DOP853 applied to
    θ̈ = −p²·sin(α − θ), p² = 3g/(4R) (Housner's exact equation of motion)."""
    block = single_block(B=1.0, H=5.0, density=2500.0, g=G)
    alpha, R, theta0 = block.alpha1, block.R1, 0.1
    response = analyze(Bridge(block), np.zeros(401), DT, "reference", initial=(theta0, 0.0))
    impacts_ = response.events["kind"] == "impact"
    first_rate = response.events["rate_before"][impacts_][0]
    expected = -math.sqrt(3.0 * G / (2.0 * R) * (math.cos(alpha - theta0) - math.cos(alpha)))
    assert first_rate == pytest.approx(expected, rel=1e-10)
    eta = response.events["rate_after"][impacts_] / response.events["rate_before"][impacts_]
    np.testing.assert_allclose(eta, 1.0 - 1.5 * math.sin(alpha) ** 2, rtol=1e-12)

    p2 = 3.0 * G / (4.0 * R)

    def hit(t, y):
        return y[0]

    hit.terminal, hit.direction = True, -1
    ref = solve_ivp(lambda t, y: (y[1], -p2 * math.sin(alpha - y[0])), (0, 10), (theta0, 0.0),
                    method="DOP853", rtol=1e-13, atol=1e-15, events=hit)  # fmt: skip
    assert response.events["time"][impacts_][0] == pytest.approx(ref.t_events[0][0], abs=1e-9)


@pytest.mark.parametrize(
    ("preset", "turning_points", "rel"),
    [
        ("reference", True, 1e-12),
        ("default", True, 1e-12),
        ("fast", True, 1e-12),
        ("paper", True, 1e-12),  # RK4: θ̈1 at the step's ends computed for the interpolant
        ("default", False, None),
    ],
)
def test_a_block_set_rocking_peaks_where_its_energy_says(preset, turning_points, rel):
    """A Housner block set rocking from rest position with θ̇1 = 0.15 rad/s peaks at θp with
    ½·I0·θ̇1² = m·g·R·(cos(α − θp) − cos α), I0 = 4/3·m·R² (Housner 1963): cos(α − θp) =
    cos α + 2·R·θ̇1²/(3g), θp ≈ 0.047 rad; later peaks are lower (every impact takes energy).
    With turning points found on the step that holds each, every preset gets θp to 1e-12
    (measured: 1.6e-13 at worst; the motion is smooth and slow, p·h ≈ 0.01, so even `fast`'s
    steps are accurate), the paper's RK4, whose steps leave θ̈1 unknown, included. With the
    peaks read at the steps' ends only, `default` is off by the sag of θ1 between the nearest
    step's end and the peak, ½·|θ̈1|·δt² ≈ 2e-6 rad (θ̈1 ≈ −0.27 rad/s², δt ≈ 4 ms; measured
    4.8e-5 relative): that is what the turning points catch. The paper's simplified kinematics
    are exact for a single block (no linkage)."""
    block = single_block(B=1.0, H=5.0, density=2500.0, g=G)
    alpha, R, rate = block.alpha1, block.R1, 0.15
    expected = alpha - math.acos(math.cos(alpha) + 2.0 * R * rate**2 / (3.0 * G))
    settled = fidelity.resolve(preset, turning_points=turning_points)
    response = analyze(Bridge(block), np.zeros(401), DT, settled, initial=(0.0, rate))
    peak = response.peaks["theta1"][0]
    if rel is None:
        assert abs(peak / expected - 1.0) > 1e-5
    else:
        assert peak == pytest.approx(expected, rel=rel, abs=0.0)


# ---------------------------------------------------------------- conservation of energy


@pytest.mark.parametrize("h_bar", [1.0, 1.25, 2.0])
def test_energy_is_conserved_between_impacts_and_across_them_with_the_mass_ratio(h_bar):
    """Free rocking of a frame (no abutments, no ground motion): at every impact the bridge is at
    rest position, so its energy is ½·M_s(0)·θ̇1². Between impacts energy is conserved; with
    η_s = √(M_s/M_−s) (docs/model.md §6) it is conserved across impacts too: every impact then
    carries the same energy."""
    frame = studied_bridge(h_bar, abutments=False)
    conservative = conservative_laws(frame)
    mass = {s: coefficients(frame, s, 0.0, EXACT)[0] for s in (1.0, -1.0)}  # M_s(0)
    settings = fidelity.resolve("reference").settings()
    result = integrate(frame, conservative, EXACT, np.zeros(2001), DT, settings, 0.004, 0.0)
    events = result.events
    hits = events[events[:, EVENT_KIND] == IMPACT]
    assert len(hits) >= 10 and result.error == NO_ERROR
    modes, rates_before = hits[:, EVENT_MODE], hits[:, EVENT_RATE_BEFORE]
    before = 0.5 * np.array([mass[-m] for m in modes]) * rates_before**2  # mode before = −after
    after = 0.5 * np.array([mass[m] for m in modes]) * hits[:, EVENT_RATE_AFTER] ** 2
    np.testing.assert_allclose(after, before, rtol=1e-12)  # across each impact
    np.testing.assert_allclose(before[1:], after[:-1], rtol=1e-8)  # between impacts


# ---------------------------------------------------------------- limit cases


def test_symmetric_bridge_keeps_its_deck_level():
    """h̄ = 1: the deck translates without rotating (θ_deck ≡ 0) and both piers rotate alike."""
    response = analyze(Bridge(studied_bridge(1.0)), ground_motion(), DT)
    assert response.n_impacts > 5
    assert np.nanmax(np.abs(response.histories["theta_deck"])) < 1e-12
    np.testing.assert_allclose(
        response.histories["theta2"], response.histories["theta1"], rtol=0, atol=1e-12
    )


def test_symmetric_frame_rocks_like_its_equivalent_block():
    """Makris & Vassiliou (2013), DeJong & Dimitrakopoulos (2014): a symmetric frame of two piers
    (mass m each) and a deck (mass m_d) rocks exactly like one block of the same slenderness α and
    size R_eq = R·(1 + 3γ')/(1 + 2γ'), γ' = m_d/(2m), given the frame's coefficient of
    restitution."""
    frame = studied_bridge(1.0, abutments=False)
    gamma = frame.md / (2.0 * frame.m1)
    r_eq = frame.R1 * (1 + 3 * gamma) / (1 + 2 * gamma)
    block = single_block(B=r_eq * math.sin(frame.alpha1), H=r_eq * math.cos(frame.alpha1),
                         density=2500.0, g=G)  # fmt: skip
    eta = impacts.restitution(frame, 1.0)
    acc = ground_motion(seed=3)
    a = analyze(Bridge(frame), acc, DT, "reference")
    b = analyze(Bridge(block, restitution=eta), acc, DT, "reference")
    assert a.n_impacts == b.n_impacts > 5
    np.testing.assert_allclose(a.events["time"], b.events["time"], rtol=0, atol=1e-9)
    scale = np.max(np.abs(a.histories["theta1"]))
    np.testing.assert_allclose(a.histories["theta1"], b.histories["theta1"], rtol=0,
                               atol=1e-8 * scale)  # fmt: skip


def test_near_symmetric_bridge_matches_the_symmetric_one():
    """h̄ = 1 + 1e-12 is no special case: the response equals h̄ = 1 to ~1e-9."""
    acc = ground_motion(seed=11)
    exact = analyze(Bridge(studied_bridge(1.0)), acc, DT, "reference")
    near = analyze(Bridge(studied_bridge(1.0 + 1e-12)), acc, DT, "reference")
    assert near.n_impacts == exact.n_impacts
    assert relative_peak_difference(near, exact) < 1e-8
    assert near.peaks["theta_deck"][0] < 1e-10


# ---------------------------------------------------------------- onset (Eq. 8) and signs


@pytest.mark.parametrize("h_bar", [1.0, 1.25, 2.0])
@pytest.mark.parametrize("direction", [1.0, -1.0])
def test_onset_threshold_separates_rest_from_rocking(h_bar, direction):
    """A pulse peaking 0.1 % below |ü_g,min| of its direction (Eq. 8) leaves the bridge at rest;
    0.1 % above, it rocks in that direction. docs/model.md §1: a positive ground acceleration drives
    mode p, which moves the deck to the left (u_deck < 0)."""
    bridge = studied_bridge(h_bar)
    threshold = abs(impacts.onset_threshold(bridge, direction))
    below = analyze(Bridge(bridge), direction * half_sine(0.999 * threshold), DT)
    assert math.isnan(below.t_onset) and below.n_impacts == 0
    for name, values in below.histories.items():
        assert np.all(values == 0.0), name
    above = analyze(Bridge(bridge), direction * half_sine(1.001 * threshold), DT)
    assert above.events["mode"][0] == direction
    first_motion = above.histories["u_deck"][np.flatnonzero(above.histories["mode"])[0]]
    assert np.sign(first_motion) == -direction


def test_onset_time_is_where_the_ground_crosses_the_threshold():
    """The onset is located exactly on the piecewise-linear ground motion: a ramp a(t) = 1 m/s³·t
    crosses ü_g,min at t = ü_g,min / (1 m/s³)."""
    bridge = studied_bridge(1.25)
    ramp = np.arange(0.0, 3.0, DT) * 1.0
    response = analyze(Bridge(bridge), ramp, DT)
    assert response.t_onset == pytest.approx(impacts.onset_threshold(bridge, 1.0), abs=1e-12)


def test_ground_sign_flip_mirrors_a_symmetric_bridge():
    """A symmetric bridge under −ü_g does the mirror image of its response under ü_g."""
    bridge, acc = studied_bridge(1.0), ground_motion(seed=5)
    a = analyze(Bridge(bridge), acc, DT, "reference")
    b = analyze(Bridge(bridge), -acc, DT, "reference")
    np.testing.assert_allclose(a.events["time"], b.events["time"], rtol=0, atol=1e-9)
    scale = np.max(np.abs(a.histories["theta1"]))
    for name in ("theta1", "u_deck", "u_pier2"):
        np.testing.assert_allclose(a.histories[name], -b.histories[name], rtol=0,
                                   atol=1e-8 * scale * 30)  # fmt: skip
    np.testing.assert_allclose(a.histories["v_deck"], b.histories["v_deck"], rtol=0, atol=1e-9)


@pytest.mark.parametrize("direction", [1.0, -1.0])
def test_bridge_with_its_tall_pier_on_the_right(direction):
    """The user's drawing, short pier on the left, against the independent reference kinematics
    of tests/conftest.py (which solves that drawing directly): a pulse 0.1 % below the drawing's
    onset threshold of a direction leaves the bridge at rest, 0.1 % above it rocks in that
    direction (mode p: counter-clockwise, deck to the left)."""
    model = studied_bridge(1.25)  # tall pier first: the config's mirrored bridge runs on it
    drawing = RefLinkage(model.B, model.H2, model.H1, model.L2, model.h)
    threshold = abs(ref_onset(drawing, (model.m2, model.m1, model.md), G, direction))
    below = analyze(Bridge(model, mirrored=True), direction * half_sine(0.999 * threshold), DT)
    assert math.isnan(below.t_onset)
    above = analyze(Bridge(model, mirrored=True), direction * half_sine(1.001 * threshold), DT)
    assert above.events["mode"][0] == direction
    first_motion = above.histories["u_deck"][np.flatnonzero(above.histories["mode"])[0]]
    assert np.sign(first_motion) == -direction


# ---------------------------------------------------------------- convergence


def test_reference_is_converged():
    """The yardstick: peaks change by less than 1e-8 between rtol 1e-11 and 1e-12."""
    bridge, acc = studied_bridge(2.0), ground_motion(seed=1)
    a = analyze(Bridge(bridge), acc, DT, "reference")
    b = analyze(Bridge(bridge), acc, DT, "reference", rtol=1e-11, event_tol=1e-12)
    assert a.n_impacts == b.n_impacts
    assert relative_peak_difference(b, a) < 1e-8


def test_default_converges_towards_reference():
    """Tightening the default preset's tolerance brings its peaks to the reference's."""
    bridge, acc = studied_bridge(1.25), ground_motion(seed=2)
    reference = analyze(Bridge(bridge), acc, DT, "reference")
    errors = [
        relative_peak_difference(analyze(Bridge(bridge), acc, DT, "default", rtol=rtol), reference)
        for rtol in (1e-4, 1e-7, 1e-10)
    ]
    assert errors[2] < 1e-8
    assert errors[2] <= errors[1] <= max(errors[0], 1e-12)


@pytest.mark.skipif(not hasattr(integrate, "py_func"), reason="NUMBA_DISABLE_JIT: all plain")
def test_compiled_and_plain_python_kernels_agree():
    """The compiled integrator and its plain-Python source give the same response."""
    bridge = studied_bridge(1.25)
    acc = ground_motion(duration=4.0, seed=9)
    settings = fidelity.resolve("default").settings()
    compiled = integrate(bridge, Bridge(bridge).laws(), EXACT, acc, DT, settings, 0.0, 0.0)
    plain = integrate.py_func(bridge, Bridge(bridge).laws(), EXACT, acc, DT, settings, 0.0, 0.0)
    for x, y in zip(compiled, plain, strict=True):
        if x is None:  # the devices' final state, without devices
            assert y is None
            continue
        np.testing.assert_allclose(x, y, rtol=1e-12, atol=1e-15)


@pytest.mark.skipif(not hasattr(integrate, "py_func"), reason="NUMBA_DISABLE_JIT: all plain")
def test_the_kernels_of_every_step_count_no_references():
    """The step and the check after it are compiled without numba's reference counting
    (`_jit.uncounted`): counting the tables' arrays in and out of every look-up took a quarter
    of a solve's CPU. A kernel compiled otherwise would still give the same numbers (the
    integrator's tests), only slower: this is where that would show."""
    for kernel in (take_step, first_event):
        assert kernel.targetoptions.get("_nrt") is False


@pytest.mark.parametrize("s", [1.0, -1.0])
@pytest.mark.parametrize("contact", [False, True])
def test_one_watched_function_is_that_of_all_of_them(s, contact):
    """`watched_one`, which spares an impact's search the linkage's displacements, gives each
    watched function bit for bit as `watched` does, in both modes, with the gap open and closed,
    at rest, rocking and beyond the piers' limits."""
    model = studied_bridge(1.25)
    segment = Segment(model, s, contact, None)
    kin = tables.tabulated(model)
    for theta in (0.0, 0.004, 0.05, 0.3):
        for rate in (0.0, -0.2, 0.7):
            every = watched(segment, kin, s * theta, rate)[0]
            for watch in range(len(every)):
                assert watched_one(segment, kin, s * theta, rate, watch) == every[watch]


# ---------------------------------------------------------------- event location


def test_the_step_interpolant_is_exact_on_a_quintic():
    """The quintic Hermite interpolant of a step's ends (θ1, θ̇1, θ̈1) reproduces any polynomial
    of degree 5 (the closed form it is built on): inside the step its value and rate equal the
    polynomial's to rounding."""
    c = np.random.default_rng(3).normal(size=6)
    h = 0.01
    theta = np.polynomial.Polynomial(c)
    rate, accel = theta.deriv(), theta.deriv(2)
    start, end = State(theta(0.0), rate(0.0), accel(0.0)), State(theta(h), rate(h), accel(h))
    step = Step(0, 0.0, h, start, end)
    for tau in np.linspace(0.0, h, 11):
        value, slope = interpolated(step, tau)
        assert value == pytest.approx(theta(tau), rel=1e-12, abs=1e-15)
        assert slope == pytest.approx(rate(tau), rel=1e-10, abs=1e-13)


def test_the_illinois_step_finds_a_closed_form_root():
    """The one Illinois step of both searches (`_falsi`, `_narrowed`) on f(x) = x³ − 2 over [0, 2]:
    the bracket closes on the closed-form root 2^(1/3) to 1e-12 within 20 trials, each inside the
    bracket, and the value at an end that stays while the other moves twice in a row is halved
    (the Illinois modification, Dowell & Jarratt 1971)."""
    b = Bracket(0.0, 2.0, -2.0, 6.0, 0)
    stayed = _narrowed(_narrowed(b, 1.0, -1.0), 1.1, -0.669)  # lo moves twice: g_hi halved once
    assert stayed.g_hi == 3.0 and stayed.side == -1
    trials = 0
    while b.hi - b.lo > 1e-12:
        mid = _falsi(b)
        assert b.lo < mid < b.hi
        b = _narrowed(b, mid, mid**3 - 2.0)
        trials += 1
    assert b.lo <= 2.0 ** (1.0 / 3.0) <= b.hi and trials <= 20


@pytest.mark.parametrize("preset", ["reference", "default", "fast", "paper"])
def test_an_event_is_located_just_past_it_within_the_tolerance(preset):
    """A Housner block rocking in mode +1 towards its impact (θ1 = 0.01 rad, θ̇1 = −0.5 rad/s):
    `locate` returns a step that ends past the event by no more than the event tolerance, and no
    more than a tenth of it where Illinois is led by the estimate of the event time (every preset
    but the paper's bisection). The event is the root of the very function `locate` sees (the
    watched function after a re-step of length τ), found here independently by 200
    bisections."""
    block = single_block(B=1.0, H=5.0, density=2500.0, g=G)
    settings = fidelity.resolve(preset).settings()
    segment, ground = Segment(block, 1.0, False, None), Ground(np.zeros(3), 1.0)
    watch, y, w, h = WATCH_IMPACT, 0.01, -0.5, 0.2
    start = State(y, w, acceleration(block, 1.0, y, w, 0.0, False, EXACT))

    def after(tau):
        unknown = State(y, w, np.nan)  # θ̈1 at the start, computed by the step
        end = take_step(segment, EXACT, ground, 0, 0.0, unknown, tau, settings.scheme)[0]
        return watched(segment, EXACT, end.theta, end.rate)[0][watch], end

    g0, g1 = after(0.0)[0], after(h)[0]
    assert g0 < 0.0 < g1
    lo, hi = 0.0, h
    for _ in range(200):
        lo, hi = (lo, 0.5 * (lo + hi)) if after(0.5 * (lo + hi))[0] > 0.0 else (0.5 * (lo + hi), hi)
    step = Step(0, 0.0, h, start, after(h)[1])
    tau = locate(segment, EXACT, ground, step, watch, g0, g1, settings).h
    assert after(tau)[0] > 0.0
    led = 0.1 if not settings.bisection else 1.0  # led by the estimate: a twentieth past it
    assert 0.0 < tau - lo <= led * settings.event_tol


@pytest.mark.parametrize("s", [1.0, -1.0])
def test_a_turning_point_is_found_on_the_step_that_holds_it(s):
    """A Housner block rocking away in mode s (θ1 = 0.01·s rad, θ̇1 = 0.005·s rad/s) turns back
    within a step of 0.02 s (θ̈1 ≈ −0.27·s rad/s², so about 18 ms in). `holds_turning_point`
    says so of the step, and `turning_point` finds it on the step's interpolant: its time and
    θ1 there agree with the turning point of the integration itself, the root of θ̇1 after a
    re-step of length τ, found independently by 200 bisections, to 1e-12 s and 1e-12 relative
    (measured: 1.4e-13 s and 3.3e-13). The two are different integrations, one step of 0.02 s
    read inside and one of τ, each within DOPRI5's local error on such a step,
    θ1·(p·h)⁵ ≈ 8e-11 rad with p ≈ 1.2 rad/s: the interpolant adds nothing that shows.
    A step that starts at θ̇1 = 0 (a release from rest) starts at its turning point and holds
    none."""
    block = single_block(B=1.0, H=5.0, density=2500.0, g=G)
    segment, ground = Segment(block, s, False, None), Ground(np.zeros(3), 1.0)
    y, w, h = 0.01 * s, 0.005 * s, 0.02
    start = State(y, w, acceleration(block, s, y, w, 0.0, False, EXACT))

    def after(tau):
        return take_step(segment, EXACT, ground, 0, 0.0, start, tau, DOPRI5)[0]

    step = Step(0, 0.0, h, start, after(h))
    assert holds_turning_point(s, step) and not holds_turning_point(-s, step)
    lo, hi = 0.0, h
    for _ in range(200):
        lo, hi = (
            (lo, 0.5 * (lo + hi))
            if s * after(0.5 * (lo + hi)).rate < 0.0
            else (0.5 * (lo + hi), hi)
        )
    tau, theta = turning_point(step, s, 1e-15)
    assert 0.015 < tau < 0.02
    assert abs(tau - lo) <= 1e-12
    assert theta == pytest.approx(after(lo).theta, rel=1e-12, abs=0.0)
    released = Step(0, 0.0, h, State(y, 0.0, start.accel), step.end)
    assert not holds_turning_point(s, released)


# ---------------------------------------------------------------- extremes


EXTREMES = {
    "e=0": with_(studied_bridge(1.25), e=0.0),
    "e=1": with_(studied_bridge(1.25), e=1.0),
    "stiff backfill k=1e12": with_(studied_bridge(1.25), k=1e12),
    "no gap u_jo=0": with_(studied_bridge(1.25), u_jo=0.0),
    "no backfill k=c=0": with_(studied_bridge(1.25), k=0.0, c=0.0, u_ab=10.0),
    "very asymmetric h=10": studied_bridge(10.0),
    "slender alpha=0.01": make_bridge(0.5, 50.0, 40.0, 20.0, 60.0, 1.7, area=6.0),
    "stocky alpha=0.5": make_bridge(5.46, 10.0, 8.0, 20.0, 30.0, 1.7, area=6.0),
    "L1 -> 0": make_bridge(2.6, 26.0, 20.8, 1e-9, 60.0, 1.7, area=6.0),
}


@pytest.mark.parametrize("name", list(EXTREMES))
@pytest.mark.parametrize("preset", ["default", "paper"])
def test_extremes_finish_cleanly(name, preset):
    """Each extreme bridge under a strong motion finishes without NaN before its end and
    without an endless event loop."""
    response = analyze(Bridge(EXTREMES[name]), ground_motion(pga=1.0 * G, seed=4), DT, preset)
    assert response.status == "ok"
    ended = response.time <= (response.failure_time if response.failure_mode != "none" else 1e9)
    for key, values in response.histories.items():
        assert np.all(np.isfinite(values[ended][:-1])), key
    assert all(math.isfinite(v) for v, _ in response.peaks.values())


def test_chattering_near_rest_ends_in_rest():
    """A pulse just above the threshold makes the bridge rock a little and come to rest through
    ever smaller impacts; the chatter guard (docs/model.md §7) ends them."""
    bridge = studied_bridge(2.0)
    threshold = impacts.onset_threshold(bridge, 1.0)
    response = analyze(Bridge(bridge), half_sine(1.05 * threshold, period=0.6, duration=20.0), DT)
    kinds = list(response.events["kind"])
    assert "rest" in kinds and response.n_impacts < 2000
    assert response.histories["mode"][-1] == 0 and response.histories["theta1"][-1] == 0.0


def test_a_rest_velocity_of_zero_is_refused_by_the_core_as_by_a_study():
    """Issue 38: a study refused ``rest_velocity: 0`` while the core took it, and at 0 the chatter
    guard (docs/model.md §7) never applies: the pulse of the test above, which comes to rest
    through about a hundred impacts, then ran on to ``max_events`` (200 000 events, a solver
    error, 20× the time). The core now refuses 0 as a study does, saying why; any positive value
    is taken."""
    from rockbridge_cli.config.study_models import FidelityConfig

    with pytest.raises(ValueError, match=r"rest_velocity must be a number above 0 and at most 1, "
                       r"not 0\.0: 0 would never apply it \(chatter guard"):  # fmt: skip
        fidelity.resolve("fast", rest_velocity=0.0)
    with pytest.raises(ValueError, match="rest_velocity must be a number above 0"):
        analyze(Bridge(studied_bridge(2.0)), np.zeros(3), DT, rest_velocity=0)
    with pytest.raises(ValueError, match="greater than 0"):  # the study's refusal (pydantic's)
        FidelityConfig.model_validate({"rest_velocity": 0.0})
    assert fidelity.resolve("fast", rest_velocity=1e-12).knobs["rest_velocity"] == 1e-12
    FidelityConfig.model_validate({"rest_velocity": 1e-12})


def test_a_long_event_log_grows_without_losing_events():
    """A 0.4 × 4 m block under 200 s of a 3 Hz, 0.3 g sine rocks through about 1200 impacts,
    more than the log holds at the start (1024 rows): the log grows and keeps every event in
    order, whatever the limit it grows to (max_events 1500 or the default 200 000)."""
    block = single_block(B=0.2, H=2.0, density=2500.0, g=G)
    t = np.arange(0.0, 200.0, DT)
    acc = 0.3 * G * np.sin(2.0 * np.pi * 3.0 * t)
    response = analyze(Bridge(block), acc, DT)
    times, kinds = response.events["time"], list(response.events["kind"])
    assert response.status == "ok" and len(times) > 1100
    assert kinds[0] == "onset" and kinds.count("impact") == response.n_impacts == len(kinds) - 1
    assert np.all(np.diff(times) > 0.0) and times[0] > 0.0  # no row left empty
    capped = analyze(Bridge(block), acc, DT, max_events=1500)
    for name, values in response.events.items():
        np.testing.assert_array_equal(capped.events[name], values)


def test_strong_motion_fails_the_abutment_first():
    """A motion far above the paper's: the abutment–backfill fails (|u_deck| = u_jo + u_ab) and
    the analysis stops there (docs/model.md §7)."""
    bridge = studied_bridge(1.25)
    response = analyze(Bridge(bridge), ground_motion(pga=3.0 * G, seed=8), DT)
    assert response.failure_mode == "abutment"
    assert response.peaks["u_deck"][0] == pytest.approx(bridge.u_jo + bridge.u_ab, rel=1e-6)
    # the backfill at its capacity: (|u_deck| − u_jo)/u_ab = u_ab/u_ab (docs/model.md §8)
    assert response.dcr_backfill == pytest.approx(1.0, rel=1e-5)
    assert response.dcr_overturning < 1.0
    assert np.all(np.isnan(response.histories["u_deck"][response.time > response.failure_time]))


def test_strong_pulse_overturns_a_frame():
    """Without abutments a long strong pulse overturns the piers (|u_pier| = B)."""
    frame = studied_bridge(1.25, abutments=False)
    response = analyze(Bridge(frame), half_sine(1.0 * G, period=4.0, duration=8.0), DT)
    assert response.failure_mode.startswith("overturning")
    assert response.dcr_overturning == pytest.approx(1.0, rel=1e-6)  # |u_pier| = B
    assert np.isnan(response.dcr_backfill)  # no abutments, no backfill


# ---------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    ("acc", "dt", "reason"),
    [
        (np.array([0.0, np.nan, 0.0]), DT, "non-finite"),
        (np.array([]), DT, "two samples"),
        # a time column beside the accelerations, as np.loadtxt reads a file (a second reviewer,
        # 2026-11-28: "needs at least two samples" of 3001 rows)
        (np.zeros((3001, 2)), DT, r"1-D array of accelerations, not of shape \(3001, 2\)"),
        (np.zeros(10), 0.0, "time step"),
        (np.zeros(10), -0.01, "time step"),
    ],
)
def test_bad_ground_motions_are_refused(acc, dt, reason):
    with pytest.raises(ValueError, match=reason):
        analyze(Bridge(studied_bridge(1.0)), acc, dt)


def test_block_overturns_as_pier1_only():
    """A single block has one pier: a long strong pulse overturns it (|u_pier1| = B); its massless
    twin (`geometry.single_block`) never reports a failure of its own. Regression: the two
    simultaneous overturning events used to be relocated in turn forever."""
    block = single_block(B=1.3, H=13.0, density=2500.0, g=G)
    response = analyze(Bridge(block), half_sine(0.5 * G, period=4.0, duration=8.0), DT)
    assert response.failure_mode == "overturning_pier1"
    assert response.peaks["u_pier1"][0] == pytest.approx(block.B, rel=1e-6)


def test_asymmetric_frame_half_cycle_against_scipy():
    """An independent integrator and event locator: scipy's DOP853 on the same equation of motion,
    from the onset to the first impact of an asymmetric frame under a triangular pulse (exactly
    piecewise linear, so both integrate the same ground motion; scipy is restarted at its kinks).
    The onset time is the ramp's crossing of Eq. 8's threshold, t0 = ü_g,min/slope."""
    frame = studied_bridge(2.0, abutments=False)
    onset = impacts.onset_threshold(frame, 1.0)
    t = np.arange(0.0, 6.0 + DT / 2, DT)
    slope = 2.0 * onset  # peak 2·ü_g,min at t = 1 s, back to zero at t = 2 s
    acc = np.interp(t, [0.0, 1.0, 2.0, 6.0], [0.0, slope, 0.0, 0.0])
    response = analyze(Bridge(frame), acc, DT, "reference")
    first_impact = response.events["time"][response.events["kind"] == "impact"][0]

    def rhs(time, y):
        ground = np.interp(time, t, acc)
        return (y[1], acceleration(frame, 1.0, y[0], y[1], ground, False, EXACT))

    def hit(time, y):
        return y[0]

    hit.terminal, hit.direction = True, -1
    state, peak = np.array([0.0, 0.0]), 0.0
    for start, end in ((onset / slope, 1.0), (1.0, 2.0), (2.0, 6.0)):
        part = solve_ivp(rhs, (start, end), state, method="DOP853", rtol=1e-13, atol=1e-16,
                         events=hit, dense_output=True)  # fmt: skip
        peak = max(peak, np.max(part.sol(np.linspace(start, part.t[-1], 20001))[0]))
        state = part.y[:, -1]
        if part.t_events[0].size:
            break
    assert response.t_onset == pytest.approx(onset / slope, abs=1e-12)
    assert first_impact == pytest.approx(part.t_events[0][0], abs=1e-8)
    assert response.peaks["theta1"][0] == pytest.approx(peak, rel=1e-8)


# ---------------------------------------------------------------- the paper's ratio


@pytest.mark.parametrize(
    ("u_deck", "expected"),
    [(0.17, 0.5), (0.12, 0.0), (0.10, 0.0), (0.22, 1.0)],  # u_jo = 0.12 m, u_ab = 0.10 m
)
def test_dcr_backfill_is_the_backfill_s_deformation_over_its_capacity(u_deck, expected):
    """docs/model.md §8: max(0, |u_deck| − u_jo)/u_ab, by hand: (0.17 − 0.12)/0.10 = 0.5; 0 while
    the gap stays open; 1 at failure."""
    assert dcr_backfill(studied_bridge(1.25), u_deck) == pytest.approx(expected, abs=1e-15)


def test_dcr_backfill_needs_abutments():
    assert np.isnan(dcr_backfill(studied_bridge(1.25, abutments=False), 0.5))


def test_significant_impacts_are_those_above_the_rate():
    """n_impacts_significant counts the impact events whose |θ̇1| before exceeds the threshold."""
    response = analyze(Bridge(studied_bridge(2.0)), ground_motion(pga=0.69 * G, seed=3), DT)
    impact = response.events["kind"] == "impact"
    rates = np.abs(response.events["rate_before"][impact])
    assert response.n_impacts_significant == np.sum(rates > SIGNIFICANT_RATE)
    assert 0 < response.n_impacts_significant <= response.n_impacts


# ---------------------------------------------------------------- after the record


def test_a_failure_after_the_record_is_seen_with_a_tail():
    """A 0.45 g half-sine pulse of 2 s period, cut at 2 s, leaves a frame rotating towards
    overturning: the 2 s record alone ends with no failure; 10 s of free vibration (zero ground
    motion) after it shows the piers overturn at 2.44 s (issue 9: failures after the record)."""
    frame = studied_bridge(1.25, abutments=False)
    ground = half_sine(0.45 * G, period=2.0, duration=2.0)
    without = analyze(Bridge(frame), ground, DT)
    with_tail = analyze(Bridge(frame), ground, DT, tail=10.0)
    assert without.failure_mode == "none" and without.time[-1] == pytest.approx(2.0)
    assert with_tail.failure_mode.startswith("overturning")
    assert 2.0 < with_tail.failure_time < 12.0
    assert with_tail.dcr_overturning == pytest.approx(1.0, rel=1e-6)


def test_a_tail_lets_the_bridge_come_to_rest_and_changes_nothing_before():
    bridge = studied_bridge(2.0)
    ground = half_sine(0.3 * G, period=1.0, duration=3.0)
    short, long = (
        analyze(Bridge(bridge), ground, DT),
        analyze(Bridge(bridge), ground, DT, tail=30.0),
    )
    assert long.time[-1] == pytest.approx(33.0) and short.time[-1] == pytest.approx(3.0)
    n = short.time.size
    np.testing.assert_array_equal(long.histories["theta1"][:n], short.histories["theta1"][:n])
    assert long.histories["mode"][-1] == 0  # at rest before the tail ends
    with pytest.raises(ValueError, match="tail"):
        analyze(Bridge(bridge), ground, DT, tail=-1.0)


def test_an_analysis_without_histories_has_the_same_peaks_and_events():
    """``histories=False`` (a study that stores none) skips the displacements at the samples and
    nothing else: the same peaks, events and verdict, bit for bit, and empty histories."""
    bridge = Bridge(studied_bridge(1.25))
    acc = ground_motion(seed=3)
    full, bare = analyze(bridge, acc, DT), analyze(bridge, acc, DT, histories=False)
    assert bare.histories == {} and bare.time.size == 0
    assert full.peaks == bare.peaks and full.failure_mode == bare.failure_mode
    for name, values in full.events.items():
        np.testing.assert_array_equal(bare.events[name], values)


def _first_pier_limit(link: RefLinkage, mode: float, width: float) -> str:
    """The failure mode a rocking frame reaches first in ``mode`` as |θ1| grows: the pier whose
    centre of gravity first moves a half-width ``width`` / 2 from rest (reference linkage)."""
    from scipy.optimize import brentq

    rest = link.solve(mode, 0.0)

    def limit(centre: str) -> float:
        def past(t: float) -> float:
            return abs(link.solve(mode, mode * t)[centre] - rest[centre]) - width / 2

        return brentq(past, 1e-9, 2e-3, xtol=1e-16)

    return "overturning_pier2" if limit("xr") < limit("xl") else "overturning_pier1"


def test_piers_reaching_their_limits_together_fail_the_same_way_at_every_preset():
    """Issue 32, finding 16: the paper's studied bridge made near-critical (2B = 0.026 m, so
    α = 1e-3 rad; h̄ = 15) under AR07. Its piers reach their overturning limits 2e-9 s apart,
    within the cheaper presets' event tolerance, where the tie went by the order of the watched
    functions (pier 1 at `fast` and `paper`) while `default` and `reference` located pier 2
    first. Expected, from the reference linkage (conftest, independent of the code's
    kinematics): in the mode the bridge fails in, the pier whose centre reaches |u| = B at the
    smaller |θ1| fails first; here pier 2's limit lies 1.06e-11 rad nearer in mode +1 (pier
    1's in mode −1)."""
    from rockbridge_cli.records.files import read_record

    model = make_bridge(0.026, 26.0, 26.0 / 15.0, 38.0, 60.0, 1.7, area=6.0)
    record = read_record(REPO / "records" / "ec8-type1-C-ag0.6g" / "AR07.txt")
    verdicts = set()
    for preset in fidelity.PRESETS:
        response = analyze(Bridge(model), record.acceleration, record.time_step, preset)
        mode = float(response.events["mode"][-2])  # the mode it rocks in as it fails
        expected = _first_pier_limit(RefLinkage.of(model), mode, 0.026)
        assert response.failure_mode == expected, preset
        verdicts.add((response.failure_mode, round(response.failure_time, 5)))
    assert len(verdicts) == 1
