"""Linear SDOF response spectra (Nigam & Jennings recurrence) against closed forms and an FFT."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time

import numpy as np
import pytest

from rockbridge_cli.motions.spectra import (
    compute_oscillator_response,
    compute_psa,
    find_peak_responses,
)


def harmonic_response(times, period, damping, amplitude, forcing_period):
    """Closed form of u'' + 2ξωu' + ω²u = −A·sin(Ωt) from rest (steady state + transient).

    Steady state C·sin Ωt + D·cos Ωt: (ω² − Ω²)C − 2ξωΩ·D = −A and 2ξωΩ·C + (ω² − Ω²)D = 0.
    Free part e^(−ξωt)(E·cos ω_d t + F·sin ω_d t) with u(0) = 0 -> E = −D and u'(0) = 0 ->
    F = (ξωE − ΩC)/ω_d.
    """
    omega, forcing = 2 * np.pi / period, 2 * np.pi / forcing_period
    damped = omega * np.sqrt(1 - damping**2)
    matrix = [
        [omega**2 - forcing**2, -2 * damping * omega * forcing],
        [2 * damping * omega * forcing, omega**2 - forcing**2],
    ]
    c, d = np.linalg.solve(matrix, [-amplitude, 0.0])
    e = -d
    f = (damping * omega * e - forcing * c) / damped
    free = np.exp(-damping * omega * times) * (
        e * np.cos(damped * times) + f * np.sin(damped * times)
    )
    return c * np.sin(forcing * times) + d * np.cos(forcing * times) + free


def smooth_record(time_step, duration=20.0, seed=3):
    """A band-limited record (sines of 0.2–5 Hz under a Hann window) in m/s²."""
    rng = np.random.default_rng(seed)
    times = np.arange(int(round(duration / time_step)) + 1) * time_step
    frequencies = rng.uniform(0.2, 5.0, 40)
    phases = rng.uniform(0, 2 * np.pi, 40)
    signal = np.sin(2 * np.pi * frequencies[:, None] * times + phases[:, None]).sum(axis=0)
    return np.sin(np.pi * times / duration) ** 2 * signal


def fft_psa(acceleration, time_step, periods, damping):
    """Independent PSA: transfer function in the frequency domain, zero padding to 8 lengths,
    then 4-fold band-limited interpolation in time so that the peak is not missed."""
    n = acceleration.size
    padded = 8 * n
    spectrum = np.fft.rfft(acceleration, padded)
    frequencies = 2 * np.pi * np.fft.rfftfreq(padded, time_step)
    values = []
    for period in periods:
        omega = 2 * np.pi / period
        transfer = -1.0 / (omega**2 - frequencies**2 + 2j * damping * omega * frequencies)
        response = np.fft.irfft(spectrum * transfer, 4 * padded) * 4
        values.append(omega**2 * np.max(np.abs(response)))
    return np.array(values)


def test_harmonic_response_history():
    period, damping, forcing_period = 0.5, 0.05, 0.37
    time_step = forcing_period / 400
    times = np.arange(0, 20.0, time_step)
    ground = 2.0 * np.sin(2 * np.pi / forcing_period * times)
    computed = compute_oscillator_response(ground, time_step, period, damping)
    exact = harmonic_response(times, period, damping, 2.0, forcing_period)
    # the piecewise-linear input differs from the sine by O((ΩΔt)²/8) ≈ 3e-5
    assert np.max(np.abs(computed - exact)) < 1e-4 * np.max(np.abs(exact))


@pytest.mark.parametrize("period", [0.2, 0.5, 1.3])
def test_harmonic_peak(period):
    damping, forcing_period = 0.05, 0.37
    time_step = forcing_period / 400
    times = np.arange(0, 20.0, time_step)
    ground = np.sin(2 * np.pi / forcing_period * times)
    fine = np.arange(0, times[-1], time_step / 50)
    exact_peak = np.max(np.abs(harmonic_response(fine, period, damping, 1.0, forcing_period)))
    psa = compute_psa(ground, time_step, [period], damping)[0]
    assert psa == pytest.approx((2 * np.pi / period) ** 2 * exact_peak, rel=1e-4)


# the FFT reference needs the response to die out within its padding (140 s): ξ >= 0.05
@pytest.mark.parametrize("damping", [0.05, 0.1, 0.3])
def test_agrees_with_frequency_domain_solution(damping):
    time_step = 0.002
    record = smooth_record(time_step)
    periods = np.geomspace(0.1, 4.0, 25)
    expected = fft_psa(record, time_step, periods, damping)
    computed = compute_psa(record, time_step, periods, damping)
    # piecewise-linear vs band-limited interpolation of 5 Hz content at 500 Hz: ~1e-4
    np.testing.assert_allclose(computed, expected, rtol=2e-3)


@pytest.mark.parametrize("period", [0.012, 0.02, 0.03, 0.05])
def test_periods_of_a_few_steps(period):
    # the same piecewise-linear function sampled at 0.01 s and at 0.001 s must give one answer:
    # sub-steps and the Hermite peak make the coarse one exact even at T = 1.2 steps
    coarse_step = 0.01
    coarse = smooth_record(coarse_step, duration=10.0) + np.random.default_rng(1).normal(
        0, 0.5, 1001
    )
    fine_times = np.arange(10001) * 0.001
    fine = np.interp(fine_times, np.arange(1001) * coarse_step, coarse)
    expected = compute_psa(fine, 0.001, [period], 0.05)[0]
    assert compute_psa(coarse, coarse_step, [period], 0.05)[0] == pytest.approx(expected, rel=1e-3)


def test_zero_period_is_pga():
    record = smooth_record(0.005)
    pga = np.max(np.abs(record))
    assert compute_psa(record, 0.005, [0.0], 0.05)[0] == pga
    # a 1000 Hz oscillator follows 5 Hz motion statically: factor 1/(1 − (5/1000)²) ≈ 1 + 2.5e-5
    assert compute_psa(record, 0.005, [0.001], 0.05)[0] == pytest.approx(pga, rel=1e-4)


def test_linear_in_amplitude():
    record = smooth_record(0.01)
    periods = np.geomspace(0.05, 4.0, 30)
    np.testing.assert_allclose(
        compute_psa(-3.0 * record, 0.01, periods),
        3.0 * compute_psa(record, 0.01, periods),
        rtol=1e-12,
    )


def test_crests_are_sorted_with_the_peak_first():
    record = smooth_record(0.01)
    values, times = find_peak_responses(record, 0.01, [0.3, 1.0, 2.0], 0.05, crests=4)
    assert values.shape == times.shape == (3, 4)
    sizes = np.abs(values)
    assert np.all(np.diff(sizes, axis=1) <= 0.0)
    peaks = (
        compute_psa(record, 0.01, [0.3, 1.0, 2.0]) / (2 * np.pi / np.array([0.3, 1.0, 2.0])) ** 2
    )
    np.testing.assert_allclose(sizes[:, 0], peaks, rtol=1e-12)


def test_spectrum_of_a_40_s_record_is_fast():
    record = np.random.default_rng(0).normal(size=4001)  # 40 s at 0.01 s
    periods = np.geomspace(0.05, 4.0, 100)
    compute_psa(record, 0.01, periods)  # compile or load the cached machine code
    elapsed = []
    for _ in range(5):
        start = time.perf_counter()
        compute_psa(record, 0.01, periods)
        elapsed.append(time.perf_counter() - start)
    assert np.median(elapsed) < 0.05


def test_compiled_and_plain_python_agree():
    record = smooth_record(0.01, duration=3.0)
    periods = [0.03, 0.2, 1.0]
    code = (
        "import json, sys, numpy as np\n"
        "from rockbridge_cli.motions.spectra import compute_psa\n"
        "data = json.load(sys.stdin)\n"
        "print(json.dumps(compute_psa(np.array(data['a']), 0.01, data['T']).tolist()))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code],
        input=json.dumps({"a": record.tolist(), "T": periods}),
        capture_output=True,
        text=True,
        check=True,
        env={**os.environ, "NUMBA_DISABLE_JIT": "1"},
    )
    np.testing.assert_allclose(
        json.loads(result.stdout), compute_psa(record, 0.01, periods), rtol=1e-12
    )


@pytest.mark.parametrize(
    ("args", "match"),
    [
        ((np.ones(1), 0.01, [1.0]), "two samples"),
        ((np.array([0.0, np.nan, 1.0]), 0.01, [1.0]), "NaN"),
        ((np.ones(10), 0.0, [1.0]), "time step"),
        ((np.ones(10), 0.01, [-1.0]), "non-negative"),
        ((np.ones(10), 0.01, [1.0], 1.0), "damping"),
    ],
)
def test_refuses_bad_input(args, match):
    with pytest.raises(ValueError, match=match):
        compute_psa(*args)


def test_free_vibration_after_the_record_counts():
    # a 4 s oscillator hit by a 1 s pulse peaks after the 1.5 s record ends; the record padded
    # with 20 s of rest is the same ground motion, so the spectra must agree
    times = np.arange(151) * 0.01
    pulse = np.where(times <= 1.0, np.sin(np.pi * times), 0.0)
    padded = np.concatenate([pulse, np.zeros(2000)])
    periods = [1.0, 4.0, 8.0]
    np.testing.assert_allclose(
        compute_psa(pulse, 0.01, periods), compute_psa(padded, 0.01, periods), rtol=1e-9
    )
