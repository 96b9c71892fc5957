"""The spectral-matching generator: building blocks, determinism, and the targets on whole sets.

Targets (issue 4), checked at 100 log-spaced periods over 0.05–4 s: every record within ±10% of
the EN 1998-1 target, the mean within ±3%, PGA = a_g·S within 1%, final velocity below 1 cm/s and
final displacement below 1 cm.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid

from rockbridge_cli.config.loading import load
from rockbridge_cli.config.record_sets import RecordSetConfig
from rockbridge_cli.motions import baseline, matching, wavelets
from rockbridge_cli.motions.ec8 import compute_elastic_spectrum
from rockbridge_cli.motions.spectra import compute_psa, find_peak_responses
from rockbridge_cli.records.set_files import read_record_set
from rockbridge_cli.records.sets import GROUND_DISPLACEMENT_AIM, generate_record_set
from rockbridge_cli.records.target import read_set_target

# Record matching only, no analysis: on a cold cache its worker need not wait for the suite's
# analysis kernels (tests/conftest.py).
pytestmark = pytest.mark.no_kernels

ROOT = Path(__file__).parents[1]
PAPER = ROOT / "configs" / "records" / "ec8-type1-C-ag0.6g.yaml"
TYPE_2 = ROOT / "configs" / "records" / "ec8-type2-A-ag0.3g.yaml"
BUNDLED = ROOT / "records" / "ec8-type1-C-ag0.6g"
CHECK = np.geomspace(0.05, 4.0, 100)


def measure(records, target):
    """Per-record ratios to the target at the check periods, PGA ratios, final v and d."""
    goal = target.evaluate(CHECK)
    ratios = np.array([compute_psa(r.acceleration, r.time_step, CHECK) / goal for r in records])
    pga = np.array([r.peak_acceleration / target.surface_pga for r in records])
    motion = np.array([baseline.compute_final_motion(r.acceleration, r.time_step) for r in records])
    return ratios, pga, motion


def assert_targets(records, target, per_record=0.10, mean=0.03):
    ratios, pga, motion = measure(records, target)
    assert np.all(np.abs(ratios - 1.0) <= per_record), np.abs(ratios - 1.0).max(axis=1)
    assert np.all(np.abs(ratios.mean(axis=0) - 1.0) <= mean)
    np.testing.assert_allclose(pga, 1.0, rtol=0.01)  # the target
    assert np.all(np.abs(motion[:, 0]) < 0.01)  # m/s, the target
    assert np.all(np.abs(motion[:, 1]) < 0.01)  # m
    # The method is exact, not just within the targets: the last step scales to a_g·S and the
    # baseline correction zeroes the final velocity and displacement, up to rounding.
    np.testing.assert_allclose(pga, 1.0, rtol=1e-9)
    assert np.all(np.abs(motion) < 1e-6)
    # rockbridge's aim for the ground's wander (issue 16): PGD within 2 d_g, the displacement
    # integrated here by scipy's trapezoids, not the generator's piecewise-linear integral
    for record in records:
        velocity = cumulative_trapezoid(record.acceleration, dx=record.time_step, initial=0)
        displacement = cumulative_trapezoid(velocity, dx=record.time_step, initial=0)
        limit = GROUND_DISPLACEMENT_AIM * target.ground_displacement
        assert np.abs(displacement).max() <= limit, (record.name, np.abs(displacement).max())


# ---------------------------------------------------------------------------------------------
# Building blocks


def test_envelope():
    envelope = matching.Envelope(rise=2.0, stationary=15.0, decay=13.0, end_level=0.05)
    times = np.array([0.0, 1.0, 2.0, 10.0, 17.0, 30.0])
    # (1/2)² = 0.25 in the build-up, 1 on the plateau, 0.05 at the very end
    np.testing.assert_allclose(
        matching.compute_envelope(times, envelope), [0.0, 0.25, 1.0, 1.0, 1.0, 0.05]
    )
    assert envelope.duration == 30.0


def test_final_motion_is_exact_for_linear_segments():
    rng = np.random.default_rng(0)
    acceleration, step = rng.normal(size=200), 0.02
    velocity = displacement = 0.0
    for a0, a1 in zip(acceleration[:-1], acceleration[1:], strict=True):
        displacement += step * velocity + step**2 * (2 * a0 + a1) / 6  # exact for linear a
        velocity += step * (a0 + a1) / 2
    v, d = baseline.compute_final_motion(acceleration, step)
    assert v == pytest.approx(velocity, rel=1e-12)
    assert d == pytest.approx(displacement, rel=1e-12)
    # a ≡ 1 for 2 s: v = 2, d = t²/2 = 2
    assert baseline.compute_final_motion(np.ones(101), 0.02) == pytest.approx((2.0, 2.0))


def test_baseline_correction_zeroes_final_motion():
    rng = np.random.default_rng(1)
    envelope = matching.compute_envelope(np.arange(1001) * 0.01, matching.Envelope(1, 6, 3))
    record = rng.normal(size=1001) + 0.3
    for terms in (2, 6, 12):
        corrected = baseline.BaselineCorrection.of(envelope, 0.01, terms)(record)
        v, d = baseline.compute_final_motion(corrected, 0.01)
        assert abs(v) < 1e-11 and abs(d) < 1e-11, terms
        assert corrected[0] == record[0]  # the correction follows the envelope, 0 at t = 0


def test_the_displacement_gradient_is_the_adjoint_of_the_integration():
    """Σ m·d(a) = gradient(m)·a for any a and m, d from `integrate_motion` (the recurrences run
    forwards) and the gradient from the same recurrences run backwards."""
    rng = np.random.default_rng(7)
    for size in (2, 3, 50, 1001):
        record, factors = rng.normal(size=size), rng.normal(size=size)
        _, displacement = baseline.integrate_motion(record, 0.02)
        gradient = baseline.displacement_gradient(factors, 0.02)
        assert factors @ displacement == pytest.approx(gradient @ record, rel=1e-12, abs=1e-15)


def test_the_baseline_correction_leaves_the_least_displacement():
    """Against an independent solution of the same problem: the trend's coefficients that zero
    the final motion, minimising Σ d² over the samples, from scipy's null space of the two
    conditions and numpy's least squares on the displacements. Two terms are Boore's enveloped
    linear trend (I and I·t span the same trends), fixed by the conditions alone, and more
    terms leave less displacement."""
    from scipy.linalg import null_space

    step, rng = 0.01, np.random.default_rng(3)
    times = np.arange(2001) * step
    envelope = matching.compute_envelope(times, matching.Envelope(3, 10, 5))
    record = envelope * rng.normal(size=times.size) + 0.2 * np.sin(2 * np.pi * 0.05 * times)
    rms = {}
    for terms in (2, 5, 9):
        correction = baseline.BaselineCorrection.of(envelope, step, terms)
        corrected = correction(record)
        functions = correction.functions
        shapes = np.stack([baseline.integrate_motion(f, step)[1] for f in functions])
        ends = np.stack([baseline.compute_final_motion(f, step) for f in functions], axis=1)
        start = np.linalg.lstsq(ends, baseline.compute_final_motion(record, step), rcond=None)[0]
        free = null_space(ends)
        residual = baseline.integrate_motion(record, step)[1] - start @ shapes
        if free.shape[1]:
            start = start + free @ np.linalg.lstsq((free.T @ shapes).T, residual, rcond=None)[0]
        np.testing.assert_allclose(corrected, record - start @ functions, rtol=0, atol=1e-9)
        rms[terms] = np.sqrt(np.mean(baseline.integrate_motion(corrected, step)[1] ** 2))
    two = np.stack([envelope, envelope * times])
    trend = record - baseline.BaselineCorrection.of(envelope, step, 2)(record)
    fitted = np.linalg.lstsq(two.T, trend, rcond=None)
    assert np.max(np.abs(two.T @ fitted[0] - trend)) < 1e-12
    assert rms[9] < rms[5] < rms[2]


def test_correction_terms_follow_the_band():
    # 30 s and a band to 4 s: degree 10 swings every 6 s = 1.5 × 4 s; never fewer than two terms
    assert baseline.correction_terms(30.0, 4.0, 1.5) == 11
    assert baseline.correction_terms(1.0, 4.0, 1.5) == 2


def test_significant_duration_of_a_steady_signal():
    # |a| constant for 20 s: the Arias intensity grows linearly, so D5-95 = 0.9·20 s
    record = np.where(np.arange(2001) % 2 == 0, 1.0, -1.0)
    assert baseline.compute_significant_duration(record, 0.01) == pytest.approx(18.0, abs=0.01)


def test_matching_periods_contain_the_check_grid():
    periods = matching.compute_matching_periods((0.05, 4.0), 100, 0.01)
    for period in CHECK:
        assert np.min(np.abs(periods / period - 1.0)) < 1e-12
    assert periods[0] >= 0.04 and periods[-1] > 4.0


def test_influence_matrix_is_the_exact_first_order_effect():
    """The wavelet system's matrix against finite differences of the actual peaks."""
    step, periods = 0.01, np.geomspace(0.045, 4.0, 30)
    target = compute_elastic_spectrum(periods, 1, "C", design_acceleration=5.886)
    times = np.arange(1501) * step
    shape = matching.compute_envelope(times, matching.Envelope(1.0, 10.0, 4.0))
    record = matching._shape_stationary_process(
        periods, target, times, shape, np.random.default_rng(3), matching.MatchSettings()
    )
    values, peak_times = find_peak_responses(record, step, periods)
    omegas = 2 * np.pi / periods
    delay = wavelets.find_wavelet_delay(0.75, 0.05)
    patterns = wavelets.build_wavelets(
        np.ones_like(times), step, omegas, 0.05, peak_times[:, 0], 0.75, delay
    )
    matrix = wavelets.compute_influence(
        peak_times[:, 0], omegas, 0.05, step, *patterns.arrays, np.array([0])
    )
    for column in (0, 12, 29):
        amplitudes = np.zeros(periods.size)
        amplitudes[column] = 1e-4
        changed = find_peak_responses(
            record + wavelets.superpose(patterns, amplitudes, record.size), step, periods
        )[0]
        effect = omegas**2 * (changed[:, 0] - values[:, 0]) / 1e-4
        np.testing.assert_allclose(effect, matrix[:-1, column], rtol=0.02, atol=1e-3)


def small_record(seed):
    periods = matching.compute_matching_periods((0.1, 2.0), 20, 0.01)
    target = compute_elastic_spectrum(periods, 1, "C", design_acceleration=2.0)
    return matching.generate_matched_record(
        periods,
        target,
        2.3,
        0.01,
        matching.Envelope(1.0, 10.0, 3.0),
        np.random.default_rng(seed),
        matching.MatchSettings(max_iterations=3, max_attempts=1),
        band=(0.1, 2.0),
    )


def test_same_seed_same_record_other_seed_other_record():
    first, again, other = small_record(5), small_record(5), small_record(6)
    assert np.array_equal(first.acceleration, again.acceleration)
    assert not np.allclose(first.acceleration, other.acceleration)
    assert np.max(np.abs(first.acceleration)) == pytest.approx(2.3, rel=1e-12)
    assert first.acceleration[0] == 0.0  # starts at rest


def test_refuses_periods_the_record_cannot_carry():
    with pytest.raises(ValueError, match="4 time steps"):
        matching.generate_matched_record(
            np.array([0.02, 1.0]),
            np.ones(2),
            1.0,
            0.01,
            matching.Envelope(1, 10, 1),
            np.random.default_rng(0),
        )


def test_core_imports_no_edge_library():
    # numba itself may load yaml (for its config file), so compare with numba loaded first
    code = (
        "import sys, numpy, scipy.fft, numba\n"
        "before = set(sys.modules)\n"
        "import rockbridge_cli.motions.ec8, rockbridge_cli.motions.spectra\n"
        "import rockbridge_cli.motions.matching\n"
        "edge = {'click', 'yaml', 'pydantic', 'h5py', 'pandas', 'matplotlib'}\n"
        "print(sorted(edge & {name.split('.')[0] for name in set(sys.modules) - before}))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert result.stdout.strip() == "[]"


# ---------------------------------------------------------------------------------------------
# Whole sets


def test_bundled_paper_set_meets_the_targets():
    records, target = read_record_set(BUNDLED), read_set_target(BUNDLED)
    assert len(records) == 10
    # the paper's set reaches the aim of ±5% per record, not only the required ±10%
    assert_targets(records, target, per_record=0.05)


@pytest.mark.slow
def test_type_2_ground_a_set_meets_the_targets(tmp_path):
    report = generate_record_set(load(RecordSetConfig, TYPE_2), tmp_path)
    assert report.compliance.compliant
    assert_targets(read_record_set(tmp_path), read_set_target(tmp_path))


@pytest.mark.slow
def test_other_seed_gives_another_compliant_set(tmp_path):
    # Two attempts (the bundled set's) leave three records of this seed 0.944-0.949 of the
    # target, outside the ±5 % tolerance; six bring all ten inside.
    config = load(RecordSetConfig, PAPER).model_copy(update={"seed": 2023, "attempts": 6})
    report = generate_record_set(config, tmp_path)
    assert report.compliance.compliant
    records = read_record_set(tmp_path)
    assert_targets(records, read_set_target(tmp_path))
    for new, old in zip(records, read_record_set(BUNDLED), strict=True):
        assert not np.allclose(new.acceleration, old.acceleration)


def test_ground_motion_integrates_exactly_for_piecewise_linear_acceleration():
    """a = c·t from rest: v = c·t²/2 and d = c·t³/6 exactly at every sample (the scheme is exact
    for linear segments); its last values are `compute_final_motion`'s."""
    step, c = 0.01, 0.7
    times = np.arange(501) * step
    velocity, displacement = baseline.integrate_motion(c * times, step)
    np.testing.assert_allclose(velocity, c * times**2 / 2, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(displacement, c * times**3 / 6, rtol=1e-12, atol=1e-15)
    record = np.sin(2 * np.pi * times) * np.exp(-times)
    final = baseline.compute_final_motion(record, step)
    motion = baseline.integrate_motion(record, step)
    assert (motion[0][-1], motion[1][-1]) == pytest.approx(final, rel=1e-10, abs=1e-14)


def test_design_ground_displacement_of_en1998():
    """§3.2.2.4: d_g = 0.025·a_g·S·T_C·T_D; type 1 ground C (S 1.15, T_C 0.6 s, T_D 2.0 s) at
    a_g = 0.6·9.81 m/s² is 0.025·5.886·1.15·0.6·2.0 = 0.2030670 m."""
    from rockbridge_cli.motions.ec8 import design_ground_displacement

    assert design_ground_displacement(1, "C", 5.886) == pytest.approx(0.203067, rel=1e-12)
