"""The one place the package chooses its compiler (for the core and for `motions`).

Every hot kernel is plain Python on floats and numpy arrays, decorated with `jit`. numba compiles it
to machine code (cached on disk after the first run); with the environment variable
``NUMBA_DISABLE_JIT=1`` the very same functions run as ordinary Python, which the tests use to
check that both give the same numbers.
"""

from __future__ import annotations

import sys
import time
from typing import Any

import numba
from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

jit = numba.njit(cache=True, nogil=True, fastmath=False, error_model="numpy")

inlined = numba.njit(cache=True, nogil=True, fastmath=False, error_model="numpy", inline="always")
"""`jit` for the tiny kernels of the innermost loop (a table lookup, a cubic): compiled into each
caller, which saves the call and the reference counting of the arrays it is passed. Each call
site is typed and compiled again, numba's compile being mostly that typing: a kernel that runs
once an event, not once a step, calls a compiled-once kernel instead (`events.watched_one`,
`schemes.accel_called`)."""


def absent(argument_type) -> bool:
    """Whether an optional argument of an `overload` (the devices, a vertical motion) is compiled
    as None: passed None, or left out."""
    return isinstance(argument_type, (types.NoneType, types.Omitted))


_WITHOUT_COUNTING: dict[str, Any] = {"_nrt": False}  # an option numba's type hints leave out
uncounted = numba.njit(
    cache=True, nogil=True, fastmath=False, error_model="numpy", **_WITHOUT_COUNTING
)
"""`jit` without numba's reference counting (its runtime's ``NRT_incref``/``NRT_decref``), for
the kernels of every step (`schemes.take_step`, `events.first_event`, `solver._sample`) and
the loop of steps (`solver._rocking`), which allocate nothing: the arrays they read (the
tables, the record, the histories) outlive the call. Compiled with counting, each inlined table
look-up counted them in and out, two atomic operations each; perf put 24 % of a `default`
solve's CPU in them. Such a kernel may call a counted one (`jit`), which counts its own."""


CLOCK = getattr(time, "CLOCK_MONOTONIC", None)
"""The clock a compiled kernel reads (`clock_ns`): the one `time.perf_counter` reads on Linux and
macOS; None where the C library has no ``clock_gettime`` (Windows), where no kernel reads one."""


@intrinsic
def clock_ns(typingctx):
    """The monotonic clock `CLOCK` in a compiled kernel, as `time.monotonic_ns` reads it [ns]:
    the C library's ``clock_gettime``, linked by name (so that a cached kernel finds it in any
    process). Only where `CLOCK` is not None."""
    assert CLOCK is not None, "no clock_gettime on this platform"

    def codegen(context, builder, signature, args):
        i32, i64 = ir.IntType(32), ir.IntType(64)
        timespec = ir.LiteralStructType([i64, i64])  # seconds, nanoseconds (LP64)
        now = builder.alloca(timespec)
        gettime = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(i32, [i32, timespec.as_pointer()]), "clock_gettime"
        )
        builder.call(gettime, [ir.Constant(i32, CLOCK), now])
        seconds = builder.load(builder.gep(now, [ir.Constant(i32, 0), ir.Constant(i32, 0)]))
        nanoseconds = builder.load(builder.gep(now, [ir.Constant(i32, 0), ir.Constant(i32, 1)]))
        return builder.add(builder.mul(seconds, ir.Constant(i64, 1_000_000_000)), nanoseconds)

    return types.int64(), codegen


def skip_blas_probe() -> None:
    """Spare this process the import of ``scipy.linalg`` (0.18 s by ``python -X importtime`` on
    2026-11-28, scipy 1.17: about a fifth of a worker's kernel loading) that numba makes when its
    compiled code first loads, only to learn whether BLAS is there for the ``np.convolve`` and
    ``np.correlate`` of compiled code (``numba.np.arraymath._HAVE_BLAS``), which no kernel here
    calls: numba is told there is none. Nothing else changes: a compiled ``np.dot`` would still
    import it when compiled, and the kernels compile to the same code either way.

    For rockbridge's own processes alone (`study.kernels.own_process`): in another program's,
    its compiled ``np.convolve`` would lose BLAS. Does nothing where numba has already probed,
    or where ``scipy.linalg``'s BLAS is already imported (the probe is then cheap)."""
    hidden = "scipy.linalg.cython_blas"
    if "numba.np.arraymath" in sys.modules or hidden in sys.modules:
        return
    sys.modules[hidden] = None  # type: ignore[assignment]  # an import of it fails at once
    try:
        import numba.np.arraymath  # noqa: F401  # numba's probe, which now finds no BLAS
    finally:
        del sys.modules[hidden]
