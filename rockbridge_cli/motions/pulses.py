"""Analytic ground-acceleration pulses, the idealised near-fault motions of the rocking literature,
as continuous functions of time and sampled on a uniform grid followed by rest.

Every pulse has an amplitude a_p, the largest |ü_g| of the continuous waveform [m/s²], and a
period T_p = 2π/ω_p [s]; some also a phase φ [rad] and a number of cycles. Time starts at 0 with
the ground at rest. The waveforms, with ω_p = 2π/T_p:

``one-sine-a``  Makris & Roussos (2000), type A (one-sine): ü_g = a_p·sin(ω_p·t + φ) for
                0 ≤ t ≤ N·T_p (N = ``cycles``, whole or half, 1 by default; 0.5 is Housner's
                (1963) half-sine).
                With φ = 0 the ground velocity, a_p/ω_p·(1 − cos ω_p·t), is one-sided: the ground
                moves forward and stays (a "fling").
``one-sine-b``  Makris & Roussos (2000), type B (one-cosine): ü_g = a_p·cos(ω_p·t + φ) for
                0 ≤ t ≤ N·T_p. With φ = 0 the velocity, a_p/ω_p·sin ω_p·t, is one full sine: the
                ground moves forward and back to where it started.
``cycloidal-a``, ``cycloidal-b``  Zhang & Makris (2001), Eqs. (1)–(2) and (5)–(6): the same
                waveforms as ``one-sine-a`` and ``one-sine-b`` under their cycloidal names
                (u̇_g = v_p/2·(1 − cos ω_p·t), a_p = ω_p·v_p/2; u̇_g = v_p·sin ω_p·t, a_p = ω_p·v_p).
``cycloidal-c`` Zhang & Makris (2001), type C_n, Eqs. (9)–(10): u̇_g = v_p·[sin(ω_p·t + φ_n) −
                sin φ_n] for 0 ≤ t ≤ (n + 1/2 − φ_n/π)·T_p, so ü_g = a_p·cos(ω_p·t + φ_n),
                a_p = ω_p·v_p, n = ``cycles`` main velocity pulses, and φ_n the phase that brings
                the ground back to where it started: 2·cos φ_n = ((2n + 1)·π − 2·φ_n)·sin φ_n
                (φ_1 = 0.0697π, φ_2 = 0.0410π).
``ricker-symmetric``  Vassiliou & Makris (2011), Eq. (3): ü_g = a_p·(1 − 2π²τ²/T_p²)·
                exp(−π²τ²/T_p²), τ = t − t_c, the "Mexican hat" whose Fourier amplitude peaks at
                ω_p; centred at t_c = 1.5·T_p and cut at 2·t_c, where it is below 1e-8·a_p.
``ricker-antisymmetric``  Vassiliou & Makris (2011), Eq. (4): ü_g = (a_p/β)·(4π²τ²/(3T_p²) − 3)
                ·(2πτ/(√3·T_p))·exp(−2π²τ²/(3T_p²)), the third derivative of a Gaussian, whose
                Fourier amplitude also peaks at ω_p; β = (3 − u₁²)·u₁·exp(−u₁²/2), u₁² = 3 − √6,
                makes a_p its peak; centred at t_c = 2·T_p, cut at 2·t_c (below 2e-9·a_p).
``mavroeidis-papageorgiou``  Mavroeidis & Papageorgiou (2003), Eq. (1): the velocity
                v(t) = (A/2)·[1 + cos(2π·f_p·τ/γ)]·cos(2π·f_p·τ + ν) for |τ| ≤ γ/(2f_p),
                τ = t − γ/(2f_p), f_p = 1/T_p, differentiated exactly (their Eq. 2); γ =
                ``cycles`` (> 1, the carrier's cycles under the envelope, 2 by default), ν =
                ``phase``; A is set so that the peak |ü_g| is a_p.

None of them is baseline-corrected beyond what its definition gives: the one-sine type A leaves
the ground displaced, as the near-fault "fling" it idealises does.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

SHAPES = (
    "one-sine-a", "one-sine-b", "cycloidal-a", "cycloidal-b", "cycloidal-c",
    "ricker-symmetric", "ricker-antisymmetric", "mavroeidis-papageorgiou",
)  # fmt: skip
"""The pulse shapes, by name."""

HAS_PHASE = frozenset({"one-sine-a", "one-sine-b", "cycloidal-a", "cycloidal-b",
                       "mavroeidis-papageorgiou"})  # fmt: skip
"""Shapes with a free phase (a type C_n's is fixed by its definition)."""

DEFAULT_CYCLES = {
    "one-sine-a": 1.0, "one-sine-b": 1.0, "cycloidal-a": 1.0, "cycloidal-b": 1.0,
    "cycloidal-c": 1.0, "mavroeidis-papageorgiou": 2.0,
}  # fmt: skip
"""Shapes with a number of cycles, and its default (the Ricker wavelets have none)."""

HALF_CYCLES = frozenset({"one-sine-a", "one-sine-b", "cycloidal-a", "cycloidal-b"})
"""Shapes whose N is a multiple of ½: their sine, cut at N·T_p, ends where it began (whole N)
or at its opposite (Housner's half-sine, N = 0.5). Cut elsewhere, the pulse would end on a
step of ü_g (a_p·sin(2πN + φ) to 0) and, under a quarter cycle, never reach its a_p."""

RICKER_CENTRE = {"ricker-symmetric": 1.5, "ricker-antisymmetric": 2.0}
"""Centre of each Ricker wavelet, in periods from t = 0; the wavelet is cut at twice it [-]."""

_U1 = 3.0 - math.sqrt(6.0)
_ANTISYMMETRIC_PEAK = math.sqrt(6.0) * math.sqrt(_U1) * math.exp(-0.5 * _U1)
"""β of the antisymmetric Ricker wavelet: max |(u² − 3)·u·exp(−u²/2)|, at u² = 3 − √6."""


@dataclass(frozen=True)
class Pulse:
    """One analytic pulse (the module's docstring gives each waveform).

    Attributes
    ----------
    shape : one of `SHAPES`
    amplitude : a_p, the peak |ü_g| [m/s²]
    period : T_p = 2π/ω_p [s]
    phase : φ, or ν of Mavroeidis & Papageorgiou [rad]; only where the shape has one
    cycles : N, n or γ (`DEFAULT_CYCLES`); None: the shape's default (or none)

    Raises
    ------
    ValueError
        An unknown shape, a non-positive amplitude or period, a phase or a number of cycles the
        shape does not have, a phase beyond ±2π, or a number of cycles it cannot take (n a
        whole number ≥ 1 for type C_n, γ > 1 for Mavroeidis & Papageorgiou).
    """

    shape: str
    amplitude: float
    period: float
    phase: float = 0.0
    cycles: float | None = None

    def __post_init__(self) -> None:
        if self.shape not in SHAPES:
            raise ValueError(f"unknown pulse shape {self.shape!r}: choose {', '.join(SHAPES)}")
        if not (self.amplitude > 0.0 and math.isfinite(self.amplitude)):
            raise ValueError(f"the amplitude must be positive, got {self.amplitude!r}")
        if not (self.period > 0.0 and math.isfinite(self.period)):
            raise ValueError(f"the period must be positive, got {self.period!r}")
        if self.phase and self.shape not in HAS_PHASE:
            raise ValueError(f"a {self.shape} pulse has no free phase")
        if not abs(self.phase) <= 2.0 * math.pi:  # 1e300 ran, its sine all round-off
            raise ValueError(f"the phase must be within ±2π rad (a turn), got {self.phase!r}")
        if self.cycles is None:
            object.__setattr__(self, "cycles", DEFAULT_CYCLES.get(self.shape))
        elif self.shape not in DEFAULT_CYCLES:
            raise ValueError(f"a {self.shape} pulse has no number of cycles")
        elif not (self.cycles > 0.0 and math.isfinite(self.cycles)):
            raise ValueError(f"the number of cycles must be positive, got {self.cycles!r}")
        cycles = self.cycles or 0.0
        if self.shape in HALF_CYCLES and 2.0 * cycles != round(2.0 * cycles):
            raise ValueError(
                f"a {self.shape} pulse has whole or half cycles (0.5: Housner's half-sine), got "
                f"{cycles!r}: cut elsewhere, its sine ends on a step of the ground acceleration"
            )
        if self.shape == "cycloidal-c" and cycles != round(cycles):
            raise ValueError(f"a type C_n pulse has n ≥ 1 whole cycles, got {cycles!r}")
        if self.shape == "mavroeidis-papageorgiou" and not cycles > 1.0:
            raise ValueError(f"γ of a Mavroeidis-Papageorgiou pulse must exceed 1, got {cycles!r}")

    @property
    def frequency(self) -> float:
        """ω_p = 2π/T_p [rad/s]."""
        return 2.0 * math.pi / self.period

    @property
    def duration(self) -> float:
        """How long the ground moves, from t = 0 [s]."""
        if self.shape in RICKER_CENTRE:
            return 2.0 * RICKER_CENTRE[self.shape] * self.period
        cycles = float(self.cycles or 0.0)
        if self.shape == "cycloidal-c":
            return (cycles + 0.5 - type_c_phase(int(cycles)) / math.pi) * self.period
        return cycles * self.period

    def acceleration(self, time: np.ndarray) -> np.ndarray:
        """ü_g at the given times, zero before 0 and after `duration` [m/s²]."""
        t = np.asarray(time, dtype=float)
        inside = (t >= 0.0) & (t <= self.duration)
        return np.where(inside, self.amplitude * _unit_waveform(self, t), 0.0)

    def time_step(self, per_period: int) -> float:
        """The time step nearest T_p/``per_period`` that puts the pulse's end midway between two
        samples: the piecewise-linear ground motion then ramps down across the end with the
        impulse and the centre of the exact pulse, so that a pulse ending with a jump (one-sine
        type B, type C_n) is represented to second order in the step, not first [s]."""
        steps = max(1, round(self.duration * per_period / self.period - 0.5))
        return self.duration / (steps + 0.5)

    def check_samples(self, time_step: float, rest: float, most: float) -> None:
        """Refuse, before any is computed, a sampling of more than ``most`` samples (the work
        limit of an analysis, `core.fidelity.MAX_GROUND_SAMPLES`): a period of 1e-9 s, 1e9
        cycles or a time step of 1e-9 s would otherwise take the memory first.

        Raises
        ------
        ValueError
            How many samples it would need, and what to change.
        """
        samples = (self.duration + rest) / time_step + 1.0
        if not samples <= most:
            raise ValueError(
                f"the pulse would need {samples:.3g} samples ({self.duration:.6g} s of pulse and "
                f"{rest:.6g} s of rest at a {time_step:.3g} s time step), more than "
                f"{most:.3g}: give a longer period or time step, fewer cycles or "
                "less rest"
            )

    def sampled(self, time_step: float, rest: float = 0.0) -> np.ndarray:
        """The pulse at t = 0, Δt, 2Δt, … up to its `duration`, followed by ``rest`` seconds of
        zeros (free vibration) [m/s²].

        Parameters
        ----------
        time_step
            Δt [s].
        rest
            Time at rest after the pulse [s], rounded to whole steps.
        """
        if not (time_step > 0.0 and math.isfinite(time_step)):
            raise ValueError(f"the time step must be positive, got {time_step!r}")
        if not (rest >= 0.0 and math.isfinite(rest)):
            raise ValueError(f"the rest must be a finite time ≥ 0 s, got {rest!r}")
        count = math.floor(self.duration / time_step * (1.0 + 1e-12)) + 1
        moving = self.acceleration(np.arange(count) * time_step)
        return np.concatenate([moving, np.zeros(round(rest / time_step))])


def type_c_phase(n: int) -> float:
    """φ_n of Zhang & Makris's type C_n pulse: the root in (0, π/2) of 2·cos φ =
    ((2n + 1)·π − 2φ)·sin φ, which brings the ground back to rest where it started [rad]."""

    def excess(phi: float) -> float:
        return 2.0 * math.cos(phi) - ((2 * n + 1) * math.pi - 2.0 * phi) * math.sin(phi)

    low, high = 0.0, 0.5 * math.pi  # excess(low) = 2 > 0 > excess(high)
    for _ in range(80):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if excess(middle) > 0.0 else (low, middle)
    return 0.5 * (low + high)


def _unit_waveform(pulse: Pulse, t: np.ndarray) -> np.ndarray:
    """The waveform of unit amplitude at times t inside the pulse [-]."""
    omega, shape = pulse.frequency, pulse.shape
    if shape in ("one-sine-a", "cycloidal-a"):
        return np.sin(omega * t + pulse.phase)
    if shape in ("one-sine-b", "cycloidal-b"):
        return np.cos(omega * t + pulse.phase)
    if shape == "cycloidal-c":
        return np.cos(omega * t + type_c_phase(int(pulse.cycles or 1)))
    if shape == "ricker-symmetric":
        x = (math.pi / pulse.period * (t - RICKER_CENTRE[shape] * pulse.period)) ** 2
        return (1.0 - 2.0 * x) * np.exp(-x)
    if shape == "ricker-antisymmetric":
        tau = t - RICKER_CENTRE[shape] * pulse.period
        u = 2.0 * math.pi * tau / (math.sqrt(3.0) * pulse.period)
        return (u * u - 3.0) * u * np.exp(-0.5 * u * u) / _ANTISYMMETRIC_PEAK
    shape_of = (pulse.period, float(pulse.cycles or 2.0), pulse.phase)  # T_p, γ, ν
    return _mp_acceleration(t, *shape_of) / _mp_peak(*shape_of)


def _mp_acceleration(t: np.ndarray, period: float, gamma: float, phase: float) -> np.ndarray:
    """dv/dt of Mavroeidis & Papageorgiou's velocity pulse with A = 1, from t = 0 [1/s]."""
    tau = 2.0 * math.pi / period * (np.asarray(t, dtype=float) - 0.5 * gamma * period)
    envelope, carrier = 1.0 + np.cos(tau / gamma), np.cos(tau + phase)
    swell = np.sin(tau / gamma) * carrier / gamma  # the envelope's rate of change
    return -math.pi / period * (swell + np.sin(tau + phase) * envelope)


@functools.lru_cache(maxsize=256)
def _mp_peak(period: float, gamma: float, phase: float) -> float:
    """max |dv/dt| of `_mp_acceleration`: the largest of 2^14 samples, refined by the parabola
    through it and its neighbours (relative error below 1e-10) [1/s]."""
    t = np.linspace(0.0, gamma * period, 2**14 + 1)
    values = np.abs(_mp_acceleration(t, period, gamma, phase))
    i = int(np.clip(np.argmax(values), 1, t.size - 2))
    left, middle, right = values[i - 1 : i + 2]
    curvature = left - 2.0 * middle + right
    shift = 0.5 * (left - right) / curvature if curvature < 0.0 else 0.0
    return float(middle - 0.25 * (left - right) * shift)
