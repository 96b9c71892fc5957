"""The one place the package chooses its compiler (for the core and for `motions`).

Every hot kernel is plain Python on floats and numpy arrays, decorated with `jit`. numba compiles it
to machine code (cached on disk after the first run); with the environment variable
``NUMBA_DISABLE_JIT=1`` the very same functions run as ordinary Python, which the tests use to
check that both give the same numbers.
"""

from __future__ import annotations

from typing import Any

import numba
from numba import types

jit = numba.njit(cache=True, nogil=True, fastmath=False, error_model="numpy")

inlined = numba.njit(cache=True, nogil=True, fastmath=False, error_model="numpy", inline="always")
"""`jit` for the tiny kernels of the innermost loop (a table lookup, a cubic): compiled into each
caller, which saves the call and the reference counting of the arrays it is passed."""


def absent(argument_type) -> bool:
    """Whether an optional argument of an `overload` (the devices, a vertical motion) is compiled
    as None: passed None, or left out."""
    return isinstance(argument_type, (types.NoneType, types.Omitted))


_WITHOUT_COUNTING: dict[str, Any] = {"_nrt": False}  # an option numba's type hints leave out
uncounted = numba.njit(
    cache=True, nogil=True, fastmath=False, error_model="numpy", **_WITHOUT_COUNTING
)
"""`jit` without numba's reference counting (its runtime's ``NRT_incref``/``NRT_decref``), for
the kernels of every step (`schemes.take_step`, `events.first_event`), which allocate nothing:
the arrays they read (the tables, the record) outlive the call. Compiled with counting, each
inlined table look-up counted them in and out, two atomic operations each; perf put 24 % of a
`default` solve's CPU in them. Such a kernel may call a counted one (`jit`), which counts its
own."""
