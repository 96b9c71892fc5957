"""Yielding tendons and hysteretic dissipators (issue 41; docs/model.md §13, "Yield and rupture
of a tendon", "Dissipator", "Yield, unloading and rupture as events"): their laws against closed
forms, their events against an independent integration, the energy they take, their configs and
their flags in the results."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import G, conservative_laws, studied_bridge
from scipy.integrate import solve_ivp

from rockbridge_cli.assessment.limit_states import Verdict
from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.core import fidelity, impacts
from rockbridge_cli.core.analysis import analyze
from rockbridge_cli.core.bridge import Bridge
from rockbridge_cli.core.device_events import settle, shifted
from rockbridge_cli.core.device_mechanics import (
    elastic_pull,
    elongation,
    pull,
    restrained,
    strain_energy,
    yield_line,
)
from rockbridge_cli.core.devices import (
    BRANCH,
    ELASTIC,
    LOADING,
    PLASTIC,
    PRESTRESS,
    STIFFNESS,
    UNLOADING,
    YIELD,
    YIELDED_AT,
    Damper,
    Dissipator,
    Tendon,
    table,
)
from rockbridge_cli.core.dynamics import energy
from rockbridge_cli.core.geometry import single_block
from rockbridge_cli.core.kinematics import EXACT
from rockbridge_cli.core.quantities import check_limit_state
from rockbridge_cli.core.solver import NO_ERROR, integrate
from rockbridge_cli.records.files import read_record
from rockbridge_cli.results.packing import device_rows, device_states

DT = 0.01
ROOT = Path(__file__).resolve().parents[1]
BLOCK = single_block(B=0.5, H=2.5, density=2500.0, g=G)  # a 1 m × 5 m block, α = 0.197 rad


def _driven(row: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """The device's force along an imposed elongation history, its state moved at each sample
    (`shifted`, the rate by a backward difference), as the integrator moves it at the events."""
    forces = np.empty(lengths.size)
    for i, length in enumerate(lengths):
        speed = length - lengths[i - 1] if i else 1.0
        shifted(row, length, speed, float(i))
        forces[i] = pull(row, length, speed)
    return forces


def test_a_dissipators_loop_is_the_bilinear_laws_parallelogram():
    """Δ = Δa·sin(2πt), Δa = 4Δy: after the first quarter the loop is the parallelogram between
    the yield lines k2·Δ ± (1 − α)·F_y (α = k2/k1) and two elastic branches of slope k1, each
    2Δy wide (they climb 2(1 − α)·F_y at k1 − k2); its area is 4·(1 − α)·F_y·(Δa − Δy), its
    peak force F_y + k2·(Δa − Δy) (closed forms of the bilinear law, e.g. Chopra, Dynamics of
    Structures, §7.1). Sampled at 2·10⁵ points a cycle: the area to 1e-4 (a yield is noted at
    the first sample past it, a force error of k1·δΔ over one sample), the peak to 1e-12."""
    k1, fy, ratio = 2.0e8, 1.0e6, 0.05
    rows = table((Dissipator(0, 0.0, k1, fy, hardening=ratio * k1),))
    yield_length = fy / k1
    amplitude = 4.0 * yield_length
    t = np.linspace(0.0, 2.25, 450_001)
    lengths = amplitude * np.sin(2 * np.pi * t)
    forces = _driven(rows[0], lengths)
    cycle = (t >= 0.25 - 1e-12) & (t <= 1.25 + 1e-12)
    f, x = forces[cycle], lengths[cycle]
    area = np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(x))
    closed = 4.0 * (1.0 - ratio) * fy * (amplitude - yield_length)
    assert area == pytest.approx(closed, rel=1e-4)
    peak = fy + ratio * k1 * (amplitude - yield_length)
    assert forces[np.argmin(np.abs(t - 1.25))] == pytest.approx(peak, rel=1e-12)
    assert forces[np.argmin(np.abs(t - 1.75))] == pytest.approx(-peak, rel=1e-12)


def test_a_tendon_pushed_past_yield_has_a_plateau_and_loses_prestress_on_unloading():
    """A block with a tendon at d (ℓ = B + d), pushed statically to 1.2 θ_y and back to rest:
    the tendon's moment about the pivot, −restrained(0, …) at θ̇ = 0 with the state moved at
    each rotation (`settle`, pushed forward then back), against T·ℓ·cos(θ/2) with the
    elastic–perfectly-plastic law written here: T = min(P0 + k·Δ, F_y) on the way out (the
    plateau F_y past Δ_y = (F_y − P0)/k), T = F_y − k·(Δ_max − Δ) on the way back, and at rest
    the residual prestress P0 − k·Δp, Δp = Δ_max − Δ_y (Δ = 2ℓ·sin(θ/2))."""
    d, prestress, stiffness, fy = 0.2, 3.0e5, 2.0e8, 1.5e6
    rows = table((Tendon(0, d, prestress, stiffness, top=False, yield_force=fy),))
    ell = BLOCK.B + d
    yield_length = (fy - prestress) / stiffness
    top = 1.2 * 2 * math.asin(yield_length / (2 * ell))
    peak = 2 * ell * math.sin(top / 2)
    out, back = np.linspace(0.0, top, 400), np.linspace(top, 0.0, 400)
    for rotations, rate in ((out, 1.0), (back, -1.0)):
        for theta in rotations:
            settle(rows, BLOCK, 1.0, theta, rate, 0.0, EXACT)
            code = -restrained(0.0, rows, BLOCK, 1.0, theta, 0.0, EXACT)
            length = 2 * ell * math.sin(theta / 2)
            if rate > 0:
                tension = min(prestress + stiffness * length, fy)
            else:
                tension = fy - stiffness * (peak - length)
            assert code == pytest.approx(tension * ell * math.cos(theta / 2), rel=1e-9)
    plastic = peak - yield_length
    assert rows[0, PLASTIC] == pytest.approx(plastic, rel=1e-12)
    assert rows[0, BRANCH] == ELASTIC
    residual = -restrained(0.0, rows, BLOCK, 1.0, 0.0, 0.0, EXACT) / ell
    assert residual == pytest.approx(prestress - stiffness * plastic, rel=1e-9)


def test_a_dissipator_past_its_lower_line_and_opening_yields_and_unloads_in_one_call():
    """The state an impact leaves when the dissipator's crossing of its lower line fell within
    the event tolerance of it: at Δ = 0 with Δp = 2 mm its elastic force k1·(0 − Δp) = −40 kN
    is past the line k2·0 − (1 − k2/k1)·F_y = −29.7 kN, and the impact has turned Δ̇ positive.
    It slid down the line to Δ = 0 and leaves it at once: elastic, with the Δp that puts its
    force on the line, (1 − k2/k1)·F_y/k1 = 1.485 mm (the law, solved by hand), yielded now.
    Before issue 41's fix it stayed on the lower line while opening, the devices' event
    function stayed positive, and no later yield was seen (4.96 MN against a 0.44 MN envelope
    on the bundled dissipator bridge under AR07)."""
    k1, fy, k2 = 2.0e7, 3.0e4, 2.0e5
    (row,) = table((Dissipator(0, 0.0, k1, fy, hardening=k2),))
    row[PLASTIC] = 2.0e-3
    shifted(row, 0.0, 1.0e-3, 7.0)
    assert row[BRANCH] == ELASTIC
    assert row[PLASTIC] == pytest.approx((1.0 - k2 / k1) * fy / k1, rel=1e-12)
    assert row[YIELDED_AT] == 7.0


def test_a_dissipator_on_its_line_and_moving_into_it_yields():
    """Elastic with its force exactly on the upper line (k1 = 2²⁴ N/m, F_y = 2¹⁴ N, k2 = 0,
    Δp = 2⁻¹⁰ m, Δ = 2⁻⁹ m: k1·(Δ − Δp) = F_y in binary, to the bit), the state a device that
    unloaded there is left in when the bridge turns back at once: loading, it yields (else its
    event function would start at zero and turn positive in a step of length zero that changes
    nothing, again and again: AR03 × 2 at ``default`` hung so); unloading, it stays elastic."""
    for speed, branch in ((1e-4, LOADING), (-1e-4, ELASTIC)):
        (row,) = table((Dissipator(0, 0.0, 2.0**24, 2.0**14),))
        row[PLASTIC] = 2.0**-10
        assert elastic_pull(row, 2.0**-9) == yield_line(row, 2.0**-9, LOADING)
        shifted(row, 2.0**-9, speed, 3.0)
        assert row[BRANCH] == branch


def test_back_at_rest_a_dissipator_on_its_lower_line_takes_the_elastic_branch_it_lifts_off_on():
    """The chatter guard puts the bridge at rest with a dissipator on its lower line (Δ = 0,
    force −(1 − k2/k1)·F_y): whichever way it lifts off next, Δ grows, so it leaves rest
    elastic, with Δp = (1 − k2/k1)·F_y/k1 (its force unchanged); a damper is left alone."""
    k1, fy, k2 = 2.0e7, 3.0e4, 2.0e5
    rows = table((Dissipator(0, 0.1, k1, fy, hardening=k2), Damper(0, 0.0, 1e5)))
    rows[0, BRANCH] = UNLOADING
    settle(rows, BLOCK, 0.0, 0.0, 0.0, 5.0, EXACT)
    assert rows[0, BRANCH] == ELASTIC
    assert rows[0, PLASTIC] == pytest.approx((1.0 - k2 / k1) * fy / k1, rel=1e-12)
    assert elastic_pull(rows[0], 0.0) == pytest.approx(-(1.0 - k2 / k1) * fy, rel=1e-12)


@pytest.mark.parametrize("side", [LOADING, UNLOADING])
def test_a_device_that_unloads_starts_its_elastic_branch_inside_the_line_it_left(side):
    """Unloading from a yield line at any elongation, the elastic force P0 + k·(Δ − Δp) is not
    past that line, to the last bit: the law's bound (F_y for a tendon, k2·Δ ± (1 − k2/k1)·F_y
    for a dissipator), which rounding of Δp = Δ − (line − P0)/k alone breaks at 45 % of these
    elongations for the dissipator and 0.1 % for the tendon (forces ~1e-10 N past the line,
    enough to start the devices' event function positive)."""
    lengths = np.linspace(1e-4, 4e-2, 997)
    rows = table(
        (Dissipator(0, 0.3, 5.027e8, 3.77e5, hardening=5.027e6), Tendon(1, 0.0, 2e6, 6e7,
                                                                        yield_force=4e6))
    )  # fmt: skip
    for row in rows if side == LOADING else rows[:1]:
        for length in lengths:
            row[BRANCH] = side
            shifted(row, length, -side * 1e-3, 1.0)
            assert row[BRANCH] == ELASTIC
            past = side * (elastic_pull(row, length) - yield_line(row, length, side))
            assert past <= 0.0, (length, past)


@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
@pytest.mark.parametrize("preset", ["fast", "default"])
def test_the_bundled_dissipators_stay_within_their_bilinear_law(preset):
    """studied-hbar1.25-dissipators.yaml under the ten bundled records at 2 × their scale (every
    dissipator yields, the deck pounds): each dissipator's peak force is at most the law's bound
    at its peak elongation Δ_max, max(k2·Δ_max + (1 − k2/k1)·F_y, (1 − k2/k1)·F_y) (the upper
    line there, or the lower line at Δ = 0: the bilinear law of docs/model.md §13 bounds the
    force by its lines). Before issue 41's fix the devices' event function could start a
    segment positive and miss the next yields: 4.96 MN against a bound of 0.44 MN under AR07 at
    ``fast`` (a dissipator left elastic 9.9 mm past its yield)."""
    bridge = load_bridge(ROOT / "configs/bridges/studied-hbar1.25-dissipators.yaml").to_bridge()
    for path in sorted((ROOT / "records/ec8-type1-C-ag0.6g").glob("AR*.txt")):
        record = read_record(path)
        response = analyze(bridge, 2.0 * record.acceleration, record.time_step, preset,
                           histories=False)  # fmt: skip
        assert response.status == "ok"
        for i, device in enumerate(bridge.devices, start=1):
            reach = response.peaks[f"dissipator{i}_elongation"][0]
            lines = (1.0 - device.hardening / device.stiffness) * device.yield_force
            bound = max(device.hardening * reach + lines, lines)
            assert response.peaks[f"dissipator{i}_force"][0] <= bound * (1.0 + 1e-12), path.name


def _yielding_block(d: float, prestress: float, stiffness: float, fy: float):
    """Housner's block with an elastic–perfectly-plastic tendon at offset d, written here from
    its own free-body diagram: I_O·θ̈ = −m·g·R·sin(s·α − θ) − T·ℓ·cos(θ/2)·s, ℓ = B + s·d,
    Δ = 2ℓ·|sin(θ/2)|, T = max(0, P0 + k·(Δ − Δp)) elastic (slack below 0), F_y yielding.
    Returns the right-hand side of (θ, θ̇) for a branch (``plastic``) and a plastic elongation
    ``dp``, and Δ(θ)."""
    m, B, H = BLOCK.m1, BLOCK.B, BLOCK.H1
    R, alpha = math.hypot(B, H), math.atan2(B, H)
    inertia = 4.0 / 3.0 * m * R * R

    def length(theta):
        s = 1.0 if theta > 0 else -1.0
        return 2 * (B + s * d) * abs(math.sin(theta / 2))

    def rhs(plastic, dp):
        def f(_t, y):
            theta, rate = y
            s = 1.0 if theta > 0 else -1.0
            tension = fy if plastic else max(0.0, prestress + stiffness * (length(theta) - dp))
            moment = (
                -m * G * R * math.sin(s * alpha - theta)
                - tension * (B + s * d) * math.cos(theta / 2) * s
            )
            return [rate, moment / inertia]

        return f

    return rhs, length


def _reference_rocking(d, prestress, stiffness, fy, rate0, impacts_wanted):
    """The yield times and (impact time, rate after) of the block of `_yielding_block` released
    at θ = 0 with θ̇ = rate0 > 0, by scipy's DOP853 with the yield (T = F_y), the unloading
    (θ̇ = 0 on the plastic branch) and the impacts (θ = 0, Housner's η = 1 − 1.5·sin²α) located
    as its events."""
    rhs, length = _yielding_block(d, prestress, stiffness, fy)
    eta = 1.0 - 1.5 * math.sin(math.atan2(BLOCK.B, BLOCK.H1)) ** 2
    y, t, dp, plastic, yields, hits = [0.0, rate0], 0.0, 0.0, False, [], []
    while len(hits) < impacts_wanted:
        sign = 1.0 if y[0] > 0 or (y[0] == 0 and y[1] > 0) else -1.0
        y0 = [sign * 1e-15 if y[0] == 0 else y[0], y[1]]

        def hit(_t, state, sign=sign):
            return state[0] * sign

        def yielded(_t, state, dp=dp):
            return prestress + stiffness * (length(state[0]) - dp) - fy

        def turned(_t, state, sign=sign):
            return state[1] * sign

        hit.terminal = yielded.terminal = turned.terminal = True
        hit.direction, yielded.direction, turned.direction = -1.0, 1.0, -1.0
        events = [turned] if plastic else [hit, yielded]
        solution = solve_ivp(rhs(plastic, dp), (t, t + 10.0), y0, method="DOP853", rtol=1e-13,
                             atol=1e-15, events=events)  # fmt: skip
        which = next(i for i, times in enumerate(solution.t_events) if times.size)
        t, y = solution.t_events[which][0], list(solution.y_events[which][0])
        if plastic:  # unloads: Δp such that P0 + k·(Δ − Δp) = F_y
            plastic, dp = False, length(y[0]) - (fy - prestress) / stiffness
        elif which == 1:
            plastic = True
            yields.append(t)
        else:
            y = [0.0, eta * y[1]]
            hits.append((t, y[1]))
    return yields, np.array(hits), dp


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
def test_free_rocking_with_a_yielding_tendon_matches_an_independent_integration():
    """Released at θ = 0 with θ̇ = 0.45 rad/s, the block's tendon yields once: the yield time
    located as an event (so that the force there is F_y to within k·Δ̇·event_tol), the first
    four impacts' times and rates, and the plastic elongation left, against scipy's DOP853 on
    the block's own equation with the yield, the unloading and the impacts as its events
    (`_reference_rocking`)."""
    d, prestress, stiffness, fy = 0.15, 3.0e5, 2.0e8, 1.5e6
    tendon = Tendon(0, d, prestress, stiffness, top=False, yield_force=fy)
    bridge = Bridge(BLOCK, devices=(tendon,))
    response = analyze(bridge, np.zeros(401), DT, "reference", initial=(0.0, 0.45))
    yields, hits, dp = _reference_rocking(d, prestress, stiffness, fy, 0.45, 4)
    assert len(yields) == 1
    yielded, when = response.peaks["tendon1_yielded"]
    assert yielded == 1.0
    event_tol = fidelity.resolve("reference").knobs["event_tol"]
    assert abs(when - yields[0]) <= 2 * event_tol
    assert response.peaks["tendon1_force"][0] == pytest.approx(fy, rel=1e-12)
    impacts_ = response.events["kind"] == "impact"
    np.testing.assert_allclose(response.events["time"][impacts_][:4], hits[:, 0], rtol=1e-8)
    np.testing.assert_allclose(response.events["rate_after"][impacts_][:4], hits[:, 1], rtol=1e-7)
    assert response.peaks["tendon1_broken"] == (0.0, pytest.approx(math.nan, nan_ok=True))
    rows = table(bridge.devices)
    length = response.peaks["tendon1_elongation"][0]
    assert length - (fy - prestress) / stiffness == pytest.approx(dp, rel=1e-7)
    assert rows[0, PLASTIC] == 0.0  # the caller's table is not the integrator's


def _dissipating_block(d: float, k1: float, fy: float, k2: float, rate0: float, wanted: int):
    """The impacts (time, θ̇ after) of Housner's block with a bilinear dissipator across its base
    at offset d, released at θ = 0 with θ̇ = rate0 > 0, by scipy's DOP853 on the block's own
    equation I_O·θ̈ = −m·g·R·sin(s·α − θ) − F·ℓ·cos(θ/2)·s (ℓ = B + s·d, Δ = 2ℓ·|sin(θ/2)|),
    the law written here: F = k1·(Δ − Δp) elastic, k2·Δ ± c on the lines (c = (1 − k2/k1)·F_y);
    events: the force reaching a line, Δ̇ turning against the line (unloading, Δp = Δ − F/k1),
    the impacts (η = 1 − 1.5·sin²α; after one, Δ̇ > 0, so a device on its lower line unloads)."""
    m, B, H = BLOCK.m1, BLOCK.B, BLOCK.H1
    R, alpha = math.hypot(B, H), math.atan2(B, H)
    inertia, c = 4.0 / 3.0 * m * R * R, (1.0 - k2 / k1) * fy
    eta = 1.0 - 1.5 * math.sin(alpha) ** 2

    def geometry(theta):
        s = 1.0 if theta > 0 else -1.0
        ell = B + s * d
        return s, ell, 2 * ell * abs(math.sin(theta / 2)), ell * math.cos(theta / 2)

    def force(theta, branch, dp):
        length = geometry(theta)[2]
        return k1 * (length - dp) if branch == 0 else k2 * length + branch * c

    y, t, branch, dp, hits = [0.0, rate0], 0.0, 0, 0.0, []
    while len(hits) < wanted:
        sign = 1.0 if y[0] > 0 or (y[0] == 0 and y[1] > 0) else -1.0
        y0 = [sign * 1e-15 if y[0] == 0 else y[0], y[1]]

        def rhs(_t, state, branch=branch, dp=dp):
            s, ell, _, arm = geometry(state[0])
            moment = (
                -m * G * R * math.sin(s * alpha - state[0]) - force(state[0], branch, dp) * arm * s
            )
            return [state[1], moment / inertia]

        def hit(_t, state, sign=sign):
            return state[0] * sign

        def upper(_t, state, dp=dp):
            return force(state[0], 0, dp) - force(state[0], 1, dp)

        def lower(_t, state, dp=dp):
            return force(state[0], -1, dp) - force(state[0], 0, dp)

        def turned(_t, state, sign=sign, branch=branch):  # Δ̇ = ∂Δ/∂θ·θ̇, ∂Δ/∂θ of sign s
            return -branch * sign * state[1]

        for event in (hit, upper, lower, turned):
            event.terminal, event.direction = True, 1.0
        hit.direction = -1.0
        events = [hit, upper, lower] if branch == 0 else [hit, turned]
        solution = solve_ivp(rhs, (t, t + 10.0), y0, method="DOP853", rtol=1e-13, atol=1e-15,
                             events=events)  # fmt: skip
        which = next(i for i, times in enumerate(solution.t_events) if times.size)
        t, y = solution.t_events[which][0], list(solution.y_events[which][0])
        if which == 0:  # an impact: Δ = 0, the mode and Δ̇ reverse
            y = [0.0, eta * y[1]]
            hits.append((t, y[1]))
            if branch == -1:  # Δ̇ > 0 after it: unloads from the lower line at Δ = 0
                branch, dp = 0, -force(0.0, -1, dp) / k1
        elif branch == 0:
            branch = 1 if which == 1 else -1
        else:
            dp, branch = geometry(y[0])[2] - force(y[0], branch, dp) / k1, 0
    return np.array(hits)


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
def test_free_rocking_with_a_dissipator_matches_an_independent_integration():
    """Released at θ = 0 with θ̇ = 0.3 rad/s, the block's dissipator (Δ_y = 1.5 mm; its
    compressive line, (1 − k2/k1)·F_y·ℓ ≈ 21 kN·m, below the weight's restoring m·g·B ≈ 61 kN·m,
    so that the block comes back) yields in tension, unloads, is pushed into compression as the
    base closes: the first six impacts' times and rates against scipy's DOP853 on the block's
    own equation with the bilinear law and its branch changes as events (`_dissipating_block`)."""
    d, k1, fy, k2 = 0.2, 2.0e7, 3.0e4, 2.0e5
    dissipator = Dissipator(0, d, k1, fy, hardening=k2)
    response = analyze(Bridge(BLOCK, devices=(dissipator,)), np.zeros(401), DT, "reference",
                       initial=(0.0, 0.3))  # fmt: skip
    hits = _dissipating_block(d, k1, fy, k2, 0.3, 6)
    assert response.peaks["dissipator1_yielded"][0] == 1.0
    impacts_ = response.events["kind"] == "impact"
    np.testing.assert_allclose(response.events["time"][impacts_][:6], hits[:, 0], rtol=1e-8)
    np.testing.assert_allclose(response.events["rate_after"][impacts_][:6], hits[:, 1], rtol=1e-7)


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
def test_energy_balances_with_yielding_tendons():
    """Free rocking of the h̄ = 1.25 frame with two tendons that yield (no ground motion, so
    no input work), η_s = √(M_s/M_−s) (impacts take no energy): at the end of records of four
    lengths, ½M·θ̇1² + V_gravity + the tendons' elastic energy in their final state
    (`strain_energy`) + their plastic work Σ F_y·Δp (elastic–perfectly-plastic: all the work
    past the yield goes into Δp at the force F_y) equals the energy at the release, to 1e-8 of
    it (the reference fidelity's tolerance)."""
    frame = studied_bridge(1.25, abutments=False)
    devices = (
        Tendon(0, 0.3, 2e6, 3e8, yield_force=3.5e6),
        Tendon(1, -0.4, 1e6, 5e8, yield_force=2.8e6),
    )
    rows = table(devices)
    laws = conservative_laws(frame, rows)
    settings = fidelity.resolve("reference").settings()
    theta0 = 0.012
    start = energy(frame, 1.0, theta0, 0.0, False, EXACT) + strain_energy(rows, frame, 1.0, theta0)
    yielded = 0
    for samples in (151, 233, 377, 601):
        result = integrate(frame, laws, EXACT, np.zeros(samples), DT, settings, theta0, 0.0,
                           None, rows)  # fmt: skip
        assert result.error == NO_ERROR
        state, s = result.devices, float(result.mode[-1])
        theta, rate = result.theta1[-1], result.rate[-1]
        plastic = 0.0
        for row in state:
            dp = row[PLASTIC]
            if row[BRANCH] == LOADING:  # Δp not yet set: Δ − Δ_y of the branch
                dp = (
                    elongation(frame, row, s, theta)[0]
                    - (row[YIELD] - row[PRESTRESS]) / row[STIFFNESS]
                )
            plastic += row[YIELD] * dp
            yielded += row[BRANCH] != ELASTIC or dp > 0.0
        total = energy(frame, s, theta, rate, False, EXACT) + strain_energy(state, frame, s, theta)
        assert total + plastic == pytest.approx(start, rel=1e-8)
    assert yielded  # the tendons did yield


def test_the_bundled_dissipator_bridge_carries_the_dissipators_its_comment_states():
    """studied-hbar1.25-dissipators.yaml: 40 mm mild-steel bars over 0.5 m at ±1.0 m across
    each pier's base: k1 = 200 GPa × π·20² mm² / 0.5 m, F_y = 300 MPa × π·20² mm² (rounded to
    four digits in the file), k2 = 0.01·k1, fracture at 8 % of 0.5 m."""
    path = Path(__file__).resolve().parents[1] / "configs/bridges/studied-hbar1.25-dissipators.yaml"
    devices = load_bridge(path).to_bridge().devices
    area = math.pi * 0.020**2
    for device, (pier, offset) in zip(devices, [(p, d) for p in (0, 1) for d in (-1.0, 1.0)],
                                      strict=True):  # fmt: skip
        assert (device.pier, device.offset, device.base, device.top) == (pier, offset, True, False)
        assert device.stiffness == pytest.approx(200e9 * area / 0.5, rel=1e-3)
        assert device.yield_force == pytest.approx(300e6 * area, rel=1e-3)
        assert device.hardening == pytest.approx(0.01 * device.stiffness, rel=1e-12)
        assert device.fracture == pytest.approx(0.04, rel=1e-12)


CONFIG = """
name: frame
piers: {{width: 2.6, heights: [26.0, 20.8]}}
deck: {{depth: 1.7, area: 6.0}}
spans: {{side: 38.0, central: 60.0}}
devices:
{devices}
"""

DISSIPATOR = (
    "  - {{kind: dissipator, pier: 2, offset: -0.8, stiffness: 4.0e+8, yield_force: 1.2e+6, "
    "post_yield_ratio: 0.02, fracture_strain: 0.1, length: 0.5, interface: both{extra}}}"
)


def test_a_configs_dissipator_is_the_cores(tmp_path):
    """The config's fields become the core's: k2 = ratio·k1, the fracture elongation
    strain·length, both interfaces, the pier and offset in the core's frame (tall pier first)."""
    path = tmp_path / "b.yaml"
    path.write_text(CONFIG.format(devices=DISSIPATOR.format(extra="")))
    (device,) = load_bridge(path).to_bridge().devices
    assert device == Dissipator(1, -0.8, 4.0e8, 1.2e6, 0.02 * 4.0e8, 0.1 * 0.5, 0.5, True, True)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (", post_yield_ratio: 1.0", "devices.0.post_yield_ratio: 1 is not below 1"),
        (", length: null", "devices.0.length: missing"),
        (", fracture_strain: 0.001", "devices.0.fracture_strain: fractures at 0.0005 m"),
    ],
)
def test_impossible_dissipators_are_refused_naming_the_field(tmp_path, extra, message):
    """A post-yield stiffness not below the elastic one, a fracture strain without a length to
    turn it into an elongation, and a fracture before the yield elongation F_y/k1 = 3 mm."""
    text = DISSIPATOR.format(extra="").replace(", post_yield_ratio: 0.02", "")
    text = text.replace(", fracture_strain: 0.1", "").replace(", length: 0.5", "")
    text = text.replace("interface: both", "interface: both, fracture_strain: 0.1, length: 0.5")
    for field in ("post_yield_ratio", "length", "fracture_strain"):
        if field in extra:
            text = text.replace(f", {field}: 0.1", "").replace(f", {field}: 0.5", "")
    path = tmp_path / "b.yaml"
    path.write_text(CONFIG.format(devices=text[:-1] + extra + "}"))
    with pytest.raises(Exception, match=message.replace("(", r"\(")):
        load_bridge(path)


def test_the_device_rows_flags_are_the_solvers_states():
    """/devices takes yielded and ruptured from the solver's state (``<name>_yielded``,
    ``<name>_broken``), not from the largest force; a limit the device does not state is −1;
    the tendon states count the tendons only, not a dissipator that yielded by design, and
    ``dissipator_fracture`` the dissipators (a strain: Δ_max/length)."""
    devices = (
        Tendon(0, 0.0, 1e6, 1e8, yield_force=2e6, rupture_strain=0.03, rigidity=1e9),
        Dissipator(1, 0.0, 4e8, 1e6),
        Dissipator(1, 0.5, 4e8, 1e6, fracture=0.05, length=0.5),
    )
    peaks = {
        "tendon1_elongation": (0.02, 3.0), "tendon1_force": (2e6, 2.5),
        "tendon1_yielded": (0.0, math.nan), "tendon1_broken": (0.0, math.nan),
        "dissipator1_elongation": (0.01, 3.0), "dissipator1_force": (1.1e6, 3.0),
        "dissipator1_yielded": (1.0, 1.2), "dissipator1_broken": (0.0, math.nan),
        "dissipator2_elongation": (0.06, 3.0), "dissipator2_force": (1.1e6, 2.9),
        "dissipator2_yielded": (1.0, 1.3), "dissipator2_broken": (1.0, 2.95),
    }  # fmt: skip
    rows = device_rows(devices, peaks)
    assert list(rows["yielded"]) == [0, 1, 1]
    assert list(rows["ruptured"]) == [0, -1, 1]
    # ε0 + Δ/L_free = (P0 + k·Δ)/(E·A) = (1e6 + 1e8·0.02)/1e9
    assert rows["strain_max"][0] == pytest.approx(3e-3, rel=1e-12)
    assert math.isnan(rows["strain_max"][1])  # no length stated
    assert rows["strain_max"][2] == pytest.approx(0.06 / 0.5, rel=1e-15)
    states = {"tendon_yield": 0.0, "tendon_rupture": 0.0, "dissipator_fracture": 1.0}
    assert device_states(rows) == states
    assert check_limit_state("dissipator_fracture") == "dissipator_fracture"
    assert Verdict("ok", "none", 0.0, *states.values()).reaches(states) == {"dissipator_fracture"}


@pytest.mark.parametrize("s", [1.0, -1.0])
def test_back_at_rest_the_onset_counts_what_a_yielded_tendon_still_pulls(s):
    """Eq. 8 at rest after a yield: a tendon that has lost prestress (Δp > 0) resists the next
    uplift with P0 − k·Δp, so the threshold is `onset_threshold` of the same block with a tendon
    of that prestress (its closed form: gravity's and the prestress's moments over the ground's
    lever); slack (k·Δp > P0) or ruptured, the free block's, g·tan α in mode p. Unchanged, the
    thresholds given are returned as they are, bit for bit (a tendon that never yielded runs as
    before). Checked on the Python function and on its compiled overload."""
    from numba import njit

    from rockbridge_cli.core.devices import BROKEN
    from rockbridge_cli.core.impacts import onset_threshold, onsets_at_rest

    @njit
    def compiled(p, n, model, devices):
        return onsets_at_rest(p, n, model, devices)

    p0, k = 1.0e6, 1.0e8
    rows = table((Tendon(0, 0.2, p0, k, top=False, yield_force=2.0e6),))
    built = onset_threshold(BLOCK, 1.0, rows), onset_threshold(BLOCK, -1.0, rows)
    for run in (onsets_at_rest, compiled):
        assert run(*built, BLOCK, rows.copy()) == built
    lost = 0.004  # Δp [m]: P0 − k·Δp = 0.6 MN
    yielded = rows.copy()
    yielded[0, PLASTIC] = lost
    reduced = table((Tendon(0, 0.2, p0 - k * lost, k, top=False),))
    expected = onset_threshold(BLOCK, s, reduced)
    assert abs(expected) < abs(built[0 if s > 0 else 1])  # the next uplift comes sooner
    for run in (onsets_at_rest, compiled):
        assert run(*built, BLOCK, yielded)[0 if s > 0 else 1] == pytest.approx(expected, rel=1e-12)
    free = onset_threshold(BLOCK, s)
    assert abs(free) == pytest.approx(G * BLOCK.B / BLOCK.H1, rel=1e-12)  # g·tan α
    slack, broken = yielded.copy(), rows.copy()
    slack[0, PLASTIC] = 2.0 * p0 / k
    broken[0, BRANCH] = BROKEN
    for state in (slack, broken):
        for run in (onsets_at_rest, compiled):
            assert run(*built, BLOCK, state)[0 if s > 0 else 1] == pytest.approx(free, rel=1e-12)


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
def test_a_bridge_back_at_rest_after_its_tendon_went_slack_lifts_off_as_a_free_block():
    """The block of the yielding-tendon test above loses more than its prestress at the yield
    (k·Δp ≈ 6.3e5 N > P0 = 3e5 N, Δp from the independent integration) and comes to rest slack:
    a ground acceleration ramped in over one sample to 2 % above the free block's g·tan α,
    a quarter of the threshold of the tendon as built, lifts it off where the ramp crosses
    g·tan α (t = 11.99 + 0.01·g·tan α/level, to 1e-9 s); 2 % below g·tan α it stays at rest."""
    d, prestress, stiffness, fy = 0.15, 3.0e5, 2.0e8, 1.5e6
    dp = _reference_rocking(d, prestress, stiffness, fy, 0.45, 4)[2]
    assert stiffness * dp > prestress  # slack at rest
    tendon = Tendon(0, d, prestress, stiffness, top=False, yield_force=fy)
    bridge = Bridge(BLOCK, devices=(tendon,))
    free = impacts.onset_threshold(BLOCK, 1.0)
    assert free == pytest.approx(G * BLOCK.B / BLOCK.H1, rel=1e-12)
    assert impacts.onset_threshold(BLOCK, 1.0, table((tendon,))) > 4.0 * free
    for level, lifts in ((1.02 * free, True), (0.98 * free, False)):
        ground = np.zeros(1401)
        ground[1200:] = level
        response = analyze(bridge, ground, DT, "reference", initial=(0.0, 0.45))
        kinds, times = response.events["kind"], response.events["time"]
        rests = times[kinds == "rest"]
        assert rests.size == 1 and rests[0] < 11.99  # at rest before the ramp
        onsets = times[kinds == "onset"][1:]  # the first is the release at t = 0
        if lifts:
            assert onsets.size == 1
            assert onsets[0] == pytest.approx(11.99 + DT * free / level, abs=1e-9)
        else:
            assert onsets.size == 0
