"""Tendons and dampers on the piers (issue 41; docs/model.md §13), against independent checks:
the onset of a post-tensioned block in closed form, free rocking of a post-tensioned block
integrated here with scipy (exact events), the elongation's φ-derivative by finite differences, the
conservation of energy with tendons, the energy a damper takes, and the free-standing bridge
unchanged without devices."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from conftest import G, conservative_laws, studied_bridge
from scipy.integrate import simpson, solve_ivp

from rockbridge_cli.cli import main
from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.config.plausibility import bridge_warnings
from rockbridge_cli.core import fidelity, impacts
from rockbridge_cli.core.analysis import analyze
from rockbridge_cli.core.bridge import Bridge
from rockbridge_cli.core.device_mechanics import elongation, restrained, strain_energy, turns
from rockbridge_cli.core.devices import DAMPING, Damper, Tendon, table
from rockbridge_cli.core.dynamics import coefficients, energy
from rockbridge_cli.core.geometry import single_block
from rockbridge_cli.core.kinematics import EXACT
from rockbridge_cli.core.solver import (
    EVENT_KIND,
    EVENT_MODE,
    EVENT_RATE_AFTER,
    EVENT_RATE_BEFORE,
    EVENT_TIME,
    IMPACT,
    NO_ERROR,
    Laws,
    integrate,
)
from rockbridge_cli.core.tables import tabulated
from rockbridge_cli.errors import InputError

REPO = Path(__file__).resolve().parents[1]
DT = 0.01
BLOCK = single_block(B=0.5, H=2.5, density=2500.0, g=G)  # a 1 m × 5 m block, α = 0.197 rad


def test_a_tendons_prestress_raises_the_onset_of_a_block_as_its_closed_form():
    """A block 2B × 2H of mass m with a tendon at offset d: at rest the ground's inertia force
    m·a·H must overcome m·g·B + P0·(B + s·d) about the pivot of mode s (the pivot at −s·B), so
    a_min = g·B/H + P0·(B + s·d)/(m·H) (statics of the block, not the code's linkage)."""
    m, B, H = BLOCK.m1, BLOCK.B, BLOCK.H1
    prestress, d = 4.0e5, 0.2
    rows = table((Tendon(0, d, prestress, 1e8, top=False),))
    for s in (1.0, -1.0):
        expected = s * (G * B / H + prestress * (B + s * d) / (m * H))
        assert impacts.onset_threshold(BLOCK, s, rows) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("h_bar", [1.0, 1.25, 2.0])
@pytest.mark.parametrize("s", [1.0, -1.0])
def test_the_elongations_derivative_is_its_finite_difference(h_bar, s):
    """∂Δ/∂φ of a tendon through each pier (both interfaces) and of a damper at a top interface,
    against a central difference of Δ (step 1e-6 rad: error ~1e-12 m/rad)."""
    model = studied_bridge(h_bar)
    devices = (
        Tendon(0, 0.4, 1e6, 1e8), Tendon(1, -0.7, 1e6, 1e8), Damper(1, 0.9, 1e6, False, True)
    )  # fmt: skip
    for row in table(devices):
        for theta1 in (0.002, 0.01, 0.03):
            x, h = s * theta1, 1e-6
            numeric = (elongation(model, row, s, x + h)[0]
                       - elongation(model, row, s, x - h)[0]) / (2 * h)  # fmt: skip
            assert elongation(model, row, s, x)[1] == pytest.approx(numeric, rel=1e-7)


def test_a_tendon_through_a_symmetric_frames_pier_stretches_4B_sin_half_theta():
    """h̄ = 1: the deck translates without turning, both interfaces of a pier turn by θ1, and the
    chords 2(B + s·d)·sin(θ/2) + 2(B − s·d)·sin(θ/2) add to 4B·sin(θ/2) wherever the duct lies."""
    model = studied_bridge(1.0, abutments=False)
    for d in (0.0, 0.5, -1.1):
        for s in (1.0, -1.0):
            row = table((Tendon(1, d, 1e6, 1e8),))[0]
            theta = s * 0.02
            assert elongation(model, row, s, theta)[0] == pytest.approx(
                4 * model.B * math.sin(0.01), rel=1e-12
            )


@pytest.mark.parametrize("s", [1.0, -1.0])
def test_the_push_over_curve_of_a_post_tensioned_block_is_its_closed_form(s):
    """The static moment–rotation curve of a rigid block 2B × 2H on its pivot, with a tendon at
    offset d (ℓ = B + s·d from the pivot), in the tendon's elastic range 0 < |θ| ≤ θ_y: the
    restoring moment the code's generalised forces give (gravity's ∂V/∂φ from `coefficients`,
    the tendon's through `restrained` at θ̇ = 0) against the block's statics,

        M(θ) = m·g·R·sin(α − |θ|) + (P0 + 2k·ℓ·sin(|θ|/2))·ℓ·cos(|θ|/2),

    weight about the pivot and the tendon's tension times the distance from the pivot to its
    chord (the isosceles triangle of the pivot, the anchor and the opened duct); θ_y where
    P0 + 2k·ℓ·sin(θ_y/2) = F_y. Its slope at rest is −m·g·H + k·ℓ² (the linear push-over's
    stiffness: the tendon's k·ℓ² against the P-Δ softening of the weight)."""
    m, B, H = BLOCK.m1, BLOCK.B, BLOCK.H1
    R, alpha = math.hypot(B, H), math.atan2(B, H)
    d, prestress, stiffness, yield_force = 0.2, 3.0e5, 2.0e8, 1.5e6
    tendon = Tendon(0, d, prestress, stiffness, top=False, yield_force=yield_force)
    rows = table((tendon,))
    ell = B + s * d
    yield_rotation = 2 * math.asin((yield_force - prestress) / (2 * stiffness * ell))
    for x in np.linspace(yield_rotation / 50, yield_rotation, 50):
        theta = s * x
        gravity = coefficients(BLOCK, s, theta, EXACT)[2]
        code = -s * restrained(-gravity, rows, BLOCK, s, theta, 0.0, EXACT)
        tension = prestress + 2 * stiffness * ell * math.sin(x / 2)
        closed = m * G * R * math.sin(alpha - x) + tension * ell * math.cos(x / 2)
        assert code == pytest.approx(closed, rel=1e-12)
    assert tension == pytest.approx(yield_force, rel=1e-12)  # the last point is the yield
    h = 1e-7  # the slope at rest by a one-sided difference (error ~ h·M'' ~ 1e-7 relative)
    moments = [
        -s * restrained(-coefficients(BLOCK, s, s * x, EXACT)[2], rows, BLOCK, s, s * x, 0.0,
                        EXACT)
        for x in (0.0, h)
    ]  # fmt: skip
    slope = (moments[1] - moments[0]) / h
    assert slope == pytest.approx(-m * G * H + stiffness * ell**2, rel=1e-6)


def _block_rhs(block, d: float, prestress: float, stiffness: float, a_g: float):
    """Housner's block with a tendon at offset d, written here from its own free-body diagram:
    I_O·θ̈ = −m·g·R·sin(s·α − θ) − m·a_g·R·cos(s·α − θ) − T·ℓ·cos(θ/2)·s, ℓ = B + s·d, with
    T = P0 + k·2ℓ·|sin(θ/2)| (the mode s = sign θ)."""
    m, B, H = block.m1, block.B, block.H1
    R, alpha = math.hypot(B, H), math.atan2(B, H)
    inertia = 4.0 / 3.0 * m * R * R

    def rhs(_t, y):
        theta, rate = y
        s = 1.0 if theta > 0 else -1.0
        ell = B + s * d
        tension = prestress + stiffness * 2 * ell * abs(math.sin(theta / 2))
        moment = (
            -m * G * R * math.sin(s * alpha - theta)
            - m * a_g * R * math.cos(s * alpha - theta)
            - tension * ell * math.cos(theta / 2) * s
        )
        return [rate, moment / inertia]

    return rhs


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
def test_free_rocking_of_a_post_tensioned_block_matches_an_independent_integration():
    """Free rocking from θ1 = 0.05 rad: the times of the first six impacts and the rates after
    them, against scipy's DOP853 on the block's own equation (`_block_rhs`) with its impacts
    located as events and Housner's η = 1 − 1.5·sin²α applied (regular dynamics: free decay)."""
    d, prestress, stiffness = 0.15, 3.0e5, 2.0e8
    bridge = Bridge(BLOCK, devices=(Tendon(0, d, prestress, stiffness, top=False),))
    response = analyze(bridge, np.zeros(401), DT, "reference", initial=(0.05, 0.0))
    impacts_ = response.events["kind"] == "impact"
    times, rates = response.events["time"][impacts_], response.events["rate_after"][impacts_]
    assert times.size >= 6

    eta = 1.0 - 1.5 * math.sin(math.atan2(BLOCK.B, BLOCK.H1)) ** 2
    rhs = _block_rhs(BLOCK, d, prestress, stiffness, 0.0)
    y, t, expected = [0.05, 0.0], 0.0, []
    for _ in range(6):
        sign = 1.0 if y[0] > 0 or (y[0] == 0 and y[1] > 0) else -1.0

        def hit(_t, state, sign=sign):
            return state[0] * sign - (1e-14 if abs(state[0]) < 1e-14 else 0.0)

        hit.terminal, hit.direction = True, -1.0
        y0 = [sign * 1e-15 if y[0] == 0 else y[0], y[1]]
        solution = solve_ivp(rhs, (t, t + 10.0), y0, method="DOP853", rtol=1e-13, atol=1e-15,
                             events=hit)  # fmt: skip
        t = solution.t_events[0][0]
        y = [0.0, eta * solution.y_events[0][0][1]]
        expected.append((t, y[1]))
    expected_ = np.array(expected)
    np.testing.assert_allclose(times[:6], expected_[:, 0], rtol=1e-8)
    np.testing.assert_allclose(rates[:6], expected_[:, 1], rtol=1e-7)


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
@pytest.mark.parametrize("h_bar", [1.0, 1.25, 2.0])
def test_energy_with_tendons_is_conserved_between_impacts(h_bar):
    """Free rocking of a frame with a tendon in each pier (no ground motion): the energy
    ½·M·θ̇1² + ΔV_gravity + Σ(P0·Δ + ½k·Δ²) is the same at every history sample between two
    impacts (to 1e-8 of it, the reference fidelity's tolerance), and at the impacts (where Δ = 0)
    with η_s = √(M_s/M_−s), as without tendons (`test_solver`)."""
    frame = studied_bridge(h_bar, abutments=False)
    devices = (Tendon(0, 0.3, 2e6, 3e8), Tendon(1, -0.4, 1e6, 5e8))
    rows = table(devices)
    laws = conservative_laws(frame, rows)
    mass = {s: coefficients(frame, s, 0.0, EXACT)[0] for s in (1.0, -1.0)}  # M_s(0)
    settings = fidelity.resolve("reference").settings()
    result = integrate(frame, laws, EXACT, np.zeros(801), DT, settings, 0.006, 0.0, None, rows)
    assert result.error == NO_ERROR
    hits = result.events[result.events[:, EVENT_KIND] == IMPACT]
    assert len(hits) >= 6
    modes = hits[:, EVENT_MODE]
    before = 0.5 * np.array([mass[-m] for m in modes]) * hits[:, EVENT_RATE_BEFORE] ** 2
    after = 0.5 * np.array([mass[m] for m in modes]) * hits[:, EVENT_RATE_AFTER] ** 2
    np.testing.assert_allclose(after, before, rtol=1e-12)
    np.testing.assert_allclose(before[1:], after[:-1], rtol=1e-8)
    total = [
        energy(frame, float(s), y, w, False, EXACT) + strain_energy(rows, frame, float(s), y)
        for y, w, s in zip(result.theta1, result.rate, result.mode, strict=True)
        if s != 0
    ]
    start = energy(frame, 1.0, 0.006, 0.0, False, EXACT) + strain_energy(rows, frame, 1.0, 0.006)
    np.testing.assert_allclose(total, start, rtol=1e-8)


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
def test_a_damper_takes_the_energy_it_dissipates():
    """A symmetric frame with a viscous damper at a pier's base, rocking freely with η = 1 (so
    that no impact takes energy): the energy lost by each impact, ½M·(θ̇_before² of the next −
    θ̇_after² of this), equals ∫c·Δ̇² dt over the half cycle, integrated here on the histories
    (Simpson's rule on the 1e-4 s samples strictly between the impacts: the slivers left out at
    both ends, < 1e-4 s of a half cycle of about 1.3 s at the largest power, bound it to 1e-3)."""
    frame = studied_bridge(1.0, abutments=False)
    damper = Damper(0, 0.6, 2.0e6)
    rows = table((damper,))
    mass = coefficients(frame, 1.0, 0.0, EXACT)[0]
    laws = Laws(
        onset_p=impacts.onset_threshold(frame, 1.0),
        onset_n=impacts.onset_threshold(frame, -1.0),
        eta_p=1.0, eta_n=1.0, pounding=1.0,
    )  # fmt: skip
    settings = fidelity.resolve("reference").changed(output_step=1e-4).settings()
    result = integrate(frame, laws, EXACT, np.zeros(601), DT, settings, 0.008, 0.0, None, rows)
    hits = result.events[result.events[:, EVENT_KIND] == IMPACT]
    assert len(hits) >= 3
    t = np.arange(result.theta1.size) * 1e-4
    power = np.array([
        damper.coefficient * (elongation(frame, rows[0], float(s), y)[1] * w) ** 2
        for y, w, s in zip(result.theta1, result.rate, result.mode, strict=True)
    ])  # fmt: skip
    for first, second in zip(hits[:-1], hits[1:], strict=False):
        lost = 0.5 * mass * (first[EVENT_RATE_AFTER] ** 2 - second[EVENT_RATE_BEFORE] ** 2)
        inside = (t > first[EVENT_TIME]) & (t < second[EVENT_TIME])
        assert simpson(power[inside], x=t[inside]) == pytest.approx(lost, rel=1e-3)


def test_a_bridge_without_devices_runs_as_before():
    """An empty tuple of devices is the free-standing bridge: the same laws and, bit for bit,
    the same response (the kernels compiled without devices)."""
    model = studied_bridge(1.25)
    t = np.arange(0.0, 8.0, DT)
    acc = 0.5 * G * np.sin(2 * np.pi * t / 1.2) * (t < 4.0)
    free, empty = Bridge(model), Bridge(model, devices=())
    assert empty.device_table() is None and free.laws() == empty.laws()
    a, b = analyze(free, acc, DT, "fast"), analyze(empty, acc, DT, "fast")
    assert a.peaks == b.peaks and np.array_equal(a.histories["theta1"], b.histories["theta1"])


# ---------------------------------------------------------------- the config's devices section

BRIDGE = """
piers: {{width: 2.6, heights: [{left}, {right}]}}
deck: {{depth: 1.7, area: 6.0}}
spans: {{side: 38.0, central: 60.0}}
abutments: {{gap: 0.12, stiffness: 1.32e+8, damping: 4.8e+7, ultimate_displacement: 0.10}}
devices:
{devices}
"""
TENDON = "  - {{kind: tendon, pier: {pier}, offset: {offset}, prestress: 4.0e+6, area: 5.0e-3}}"


ONE_TENDON = TENDON.format(pier=1, offset=0.3)


def _config(tmp_path, left=26.0, right=20.8, devices=ONE_TENDON):
    path = tmp_path / "bridge.yaml"
    path.write_text(BRIDGE.format(left=left, right=right, devices=devices), encoding="utf-8")
    return load_bridge(path)


def test_a_configs_tendon_is_the_cores_with_its_stiffness_from_e_a_and_the_pier_height(tmp_path):
    """k = E·A/L_free with the default E = 195 GPa and L_free = the pier's height 2H = 26 m; no
    yield force or rupture strain unless stated (inf), its rigidity E·A for its strains."""
    (tendon,) = _config(tmp_path).to_bridge().devices
    assert tendon == Tendon(0, 0.3, 4.0e6, 195e9 * 5.0e-3 / 26.0, top=True,
                            rigidity=195e9 * 5.0e-3)  # fmt: skip
    assert math.isinf(tendon.yield_force) and math.isinf(tendon.rupture_strain)
    limited = TENDON.format(pier=1, offset=0.3).replace("}", ", yield_force: 6.0e+6, "
                                                       "rupture_strain: 0.02}")  # fmt: skip
    (tendon,) = _config(tmp_path, devices=limited).to_bridge().devices
    assert (tendon.yield_force, tendon.rupture_strain) == (6.0e6, 0.02)


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
def test_a_mirrored_bridges_devices_are_mirrored_with_it(tmp_path):
    """The user's bridge with its tall pier on the right, a tendon in it at +0.3 m and a damper
    in the short pier at −0.5 m: the core's tall pier is pier 0, offsets change sign; and its
    response to a motion is the mirror image of the drawn-the-other-way bridge's."""
    devices = (TENDON.format(pier=2, offset=0.3)
               + "\n  - {kind: damper, pier: 1, offset: -0.5, coefficient: 1.0e+7}")  # fmt: skip
    mirrored = _config(tmp_path, left=20.8, right=26.0, devices=devices).to_bridge()
    assert mirrored.mirrored
    tendon, damper = mirrored.devices
    assert (tendon.pier, tendon.offset, damper.pier, damper.offset) == (0, -0.3, 1, 0.5)
    drawn = (TENDON.format(pier=1, offset=-0.3)
             + "\n  - {kind: damper, pier: 2, offset: 0.5, coefficient: 1.0e+7}")  # fmt: skip
    direct = _config(tmp_path, devices=drawn).to_bridge()
    assert direct.devices == mirrored.devices and direct.model == mirrored.model
    t = np.arange(0.0, 6.0, DT)
    acc = 0.6 * G * np.sin(2 * np.pi * t / 1.5) * (t < 3.0)
    a, b = analyze(direct, acc, DT, "fast"), analyze(mirrored, -acc, DT, "fast")
    np.testing.assert_array_equal(a.histories["theta1"], -b.histories["theta1"])
    assert a.peaks["tendon1_force"] == b.peaks["tendon1_force"]


@pytest.mark.parametrize(
    ("devices", "message"),
    [
        (TENDON.format(pier=1, offset=1.3), "devices.0.offset: 1.3 m lies outside the section"),
        (TENDON.format(pier=3, offset=0.0), "devices.0.tendon.pier: Input should be less than"),
        ("  - {kind: spring, pier: 1}", "kind is tendon, damper or dissipator"),
        ("  - {kind: tendon, pier: 1, prestress: -1.0, area: 0.005}", "devices.0.tendon.prestress"),
        ("  - {kind: damper, pier: 1, coefficient: 0.0}", "devices.0.damper.coefficient"),
    ],
)
def test_impossible_devices_are_refused_naming_the_field(tmp_path, devices, message):
    with pytest.raises(InputError) as info:
        _config(tmp_path, devices=devices)
    assert message in str(info.value)


@pytest.mark.parametrize(
    ("limit", "message"),
    [
        ("yield_force: 4.0e+6", "devices.0.yield_force: 4e+06 N does not exceed the prestress"),
        ("yield_force: 3.0e+6", "devices.0.yield_force: 3e+06 N does not exceed the prestress"),
        # ε0 = P0/(E·A) = 4 MN / (195 GPa × 5000 mm²) = 0.0041026
        ("rupture_strain: 0.0041", "devices.0.rupture_strain: 0.0041 does not exceed the strain "
         "at prestress P0/(E·A) = 0.004103"),
        ("rupture_strain: -0.01", "devices.0.tendon.rupture_strain"),
    ],
)  # fmt: skip
def test_a_tendon_past_its_limits_at_rest_is_refused_naming_the_field(tmp_path, limit, message):
    """A yield force not above the prestress, a rupture strain not above the strain at
    prestress: the tendon would reach the limit at rest. One line naming the field."""
    devices = TENDON.format(pier=1, offset=0.3).replace("}", f", {limit}}}")
    with pytest.raises(InputError) as info:
        _config(tmp_path, devices=devices)
    assert message in str(info.value) and "\n" not in str(info.value).strip()
    accepted = "rupture_strain: 0.0042" if "rupture" in limit else "yield_force: 4.1e+6"
    _config(tmp_path, devices=TENDON.format(pier=1, offset=0.3).replace("}", f", {accepted}}}"))


def test_a_single_block_has_no_top_interface_for_a_damper(tmp_path):
    path = tmp_path / "block.yaml"
    path.write_text("piers: {width: 1.0, heights: [5.0]}\ndevices:\n"
                    "  - {kind: damper, pier: 1, coefficient: 1.0e+5, interface: top}\n",
                    encoding="utf-8")  # fmt: skip
    with pytest.raises(InputError, match="devices.0.interface: a single block rocks on its base"):
        load_bridge(path)


def test_a_tendon_stressed_beyond_strand_strength_is_warned_of(tmp_path):
    """4 MN on 1000 mm² is 4000 MPa, over Y1860 strand's 1860 MPa (EN 10138-3)."""
    devices = "  - {kind: tendon, pier: 1, prestress: 4.0e+6, area: 1.0e-3}"
    warnings = bridge_warnings(_config(tmp_path, devices=devices))
    assert any(w.startswith("devices.0.prestress: 4000 MPa") for w in warnings)


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
def test_analyze_lists_each_devices_peaks_with_their_units(tmp_path):
    """`rockbridge analyze --json` of the bundled bridge with tendons: each tendon's largest force
    (in N) and elongation (in m), as the library gives them; the force is P0 + k·Δ at the largest
    elongation (an elastic tendon's force grows with Δ alone)."""
    bridge = REPO / "configs" / "bridges" / "studied-hbar1.25-tendons.yaml"
    record = REPO / "records" / "ec8-type1-C-ag0.6g" / "AR07.txt"
    result = CliRunner().invoke(main, ["analyze", str(bridge), str(record), "--json",
                                       "--fidelity", "fast"])  # fmt: skip
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    tendon = load_bridge(bridge).to_bridge().devices[0]
    for n in (1, 2):
        assert data["units"][f"tendon{n}_force_max"] == "N"
        assert data["units"][f"tendon{n}_elongation_max"] == "m"
    stretched = tendon.prestress + tendon.stiffness * data["tendon1_elongation_max"]
    assert data["tendon1_force_max"] == pytest.approx(stretched, rel=1e-12)
    assert data["tendon1_elongation_max"] > 0.0


@pytest.mark.parametrize("h_bar", [1.25, 2.0])
def test_the_tables_turns_are_the_linkages(h_bar):
    """`fast` and `default` take θ2, ψ', θ_deck and θ' for the devices from the tabulated
    kinematics (cubic splines of exact samples, and their slopes): against the exact linkage at
    200 rotations up to the abutment's failure in both modes, to 2e-8 (measured 4e-9 at worst,
    θ' of h̄ = 1.25, the slope of the smallest quantity)."""
    model = studied_bridge(h_bar)
    kin = tabulated(model)
    for s in (1.0, -1.0):
        for x in np.linspace(1e-5, 0.009, 200):
            np.testing.assert_allclose(
                turns(model, s, s * x, kin), turns(model, s, s * x, EXACT), rtol=2e-8, atol=0
            )


def test_the_bundled_restrained_bridges_carry_the_devices_their_comments_state():
    """studied-hbar1.25-tendons.yaml: a tendon through each pier, P0 = 0.5·1860 MPa × 5040 mm²
    = 4.6872 MN, k = 195 GPa × 5040 mm² / 2H (26 and 20.8 m), F_y = 0.9·1860 MPa × 5040 mm²,
    ε_u = 3.5 % (EN 10138-3's A_gt); -dampers.yaml: 20 MN·s/m at ±1.0 m across each pier's
    base."""
    bridges = REPO / "configs" / "bridges"
    tendons = load_bridge(bridges / "studied-hbar1.25-tendons.yaml").to_bridge().devices
    area = 5.04e-3
    limits = {"yield_force": 0.9 * 1860e6 * area, "rupture_strain": 0.035,
              "rigidity": 195e9 * area}  # fmt: skip
    assert tendons == (
        Tendon(0, 0.0, 0.5 * 1860e6 * area, 195e9 * area / 26.0, **limits),
        Tendon(1, 0.0, 0.5 * 1860e6 * area, 195e9 * area / 20.8, **limits),
    )
    dampers = load_bridge(bridges / "studied-hbar1.25-dampers.yaml").to_bridge().devices
    assert dampers == tuple(Damper(p, d, 20e6) for p in (0, 1) for d in (-1.0, 1.0))


def test_a_study_with_devices_makes_their_kernels_ready_and_says_so_once(tmp_path, monkeypatch):
    """The kernels of a bridge with devices are compiled for them of their own: a study whose
    grid has such a bridge makes them ready before its first analysis (one process at a time),
    saying so once with `COMPILING_DEVICES`; a worker's word for it reads back as that message.
    (A function numba compiles afresh stands for the kernels.)"""
    import numba

    from rockbridge_cli import warmup
    from rockbridge_cli.study import kernels
    from rockbridge_cli.study.executors.worker import compiling_said
    from rockbridge_cli.study.grid import BridgeCase, Grid

    def compile_a_kernel(vertical=None):
        numba.njit(lambda x: x + 3.0)(1.0)

    monkeypatch.setattr(warmup, "device_kernels", compile_a_kernel)
    monkeypatch.setattr(kernels, "_ready", {"horizontal"})
    said: list[int] = []
    assert kernels.prepare(lambda: said.append(1), devices=True)
    assert said == [1] and kernels._ready == {"horizontal", "devices"}
    assert kernels.prepare(lambda: said.append(1), devices=True) and said == [1]  # once
    told = compiling_said(False, True)
    assert kernels.compiling_message("vertical" in told, "devices" in told) == (
        kernels.COMPILING_DEVICES
    )
    restrained = load_bridge(REPO / "configs" / "bridges" / "studied-hbar1.25-tendons.yaml")
    free = load_bridge(REPO / "configs" / "bridges" / "studied-hbar1.25.yaml")
    for cases, expected in (([free], False), ([free, restrained], True)):
        bridges = tuple(BridgeCase(f"b{i}", c.to_bridge()) for i, c in enumerate(cases))
        assert Grid(bridges, (), fidelity.resolve("fast"), (), "").devices is expected


# ------------------------------------------------------------ energy balance under ground motion


def _crossing(model, s, times, theta, when):
    """θ1 where |u_deck| = u_jo at an event at ``when`` [s] in mode s: bracketed by the two
    history samples around it (the same mode) and solved on the exact kinematics."""
    from scipy.optimize import brentq

    i = np.searchsorted(times, when)
    return brentq(
        lambda y: abs(coefficients(model, s, y, EXACT)[4]) - model.u_jo, theta[i - 1], theta[i],
        xtol=1e-16, rtol=4 * np.finfo(float).eps,
    )  # fmt: skip


def _powers(model, rows, damper, s, theta, rate, ground, contact):
    """At the nodes (θ1, θ̇1) of a stretch in mode s: the ground's input power −ü_g·Σm·∂x/∂φ·θ̇,
    the damper's c·Δ̇² and the backfill dashpot's c_b·(∂u/∂φ·θ̇)² (in contact) [W]; written
    here from §4 and §13's generalised forces."""
    out = np.zeros((3, theta.size))
    for j, (y, w, a) in enumerate(zip(theta, rate, ground, strict=True)):
        _, _, _, inertia, _, du = coefficients(model, s, y, EXACT)
        lever = elongation(model, rows[damper], s, y)[1]
        out[:, j] = (-a * inertia * w, rows[damper, DAMPING] * (lever * w) ** 2,
                     model.c * (du * w) ** 2 if contact else 0.0)  # fmt: skip
    return out


def _piecewise(powers, t):
    """∫ powers dt by Simpson's rule on each piece between two record samples (multiples of
    `DT`, which are history samples too): ü_g is linear between them, so the integrands are
    smooth on each piece and their kinks fall on its ends."""
    kinks = np.flatnonzero(np.abs(t / DT - np.round(t / DT)) < 1e-9)
    cuts = np.unique(np.concatenate([[0], kinks, [t.size - 1]]))
    return sum(
        simpson(powers[:, a : b + 1], x=t[a : b + 1], axis=1) if b - a > 1
        else 0.5 * (powers[:, a] + powers[:, b]) * (t[b] - t[a])
        for a, b in zip(cuts[:-1], cuts[1:], strict=True)
    )  # fmt: skip


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
def test_energy_balances_the_input_work_under_ground_motion_with_devices():
    """The bridge of h̄ = 1.25 with a tendon through each pier and a damper across the tall
    pier's base, under a 0.45 g sine of 1.2 s for 4 s (its deck closes the gaps): at the end of
    the analysis, kinetic + potential (gravity, backfill spring) + tendon strain energy + the
    damper's and backfill dashpot's work + the losses at interface impacts and poundings equals
    the input work of the ground, ∫ −ü_g·Σm_i·∂x_i/∂φ·θ̇1 dt, integrated here on the history
    (reference fidelity, 1e-4 s samples, Simpson's rule on each stretch between two events with
    the events' own states as its ends, so that no jump is integrated across, and between the
    record's samples, where ü_g has its kinks: `_piecewise`).

    Tolerance 1e-8 of the input work (the issue's): measured 1.4e-10 (17.43 MJ of input; damper
    0.19 MJ, backfill dashpot 15.65 MJ, impacts and poundings 1.24 MJ, left at the end 0.35 MJ),
    1.6e-10 with 2e-4 s samples, so the quadrature has converged and what is left is the
    integration's own error (rtol 1e-12 a step); a term left out would miss by its share, the
    smallest (the damper's) 1.1e-2."""
    model = studied_bridge(1.25)
    devices = (Tendon(0, 0.0, 4.6872e6, 3.78e7), Tendon(1, 0.0, 4.6872e6, 4.73e7),
               Damper(0, 1.0, 2.0e7))  # fmt: skip
    rows, damper = table(devices), 2
    step = 1e-4
    t_record = np.arange(0.0, 8.0, DT)
    acc = 0.45 * G * np.sin(2 * np.pi * t_record / 1.2) * (t_record < 4.0)
    response = analyze(Bridge(model, devices=devices), acc, DT, "reference", output_step=step)
    assert response.status == "ok" and response.failure_mode == "none"
    kinds = list(response.events["kind"])
    assert kinds.count("pounding") >= 1 and kinds.count("impact") >= 4
    times, theta = response.time, response.histories["theta1"]
    rate, mode = response.histories["theta1_rate"], response.histories["mode"]

    def ground(t):
        return np.interp(t, t_record, acc, right=0.0)  # linear between samples, as the solver

    events = response.events
    work = np.zeros(3)  # input, damper, backfill dashpot
    lost, contact = 0.0, False
    start = (0.0, 0.0, 0.0, 0.0)  # time, θ1, θ̇1, mode after the last event
    ends = [*zip(events["time"], events["kind"], events["mode"], events["rate_before"],
                 events["rate_after"], strict=True), (times[-1], "end", mode[-1], rate[-1],
                                                      rate[-1])]  # fmt: skip
    for when, kind, after, before, rate_after in ends:
        t0, y0, w0, s = start
        y1 = 0.0 if kind in ("onset", "impact", "rest") else (
            theta[-1] if kind == "end" else _crossing(model, s, times, theta, when))  # fmt: skip
        if s != 0.0:
            inside = (times > t0) & (times < when)
            t = np.concatenate([[t0], times[inside], [when]])
            y = np.concatenate([[y0], theta[inside], [y1]])
            w = np.concatenate([[w0], rate[inside], [before]])
            powers = _powers(model, rows, damper, s, y, w, ground(t), contact)
            work += _piecewise(powers, t)
        mass = coefficients(model, s or after, y1, EXACT)[0]
        if kind == "impact":  # at θ1 = 0 every Δ and the potential vanish: the kinetic change
            lost += 0.5 * mass * before**2 - 0.5 * coefficients(model, after, 0.0, EXACT)[0] * (
                rate_after**2)  # fmt: skip
        elif kind in ("pounding", "rest"):
            lost += 0.5 * mass * (before**2 - rate_after**2)
        contact = kind == "pounding" or (contact and kind not in ("reopening", "impact"))
        start = (when, y1, rate_after, after)
    s = float(mode[-1])
    stored = 0.0 if s == 0 else (
        energy(model, s, theta[-1], rate[-1], contact, EXACT)
        + strain_energy(rows, model, s, theta[-1])
    )  # fmt: skip
    total = stored + work[1] + work[2] + lost
    assert work[0] > 0 and work[1] > 0 and work[2] > 0
    assert total == pytest.approx(work[0], rel=1e-8)
