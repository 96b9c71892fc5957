"""Compile every numerical kernel once, so that later processes load them from numba's disk cache.

numba compiles a kernel on its first call in a process unless its disk cache (``__pycache__``
next to the source, or the folder named by ``NUMBA_CACHE_DIR``) already holds it; compiling the
whole package (the core and the ground-motion numerics) takes 8–10 s. A container image runs
``python -m rockbridge_cli.warmup`` at build time with ``NUMBA_CACHE_DIR`` set for good (see the
Dockerfile), so that every container of a batch job starts analysing at once. Any installation can
run it after ``pip install`` for the same effect.

The calls below reach every compiled kernel with the argument types the package uses: one
analysis at every fidelity preset, of a bridge and of a single block, a response spectrum and one
short matched record. Compilation depends on the types only, so small inputs suffice.
"""

from __future__ import annotations

import numpy as np

from .core import geometry
from .core.analysis import analyze
from .core.bridge import Bridge
from .core.fidelity import PRESETS
from .motions import matching, spectra

TIME_STEP = 0.01
"""Sample interval of the warm-up ground motion [s]."""


def studied_bridge() -> geometry.Model:
    """The paper's studied bridge with h̄ = 1.25 (Thomaidis et al. 2022, Table 1), in SI units."""
    density, B, H1, H2, L1, L2, h, area = 2500.0, 1.3, 13.0, 10.4, 38.0, 60.0, 0.85, 6.0
    length = 2.0 * L1 + L2
    m1, m2 = geometry.pier_mass(density, B, H1), geometry.pier_mass(density, B, H2)
    md = density * area * length
    return geometry.Model(
        B=B, H1=H1, H2=H2, L1=L1, L2=L2, h=h, m1=m1, m2=m2, md=md,
        I1=geometry.pier_inertia(m1, B, H1), I2=geometry.pier_inertia(m2, B, H2),
        Id=geometry.deck_inertia(md, length, 2.0 * h), g=9.81, has_abutments=1.0,
        u_jo=0.12, k=132e6, c=48e6, u_ab=0.10, e=0.6,
        m_abut=geometry.backfill_mass(2000.0, 1.0, 9.5, 2.0),
    )  # fmt: skip


def pulse(amplitude: float = 6.0, period: float = 1.0, duration: float = 4.0) -> np.ndarray:
    """One sine cycle of ground acceleration followed by rest, at `TIME_STEP` [m/s²]."""
    time = np.arange(0.0, duration, TIME_STEP)
    return np.where(time < period, amplitude * np.sin(2.0 * np.pi * time / period), 0.0)


def compile_kernels() -> None:
    """Call every compiled kernel once (compiling it, or loading it from the disk cache)."""
    ground = pulse()
    for model in (studied_bridge(), geometry.single_block(1.3, 13.0, 2500.0, 9.81)):
        for preset in PRESETS:
            analyze(Bridge(model), ground, TIME_STEP, preset)
    periods = matching.compute_matching_periods((0.1, 1.0), 10, TIME_STEP)
    spectra.compute_psa(ground, TIME_STEP, periods, 0.05)
    matching.generate_matched_record(
        periods,
        np.full(periods.size, 10.0),
        4.0,
        TIME_STEP,
        matching.Envelope(0.5, 10.0, 0.5, 0.05),
        np.random.default_rng(0),
        matching.MatchSettings(max_iterations=1, max_attempts=1),
    )


if __name__ == "__main__":  # pragma: no cover (run by the Dockerfile and by tests in a subprocess)
    compile_kernels()
