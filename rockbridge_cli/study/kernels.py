"""The compiled kernels a worker needs, made ready before its first analysis.

numba compiles a kernel on its first call in a process unless its disk cache holds it
(`warmup`). On a cold cache every worker of a run would compile the same kernels at once, each
taking a core for 15–30 s, and the progress would count the compile as analysis time. `prepare`
loads them under a lock per installation on this machine: shared while they load from the cache
(every worker at once), exclusive where one must be compiled (one process at a time: the first
compiles and fills the cache, the next ones load from it). A process that compiles says so, once,
before it starts. A worker that starts before it knows whether it will run anything (its run may
yet be refused) only loads, and compiles once given work. A process that must stop promptly on a
signal and cannot be ended by another (a run's parent, which analyzes itself with one worker)
compiles in a child process instead (`prepare_stoppable`): a compile cannot be stopped from inside.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import signal
import subprocess
import sys
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from ..interrupts import STOPPING, held

COMPILE_TIME_S = 70
"""About how long compiling an analysis's kernels takes on an idle core [s]: 71 s wall, 65 s of
CPU, for a cold `analyze` on the 2-core x86-64 machine of the manual's timings (2026-11-28, load
average 0.8). The 15 s stated before was never this: the integrator alone compiled in 57 s of
CPU at the code of 2026-11-26, and in 56 s before the yielding devices' events. On 2026-11-29,
a slower host, `benchmarks/bench_compile.py` gave 77–96 s of CPU (92 s for the code before the
search for events called what it had inlined)."""

VERTICAL_COMPILE_TIME_S = 50
"""The same for the kernels of an analysis with a vertical ground motion, compiled for it of
their own (`core.schemes.VerticalGround`) [s]: 48 s of CPU for the bundled vertical example
once the others were compiled (2026-11-28); 51–58 s on 2026-11-29 (`bench_compile.py`; 74 s
for the code before)."""

COMPILING = (
    f"compiling the analysis kernels, once for this installation (about {COMPILE_TIME_S} s on an "
    "idle core; later runs load them from numba's cache; 'python -m rockbridge_cli.warmup' "
    "compiles them ahead)"
)
"""What a run says when its kernels are being compiled."""

COMPILING_VERTICAL = (
    "compiling the analysis kernels for a vertical ground motion, once for this installation "
    f"(about {VERTICAL_COMPILE_TIME_S} s on an idle core; later runs load them from numba's "
    "cache; 'python -m rockbridge_cli.warmup' compiles them ahead)"
)
"""What a run with vertical ground motions says when its kernels are being compiled."""

DEVICES_COMPILE_TIME_S = 80
"""The same for the kernels of a bridge with devices, compiled for them of their own
(`core.device_mechanics`) [s]: 78–79 s of CPU on 2026-11-29 (`benchmarks/bench_compile.py`, its
``devices`` row; 115 s for the code before, and 60 s was stated: 4 min in a test run that
compiled them at two fidelities while four other jobs kept a 2-core host busy, issue 41); about
60 s more for those of a bridge with devices under a vertical ground motion."""

COMPILING_DEVICES = (
    "compiling the analysis kernels for bridges with devices (tendons, dampers, dissipators), "
    f"once for this installation (about {DEVICES_COMPILE_TIME_S} s on an idle core; later runs "
    "load them from numba's cache; 'python -m rockbridge_cli.warmup' compiles them ahead)"
)
"""What a run with a bridge that has devices says when their kernels are being compiled."""

_own = False
"""Whether this process is rockbridge's own (`own_process`)."""

_ready: set[str] = set()
"""The kernels this process has: ``horizontal``, ``vertical`` (a vertical ground motion's),
``devices`` (a bridge's with devices), ``devices vertical`` (both)."""


def own_process() -> None:
    """Declare this process rockbridge's own (a ``rockbridge`` command, a local pool's worker),
    not another program's that uses the package: its kernels then load without numba's probe
    for BLAS (`core._jit.skip_blas_probe`)."""
    global _own
    _own = True


def compiling_message(vertical: bool, devices: bool = False) -> str:
    """`COMPILING_DEVICES`, `COMPILING_VERTICAL` or `COMPILING`."""
    if devices:
        return COMPILING_DEVICES
    return COMPILING_VERTICAL if vertical else COMPILING


def prepare(
    announce: Callable[[], None] | None = None,
    compiling: bool = True,
    vertical: bool = False,
    devices: bool = False,
) -> bool:
    """Load the kernels of an analysis into this process (`warmup.analysis_kernels`, with
    ``vertical`` `warmup.vertical_kernels` too, with ``devices`` `warmup.device_kernels` too),
    compiling those numba's cache does not hold, one process of this installation at a time.

    Parameters
    ----------
    announce
        Called, once, if this process compiles a kernel, before it starts.
    compiling
        False: load them only if none needs compiling (a worker that does not know yet whether
        it will run anything), else leave them for a later call.
    vertical
        Also the kernels of an analysis with a vertical ground motion.
    devices
        Also the kernels of a bridge with devices.

    Returns
    -------
    Whether this process has its kernels.
    """
    wanted = {"horizontal"} | ({"vertical"} if vertical else set())
    if devices:
        wanted.add("devices vertical" if vertical else "devices")
    if wanted <= _ready:
        return True
    from .. import warmup  # the compiled kernels: a worker's, not the parent's

    if _own:
        from ..core._jit import skip_blas_probe

        skip_blas_probe()

    loaders = {
        "horizontal": lambda: warmup.analysis_kernels((warmup.studied_bridge(),)),
        "vertical": warmup.vertical_kernels,
        "devices": lambda: warmup.device_kernels(vertical=False),
        "devices vertical": lambda: warmup.device_kernels(vertical=True),
    }

    def load() -> None:
        for variant in sorted(wanted - _ready):
            loaders[variant]()
            _ready.add(variant)

    try:
        with _kernel_lock(exclusive=False), warmup.announced(_refuse):
            load()
    except _Cold:  # one kernel at least must be compiled: by one process at a time
        if not compiling:
            return False
        with _kernel_lock(exclusive=True), warmup.announced(announce):
            load()
    return True


def prepare_stoppable(
    announce: Callable[[], None] | None = None, vertical: bool = False, devices: bool = False
) -> None:
    """`prepare` in a process that a stopping signal must stop within moments: kernels that
    numba's cache holds are loaded here (the signal held meanwhile, `interrupts.held`, but not
    while this waits for another process of the installation to end its compile: a stop ends the
    wait); those it does not hold are compiled in a child process (`_compile_child`), which a stop
    kills at once, and then loaded here from the cache it filled (compiled here if it could not
    fill it).

    Parameters
    ----------
    announce
        Called, once, before the child compiles.
    vertical, devices
        Also the kernels of an analysis with a vertical ground motion, of a bridge with devices.

    Raises
    ------
    KeyboardInterrupt
        A stopping signal while the child compiled (the child is killed first).
    """
    with _kernel_lock(exclusive=False):  # waiting for another process's compile: a stop ends it
        with held():  # (loading only: a shared lock, which this one's does not block)
            if prepare(compiling=False, vertical=vertical, devices=devices):
                return
    if announce is not None:
        announce()
    root = str(Path(os.path.abspath(__file__)).parents[2])  # this copy (numba's cache is per path)
    code = (f"import sys; sys.path.insert(0, {root!r}); from rockbridge_cli.study import kernels; "
            f"kernels._compile_child({os.getpid()}, {vertical}, {devices})")  # fmt: skip
    child = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.DEVNULL,
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    try:
        child.wait()  # a stopping signal raises here
    except BaseException:
        child.kill()
        child.wait()
        raise
    with held():
        prepare(vertical=vertical, devices=devices)


def _compile_child(parent: int, vertical: bool, devices: bool) -> None:
    """The child process of `prepare_stoppable`: compile the kernels into numba's cache. It
    leaves the stopping signals to its parent, which kills it, and dies with it (Linux)."""
    for signum in STOPPING:
        signal.signal(signum, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        ctypes.CDLL(None).prctl(_PR_SET_PDEATHSIG, signal.SIGKILL)
    if os.getppid() == parent:  # else the parent died before the request took effect
        prepare(vertical=vertical, devices=devices)


_PR_SET_PDEATHSIG = 1
"""Linux prctl(2) option: the signal a process gets when its parent dies."""


class _Cold(Exception):
    """numba was about to compile a kernel: its cache does not hold it."""


def _refuse() -> None:
    raise _Cold


@contextmanager
def _kernel_lock(exclusive: bool) -> Iterator[None]:
    """Hold this installation's kernel lock, shared or exclusive, for the block: an advisory
    ``flock`` on a file in the temporary folder named after the package's folder, Python and
    numba. Where no lock can be taken (no ``fcntl``, a folder that cannot be written) the block
    runs without."""
    try:
        import fcntl

        import numba

        key = f"{Path(__file__).resolve().parents[1]} {sys.version} {numba.__version__}"
        name = f"rockbridge-kernels-{hashlib.sha256(key.encode()).hexdigest()[:16]}.lock"
        descriptor = os.open(Path(tempfile.gettempdir()) / name, os.O_RDWR | os.O_CREAT, 0o666)
    except (ImportError, OSError):
        yield
        return
    try:
        fcntl.flock(descriptor, fcntl.LOCK_EX if exclusive else fcntl.LOCK_SH)
        yield
    finally:
        os.close(descriptor)
