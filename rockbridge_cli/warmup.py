"""Compile every numerical kernel once, so that later processes load them from numba's disk cache.

numba compiles a kernel on its first call in a process unless its disk cache already holds it:
the folder named by ``NUMBA_CACHE_DIR`` if set, else ``__pycache__`` beside the package's sources
(in ``site-packages`` for an installed package) where that folder is writable, else the user's
cache folder (``~/.cache/numba`` on Linux). Compiling the whole package (the core and the
ground-motion numerics) takes 15–30 s. A container image runs ``python -m rockbridge_cli.warmup``
at build time with ``NUMBA_CACHE_DIR`` set for good (see the Dockerfile), so that every container of
a batch job starts analyzing at once. Any installation can run it after ``pip install`` for the
same effect: run from a checkout, whose ``rockbridge_cli`` folder Python imports before the
installed one, it compiles both, so that the ``rockbridge`` command finds its kernels too.

The calls below reach every compiled kernel with the argument types the package uses: one
analysis at every fidelity preset, of a bridge and of a single block, and of a bridge under a
vertical ground motion too, a response spectrum and one short matched record. Compilation
depends on the types only, so small inputs suffice.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from .core import analysis, batch, geometry
from .core.analysis import analyze
from .core.bridge import Bridge
from .core.devices import Damper, Tendon
from .core.fidelity import PRESETS, resolve
from .motions import spectra

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


def analysis_kernels(models: tuple[geometry.Model, ...] | None = None) -> None:
    """Call every kernel an analysis uses (compiling it, or loading it from the disk cache): an
    analysis of a short pulse at every fidelity preset, of each model (default: the studied
    bridge and a single block), and a study's batch of the first (`core.batch`)."""
    ground = pulse(duration=1.0)
    models = models or (studied_bridge(), geometry.single_block(1.3, 13.0, 2500.0, 9.81))
    for model in models:
        for preset in PRESETS:
            analyze(Bridge(model), ground, TIME_STEP, preset)
    if batch.AVAILABLE:  # a study's batches (`study.work`), where the platform runs them
        for preset in PRESETS:
            batch.summarized(analysis.prepare(Bridge(models[0]), resolve(preset)), [ground],
                             [TIME_STEP])  # fmt: skip


def vertical_kernels() -> None:
    """Call every kernel an analysis with a vertical ground motion uses (compiled for it of their
    own, `core.schemes.VerticalGround`): the studied bridge under a short pulse at every
    fidelity preset."""
    motion = pulse(duration=1.0)
    for preset in PRESETS:
        analyze(Bridge(studied_bridge()), motion, TIME_STEP, preset, vertical=0.2 * motion)


def device_kernels(vertical: bool | None = None) -> None:
    """Call every kernel an analysis of a bridge with tendons and dampers uses (compiled for them
    of their own, `core.device_mechanics`): the studied bridge with one of each under a short
    pulse at every fidelity preset, without a vertical ground motion, with one, or (None) both."""
    motion = pulse(duration=1.0)
    restrained = Bridge(
        studied_bridge(), devices=(Tendon(0, 0.0, 4.0e6, 4.0e7), Damper(1, 0.5, 1.0e7))
    )
    verticals = (None, 0.2 * motion) if vertical is None else (0.2 * motion if vertical else None,)
    for preset in PRESETS:
        for up in verticals:
            analyze(restrained, motion, TIME_STEP, preset, vertical=up)


def compile_kernels() -> None:
    """Call every compiled kernel once (compiling it, or loading it from the disk cache); the
    kernels of an analysis with a vertical ground motion and of a bridge with devices too,
    compiled for them of their own (`core.schemes.VerticalGround`, `core.device_mechanics`)."""
    analysis_kernels()
    vertical_kernels()
    device_kernels()
    from .motions import matching  # here: its scipy.fft is not a worker's (`study.kernels`)

    ground = pulse()
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


@contextmanager
def announced(announce: Callable[[], None] | None) -> Iterator[None]:
    """While the block runs, call ``announce`` once, when numba starts compiling a kernel (not
    when it loads one from its disk cache: numba's ``numba:compile`` event)."""
    if announce is None:
        yield
        return
    from numba.core import event

    told: list[bool] = []
    say = announce

    class First(event.Listener):
        def on_start(self, _: event.Event) -> None:
            if not told:
                told.append(True)
                say()

        def on_end(self, _: event.Event) -> None:
            pass

    with event.install_listener("numba:compile", First()):
        yield


def cache_folder() -> str:
    """Where numba keeps the compiled analysis kernels of this package ("?" where this numba does
    not say)."""
    from .core import solver

    return str(getattr(getattr(solver.integrate, "_cache", None), "cache_path", "?"))


def main() -> None:
    """``python -m rockbridge_cli.warmup``: compile every kernel of this package and, when the
    ``rockbridge`` command imports another copy of it (an installed package behind a checkout in
    the current folder), of that copy too; print where each went."""
    started = time.perf_counter()
    compile_kernels()
    here = Path(__file__).resolve().parent
    print(f"kernels of {here} ready in {cache_folder()} ({time.perf_counter() - started:.0f} s)")
    installed = commanded_package()
    if installed is not None and installed != here:
        with tempfile.TemporaryDirectory() as elsewhere:  # no checkout to import first
            subprocess.run([sys.executable, "-m", "rockbridge_cli.warmup"], cwd=elsewhere,
                           check=True)  # fmt: skip


def commanded_package() -> Path | None:
    """The ``rockbridge_cli`` folder a fresh interpreter imports outside the current folder (the
    one the ``rockbridge`` command runs); None if it imports none."""
    code = "import rockbridge_cli, pathlib; print(pathlib.Path(rockbridge_cli.__file__).parent)"
    with tempfile.TemporaryDirectory() as elsewhere:
        found = subprocess.run([sys.executable, "-c", code], cwd=elsewhere, capture_output=True,
                               text=True, check=False)  # fmt: skip
    return Path(found.stdout.strip()).resolve() if found.returncode == 0 else None


if __name__ == "__main__":  # pragma: no cover (run by the Dockerfile and by tests in a subprocess)
    main()
