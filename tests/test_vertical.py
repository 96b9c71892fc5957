"""Vertical ground motion in the core (docs/model.md §12): g becomes g + ü_v in the equation of
motion and in the onset of rocking; a ground that falls faster than g is a free flight, which the
model does not follow; without a vertical component nothing changes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import G, studied_bridge
from scipy.integrate import simpson

from rockbridge_cli.core.analysis import analyze
from rockbridge_cli.core.bridge import Bridge
from rockbridge_cli.core.geometry import single_block
from rockbridge_cli.core.impacts import onset_threshold
from rockbridge_cli.core.solver import FREE_FLIGHT, SOLVER_ERRORS

pytestmark = pytest.mark.usefixtures("vertical_kernels")  # compiled once a suite (conftest)

DT = 0.01  # [s]


def shaking(duration: float = 12.0, seed: int = 4) -> np.ndarray:
    """A horizontal motion that rocks the studied bridges with impacts and poundings: a sum of
    sines under a 2-s build-up, peak 0.45 g [m/s²]."""
    t = np.arange(0.0, duration, DT)
    rng = np.random.default_rng(seed)
    waves = sum(
        np.sin(2.0 * np.pi * f * t + phase)
        for f, phase in zip(rng.uniform(0.5, 3.0, 8), rng.uniform(0, 2 * np.pi, 8), strict=True)
    )
    motion = waves * np.minimum(1.0, t / 2.0)
    return 0.45 * G * motion / np.abs(motion).max()


@pytest.mark.parametrize("up", [-2.5, 1.5])
@pytest.mark.parametrize(("h_bar", "mirrored"), [(1.0, False), (2.0, False), (2.0, True)])
def test_a_constant_vertical_acceleration_is_a_change_of_gravity(up, h_bar, mirrored):
    """Closed form (docs/model.md §12): ü_v enters the equations only as g + ü_v, so a constant
    a_v gives the response of the same bridge with gravity g + a_v and no vertical motion: the
    whole histories, the events and the peaks, to rounding. The mirror image turns the
    horizontal motion, never the vertical one."""
    model = studied_bridge(h_bar)
    acc = shaking()
    vertical = np.full(acc.size, up)
    got = analyze(Bridge(model, mirrored), acc, DT, "reference", vertical=vertical)
    heavier = Bridge(model._replace(g=model.g + up), mirrored)
    expected = analyze(heavier, acc, DT, "reference")
    assert got.status == expected.status == "ok"
    assert got.n_impacts == expected.n_impacts > 5 and got.n_poundings == expected.n_poundings
    assert list(got.events["kind"]) == list(expected.events["kind"])
    np.testing.assert_allclose(got.events["time"], expected.events["time"], rtol=0, atol=1e-9)
    for name, history in expected.histories.items():
        scale = max(np.nanmax(np.abs(history)), 1e-6)  # a symmetric deck turns by round-off
        np.testing.assert_allclose(got.histories[name], history, rtol=0, atol=1e-8 * scale)
    unchanged = analyze(Bridge(model, mirrored), acc, DT, "reference")
    assert abs(unchanged.peaks["theta1"][0] / got.peaks["theta1"][0] - 1.0) > 1e-4  # it matters


def test_the_chatter_guard_tests_the_lifted_threshold():
    """A half-sine pulse just above the onset threshold of gravity g + a makes the bridge rock a
    little and come to rest through ever smaller impacts (docs/model.md §7): under a constant
    ü_v = a exactly as the bridge with gravity g + a does, the rest included."""
    model, up = studied_bridge(2.0), 1.5
    heavier = model._replace(g=model.g + up)
    t = np.arange(0.0, 20.0, DT)
    pulse = np.where(t < 0.6, 1.05 * onset_threshold(heavier, 1.0) * np.sin(np.pi * t / 0.6), 0.0)
    got = analyze(Bridge(model), pulse, DT, vertical=np.full(t.size, up))
    expected = analyze(Bridge(heavier), pulse, DT)
    kinds = list(expected.events["kind"])
    assert "rest" in kinds and list(got.events["kind"]) == kinds
    np.testing.assert_allclose(got.events["time"], expected.events["time"], rtol=0, atol=1e-9)


@pytest.mark.parametrize("s", [1.0, -1.0])
@pytest.mark.parametrize("climb", [0.0, 3.0, -4.0])
def test_rocking_starts_where_the_horizontal_acceleration_reaches_the_lifted_threshold(s, climb):
    """Housner (1963): a block starts to rock when |ü_g| = g·tan α; under a vertical ü_v the
    weight is m·(g + ü_v), so when |ü_g| = (g + ü_v)·tan α. With ü_g = s·c·t and ü_v = d·t
    (linear, as the record's samples are between them) the onset is at
    t* = g·tan α / (c − d·tan α): a closed form, inside a sample interval."""
    block = single_block(B=0.5, H=2.5, density=2500.0, g=G)
    tan_alpha, rate = 0.2, 1.3  # B/H [-]; c [m/s³]
    t = np.arange(0.0, 5.0, DT)
    response = analyze(Bridge(block), s * rate * t, DT, "reference", vertical=climb * t)
    expected = G * tan_alpha / (rate - climb * tan_alpha)
    assert response.t_onset == pytest.approx(expected, rel=0, abs=1e-9)
    assert response.events["mode"][0] == s
    assert (expected / DT) % 1.0 > 1e-3  # not at a sample


def _block_energy_terms(block, theta, rate):
    """Closed forms for Housner's block rocking about a base corner (docs/model.md §1: mode +1
    turns counter-clockwise about the bottom-left corner): the mechanical energy above rest
    ½·I_O·θ̇² + m·g·(z − H) with I_O = 4/3·m·R², and the centre of gravity's x and z [J, m]."""
    R, alpha, m = block.R1, block.alpha1, block.m1
    x = R * np.sin(alpha - np.abs(theta)) * np.sign(theta) - block.B * np.sign(theta)
    z = R * np.cos(alpha - np.abs(theta))
    energy = 0.5 * (4.0 / 3.0) * m * R * R * rate * rate + m * block.g * (z - block.H1)
    return energy, x, z


def test_the_energy_changes_by_the_work_of_both_ground_motions():
    """Conservation of energy: over a rocking half cycle without impacts, the block's mechanical
    energy (closed forms, constant g) changes by the work of the inertia forces −m·ü_h and
    −m·ü_v: W = −m·∫(ü_h·ẋ + ü_v·ż) dt, integrated by parts, −m·[ü_h·x + ü_v·z] +
    m·∫(u⃛_h·x + u⃛_v·z) dt, where the jerks are the slopes of the samples (the motion is linear
    between them) and x, z are integrated over each sample interval by Simpson's rule on ten
    output steps. Both motions are sines, the vertical one 0.4 g."""
    block = single_block(B=2.0, H=10.0, density=2500.0, g=G)
    sample, substeps = 1e-3, 10  # [s], output steps per sample interval
    t = np.arange(0.0, 1.0 + 0.5 * sample, sample)
    motions = np.array(
        [0.5 * np.sin(2.0 * np.pi * t / 0.7), 0.4 * G * np.sin(2 * np.pi * t / 0.25)]
    )
    response = analyze(
        Bridge(block), motions[0], sample, "reference", initial=(0.5 * block.alpha1, 0.0),
        vertical=motions[1], output_step=sample / substeps,
    )  # fmt: skip
    assert response.n_impacts == 0 and response.status == "ok"
    theta, rate = response.histories["theta1"], response.histories["theta1_rate"]
    energy, x, z = _block_energy_terms(block, theta, rate)
    assert theta.size == substeps * (t.size - 1) + 1
    positions = np.array([x, z])  # per sample interval: the integrals of x and z over it
    pieces = np.lib.stride_tricks.sliding_window_view(positions, substeps + 1, axis=1)
    integrals = simpson(pieces[:, ::substeps], dx=sample / substeps, axis=-1)
    jerks = np.diff(motions, axis=1) / sample
    m = block.m1
    works = -m * (motions[:, -1] * positions[:, -1] - motions[:, 0] * positions[:, 0])
    works += m * np.sum(jerks * integrals, axis=1)
    change = energy[-1] - energy[0]
    assert abs(works[1]) > 0.1 * abs(change)  # the vertical motion does work
    assert change == pytest.approx(works.sum(), rel=1e-10)


def test_a_ground_falling_faster_than_gravity_ends_the_analysis_as_a_free_flight():
    """Where g + ü_v ≤ 0 the bridge would leave the ground: a vertical ramp down from 0 reaches
    −g at t = g/d, the first sample at or after it ends the analysis, with the solver status of
    a free flight, the time, no peak and no history after it (docs/model.md §12)."""
    model = studied_bridge(2.0)
    acc = shaking(duration=8.0)
    t = np.arange(acc.size) * DT
    dive = 2.0  # d [m/s³]
    response = analyze(Bridge(model), acc, DT, "default", vertical=-dive * t)
    flight = math.ceil(G / dive / DT - 1e-9) * DT  # the first sample with g + ü_v ≤ 0
    assert response.status.startswith(SOLVER_ERRORS[FREE_FLIGHT])
    assert f"t = {flight:.6g} s" in response.status
    assert all(math.isnan(value) for value, _ in response.peaks.values())
    theta = response.histories["theta1"]
    assert np.all(np.isnan(theta[response.time >= flight]))
    assert np.all(np.isfinite(theta[response.time < flight - DT]))
    almost = analyze(Bridge(model), acc, DT, "default", vertical=np.full(acc.size, -0.99 * G))
    assert almost.status == "ok"


def test_a_vertical_component_must_match_the_horizontal_one():
    """A vertical component of another length, or not finite, is refused."""
    bridge, acc = Bridge(studied_bridge(1.0)), shaking(duration=2.0)
    with pytest.raises(ValueError, match="samples"):
        analyze(bridge, acc, DT, vertical=np.zeros(acc.size - 1))
    with pytest.raises(ValueError, match="non-finite"):
        analyze(bridge, acc, DT, vertical=np.full(acc.size, np.nan))


def test_without_a_vertical_component_the_response_is_the_papers_bit_for_bit():
    """No vertical component, or one of zeros, gives exactly today's response: a zero vertical
    acceleration multiplies gravity by exactly 1 (IEEE 754) and leaves the thresholds as they
    are."""
    bridge, acc = Bridge(studied_bridge(1.25)), shaking()
    plain = analyze(bridge, acc, DT, "default")
    zeros = analyze(bridge, acc, DT, "default", vertical=np.zeros(acc.size))
    for name, history in plain.histories.items():
        assert history.tobytes() == zeros.histories[name].tobytes()
    assert plain.events["time"].tobytes() == zeros.events["time"].tobytes()


def test_a_motion_cut_at_take_off_reaches_the_integrator_writable():
    """The motion up to a take-off is handed on as copies: numba types a read-only array apart,
    so a view of a record's read-only samples compiled `integrate` a second time (about 60 s
    that the warm-up never covered)."""
    from rockbridge_cli.core.analysis import _integrated

    acc, up = np.arange(10.0), np.ones(10)
    acc.flags.writeable = up.flags.writeable = False
    cut, cut_up = _integrated(acc, up, 4, 0)
    assert cut.flags.writeable and cut_up is not None and cut_up.flags.writeable
    np.testing.assert_array_equal(cut, acc[:4])
    np.testing.assert_array_equal(cut_up, up[:4])
