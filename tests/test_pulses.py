"""Analytic pulses (rockbridge_cli.motions.pulses) against the definitions of their papers, and
as a record source of studies.

Sources of the expected values, test by test: the velocity pulses by which Zhang & Makris (2001)
define the cycloidal pulses, and their published phases φ_1 = 0.0697π and φ_2 = 0.0410π; the
acceleration pulses of Makris & Roussos (2000) and Housner's (1963) half-sine; the Ricker wavelets
of Vassiliou & Makris (2011), whose Fourier amplitude peaks at ω_p; the velocity pulse of
Mavroeidis & Papageorgiou (2003). The velocities are the code's accelerations integrated by the
trapezoidal rule on 200 001 points (error ~1e-10 of the peak), never the code's own velocities.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rockbridge_cli.config.study import load_study
from rockbridge_cli.core.quantities import STANDARD_GRAVITY
from rockbridge_cli.errors import InputError
from rockbridge_cli.motions.pulses import SHAPES, Pulse, type_c_phase
from rockbridge_cli.results import read_peaks
from rockbridge_cli.results.reading import open_results
from rockbridge_cli.study.run import run_study

AMPLITUDE, PERIOD = 2.0, 0.8  # a_p [m/s²], T_p [s]
OMEGA = 2.0 * math.pi / PERIOD


def integrated(pulse: Pulse, points: int = 200_001) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Time, velocity and displacement of a pulse from rest, by the trapezoidal rule."""
    t = np.linspace(0.0, pulse.duration, points)
    a = pulse.acceleration(t)
    v = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * np.diff(t))])
    d = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])
    return t, v, d


def test_the_type_c_phases_are_the_published_ones():
    """Zhang & Makris (2001) give φ_1 = 0.0697π and φ_2 = 0.0410π for the C_1 and C_2 pulses."""
    assert type_c_phase(1) / math.pi == pytest.approx(0.0697, abs=5e-5)
    assert type_c_phase(2) / math.pi == pytest.approx(0.0410, abs=5e-5)


@pytest.mark.parametrize("n", [1, 2, 3])
def test_cycloidal_pulses_have_zhang_and_makris_s_velocities(n):
    """Type A: u̇ = v_p/2·(1 − cos ω_p·t), a_p = ω_p·v_p/2; type B: u̇ = v_p·sin ω_p·t,
    a_p = ω_p·v_p, back where it started; type C_n: u̇ = v_p·(sin(ω_p·t + φ_n) − sin φ_n) over
    (n + 1/2 − φ_n/π)·T_p, a_p = ω_p·v_p, back at rest where it started."""
    expected = {
        "cycloidal-a": lambda t: AMPLITUDE / OMEGA * (1.0 - np.cos(OMEGA * t)),
        "cycloidal-b": lambda t: AMPLITUDE / OMEGA * np.sin(OMEGA * t),
    }
    phi = type_c_phase(n)
    expected["cycloidal-c"] = lambda t: AMPLITUDE / OMEGA * (np.sin(OMEGA * t + phi) - np.sin(phi))
    for shape, velocity in expected.items():
        pulse = Pulse(shape, AMPLITUDE, PERIOD, cycles=n if shape == "cycloidal-c" else None)
        t, v, d = integrated(pulse)
        np.testing.assert_allclose(v, velocity(t), rtol=0, atol=1e-9)
        if shape != "cycloidal-a":  # B and C_n return the ground to where it started
            assert abs(d[-1]) < 1e-9
    assert Pulse("cycloidal-c", AMPLITUDE, PERIOD, cycles=n).duration == pytest.approx(
        (n + 0.5 - phi / math.pi) * PERIOD, rel=1e-15
    )


def test_one_sine_pulses_of_makris_and_roussos_and_housner_s_half_sine():
    """Type A: a_p·sin(ω_p·t + φ) and type B: a_p·cos(ω_p·t + φ) over N periods (Makris &
    Roussos 2000); N = 1/2 of type A is Housner's (1963) half-sine pulse; zero outside."""
    t = np.linspace(-0.5, 3.0, 7001)
    for shape, phase, cycles, wave in (
        ("one-sine-a", 0.0, None, np.sin), ("one-sine-b", 0.0, None, np.cos),
        ("one-sine-a", 0.3, 2.0, np.sin), ("one-sine-b", -0.7, 1.5, np.cos),
        ("one-sine-a", 0.0, 0.5, np.sin),
    ):  # fmt: skip
        pulse = Pulse(shape, AMPLITUDE, PERIOD, phase, cycles)
        inside = (t >= 0.0) & (t <= (cycles or 1.0) * PERIOD)
        expected = np.where(inside, AMPLITUDE * wave(OMEGA * t + phase), 0.0)
        np.testing.assert_allclose(pulse.acceleration(t), expected, rtol=0, atol=1e-14)


def test_ricker_wavelets_of_vassiliou_and_makris():
    """The symmetric wavelet is a_p·(1 − 2π²τ²/T_p²)·exp(−π²τ²/T_p²), even about its centre; the
    antisymmetric one is odd; both peak at a_p, end at rest, and their Fourier amplitude peaks at
    ω_p = 2π/T_p (Vassiliou & Makris 2011's definition of T_p)."""
    for shape, parity in (("ricker-symmetric", 1.0), ("ricker-antisymmetric", -1.0)):
        pulse = Pulse(shape, AMPLITUDE, PERIOD)
        t, v, _ = integrated(pulse)
        a = pulse.acceleration(t)
        np.testing.assert_allclose(a[::-1], parity * a, rtol=0, atol=1e-13)
        fine = np.linspace(0.0, pulse.duration, 2_000_001)
        assert np.abs(pulse.acceleration(fine)).max() == pytest.approx(AMPLITUDE, rel=1e-9)
        assert abs(v[-1]) < 1e-8 * AMPLITUDE
        step = t[1] - t[0]
        spectrum = np.abs(np.fft.rfft(a, 2**22))
        frequencies = 2.0 * math.pi * np.fft.rfftfreq(2**22, step)
        assert frequencies[np.argmax(spectrum)] == pytest.approx(OMEGA, rel=2e-3)
    tau = np.linspace(-1.5 * PERIOD, 1.5 * PERIOD, 10001)  # the wavelet's window
    symmetric = Pulse("ricker-symmetric", AMPLITUDE, PERIOD).acceleration(tau + 1.5 * PERIOD)
    x = (math.pi * tau / PERIOD) ** 2
    np.testing.assert_allclose(symmetric, AMPLITUDE * (1 - 2 * x) * np.exp(-x), atol=1e-14)


@pytest.mark.parametrize("gamma, nu", [(2.0, 0.0), (3.0, 0.5 * math.pi), (1.5, 1.0)])
def test_mavroeidis_papageorgiou_velocity(gamma, nu):
    """The acceleration integrates to (A/2)·(1 + cos(2π·f_p·τ/γ))·cos(2π·f_p·τ + ν), τ = t −
    γ/(2f_p), for one A (their Eq. 1), and its peak is a_p."""
    pulse = Pulse("mavroeidis-papageorgiou", AMPLITUDE, PERIOD, nu, gamma)
    t, v, _ = integrated(pulse)
    tau = 2.0 * math.pi / PERIOD * (t - 0.5 * gamma * PERIOD)
    shape = 0.5 * (1.0 + np.cos(tau / gamma)) * np.cos(tau + nu)
    scale = float(np.dot(v, shape) / np.dot(shape, shape))
    np.testing.assert_allclose(v, scale * shape, rtol=0, atol=1e-9 * abs(scale))
    fine = np.linspace(0.0, pulse.duration, 2_000_001)
    assert np.abs(pulse.acceleration(fine)).max() == pytest.approx(AMPLITUDE, rel=1e-10)


def test_sampling_puts_the_end_midway_and_rests():
    """Samples are the waveform at k·Δt, then zeros for the rest; `time_step` puts the end of the
    pulse midway between two samples, near T_p/per_period."""
    pulse = Pulse("cycloidal-c", AMPLITUDE, PERIOD, cycles=1)
    step = pulse.time_step(100)
    assert (pulse.duration / step) % 1.0 == pytest.approx(0.5, abs=1e-9)
    assert step == pytest.approx(PERIOD / 100, rel=0.01)
    samples = pulse.sampled(step, rest=1.0)
    moving = math.floor(pulse.duration / step) + 1
    assert samples.size == moving + round(1.0 / step)
    np.testing.assert_array_equal(samples[:moving], pulse.acceleration(np.arange(moving) * step))
    assert not samples[moving:].any()


@pytest.mark.parametrize(
    "arguments, message",
    [
        (("square", 1.0, 1.0), "unknown pulse shape"),
        (("one-sine-a", -1.0, 1.0), "amplitude must be positive"),
        (("one-sine-a", 1.0, 0.0), "period must be positive"),
        (("ricker-symmetric", 1.0, 1.0, 0.5), "has no free phase"),
        (("cycloidal-c", 1.0, 1.0, 0.5), "has no free phase"),
        (("ricker-antisymmetric", 1.0, 1.0, 0.0, 2.0), "has no number of cycles"),
        (("cycloidal-c", 1.0, 1.0, 0.0, 1.5), "whole cycles"),
        (("one-sine-a", 1.0, 1.0, 0.0, 0.3), "has whole or half cycles"),
        (("cycloidal-b", 1.0, 1.0, 0.0, 1.25), "has whole or half cycles"),
        (("mavroeidis-papageorgiou", 1.0, 1.0, 0.0, 1.0), "must exceed 1"),
        (("one-sine-b", 1.0, 1.0, 0.0, -1.0), "must be positive"),
    ],
)
def test_bad_pulses_are_refused(arguments, message):
    with pytest.raises(ValueError, match=message):
        Pulse(*arguments)


BLOCK = "  - id: block\n    piers: {width: 0.4, heights: [4.0]}\n"


def test_a_one_sine_pulse_cut_mid_cycle_is_refused(tmp_path):
    """Issue 39: ``cycles: 0.3`` of a one-sine pulse was accepted. Its sine, a_p·sin(ω_p·t), cut
    at 0.3·T_p ends on a step from a_p·sin(0.6π) = 0.95·a_p to 0 (under a quarter cycle it would
    not even reach a_p): not the pulse of Makris & Roussos (2000), whose N is whole, nor
    Housner's half-sine (N = 0.5), whose sine ends at 0. Refused, naming the file and the pulse;
    whole and half cycles load."""
    refused = "    - {shape: one-sine-a, amplitude_g: 0.3, period: 0.5, cycles: 0.3}\n"
    with pytest.raises(InputError) as caught:
        load_study(pulse_study(tmp_path, refused))
    assert caught.value.source == str(tmp_path / "pulses.yaml")
    ((field, reason),) = caught.value.problems
    assert field.startswith("records.pulses.0") and "has whole or half cycles" in reason
    for cycles in (0.5, 1.5, 2):
        fine = f"    - {{shape: one-sine-a, amplitude_g: 0.3, period: 0.5, cycles: {cycles}}}\n"
        assert load_study(pulse_study(tmp_path, fine)).records


def pulse_study(tmp_path, records: str, extra: str = ""):
    path = tmp_path / "pulses.yaml"
    path.write_text(f"bridges:\n{BLOCK}records:\n  pulses:\n{records}{extra}", encoding="utf-8")
    return path


def test_a_study_runs_pulses_named_by_their_parameters(tmp_path):
    """Pulses are records: named by shape, amplitude (g) and period, described in the results
    file; with stripes and a sweep like any record."""
    records = (
        "    - {shape: one-sine-a, amplitude_g: 0.3, period: 0.5, rest: 4.0}\n"
        "    - {shape: ricker-symmetric, amplitude_g: 0.2, frequency: 2.0, rest: 4.0}\n"
        "    - {shape: cycloidal-c, amplitude_g: 0.25, period: 0.5, cycles: 2, id: C2}\n"
    )
    extra = ("intensity: {measure: scale, levels: [1.0, 2.0]}\n"
             "sweep: {fields: {piers.width: [0.4, 0.5]}}\noutput: {histories: none}\n")  # fmt: skip
    study = load_study(pulse_study(tmp_path, records, extra), output=tmp_path / "pulses.h5")
    assert [r.id for r in study.records][::2] == [
        "one-sine-a_0.3g_0.5s+1x", "ricker-symmetric_0.2g_0.5s+1x", "C2+1x",
    ]  # fmt: skip
    first = study.records[0].record
    # the samples miss the crest by at most half a step: a_p·cos(ω_p·Δt/2) ≈ a_p·(1 − 1.2e-4)
    peak = 0.3 * STANDARD_GRAVITY
    assert peak * math.cos(math.pi / 200) <= first.peak_acceleration <= peak
    assert first.time_step == pytest.approx(0.5 / 200.0, rel=0.01)
    assert first.duration == pytest.approx(0.5 + 4.0, abs=first.time_step)
    report = run_study(study, workers=1)
    peaks = read_peaks(report.output)
    assert len(peaks) == 2 * 6 and set(peaks["status"]) == {"ok"}
    with open_results(report.output) as file:
        attributes = dict(file["records/C2+1x"].attrs)
    assert attributes["pulse_shape"] == "cycloidal-c" and attributes["pulse_cycles"] == 2.0
    assert attributes["pulse_period_s"] == pytest.approx(0.5)


@pytest.mark.parametrize(
    "entry, field, reason",
    [
        ("{shape: one-sine-a, amplitude_g: 0.3}", "records.pulses.0", "exactly one of period"),
        ("{shape: ricker-symmetric, amplitude_g: 0.3, period: 1, phase: 1}", "records.pulses.0",
         "no free phase"),
        ("{shape: sine-c, amplitude_g: 0.3, period: 1}", "records.pulses.0.shape", "one-sine-a"),
        ("{shape: one-sine-a, amplitude_g: -0.3, period: 1}", "records.pulses.0.amplitude_g",
         "greater than 0"),
    ],
)  # fmt: skip
def test_bad_pulse_entries_name_the_field(tmp_path, entry, field, reason):
    with pytest.raises(InputError) as excinfo:
        load_study(pulse_study(tmp_path, f"    - {entry}\n"))
    problems = dict(excinfo.value.problems)
    assert field in problems and reason in problems[field], problems


def test_every_shape_samples():
    for shape in SHAPES:
        pulse = Pulse(shape, AMPLITUDE, PERIOD)
        samples = pulse.sampled(pulse.time_step(50), rest=0.5)
        assert np.all(np.isfinite(samples)) and np.abs(samples).max() <= AMPLITUDE * (1 + 1e-12)
