"""Tabulated kinematics against the exact linkage they are built from.

The yardstick is the exact path (loop closure, velocity and acceleration analysis), itself tested
against finite differences and an independent rigid-body kinematics (test_kinematics). Measured
worst errors at 2048 intervals over 1000 random states per mode from a quarter of the range below
rest to its top, for every bridge of `BRIDGES`, a frame and a single block: θ̈1 relative 3.5e-14
(with a floor of 1 rad/s²; 2.8e-14 below rest), displacements 2.9e-14 m (2.3e-14 m below rest).
The bounds below are 1e-12, far above rounding and far below anything the integrator resolves.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import BRIDGES, studied_bridge

from rockbridge_cli.core.analysis import analyze
from rockbridge_cli.core.bridge import Bridge
from rockbridge_cli.core.dynamics import acceleration, coefficients
from rockbridge_cli.core.geometry import single_block
from rockbridge_cli.core.impacts import failure_rotations
from rockbridge_cli.core.kinematics import EXACT, displacements
from rockbridge_cli.core.tables import (
    BELOW_REST,
    INTERVALS,
    MARGIN,
    _sample,
    not_a_knot,
    tabulated,
)

MODELS = [
    *BRIDGES,
    ("frame", studied_bridge(1.25, abutments=False)),
    ("block", single_block(1.3, 13.0, 2500.0, 9.81)),
]


@pytest.fixture(params=MODELS, ids=[name for name, _ in MODELS])
def model(request):
    return request.param[1]


def test_the_tables_reach_past_the_first_failure_and_below_rest(model):
    table = tabulated(model)
    below = int(BELOW_REST * INTERVALS)
    assert table.table.shape == (2, below + INTERVALS, 14, 4)
    first = max(min(abs(r[mode]) for r in failure_rotations(model).values()) for mode in ("p", "n"))
    assert table.limit == pytest.approx(MARGIN * first, rel=1e-12)
    assert table.step == pytest.approx(table.limit / INTERVALS)
    assert table.start == pytest.approx(-BELOW_REST * table.limit, rel=1e-12)


def test_acceleration_and_displacements_equal_the_exact_path(model):
    table = tabulated(model)
    rng = np.random.default_rng(1)
    for s in (1.0, -1.0):
        for x in rng.uniform(table.start, table.limit, 500):
            theta1, omega, ground = s * x, rng.uniform(-0.2, 0.2), rng.uniform(-10.0, 10.0)
            for contact in (False, True) if model.has_abutments else (False,):
                fast = acceleration(model, s, theta1, omega, ground, contact, table)
                exact = acceleration(model, s, theta1, omega, ground, contact, EXACT)
                assert abs(fast - exact) <= 1e-12 * (abs(exact) + 1.0)
            fast = np.array(displacements(model, s, theta1, table))
            exact = np.array(displacements(model, s, theta1, EXACT))
            np.testing.assert_allclose(fast, exact, rtol=0.0, atol=1e-12)


def test_outside_the_tables_the_kernels_are_exact(model):
    """Beyond the tabulated range, above or below, nothing is extrapolated: the kernels compute
    the linkage itself, so the results are the exact ones bit for bit."""
    table = tabulated(model)
    for s in (1.0, -1.0):
        for x in (table.limit, 1.2 * table.limit, table.start - 1e-9, 2.0 * table.start):
            theta1 = s * x
            assert coefficients(model, s, theta1, table) == coefficients(model, s, theta1, EXACT)
            assert displacements(model, s, theta1, table) == displacements(model, s, theta1, EXACT)


def test_tables_are_built_once_per_bridge():
    assert tabulated(studied_bridge(2.0)) is tabulated(studied_bridge(2.0))


def test_an_analysis_on_tables_equals_the_exact_one():
    """The same preset with exact or tabulated kinematics: peaks and events within 1e-9.

    A smooth, strong motion (regular dynamics: a sine burst), so that the comparison of single
    responses is meaningful; the Fig. 9 ensembles are compared in benchmarks/bench_fidelity.py."""
    bridge = studied_bridge(2.0)
    t = np.arange(0.0, 12.0, 0.01)
    ground = 0.45 * 9.81 * np.sin(2 * np.pi * t / 1.2) * np.exp(-(((t - 5.0) / 2.5) ** 2))
    exact = analyze(Bridge(bridge), ground, 0.01, "default", kinematics="exact")
    table = analyze(Bridge(bridge), ground, 0.01, "default", kinematics="tabulated")
    assert exact.n_impacts == table.n_impacts and exact.failure_mode == table.failure_mode
    for name, (value, _) in exact.peaks.items():
        if name in ("theta_deck", "u_deck", "v_deck", "theta1", "theta2"):
            assert table.peaks[name][0] == pytest.approx(value, rel=1e-9), name
    np.testing.assert_allclose(table.events["time"], exact.events["time"], rtol=0, atol=1e-9)


def _cubic(x):
    """y = 1.5 − 2x + 0.7x² − 0.3x³ and its Taylor coefficients at x, powers 3…0."""
    return np.stack([np.full_like(x, -0.3), 0.7 - 0.9 * x, -2.0 + 1.4 * x - 0.9 * x**2,
                     1.5 - 2.0 * x + 0.7 * x**2 - 0.3 * x**3], axis=-1)  # fmt: skip


def test_a_not_a_knot_spline_reproduces_a_cubic():
    """A cubic is its own not-a-knot spline (both end conditions hold for it), so each interval's
    coefficients are its Taylor coefficients at the interval's start, in closed form; on a grid
    of uneven intervals, and for two quantities at once."""
    x = np.linspace(-1.0, 2.0, 40) + 0.02 * np.sin(np.arange(40.0))
    expected = _cubic(x)
    y = np.column_stack([expected[:, 3], 2.0 * expected[:, 3]])
    coefficients = not_a_knot(x, y)
    assert coefficients.shape == (39, 2, 4)
    h = np.diff(x)[:, None] ** np.arange(3, -1, -1)  # each coefficient's weight in a value
    for column, factor in enumerate((1.0, 2.0)):
        error = (coefficients[:, column] - factor * expected[:-1]) * h
        assert np.abs(error).max() <= 1e-14 * factor * np.abs(y[:, 0]).max()


def test_a_not_a_knot_spline_needs_four_points():
    with pytest.raises(ValueError, match="n ≥ 4 points"):
        not_a_knot(np.arange(3.0), np.zeros((3, 1)))


def test_the_tables_equal_scipys_not_a_knot_spline(model):
    """Each table's cubics against ``scipy.interpolate.CubicSpline(bc_type="not-a-knot")`` through
    the same samples (the tables' builder until issue 43): the values and slopes of the two within
    1e-12 of the largest of each quantity, at each interval's ends and middle."""
    from scipy.interpolate import CubicSpline

    table = tabulated(model)
    intervals = table.table.shape[1]
    below = round(-table.start / table.step)
    x = table.step * np.arange(-below, intervals - below + 1)
    for mode, s in enumerate((1.0, -1.0)):
        spline = CubicSpline(x, _sample(model, s, x), axis=0, bc_type="not-a-knot")
        theirs = np.moveaxis(spline.c, 0, -1)
        for dx in table.step * np.array([0.0, 0.5, 1.0]):
            pairs = [_value_and_slope(c, dx) for c in (table.table[mode], theirs)]
            for ours, reference in zip(*pairs, strict=True):  # the values, then the slopes
                scale = np.abs(reference).max(axis=0)
                assert np.all(np.abs(ours - reference).max(axis=0) <= 1e-12 * scale)


def _value_and_slope(c, dx):
    """The cubics of a table at dx from each interval's start, and their slopes."""
    value = ((c[..., 0] * dx + c[..., 1]) * dx + c[..., 2]) * dx + c[..., 3]
    return value, (3.0 * c[..., 0] * dx + 2.0 * c[..., 1]) * dx + c[..., 2]
